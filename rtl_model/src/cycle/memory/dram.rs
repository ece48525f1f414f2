//! External DRAM behind the cache: the miss-status registers (MSHRs, one per line in
//! flight, any number of reads merged into each) and the line fills sharing one data bus of
//! `bytes_per_cycle` bytes per cycle, in issue order.
//!
//! Pipeline position: inside [`super::NodeMemory`]; a miss in step 4 of a simulated cycle
//! issues a fill here or merges into one in flight, step 1 retires the fills that complete
//! (installing their line in the cache tags), step 3 counts the bytes on the bus.

use super::cache::Tags;
use super::config::NodeMemoryConfig;
use super::request::Source;
use std::collections::VecDeque;

/// A line fill on the DRAM bus. Byte slots count bus capacity: cycle `c` carries slots
/// `c·B .. (c+1)·B`, so fills serialised on slots never exceed the per-cycle budget.
#[derive(Clone, Copy, Debug)]
struct Fill {
    line: u64,
    start: u128,
    end: u128,
    done: u64,
}

/// An MSHR: a line in flight.
#[derive(Clone, Copy, Debug)]
struct Mshr {
    done: u64,
    /// Install the line when it arrives (some cached read wants it).
    install: bool,
}

/// The MSHRs and the fills on the bus.
#[derive(Clone, Debug)]
pub(super) struct Dram {
    /// Peak bytes per cycle (B).
    rate: u128,
    /// Cycles from a fill's issue to its first data.
    latency: u128,
    /// Bytes of one fill (a cache line).
    line_bytes: u128,
    /// MSHRs there are.
    max_mshrs: usize,
    /// Lines in flight and their MSHRs; a handful (`dram.mshrs`), so a linear search beats
    /// a tree.
    mshrs: Vec<(u64, Mshr)>,
    fills: VecDeque<Fill>,
    /// First free byte slot of the bus.
    bus_next: u128,
}

impl Dram {
    /// An idle DRAM of `cfg` at cycle 0.
    pub(super) fn new(cfg: &NodeMemoryConfig) -> Self {
        Self {
            rate: u128::from(cfg.dram.bytes_per_cycle),
            latency: u128::from(cfg.dram.latency),
            line_bytes: u128::from(cfg.cache.line_bytes),
            max_mshrs: cfg.dram.mshrs as usize,
            mshrs: Vec::new(),
            fills: VecDeque::new(),
            bus_next: 0,
        }
    }

    /// Whether no fill is in flight.
    #[inline]
    pub(super) fn is_idle(&self) -> bool {
        self.fills.is_empty()
    }

    /// MSHRs in use.
    #[inline]
    pub(super) fn mshrs_in_use(&self) -> usize {
        self.mshrs.len()
    }

    /// Whether a fill completes or moves bytes in cycle `k`.
    #[inline]
    pub(super) fn has_work(&self, k: u64) -> bool {
        match self.fills.front() {
            // Fills complete in issue order, so the front one completes and transfers first.
            Some(f) => f.done <= k || f.start < (u128::from(k) + 1) * self.rate,
            None => false,
        }
    }

    /// The cycle the front fill starts to transfer, if any fill is in flight.
    #[inline]
    pub(super) fn next_transfer(&self) -> Option<u64> {
        self.fills
            .front()
            .map(|f| u64::try_from(f.start / self.rate).unwrap_or(u64::MAX))
    }

    /// Step 1 of cycle `k`: fills that complete now install their line (when a cached read
    /// wants it) and free their MSHR, before this cycle's lookups, so a lookup in the
    /// completion cycle hits.
    #[inline]
    pub(super) fn retire(&mut self, k: u64, tags: &mut Tags) {
        while let Some(f) = self.fills.front().copied() {
            if f.done > k {
                break;
            }
            self.fills.pop_front();
            let freed = self.mshrs.iter().position(|&(l, _)| l == f.line);
            if let Some((_, m)) = freed.map(|i| self.mshrs.swap_remove(i)) {
                if m.install {
                    tags.install(f.line);
                }
            }
        }
    }

    /// Step 3 of cycle `k`: bytes the bus moves in it (at most `bytes_per_cycle`).
    #[inline]
    pub(super) fn bytes_in(&self, k: u64) -> u64 {
        let (lo, hi) = (u128::from(k) * self.rate, (u128::from(k) + 1) * self.rate);
        let mut bytes = 0u128;
        for f in &self.fills {
            if f.start >= hi {
                break;
            }
            let (s, e) = (f.start.max(lo), f.end.min(hi));
            bytes += e.saturating_sub(s);
        }
        bytes as u64
    }

    /// A miss on `line` looked up in cycle `k`: merges into the fill in flight for the line
    /// ([`Source::Merged`]) or issues one ([`Source::Miss`]), and returns when it completes;
    /// `None` when every MSHR is taken (nothing changes then). `cached`: the line is to be
    /// installed when it arrives.
    #[inline]
    pub(super) fn miss(&mut self, line: u64, cached: bool, k: u64) -> Option<(Source, u64)> {
        if let Some((_, m)) = self.mshrs.iter_mut().find(|(l, _)| *l == line) {
            m.install |= cached;
            return Some((Source::Merged, m.done));
        }
        if self.mshrs.len() >= self.max_mshrs {
            return None;
        }
        let rate = self.rate;
        let earliest = (u128::from(k) + self.latency) * rate;
        let start = earliest.max(self.bus_next);
        let end = start + self.line_bytes;
        let done = u64::try_from(end.div_ceil(rate)).unwrap_or(u64::MAX);
        self.bus_next = end;
        self.fills.push_back(Fill {
            line,
            start,
            end,
            done,
        });
        self.mshrs.push((
            line,
            Mshr {
                done,
                install: cached,
            },
        ));
        Some((Source::Miss, done))
    }
}
