//! A read's service in a simulated cycle, once the cycle's order is set: the arrivals put in
//! service order, the cache lookup, the miss queue's tag re-check, the send to DRAM (merge or
//! fill), and the completion record handed to the wheel.
//!
//! Pipeline position: inside [`super::NodeMemory`]; its `step` calls these for every read it
//! arbitrates (the module doc of `memory/mod.rs` states the timing they implement).

use super::cache::line_of;
use super::request::Req;
use super::{Completion, FetchKind, NodeMemory, RequestId, Source};

impl NodeMemory {
    /// Puts the cycle's arrivals in service order, (requester, id), as `order`'s low 32 bits
    /// (indices into `arrivals`; `order` left empty: `arrivals` is in order itself). `direct`:
    /// how many of them were requested for the cycle being stepped (they come first, with
    /// ids rising with their index, as `request` numbers them); the rest came from the heap.
    ///
    /// The common case, no heap entry, sorts one `u64` per read, requester above index:
    /// within a requester the index order is the id order, and the keys are unique, so the
    /// unstable sort gives exactly the (requester, id) order. A sort of plain integers runs a
    /// sorting network where a sort of the 32-byte requests by a 128-bit key ran a general
    /// insertion sort (issue 30: 4 % of the cycle loop). Heap entries (requests made for a
    /// later cycle, never by the walker pool) have lower ids than every direct one, so the
    /// index no longer orders them: then the requests themselves are sorted by the pair.
    pub(super) fn sort_arrivals(&mut self, direct: usize) {
        let n = self.arrivals.len();
        if n < 2 || (direct == n && self.arrivals.is_sorted_by_key(|r| r.requester)) {
            return;
        }
        if direct < n || n > u32::MAX as usize {
            // (requester, id) packed in one integer: the same order as the pair (ids are
            // unique), compared without branches.
            self.arrivals
                .sort_unstable_by_key(|r| (u128::from(r.requester) << 64) | u128::from(r.id));
            return;
        }
        self.order.extend(
            self.arrivals
                .iter()
                .enumerate()
                .map(|(i, r)| (u64::from(r.requester) << 32) | i as u64),
        );
        self.order.sort_unstable();
    }

    /// Looks up a read in cycle `k`: where it is served and when it completes, or `None` when
    /// it misses with every MSHR taken (nothing changes then).
    #[inline]
    pub(super) fn lookup(&mut self, r: Req, k: u64) -> Option<(Source, Option<u64>)> {
        let line = line_of(r.kind, r.addr, self.line_bytes);
        let cached = r.kind != FetchKind::Attr || self.cfg.cache.attr_cached;
        if cached && self.tags.touch(line) {
            self.stats.cache_lookups += 1;
            self.stats.cache_hits += 1;
            let done = k + u64::from(self.cfg.cache.hit_latency);
            return Some((Source::CacheHit, Some(done)));
        }
        self.send_to_dram(r, k)
    }

    /// The tag re-check of the miss queue's head `r` in cycle `k`: `None` if its line is not
    /// cached (it goes on to DRAM), `Some(true)` if it hit and was served through a lookup
    /// port of its bank (counted as a cache hit, completing `hit_latency` later), `Some(false)`
    /// if it hits but every port of its bank was taken this cycle by earlier re-checks.
    #[inline]
    pub(super) fn replay_hit(&mut self, r: Req, k: u64) -> Option<bool> {
        let line = line_of(r.kind, r.addr, self.line_bytes);
        let cached = r.kind != FetchKind::Attr || self.cfg.cache.attr_cached;
        if !cached || !self.tags.contains(line) {
            return None;
        }
        let bank = (line % self.cache_q.len() as u64) as usize;
        if self.replay_ports[bank] >= self.cfg.cache.ports {
            return Some(false);
        }
        self.replay_ports[bank] += 1;
        self.tags.touch(line);
        self.stats.cache_lookups += 1;
        self.stats.cache_hits += 1;
        let done = k + u64::from(self.cfg.cache.hit_latency);
        self.complete(r, k, done, Source::CacheHit);
        Some(true)
    }

    /// A read that missed the tags (or is not cached) goes to DRAM in cycle `k`: it merges
    /// into the fill of its line in flight or issues one, and is counted; `None` when every
    /// MSHR is taken (nothing changes then). A read from the miss queue comes here after its
    /// tags were checked again ([`replay_hit`](Self::replay_hit)), so it never fetches a line
    /// that a fill issued while it waited has brought in.
    #[inline]
    pub(super) fn send_to_dram(&mut self, r: Req, k: u64) -> Option<(Source, Option<u64>)> {
        let line = line_of(r.kind, r.addr, self.line_bytes);
        let cached = r.kind != FetchKind::Attr || self.cfg.cache.attr_cached;
        let (source, done) = self.dram.miss(r, line, cached, k)?;
        let merged = source == Source::Merged;
        if !merged {
            self.stats.dram_fills += 1;
            self.stats.mshr_max_in_use = self
                .stats
                .mshr_max_in_use
                .max(self.dram.mshrs_in_use() as u64);
        }
        if cached {
            self.stats.cache_lookups += 1;
            if merged {
                self.stats.cache_merged += 1;
            } else {
                self.stats.cache_misses += 1;
            }
        } else {
            self.stats.uncached_reads += 1;
            if merged {
                self.stats.uncached_merged += 1;
            }
        }
        Some((source, done))
    }

    /// Counts a served read and queues its completion. Inlined into `step`: it runs for every
    /// read, and out of line (as it was once moved here from `mod.rs`, another codegen unit)
    /// the one-frame profile of docs/cycle-model.md §3 took 18 M more instructions (issue 30).
    #[inline]
    pub(super) fn complete(&mut self, r: Req, served: u64, done: u64, source: Source) {
        let latency = done - r.cycle;
        self.stats.served += 1;
        self.stats.latency_sum += latency;
        self.stats.latency_max = self.stats.latency_max.max(latency);
        self.pending.push(Completion {
            id: RequestId(r.id),
            requester: r.requester,
            kind: r.kind,
            addr: r.addr,
            cycle_requested: r.cycle,
            cycle_served: served,
            cycle_done: done,
            source,
        });
    }
}
