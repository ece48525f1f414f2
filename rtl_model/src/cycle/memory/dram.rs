//! External DRAM behind the cache: the miss-status registers (MSHRs, one per line in
//! flight, any number of reads merged into each) and the backend that times the line fills:
//! the built-in model (fills share one data bus of `bytes_per_cycle` bytes per cycle, in issue
//! order, after a fixed latency) or DRAMsim3 ([`super::dramsim3`]).
//!
//! Pipeline position: inside [`super::NodeMemory`]; a miss in step 4 of a simulated cycle
//! issues a fill here or merges into one in flight, step 1 retires the fills that complete
//! (installing their line in the cache tags), step 3 counts the bytes on the bus.
//!
//! With the built-in model a fill's completion cycle is known when it is issued, so every
//! read's completion is too. With DRAMsim3 it is known only when DRAMsim3 returns the fill's
//! last transaction (in step 1 of a later cycle, at least `controller_latency` cycles before
//! the completion): the reads that miss or merge meanwhile are parked in their MSHR and
//! handed back by [`Dram::retire`] with their completion cycle.

use super::cache::Tags;
use super::config::{ConfigError, DramBackend, NodeMemoryConfig};
use super::dramsim3::DramSim3;
use super::mshr::MshrTable;
use super::request::{Req, Source};
use super::stats::DramDeviceStats;
use std::collections::VecDeque;

/// A read waiting in an MSHR whose fill's completion cycle is not known yet: the request,
/// the cycle it was looked up in, and where it was served.
pub(super) type Parked = (Req, u64, Source);

/// A parked read whose completion cycle became known: request, lookup cycle, completion
/// cycle, source.
pub(super) type Resolved = (Req, u64, u64, Source);

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
#[derive(Clone, Debug)]
struct Mshr {
    /// When the fill completes; `None` while DRAMsim3 has not returned it.
    done: Option<u64>,
    /// Install the line when it arrives (some cached read wants it).
    install: bool,
    /// Cycle the fill was issued.
    issued: u64,
    /// Reads waiting for `done` to be known (DRAMsim3 only).
    parked: Vec<Parked>,
}

/// The MSHRs and the backend that times their fills.
#[derive(Debug)]
pub(super) struct Dram {
    /// MSHRs there are.
    max_mshrs: usize,
    /// Lines in flight and their MSHRs, found by line through an index (up to `dram.mshrs`
    /// of them: 256 by default, too many to scan per miss).
    mshrs: MshrTable<Mshr>,
    /// DRAMsim3's fills returned in the cycle being stepped (kept to reuse its allocation).
    returned: Vec<(u64, u64)>,
    /// Reads parked in the MSHRs.
    parked: usize,
    backend: Backend,
}

#[derive(Debug)]
enum Backend {
    BuiltIn(Bus),
    DramSim3(Box<DramSim3>),
}

/// The built-in model's data bus and the fills on it.
#[derive(Clone, Debug)]
struct Bus {
    /// Peak bytes per cycle (B).
    rate: u128,
    /// Cycles from a fill's issue to its first data.
    latency: u128,
    /// Bytes of one fill (a cache line).
    line_bytes: u128,
    fills: VecDeque<Fill>,
    /// First free byte slot of the bus.
    bus_next: u128,
}

impl Bus {
    /// The cycle the front fill starts to transfer, if any fill is in flight.
    #[inline]
    fn next_transfer(&self) -> Option<u64> {
        self.fills
            .front()
            .map(|f| u64::try_from(f.start / self.rate).unwrap_or(u64::MAX))
    }

    /// Bytes the bus moves in cycle `k` (at most `bytes_per_cycle`).
    #[inline]
    fn bytes_in(&self, k: u64) -> u64 {
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

    /// Puts the fill of `line`, issued in cycle `k`, on the bus; returns its completion.
    #[inline]
    fn issue(&mut self, line: u64, k: u64) -> u64 {
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
        done
    }
}

impl Dram {
    /// An idle DRAM of `cfg` at cycle 0, behind a pipeline clocked at `clock_mhz` (used by
    /// DRAMsim3 only).
    pub(super) fn new(cfg: &NodeMemoryConfig, clock_mhz: u32) -> Result<Self, ConfigError> {
        let backend = match &cfg.dram.backend {
            DramBackend::BuiltIn => Backend::BuiltIn(Bus {
                rate: u128::from(cfg.dram.bytes_per_cycle),
                latency: u128::from(cfg.dram.latency),
                line_bytes: u128::from(cfg.cache.line_bytes),
                fills: VecDeque::new(),
                bus_next: 0,
            }),
            DramBackend::DramSim3 {
                config,
                channels,
                controller_latency,
            } => Backend::DramSim3(Box::new(DramSim3::new(
                config,
                *channels,
                *controller_latency,
                cfg.cache.line_bytes,
                clock_mhz,
            )?)),
        };
        Ok(Self {
            max_mshrs: cfg.dram.mshrs as usize,
            mshrs: MshrTable::with_capacity(cfg.dram.mshrs as usize),
            returned: Vec::new(),
            parked: 0,
            backend,
        })
    }

    /// Whether no fill is in flight.
    #[inline]
    pub(super) fn is_idle(&self) -> bool {
        match &self.backend {
            Backend::BuiltIn(bus) => bus.fills.is_empty(),
            Backend::DramSim3(_) => self.mshrs.is_empty(),
        }
    }

    /// MSHRs in use.
    #[inline]
    pub(super) fn mshrs_in_use(&self) -> usize {
        self.mshrs.len()
    }

    /// Reads parked in the MSHRs, not yet given a completion cycle.
    #[inline]
    pub(super) fn parked(&self) -> usize {
        self.parked
    }

    /// A lower bound on the completion cycle of every parked read (`None` without any): a
    /// fill issued in cycle `s` completes at `s + 1 + controller_latency` at the earliest
    /// (docs/cycle-model.md, DRAM); at least `now`.
    pub(super) fn parked_bound(&self, now: u64) -> Option<u64> {
        let Backend::DramSim3(d) = &self.backend else {
            return None;
        };
        self.mshrs
            .iter()
            .filter(|(_, m)| !m.parked.is_empty())
            .map(|(_, m)| (m.issued + 1 + d.controller_latency()).max(now))
            .min()
    }

    /// Whether a fill completes or moves bytes in cycle `k`.
    #[inline]
    pub(super) fn has_work(&self, k: u64) -> bool {
        match &self.backend {
            Backend::BuiltIn(bus) => match bus.fills.front() {
                // Fills complete in issue order, so the front one completes and transfers
                // first.
                Some(f) => f.done <= k || f.start < (u128::from(k) + 1) * bus.rate,
                None => false,
            },
            // DRAMsim3 runs every cycle while a fill is in it (its completions are not known
            // ahead); after that only the known completions are events.
            Backend::DramSim3(d) => {
                d.busy()
                    || self
                        .mshrs
                        .iter()
                        .any(|(_, m)| m.done.is_some_and(|t| t <= k))
            }
        }
    }

    /// The first cycle with DRAM work, if any fill is in flight.
    #[inline]
    pub(super) fn next_transfer(&self) -> Option<u64> {
        match &self.backend {
            Backend::BuiltIn(bus) => bus.next_transfer(),
            Backend::DramSim3(_) => self.mshrs.iter().filter_map(|(_, m)| m.done).min(),
        }
    }

    /// Step 1 of cycle `k`: fills that complete now install their line (when a cached read
    /// wants it) and free their MSHR, before this cycle's lookups, so a lookup in the
    /// completion cycle hits. With DRAMsim3, runs the DRAM clocks of cycle `k` first and
    /// appends to `resolved` the parked reads whose fill's completion cycle became known.
    #[inline]
    pub(super) fn retire(&mut self, k: u64, tags: &mut Tags, resolved: &mut Vec<Resolved>) {
        match &mut self.backend {
            Backend::BuiltIn(bus) => {
                while let Some(f) = bus.fills.front().copied() {
                    if f.done > k {
                        break;
                    }
                    bus.fills.pop_front();
                    if let Some(m) = self.mshrs.remove(f.line) {
                        if m.install {
                            tags.install(f.line);
                        }
                    }
                }
            }
            Backend::DramSim3(d) => {
                let mut done = std::mem::take(&mut self.returned);
                done.clear();
                d.advance(k, &mut done);
                for &(line, at) in &done {
                    if let Some(m) = self.mshrs.get_mut(line) {
                        m.done = Some(at);
                        self.parked -= m.parked.len();
                        resolved.extend(m.parked.drain(..).map(|(r, s, src)| (r, s, at, src)));
                    }
                }
                self.returned = done;
                // Free in (done, line) order so the tags see the same installs every run.
                loop {
                    let next = self
                        .mshrs
                        .iter()
                        .filter(|(_, m)| m.done.is_some_and(|t| t <= k))
                        .min_by_key(|&(l, m)| (m.done, l))
                        .map(|(l, _)| l);
                    let Some(line) = next else { break };
                    if self.mshrs.remove(line).is_some_and(|m| m.install) {
                        tags.install(line);
                    }
                }
            }
        }
    }

    /// Step 3 of cycle `k`: bytes the DRAM moved in it. Built-in: at most `bytes_per_cycle`.
    /// DRAMsim3: the bursts that completed in the DRAM clocks of cycle `k`.
    #[inline]
    pub(super) fn bytes_in(&self, k: u64) -> u64 {
        match &self.backend {
            Backend::BuiltIn(bus) => bus.bytes_in(k),
            Backend::DramSim3(d) => d.bytes_last(),
        }
    }

    /// A miss of read `r` on `line` looked up in cycle `k`: merges into the fill in flight
    /// for the line ([`Source::Merged`]) or issues one ([`Source::Miss`]), and returns when it
    /// completes, `None` inside when that is not known yet (DRAMsim3: the read is parked and
    /// [`Self::retire`] returns it later); `None` when every MSHR is taken (nothing changes
    /// then). `cached`: the line is to be installed when it arrives.
    #[inline]
    pub(super) fn miss(
        &mut self,
        r: Req,
        line: u64,
        cached: bool,
        k: u64,
    ) -> Option<(Source, Option<u64>)> {
        if let Some(m) = self.mshrs.get_mut(line) {
            m.install |= cached;
            if m.done.is_none() {
                m.parked.push((r, k, Source::Merged));
                self.parked += 1;
            }
            return Some((Source::Merged, m.done));
        }
        if self.mshrs.len() >= self.max_mshrs {
            return None;
        }
        let (done, parked) = match &mut self.backend {
            Backend::BuiltIn(bus) => (Some(bus.issue(line, k)), Vec::new()),
            Backend::DramSim3(d) => {
                d.issue(line);
                self.parked += 1;
                (None, vec![(r, k, Source::Miss)])
            }
        };
        self.mshrs.insert(
            line,
            Mshr {
                done,
                install: cached,
                issued: k,
                parked,
            },
        );
        Some((Source::Miss, done))
    }

    /// The DRAMsim3 device's counters of the current window (`None` for the built-in model).
    pub(super) fn device_stats(&self) -> Option<DramDeviceStats> {
        match &self.backend {
            Backend::BuiltIn(_) => None,
            Backend::DramSim3(d) => Some(d.stats()),
        }
    }

    /// Starts a new statistics window of the device's counters.
    pub(super) fn reset_device_stats(&mut self) {
        if let Backend::DramSim3(d) = &mut self.backend {
            d.reset_stats();
        }
    }
}
