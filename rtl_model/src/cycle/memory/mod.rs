//! Node memory: the cycle-level model of where the octree walkers' reads go and when they
//! come back.
//!
//! # Where it sits
//!
//! Between the walker pool and the memories of the part. Every walker context reads the SVO
//! image of `docs/svo-format.md` (§12 lists the traffic): one 32-bit word per child descriptor
//! (the root's included), one more word when a descriptor uses the far escape, one word per
//! leaf slot, and one 8-byte record (two words) from the separate attribute array for the leaf
//! a ray hits. The walker pool calls [`NodeMemory::request`] for each of those reads and
//! [`NodeMemory::tick_into`] once per cycle to collect the reads that have completed. The model
//! does not hold the data; the walkers read the words from the [`SvoImage`](crate::svo::SvoImage) themselves (the
//! functional result cannot depend on timing) and use this model only for *when*.
//!
//! # The three places a read can be served
//!
//! 1. **On-chip node store** (block RAM): the top [`OnChipConfig::levels`] levels of the tree.
//!    Fixed latency, `banks` word-interleaved banks of `ports_per_bank` ports each, each bank
//!    with its request queue; with `combine`, reads of a word already queued share its read.
//! 2. **Cache** (set-associative, LRU, UltraRAM-sized) in front of external DRAM, shared by the
//!    rest of the node image and the attribute array: `banks` line-interleaved banks, each
//!    with its request queue and `ports` lookup ports, and a miss queue (hit under miss).
//!    Requests reach a bank's queue through the walker-to-bank crossbar (what it costs:
//!    [`crossbar`]).
//! 3. **External DRAM**: a fixed latency, a peak byte rate per cycle, and a limited number of
//!    outstanding line fills (MSHRs). A miss fills a whole cache line.
//!
//! # Why the on-chip part is "the top levels", and why they are the first words
//!
//! The part of the image every ray touches is the top of the tree: each walk starts at the
//! root and descends through levels 1, 2, …, so those few words are read by every ray, and
//! there are at most 8^l of them at level l (about 4^l for the surface voxels the builders
//! make). The on-chip region is therefore the image's top `levels` levels
//! ([`MemoryLayout::from_image`]): the root word and the groups (slots and far words) of
//! every internal node above level `levels − 1`, i.e. every descriptor of a node at a level
//! below `levels`, the far word needed to descend from it, and any leaf slot at those levels.
//! The image lays those levels out first, level by level (`svo/build.rs`, up to
//! `PREFIX_LEVELS` = 8; deeper subtrees follow depth first), so for `levels ≤ 8` the region
//! is one prefix `[0, end)` of each image: the RTL store tests an address with one compare
//! and holds each word at its own address (bank = word address mod banks, as modelled). For
//! `levels > 8` the model still holds the deeper levels' groups, scattered through the
//! depth-first part, as a whitelist (an RTL store would need an address translation for
//! them). Whole levels are kept, up to [`OnChipConfig::max_bytes`], because a partial level
//! is not a useful prefix of the top. To size the store by bytes instead, set `levels` to its
//! maximum (21) and `max_bytes` to the budget: it then holds as many whole top levels as fit.
//!
//! # Use
//!
//! ```text
//! let layout = MemoryLayout::from_image(&image, &cfg.onchip)?;
//! let mut mem = NodeMemory::new(cfg, layout)?;
//! let mut done = Vec::new();
//! for cycle in 0.. {
//!     done.clear();
//!     mem.tick_into(cycle, &mut done);
//!     for c in &done { /* c.id's data is valid now: wake its walker context */ }
//!     /* evaluate the walkers; each read: */ mem.request(cycle, addr, FetchKind::Node, ctx)?;
//! }
//! let frame = mem.reset_stats(); // per-frame window: hit rate, DRAM % of peak, stalls
//! ```
//!
//! # Timing semantics
//!
//! * **Calling convention.** `tick_into(c, ..)` is called at the *start* of cycle `c`: it finishes the
//!   arbitration of every cycle before `c` and returns the reads whose data is valid in cycle
//!   `c` (`cycle_done ≤ c`). Requests made during cycle `c` (after that call) are arbitrated
//!   as cycle-`c` requests in the next one. This is the two-phase discipline of
//!   [`super::clocked`]: what a walker sees in cycle `c` depends only on requests made in
//!   earlier cycles. Skipping cycles is safe: `tick_into(c, ..)` processes every cycle before
//!   `c`.
//! * **Order.** Each bank's queue (on chip and cache) is served in the order (request cycle,
//!   requester id, request id): older first, then the lower requester, then the earlier call.
//!   The crossbar puts a request in its bank's queue in the cycle it is made (no cycle of its
//!   own: the queue's input register is the crossbar's output register); the model does not
//!   limit how many requests one queue takes per cycle (each context has at most one read
//!   out, so a queue holds at most the pool's contexts). The cache banks take MSHRs (and miss
//!   queue entries) in a rotating priority: in cycle `k` bank `k mod banks` first, then the
//!   next. The miss queue is served before any lookup of the cycle, in its own order.
//!   Nothing depends on hash order or wall time, so the same request sequence gives the same
//!   completions and statistics on every run.
//! * **Latency.** A request made in cycle `c` and served (given a port) in cycle `s ≥ c`
//!   completes at
//!   - on chip: `s + onchip.latency`;
//!   - cache hit: `s + cache.hit_latency`;
//!   - miss: when its line fill completes; an isolated miss completes at
//!     `s + dram.latency + ⌈line_bytes / bytes_per_cycle⌉` (the fill data is forwarded to the
//!     waiting reads as it is written, so no hit latency is added);
//!   - miss to a line already being filled (merged): with that fill.
//! * **Ports.** Each on-chip bank serves at most `ports_per_bank` distinct words per cycle;
//!   with `onchip.combine` a read of a word whose read is already scheduled at its bank in
//!   this cycle or a later one is served with it (same cycle, no port; counted as combined).
//!   Each cache bank (bank = line mod `cache.banks`) looks up at most `cache.ports` reads per
//!   cycle. The rest wait to the next cycle (counted as port-wait request-cycles; the cache
//!   banks' share also as cache port-wait).
//! * **MSHRs and hit under miss.** A miss needs a free MSHR unless its line is already in
//!   flight (then it merges; an MSHR takes any number of merged reads). When none is free the
//!   miss leaves its bank's pipeline for the miss queue (`cache.miss_queue` entries; its
//!   served cycle stays its lookup cycle), so the lookups behind it go on: hits under a miss.
//!   At the start of each cycle, after the fills that complete, the queue's head merges into
//!   a fill of its line in flight or takes a free MSHR, in order, until one can do neither
//!   (request-cycles spent there counted as miss-queue wait when a read leaves). Before that
//!   the head's tags are checked again: if a fill issued while it waited has brought its line
//!   in, it is a hit (counted as one), read through one of its bank's lookup ports in that
//!   cycle (the bank's lookups of the cycle get the ports left; with none left the head
//!   waits, in order, for the next cycle), served in that cycle and done `hit_latency`
//!   later. When the miss queue is full (always, with 0 entries) the bank's in-order
//!   pipeline stalls until a fill completes, as a non-blocking cache does when its miss table
//!   is full: reads behind the stalled one wait too (counted as MSHR-wait request-cycles, and
//!   the cycle as an MSHR-full cycle). An MSHR is freed, and the line installed as most
//!   recently used, in the cycle its fill completes; a lookup in that same cycle hits.
//! * **Bandwidth.** Fills share one data bus of `bytes_per_cycle` bytes per cycle, in the
//!   order they were issued. A fill issued in cycle `s` may start to transfer at cycle
//!   `s + latency` (latency overlaps with other fills' transfers) and occupies `line_bytes` of
//!   the bus's byte budget; a cycle never moves more than `bytes_per_cycle` bytes, also when
//!   the line is not a multiple of it (two fills then share a cycle).
//!
//! With the DRAMsim3 backend ([`DramBackend::DramSim3`], `dramsim3.rs`) a fill's completion
//! is DRAMsim3's instead, known only when DRAMsim3 returns it: reads waiting for it are parked
//! in its MSHR until then (`dram.rs`), and the bandwidth is the device's.
//!
//! Simplifications (stated so reports can be read correctly): with the built-in backend, DRAM
//! refresh, bank and row effects are folded into the fixed latency; refills write the cache through their own port
//! (the data array is built from 1R1W copies, see [`NodeMemoryConfig::resources`]); the
//! on-chip store is read only during a frame (it is loaded between frames), so it has no
//! read-during-write case.
//!
//! # Files
//!
//! [`config`] (the configuration and its block count), [`crossbar`] (the logic around the
//! blocks: crossbars, bank and miss queues, MSHR search, in LUTs and FFs), [`layout`] (the
//! address map and the on-chip whitelist), [`request`] (requests, completions, refusals),
//! [`stats`] (the counters), and the three places a read is served: `onchip.rs` (bank ports
//! and combining), `cache.rs` (lines and LRU tags) and `dram.rs` (MSHRs, their table in `mshr.rs`, and the fill bus; the DRAMsim3
//! backend in [`dramsim3`]). This file holds the model
//! that arbitrates them cycle by cycle ([`NodeMemory`]); `serve.rs` what happens to a read
//! once its cycle's order is set (the arrivals' service order, the lookup, the miss queue's
//! re-check, the send to DRAM, the completion record).

mod cache;
pub mod config;
pub mod crossbar;
mod dram;
pub mod dramsim3;
pub mod layout;
mod mshr;
mod onchip;
pub mod request;
mod serve;
pub mod stats;

/// What a read fetches: the request API takes it (its home is the image's side, `svo`).
pub use crate::svo::FetchKind;
pub use cache::ATTR_REGION_BASE;
pub use config::{
    CacheConfig, ConfigError, DramBackend, DramConfig, MemoryResources, NodeMemoryConfig,
    OnChipConfig, MAX_CACHE_BANKS, MAX_CACHE_BYTES, MAX_LATENCY, MAX_PARALLEL,
};
pub use crossbar::MemoryFabricItem;
pub use layout::{LayoutError, MemoryLayout, MAX_ONCHIP_BITMAP_WORDS};
pub use request::{Completion, RequestError, RequestId, Source, MAX_CYCLE};
pub use stats::{DramDeviceStats, KindCounts, NodeMemoryStats};

use super::completion_wheel::CompletionWheel;
use cache::{line_of, Tags};
use dram::{Dram, Resolved};
use onchip::Banks;
use request::Req;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

/// The node-memory model. See the module documentation for the semantics.
///
/// ```
/// use rtl_model::cycle::memory::{FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, Source};
/// let cfg = NodeMemoryConfig::default();
/// let layout = MemoryLayout::with_onchip_ranges(1 << 20, 1 << 16, vec![(0, 64)]).unwrap();
/// let mut mem = NodeMemory::new(cfg, layout).unwrap();
/// let a = mem.request(10, 5, FetchKind::Node, 0).unwrap(); // on chip
/// let b = mem.request(10, 5000, FetchKind::Node, 1).unwrap(); // cold miss
/// let done = mem.drain();
/// assert_eq!((done[0].id, done[0].cycle_done), (a, 13)); // 3-cycle block RAM
/// assert_eq!((done[1].id, done[1].source), (b, Source::Miss));
/// assert_eq!(done[1].cycle_done, 10 + 60 + 1); // latency + one 64-byte beat
/// ```
#[derive(Debug)]
pub struct NodeMemory {
    cfg: NodeMemoryConfig,
    layout: MemoryLayout,
    /// First cycle not yet simulated.
    next: u64,
    next_id: u64,
    /// Requests made for a later cycle than `next`.
    future: BinaryHeap<Reverse<Req>>,
    /// Requests made for cycle `next` (the usual case: a walker asks in the cycle it is
    /// evaluated); sorted into service order when that cycle is simulated.
    arrivals: Vec<Req>,
    /// The service order of `arrivals` when they are not in it already (`sort_arrivals`;
    /// empty between steps).
    order: Vec<u64>,
    /// The on-chip banks' ports. An on-chip read's service cycle is known when it arrives,
    /// so it goes straight to `pending` instead of waiting in a queue of its own.
    banks: Banks,
    /// Per cache bank, the requests waiting for one of its lookup ports, in service order.
    cache_q: Vec<VecDeque<Req>>,
    /// Requests in `cache_q`.
    waiting: usize,
    /// The miss queue: misses that found every MSHR taken, with the cycle of their lookup,
    /// in order (hit under miss, `cache.miss_queue` entries).
    miss_q: VecDeque<(Req, u64)>,
    /// Per cache bank, the lookup ports the miss queue's tag re-checks took in the cycle
    /// being stepped (a queued miss whose line has arrived is read as a hit through one).
    replay_ports: Vec<u32>,
    /// The miss queue's head hit the tags but its bank had no lookup port left in the last
    /// cycle stepped: the next cycle has work even if nothing else happens in it.
    replay_waiting: bool,
    tags: Tags,
    /// Bytes of a cache line (the divisor of [`line_of`]).
    line_bytes: u64,
    dram: Dram,
    /// Parked reads whose completion DRAMsim3 returned in the cycle being stepped (kept to
    /// reuse its allocation; always empty between steps).
    resolved: Vec<Resolved>,
    pending: CompletionWheel,
    stats: NodeMemoryStats,
}

impl NodeMemory {
    /// A model with empty caches at cycle 0, behind a pipeline clocked at 300 MHz.
    pub fn new(cfg: NodeMemoryConfig, layout: MemoryLayout) -> Result<Self, ConfigError> {
        Self::with_clock(cfg, layout, 300)
    }

    /// A model with empty caches at cycle 0, behind a pipeline clocked at `clock_mhz` (which
    /// only the DRAMsim3 backend needs: it runs at the device's own clock).
    pub fn with_clock(
        cfg: NodeMemoryConfig,
        layout: MemoryLayout,
        clock_mhz: u32,
    ) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let tags = Tags::new(cfg.cache_sets(), cfg.cache.ways);
        let cache_q = vec![VecDeque::new(); cfg.cache.banks as usize];
        let stats = NodeMemoryStats {
            dram_peak_bytes_per_cycle: cfg.dram.peak_bytes_per_cycle(clock_mhz),
            ..Default::default()
        };
        Ok(Self {
            banks: Banks::new(&cfg.onchip),
            line_bytes: u64::from(cfg.cache.line_bytes),
            dram: Dram::new(&cfg, clock_mhz)?,
            resolved: Vec::new(),
            cfg,
            layout,
            next: 0,
            next_id: 0,
            future: BinaryHeap::new(),
            arrivals: Vec::new(),
            order: Vec::new(),
            waiting: 0,
            miss_q: VecDeque::new(),
            replay_ports: vec![0; cache_q.len()],
            replay_waiting: false,
            cache_q,
            tags,
            pending: CompletionWheel::default(),
            stats,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &NodeMemoryConfig {
        &self.cfg
    }

    /// The address map.
    pub fn layout(&self) -> &MemoryLayout {
        &self.layout
    }

    /// First cycle not yet simulated: requests must be for this cycle or later.
    pub fn now(&self) -> u64 {
        self.next
    }

    /// Requests made and not yet returned by [`tick_into`](Self::tick_into) or
    /// [`drain`](Self::drain).
    pub fn outstanding(&self) -> usize {
        self.future.len()
            + self.arrivals.len()
            + self.waiting
            + self.miss_q.len()
            + self.pending.len()
            + self.dram.parked()
    }

    /// Whether every request has been returned.
    pub fn is_idle(&self) -> bool {
        self.outstanding() == 0
    }

    /// Requests a read in `cycle` (this cycle or a later one) by `requester`. For
    /// [`FetchKind::Attr`], `addr` is the attribute index; otherwise a node word address.
    /// The read is arbitrated when the simulation reaches `cycle`, so requests of one cycle
    /// may be made in any order.
    pub fn request(
        &mut self,
        cycle: u64,
        addr: u32,
        kind: FetchKind,
        requester: u32,
    ) -> Result<RequestId, RequestError> {
        if cycle > MAX_CYCLE {
            return Err(RequestError::CycleTooLarge(cycle));
        }
        if cycle < self.next {
            return Err(RequestError::InPast {
                cycle,
                now: self.next,
            });
        }
        let limit = match kind {
            FetchKind::Node | FetchKind::Far => self.layout.node_words(),
            FetchKind::Attr => self.layout.attr_records(),
        };
        if u64::from(addr) >= limit {
            self.stats.out_of_range += 1;
            return Err(RequestError::OutOfRange { kind, addr, limit });
        }
        let id = self.next_id;
        self.next_id += 1;
        self.stats.fetches.add(kind);
        self.stats.words += kind.words();
        self.stats.bytes += 4 * kind.words();
        let req = Req {
            cycle,
            requester,
            id,
            addr,
            kind,
        };
        if cycle == self.next {
            self.arrivals.push(req);
        } else {
            self.future.push(Reverse(req));
        }
        Ok(RequestId(id))
    }

    /// Functional warming (sampled timing, docs/cycle-model.md §3.5): the cache's tags take
    /// the read of `addr` as if it had been served — an on-chip read changes nothing, a cached
    /// read that hits becomes most recently used, one that misses installs its line at once —
    /// with no cycle, port, MSHR, DRAM transfer or statistic. Only between timed parts, with
    /// nothing outstanding (a fill in flight would install its line later).
    pub fn warm(&mut self, kind: FetchKind, addr: u32) {
        if kind != FetchKind::Attr && self.layout.is_onchip(addr) {
            return;
        }
        if kind == FetchKind::Attr && !self.cfg.cache.attr_cached {
            return;
        }
        let line = line_of(kind, addr, self.line_bytes);
        if !self.tags.touch(line) {
            self.tags.install(line);
        }
    }

    /// A lower bound on the first cycle at or after [`now`](Self::now) in which a read not yet
    /// returned can complete, or `None` when nothing is outstanding. Completions already
    /// computed give their own cycle; a request not yet served may complete as early as the
    /// cycle it can be served in, so any waiting or arriving request bounds it by that cycle.
    /// The pipeline's idle-cycle skipping (docs/cycle-model.md §3.3) jumps no further.
    pub fn next_completion_bound(&self) -> Option<u64> {
        let mut bound = self.pending.next_due();
        let mut at = |c: u64| bound = Some(bound.map_or(c, |b| b.min(c)));
        if self.waiting > 0 || !self.arrivals.is_empty() || self.replay_waiting {
            at(self.next);
        }
        if let Some(Reverse(r)) = self.future.peek() {
            at(r.cycle.max(self.next));
        }
        if let Some(c) = self.dram.parked_bound(self.next) {
            at(c);
        }
        bound
    }

    /// Simulates every cycle before `cycle` without collecting completions (a later
    /// [`tick_into`](Self::tick_into) of the same cycle returns them). Requests for `cycle`
    /// made after this take the fast path of the current cycle instead of the heap of future
    /// requests.
    pub fn catch_up(&mut self, cycle: u64) {
        self.advance_to(cycle.min(MAX_CYCLE + 1));
    }

    /// Called at the start of `cycle`: simulates every cycle before it and appends to `out`
    /// the reads whose data is valid by `cycle` (`cycle_done ≤ cycle`) and were not returned
    /// before, ordered by (done, id). A caller that ticks every cycle reuses one buffer
    /// instead of allocating per cycle.
    pub fn tick_into(&mut self, cycle: u64, out: &mut Vec<Completion>) {
        self.advance_to(cycle.min(MAX_CYCLE + 1));
        self.pending.pop_due(cycle, out);
    }

    /// [`tick_into`](Self::tick_into) for a caller that needs only who asked (the walker
    /// pool): appends the requester of each of those completions, in the same order, without
    /// copying the records.
    pub fn tick_requesters_into(&mut self, cycle: u64, out: &mut Vec<u32>) {
        self.advance_to(cycle.min(MAX_CYCLE + 1));
        self.pending.pop_due_with(cycle, |c| out.push(c.requester));
    }

    /// Simulates until every request has been served and returns all completions not yet
    /// returned, ordered by (done, id). `now` is then the cycle after the last one with any
    /// activity, which may be before the last `cycle_done`.
    pub fn drain(&mut self) -> Vec<Completion> {
        while !(self.future.is_empty()
            && self.arrivals.is_empty()
            && self.waiting == 0
            && self.miss_q.is_empty()
            && self.dram.is_idle())
        {
            let k = self.next;
            if self.has_work(k) {
                self.step(k);
                self.next = k + 1;
            } else {
                // Not idle, so there is a next event after k.
                self.next = self.next_event().unwrap_or(k + 1);
            }
        }
        // The banks' last service (a read that waited) is activity too, though no step runs
        // for it: it happens in cycle `busy_until`. (A read served as it arrived was stepped
        // in its own cycle, so `next` is past it already.)
        let busy_until = self.banks.busy_until();
        if busy_until > 0 && busy_until >= self.next {
            self.next = busy_until + 1;
        }
        let mut out = Vec::new();
        self.pending.drain_all(&mut out);
        out
    }

    /// The statistics of the current window (up to the last simulated cycle).
    pub fn stats(&self) -> NodeMemoryStats {
        let mut s = self.stats.clone();
        s.window_cycles = self.next.saturating_sub(s.window_start);
        s.port_conflict_cycles += self.banks.conflicts_before(self.next);
        s.dram_device = self.dram.device_stats();
        s
    }

    /// Returns the current window's statistics and starts a new window at [`now`](Self::now)
    /// (e.g. per frame). Cache contents and requests in flight are kept.
    pub fn reset_stats(&mut self) -> NodeMemoryStats {
        let out = self.stats();
        self.banks.counted_to(self.next);
        self.dram.reset_device_stats();
        self.stats = NodeMemoryStats {
            window_start: self.next,
            dram_peak_bytes_per_cycle: out.dram_peak_bytes_per_cycle,
            ..Default::default()
        };
        out
    }

    fn advance_to(&mut self, target: u64) {
        while self.next < target {
            let k = self.next;
            if self.has_work(k) {
                self.step(k);
                self.next = k + 1;
            } else {
                self.next = self.next_event().map_or(target, |e| e.min(target));
            }
        }
    }

    /// Whether cycle `k` changes anything: a request arrives or waits, a fill completes or
    /// moves bytes.
    #[inline]
    fn has_work(&self, k: u64) -> bool {
        if self.waiting > 0 || !self.arrivals.is_empty() || self.replay_waiting {
            return true;
        }
        if self.future.peek().is_some_and(|Reverse(r)| r.cycle <= k) {
            return true;
        }
        self.dram.has_work(k)
    }

    /// The next cycle with work, given that the current one has none.
    fn next_event(&self) -> Option<u64> {
        let arrival = self.future.peek().map(|Reverse(r)| r.cycle);
        let transfer = self.dram.next_transfer();
        match (arrival, transfer) {
            (Some(a), Some(t)) => Some(a.min(t)),
            (a, t) => a.or(t),
        }
    }

    /// Simulates cycle `k`.
    fn step(&mut self, k: u64) {
        // 1. Fills that complete now install their line and free their MSHR, before this
        //    cycle's lookups (so a lookup in the completion cycle hits).
        self.dram.retire(k, &mut self.tags, &mut self.resolved);
        if !self.resolved.is_empty() {
            let mut resolved = std::mem::take(&mut self.resolved);
            for &(r, served, done, source) in &resolved {
                self.complete(r, served, done, source);
            }
            resolved.clear();
            self.resolved = resolved;
        }
        //    Then the miss queue's head, in order: its tags are checked again (a fill issued
        //    while it waited may have brought its line in: then it is a hit, read through a
        //    lookup port of its bank in this cycle), else it merges into a fill of its line
        //    in flight or takes an MSHR freed.
        self.replay_ports.fill(0);
        self.replay_waiting = false;
        while let Some(&(r, looked_up)) = self.miss_q.front() {
            match self.replay_hit(r, k) {
                Some(true) => {
                    self.miss_q.pop_front();
                    self.stats.miss_queue_wait += k - looked_up;
                    continue;
                }
                Some(false) => {
                    // A hit with no port left: it waits, in order, for the next cycle.
                    self.replay_waiting = true;
                    break;
                }
                None => {}
            }
            let Some((source, done)) = self.send_to_dram(r, k) else {
                break;
            };
            self.miss_q.pop_front();
            self.stats.miss_queue_wait += k - looked_up;
            if let Some(done) = done {
                self.complete(r, looked_up, done, source);
            } // else parked in its MSHR until DRAMsim3 returns the fill (`dram.retire`)
        }
        // 2. Requests of this cycle are arbitrated in (requester, id) order: all are of cycle k
        //    (`arrivals` holds those made for `next` = k, the heap any made earlier for k) and
        //    everything before them is from an earlier cycle, so taking them in this order
        //    keeps each bank and the cache queue in (cycle, requester, id) service order.
        //    An on-chip read is given its bank's next free port (or, combining, the read of
        //    its word already queued there) at once; a cached one crosses to its cache
        //    bank's queue (line mod banks).
        let direct = self.arrivals.len();
        while let Some(Reverse(r)) = self.future.peek().copied() {
            if r.cycle > k {
                break;
            }
            self.future.pop();
            self.arrivals.push(r);
        }
        self.sort_arrivals(direct);
        self.stats.port_conflict_cycles += self.banks.take_conflicts_before(k);
        let latency = u64::from(self.cfg.onchip.latency);
        for j in 0..self.arrivals.len() {
            let r = self.arrivals[self.order.get(j).map_or(j, |&o| o as u32 as usize)];
            let onchip = r.kind != FetchKind::Attr && self.layout.is_onchip(r.addr);
            if onchip {
                let (bank, served, combined) = self.banks.serve(r.addr, k);
                // Waiting in cycles k .. served − 1.
                self.stats.port_wait += served - k;
                self.stats.onchip_reads += 1;
                self.stats.onchip_combined += u64::from(combined);
                self.complete(r, served, served + latency, Source::OnChip { bank });
            } else {
                let line = line_of(r.kind, r.addr, self.line_bytes);
                let bank = (line % self.cache_q.len() as u64) as usize;
                self.cache_q[bank].push_back(r);
                self.waiting += 1;
            }
        }
        self.arrivals.clear();
        self.order.clear();
        // 3. Bytes on the DRAM bus in this cycle.
        let bytes = self.dram.bytes_in(k);
        if bytes > 0 {
            self.stats.dram_bytes += bytes;
            self.stats.dram_busy_cycles += 1;
            self.stats.dram_max_bytes_in_cycle = self.stats.dram_max_bytes_in_cycle.max(bytes);
        }
        // A bank has a request left waiting after this cycle's service.
        let mut port_conflict = self.banks.busy_until() > k;
        // 4. Each cache bank's lookup pipeline, in order within the bank; the banks take
        //    MSHRs in a rotating priority starting at bank k mod banks.
        let banks = self.cache_q.len();
        let mut blocked_any = false;
        for j in 0..banks {
            let b = (j + (k % banks as u64) as usize) % banks;
            let mut blocked = false;
            let ports = self.cfg.cache.ports.saturating_sub(self.replay_ports[b]);
            for _ in 0..ports {
                let Some(&r) = self.cache_q[b].front() else {
                    break;
                };
                match self.lookup(r, k) {
                    Some((source, Some(done))) => self.complete(r, k, done, source),
                    // Parked in its MSHR until DRAMsim3 returns the fill (`dram.retire`).
                    Some((_, None)) => {}
                    None if self.miss_q.len() < self.cfg.cache.miss_queue as usize => {
                        // Hit under miss: the miss leaves the pipeline for the miss queue.
                        self.miss_q.push_back((r, k));
                        self.stats.miss_queued += 1;
                        let n = self.miss_q.len() as u64;
                        self.stats.miss_queue_max = self.stats.miss_queue_max.max(n);
                    }
                    None => {
                        blocked = true;
                        break;
                    }
                }
                self.cache_q[b].pop_front();
                self.waiting -= 1;
            }
            let left = self.cache_q[b].len() as u64;
            if left > 0 {
                if blocked {
                    blocked_any = true;
                    self.stats.mshr_wait += left;
                } else {
                    port_conflict = true;
                    self.stats.port_wait += left;
                    self.stats.cache_port_wait += left;
                }
            }
        }
        if blocked_any {
            self.stats.mshr_full_cycles += 1;
        }
        if port_conflict {
            self.stats.port_conflict_cycles += 1;
        }
        self.banks.counted_to(k + 1);
    }
}
