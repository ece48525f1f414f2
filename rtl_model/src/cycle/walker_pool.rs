//! The walker pool: W octree walkers, each interleaving R ray contexts, a dispatcher that
//! hands each walk to a free context, and the node memory they share.
//!
//! Pipeline position: after the walker-root units (`root_to_dispatch`), before the record
//! stage (`walker_to_record`). A walk arrives as its ops (`walk_op`): runs of issue slots
//! (children examined, stack pops) and the reads it waits for. Per cycle:
//!
//! 1. **Wake-up.** First each walker sends the reads waiting in its send queue (below). Then
//!    contexts whose step latency has passed (and walks dispatched in the cycle before), and
//!    those whose read completed in this cycle ([`NodeMemory::tick_into`]), move on to their
//!    next op: an issue run makes them ready; a read is requested from the node memory in this
//!    cycle if the walker has a request port left, else it joins the walker's send queue; the
//!    context waits either way.
//! 2. **Dispatch** (at most one walk per walk lane and cycle, the caller's loop: one at
//!    `HwConfig::walk_lanes` 1, two at the default): each to the walker with the most free
//!    contexts (the lowest index on ties, counted after the cycle's earlier dispatches, so two
//!    walks of one cycle can go to one walker); the context starts in the next cycle with the
//!    walk's first op, the root descriptor read.
//! 3. **Issue.** Each walker issues one ready context per `step_cycles` (its datapath's II),
//!    round robin in the order contexts became ready; a context's next slot, or the read its
//!    last slot computed the address of, comes `step_latency` cycles later. Other contexts
//!    issue in between: that is how R contexts hide the step pipeline and memory latency.
//! 4. **Retire.** Finished walks leave in the order they finished, one per walk lane and
//!    cycle (the caller's loop), while the record stage's FIFO takes them. The caller retires
//!    before it dispatches, so a context freed in a cycle can take a walk dispatched in that
//!    cycle, which starts in the next.
//!
//! **Request ports** (`walker_pool.read_ports`, issue 29). A walker sends at most `read_ports`
//! reads per cycle (0: unlimited): the RTL walker interleaves its contexts in one datapath and
//! has one request port to the node memory. Reads beyond that wait in the walker's send queue
//! (a FIFO of at most R entries, since a context has one read out) and are sent in later
//! cycles before any new read: oldest first. Among the reads of one cycle the order is the
//! order contexts move on in the wake-up: step-latency ends and dispatched walks' root reads
//! (in the cycle they were scheduled), then completions in the node memory's order (done
//! cycle, then request age). That is what a request FIFO in front of the port gives a barrel
//! walker with no reordering logic: a queued read waits at most R − 1 cycles, where a
//! fixed-priority pick by context index, the cheapest arbiter, could starve a high context.
//! The RTL must enqueue a cycle's reads in the same order to agree cycle for cycle. A queued read
//! counts as waiting on memory; its context-cycles in the queue are `read_port_waits`.
//!
//! **Registered response and request** (`walker_pool.response_register_cycles`,
//! `walker_pool.request_register_cycles`, 0 or 1 each, default 0; issue 29, for 300 MHz:
//! they cut the pool RTL's same-cycle path from a response to the chained read it sends). The
//! rule the RTL implements:
//!
//! - **Response register 1.** The completions the node memory gives in cycle C (its
//!   [`NodeMemory::tick_into`] order) are latched and seen by the pool in C + 1, in the
//!   wake-up's completion place (after the contexts the wheel wakes in C + 1, in the memory's
//!   order). The context moves on in C + 1: its next read takes a port, or joins the send
//!   queue, in C + 1. The memory's own state (an MSHR freed, a bank port) is the memory's
//!   cycle C; nothing there waits for the register.
//! - **Request register 1.** A read the walker's port picks in cycle C (from the send queue
//!   or a wake-up, by the request-port rule above, which is unchanged) reaches the node
//!   memory in C + 1, before any other read of C + 1, in the order picked (walker by walker
//!   as picked in C). The memory decides in C + 1, as for any read arriving in C + 1: its
//!   bank-port arbitration, combining, cache lookup and MSHR merge see the fills it
//!   received in C and earlier (those the RTL's register stage must bypass: sent in C) and
//!   not the reads picked in C + 1. A read counts in `reads` when it reaches the memory.
//! - **Both 1.** A response in C, seen in C + 1, sends its chained read to the memory in
//!   C + 2. The RTL may compute the chain address (base + word) and compare it against the
//!   fills in the memory's cycle C, ahead of the registers, as long as the merge it makes is
//!   the one the memory makes with the read arriving in C + 2: a fill counts as in flight if
//!   it is in flight in C + 2 (one sent in C or C + 1 included, one whose data arrives in
//!   C + 1 not).
//!
//! On a node memory where no read ever waits (every word on chip, ports enough, no
//! combining), each register is exactly one more cycle of read latency as a context sees it:
//! `rtl_model/tests/cycle_walker_pool_order.rs` checks that equivalence, and checks the rule
//! above against its reference pool on the default memory. Neither register is in the
//! resource estimate (pipeline flip-flops are not counted, `cost/estimate.rs`): about
//! 1 + ⌈log₂ W·R⌉ + 64 flip-flops per response port and 1 + ⌈log₂ W·R⌉ + 2 + 32 per request port.
//!
//! Memory contention is the node memory's: bank ports, cache lookup ports, MSHRs and the
//! DRAM bus (`memory/`); outstanding misses are limited by its MSHRs. Every walker-cycle is
//! classified as issuing (busy), waiting on memory, waiting on its own step latency, holding a
//! finished walk the record stage cannot take (back-pressured), or empty (starved).
//!
//! **How it is kept (issue 30).** The orders above are the spec; the model keeps them with
//! less work per event than it states them. A context whose issue run goes on after a slot
//! does not go through the pool-wide wake-up wheel: it goes back to the tail of its walker's
//! issue ring with the cycle it is ready in, as nothing but that walker's queue sees it
//! (`walker_pool/rings.rs`, which also shows why the ring's order is the ready queue's).
//! The wheel holds only dispatched walks and contexts whose run ended (they read or
//! finish, which other walkers and the node memory see, in wake-up order).
//! `rtl_model/tests/cycle_walker_pool_order.rs` checks every order against a reference
//! pool that does it the spec's way.

mod rings;
mod state;

pub use state::PoolCycles;
use state::{Class, ClassCounts, Context, Walker, WalkerSet};

use std::collections::VecDeque;

use rings::{key, Rings, PHASE_DISPATCH_LAT1, PHASE_STEP, PHASE_WAKE};

use super::hw_config::WalkerPool as PoolConfig;
use super::memory::{FetchKind, NodeMemory, RequestError};
use super::walk_op::WalkOp;

/// Why the pool stopped.
#[derive(Debug, thiserror::Error)]
pub enum PoolError {
    /// A read was refused by the node memory (an address outside the image: a broken trace).
    #[error("walker read refused: {0}")]
    Read(#[from] RequestError),
    /// The configuration cannot be built.
    #[error("walker pool: {0}")]
    Config(String),
}

/// The pool (see the module doc). `tag` identifies a walk to its owner (the record stage).
#[derive(Debug)]
pub struct WalkerPoolModel {
    ctxs: Vec<Context>,
    /// `remaining[ctx]`: issue slots left in the context's current run (kept apart from
    /// [`Context`]: the one field the issue phase touches per slot).
    remaining: Vec<u32>,
    walkers: Vec<Walker>,
    rings: Rings,
    /// Contexts due in a cycle, in order: dispatched walks and contexts whose issue run ended
    /// (runs that go on wait in their walker's issue ring, `rings.rs`).
    wheel: Vec<Vec<u32>>,
    finished: VecDeque<u32>,
    busy_total: u32,
    now: u64,
    /// Walkers with a context in their issue ring (ready, or a step under way).
    has_ready: WalkerSet,
    /// `steps_due[c mod span]`: steps under way that end in cycle `c`. Each counts as
    /// activity in its cycle, as the wake-up of its context on the wheel did.
    steps_due: Vec<u32>,
    /// `by_free[f]`: the walkers with exactly `f` free contexts (the dispatcher's choice).
    by_free: Vec<WalkerSet>,
    /// Walkers that issued in the current cycle.
    issued_count: u32,
    /// `step_latency_cycles` (at least 1) and `step_cycles` (at least 1).
    lat: u64,
    ii: u64,
    classes: ClassCounts,
    /// The requesters of the cycle's completions, in the node memory's order (reused).
    completions: Vec<u32>,
    cycles: PoolCycles,
    /// Context wake-ups, dispatches, issues and retirements so far: unchanged over a cycle
    /// means nothing in the pool moved (idle-cycle skipping, [`WalkerPoolModel::activity`]).
    activity: u64,
    /// A walk waited at the dispatcher in the current cycle.
    stalled_now: bool,
    /// Reads a walker may send per cycle; `u32::MAX` for unlimited (`read_ports` 0).
    ports: u32,
    /// Walkers with a read waiting in their send queue.
    has_send: WalkerSet,
    /// Reads waiting in all send queues.
    queued_total: u32,
    /// `walker_pool.response_register_cycles` 1: completions are seen one cycle late.
    resp_reg: bool,
    /// `walker_pool.request_register_cycles` 1: reads reach the node memory one cycle late.
    req_reg: bool,
    /// The response register: the completions (their requesters) the node memory gave in the
    /// cycle before, in its order (`resp_reg` only).
    held: Vec<u32>,
    /// The request register: the reads the walkers' ports picked in the cycle before, in the
    /// order picked (context, kind, address; `req_reg` only).
    picked: Vec<(u32, FetchKind, u32)>,
}

impl WalkerPoolModel {
    /// An idle pool.
    pub fn new(cfg: &PoolConfig) -> Result<Self, PoolError> {
        if cfg.walkers == 0 || cfg.contexts_per_walker == 0 {
            return Err(PoolError::Config(
                "walkers and contexts must be positive".into(),
            ));
        }
        let w = cfg.walkers as usize;
        let r = cfg.contexts_per_walker as usize;
        let span = (cfg.step_latency_cycles.max(cfg.step_cycles) as usize + 2).next_power_of_two();
        let mut ctxs = vec![Context::default(); w * r];
        let mut walkers = vec![Walker::default(); w];
        for (i, c) in ctxs.iter_mut().enumerate() {
            c.walker = (i / r) as u32;
        }
        for (wi, wk) in walkers.iter_mut().enumerate() {
            // Popped from the back: the lowest context first.
            wk.free = (0..r).rev().map(|k| (wi * r + k) as u32).collect();
            wk.issued_at = u64::MAX;
        }
        Ok(Self {
            ctxs,
            remaining: vec![0; w * r],
            walkers,
            rings: Rings::new(w, cfg.contexts_per_walker),
            wheel: vec![Vec::new(); span],
            finished: VecDeque::new(),
            busy_total: 0,
            now: 0,
            has_ready: WalkerSet::new(w),
            steps_due: vec![0; span],
            by_free: (0..=r)
                .map(|f| {
                    let mut set = WalkerSet::new(w);
                    if f == r {
                        (0..w).for_each(|i| set.insert(i));
                    }
                    set
                })
                .collect(),
            issued_count: 0,
            lat: u64::from(cfg.step_latency_cycles.max(1)),
            ii: u64::from(cfg.step_cycles.max(1)),
            classes: ClassCounts([w as u32, 0, 0, 0]),
            completions: Vec::new(),
            cycles: PoolCycles::default(),
            activity: 0,
            stalled_now: false,
            ports: if cfg.read_ports == 0 {
                u32::MAX
            } else {
                cfg.read_ports
            },
            has_send: WalkerSet::new(w),
            queued_total: 0,
            resp_reg: match cfg.response_register_cycles {
                0 => false,
                1 => true,
                n => {
                    return Err(PoolError::Config(format!(
                        "walker_pool.response_register_cycles = {n}: 0 or 1"
                    )))
                }
            },
            req_reg: match cfg.request_register_cycles {
                0 => false,
                1 => true,
                n => {
                    return Err(PoolError::Config(format!(
                        "walker_pool.request_register_cycles = {n}: 0 or 1"
                    )))
                }
            },
            held: Vec::new(),
            picked: Vec::new(),
        })
    }

    /// Contexts busy (walking or holding a finished walk).
    pub fn busy_contexts(&self) -> u32 {
        self.busy_total
    }

    /// Busy contexts of walker `w`.
    pub fn walker_busy(&self, w: usize) -> u32 {
        self.walkers.get(w).map_or(0, |k| k.busy)
    }

    /// Contexts of walker `w` waiting on a read.
    pub fn walker_waiting(&self, w: usize) -> u32 {
        self.walkers.get(w).map_or(0, |k| k.waiting_mem)
    }

    /// Contexts of walker `w` holding a finished walk the record stage has not taken.
    pub fn walker_finished(&self, w: usize) -> u32 {
        self.walkers.get(w).map_or(0, |k| k.finished)
    }

    /// Reads walker `w` sent to the node memory in the current cycle.
    pub fn walker_sent(&self, w: usize) -> u32 {
        self.walkers
            .get(w)
            .map_or(0, |k| if k.sent_at == self.now { k.sent } else { 0 })
    }

    /// Contexts of walker `w` whose read waits in its send queue for a request port (they
    /// count among [`walker_waiting`](Self::walker_waiting)).
    pub fn walker_queued(&self, w: usize) -> u32 {
        self.walkers.get(w).map_or(0, |k| k.send.len() as u32)
    }

    /// Whether walker `w` issued in the current cycle.
    pub fn walker_issued(&self, w: usize) -> bool {
        self.walkers.get(w).is_some_and(|k| k.issued_at == self.now)
    }

    /// Walkers that issued in the current cycle.
    pub fn issued_count(&self) -> u32 {
        self.issued_count
    }

    /// Whether a walk can be dispatched (a context is free).
    pub fn has_free(&self) -> bool {
        (self.busy_total as usize) < self.ctxs.len()
    }

    /// Whether nothing is in the pool.
    pub fn is_idle(&self) -> bool {
        self.busy_total == 0
    }

    /// The counters so far; [`take_cycles`](Self::take_cycles) starts a new window.
    pub fn cycles(&self) -> &PoolCycles {
        &self.cycles
    }

    /// Returns the counters and resets them (per frame).
    pub fn take_cycles(&mut self) -> PoolCycles {
        std::mem::take(&mut self.cycles)
    }

    fn schedule(&mut self, ctx: u32, at: u64) {
        let mask = self.wheel.len() - 1;
        self.wheel[(at as usize) & mask].push(ctx);
    }

    /// Runs context `ctx` forward in the current cycle until it needs an issue slot, waits on
    /// a read, or finishes. If it becomes ready, it joins its walker's issue ring in wake-up
    /// phase `phase` (`rings.rs`). Inlined into the wake-up's two loops: it runs for every
    /// read issued and every run started, and the call's register saves cost about a
    /// quarter of its own instructions.
    #[inline(always)]
    fn advance(&mut self, ctx: u32, phase: u64, mem: &mut NodeMemory) -> Result<(), PoolError> {
        let now = self.now;
        self.activity += 1;
        let c = &mut self.ctxs[ctx as usize];
        let remaining = &mut self.remaining[ctx as usize];
        let wi = c.walker as usize;
        let wk = &mut self.walkers[wi];
        loop {
            if c.in_issue {
                if *remaining > 0 {
                    self.rings.insert(wi, &mut wk.pos, key(now, phase), ctx);
                    self.has_ready.insert(wi);
                    return Ok(());
                }
                c.in_issue = false;
                c.pc += 1;
            }
            let Some(&op) = c.ops.get(c.pc) else {
                c.finished = true;
                wk.finished += 1;
                wk.reclass(&mut self.classes);
                self.finished.push_back(ctx);
                return Ok(());
            };
            match WalkOp::unpack(op) {
                WalkOp::Issue(0) => c.pc += 1,
                WalkOp::Issue(n) => {
                    c.in_issue = true;
                    *remaining = n;
                }
                WalkOp::Read(kind, addr) => {
                    // One of the walker's request ports this cycle, or its send queue: the
                    // queue is served first each cycle (`send_queued`), so a port left now
                    // means the queue is empty and this read is the oldest waiting.
                    if wk.sent_at != now {
                        wk.sent_at = now;
                        wk.sent = 0;
                    }
                    if wk.sent < self.ports {
                        wk.sent += 1;
                        if self.req_reg {
                            self.picked.push((ctx, kind, addr));
                        } else {
                            mem.request(now, addr, kind, ctx)?;
                            self.cycles.reads += 1;
                        }
                    } else {
                        wk.send.push_back((ctx, kind, addr));
                        self.has_send.insert(wi);
                        self.queued_total += 1;
                    }
                    c.pc += 1;
                    c.waiting_mem = true;
                    wk.waiting_mem += 1;
                    wk.reclass(&mut self.classes);
                    return Ok(());
                }
            }
        }
    }

    /// Sends the reads waiting in the walkers' send queues, oldest first, up to `ports` per
    /// walker, in cycle `now` (before any read of the cycle's wake-ups).
    fn send_queued(&mut self, now: u64, mem: &mut NodeMemory) -> Result<(), PoolError> {
        for word in 0..self.has_send.0.len() {
            let mut bits = self.has_send.0[word];
            while bits != 0 {
                let w = word * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let wk = &mut self.walkers[w];
                wk.sent_at = now;
                wk.sent = 0;
                while wk.sent < self.ports {
                    let Some((ctx, kind, addr)) = wk.send.pop_front() else {
                        break;
                    };
                    wk.sent += 1;
                    if self.req_reg {
                        self.picked.push((ctx, kind, addr));
                    } else {
                        mem.request(now, addr, kind, ctx)?;
                        self.cycles.reads += 1;
                    }
                    self.queued_total -= 1;
                    self.activity += 1;
                }
                if wk.send.is_empty() {
                    self.has_send.remove(w);
                }
            }
        }
        Ok(())
    }

    /// Phase 1 of cycle `now`: sends the reads that waited for a request port, then wakes the
    /// contexts whose step latency ended and whose reads completed. Call once per cycle, in
    /// order, before the other phases.
    pub fn wake(&mut self, now: u64, mem: &mut NodeMemory) -> Result<(), PoolError> {
        self.now = now;
        self.stalled_now = false;
        // Bring the memory to this cycle first, so the reads requested below are this
        // cycle's arrivals (the same arbitration either way; only cheaper).
        mem.catch_up(now);
        if !self.picked.is_empty() {
            // The request register: last cycle's picks reach the memory first, in pick order.
            for (ctx, kind, addr) in std::mem::take(&mut self.picked) {
                mem.request(now, addr, kind, ctx)?;
                self.cycles.reads += 1;
                self.activity += 1;
            }
        }
        if self.queued_total > 0 {
            self.send_queued(now, mem)?;
        }
        let mask = self.wheel.len() - 1;
        let due = std::mem::take(&mut self.wheel[(now as usize) & mask]);
        // A walk dispatched in the cycle before was put on the wheel before the slots of
        // that cycle issued: with a step latency of 1, a run's step that ends now (issued in
        // the cycle before) comes after it in the ready queue; otherwise before. A context
        // whose run ended is in a run (`in_issue`), a dispatched one not.
        let lat1 = self.lat == 1;
        for &ctx in &due {
            let dispatched = self.ctxs.get(ctx as usize).is_some_and(|c| !c.in_issue);
            let phase = if lat1 && dispatched {
                PHASE_DISPATCH_LAT1
            } else {
                PHASE_WAKE
            };
            self.advance(ctx, phase, mem)?;
        }
        let mut due = due;
        due.clear();
        self.wheel[(now as usize) & mask] = due;
        let mut done = std::mem::take(&mut self.completions);
        done.clear();
        mem.tick_requesters_into(now, &mut done);
        if self.resp_reg {
            // The response register: this cycle's completions are latched, the cycle
            // before's are seen now (after the wheel's contexts, in the memory's order).
            std::mem::swap(&mut done, &mut self.held);
            if !self.held.is_empty() {
                self.activity += 1;
            }
        }
        for &ctx in &done {
            let Some(c) = self.ctxs.get_mut(ctx as usize) else {
                continue;
            };
            if c.waiting_mem {
                c.waiting_mem = false;
                let wk = &mut self.walkers[c.walker as usize];
                wk.waiting_mem -= 1;
                wk.reclass(&mut self.classes);
                self.advance(ctx, PHASE_WAKE, mem)?;
            }
        }
        self.completions = done;
        // Reads still queued wait this cycle (counted here, after the cycle's sends).
        self.cycles.read_port_waits += u64::from(self.queued_total);
        Ok(())
    }

    /// Counts a cycle in which a walk waited at the dispatcher with every context busy.
    pub fn note_dispatch_stall(&mut self) {
        self.cycles.dispatch_stalls += 1;
        self.stalled_now = true;
    }

    /// A count that changes whenever anything in the pool moves (a context wakes or moves on,
    /// a walk is dispatched or retired, a walker issues). Equal before and after a cycle:
    /// the pool was idle in it, and stays so until [`next_event`](Self::next_event).
    pub fn activity(&self) -> u64 {
        self.activity
    }

    /// After an idle cycle `now` (nothing moved): the first later cycle in which the pool can
    /// move by itself — a step latency ends, a walker's initiation interval ends with a
    /// ready context, or a read may complete (`mem`'s bound). `None`: nothing is due.
    pub fn next_event(&self, now: u64, mem: &NodeMemory) -> Option<u64> {
        if self.queued_total > 0 || !self.held.is_empty() || !self.picked.is_empty() {
            // A queued read is sent, a registered read or completion moves on, in the next
            // cycle (not idle; stated for safety).
            return Some(now + 1);
        }
        let mut next = mem.next_completion_bound();
        let mut at = |c: u64| next = Some(next.map_or(c, |n: u64| n.min(c)));
        let span = self.wheel.len() as u64;
        let mask = self.wheel.len() - 1;
        if let Some(d) = (1..span).find(|&d| !self.wheel[((now + d) as usize) & mask].is_empty()) {
            at(now + d);
        }
        for word in 0..self.has_ready.0.len() {
            let mut bits = self.has_ready.0[word];
            while bits != 0 {
                let w = word * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let wk = &self.walkers[w];
                // The ring is in key order: ready contexts, then steps under way.
                if wk.pos.front / 4 <= now {
                    // Ready: the walker issues when its interval allows.
                    at(wk.next_issue.max(now + 1));
                }
                // The first step under way: the cycle its context would have been woken in
                // on the wheel.
                if let Some(c) = self
                    .rings
                    .keys(w, &wk.pos)
                    .map(|k| k / 4)
                    .find(|&c| c > now)
                {
                    at(c);
                }
            }
        }
        next
    }

    /// Takes `k` idle cycles at once, each as the last one (no walker issues, every walker
    /// keeps its class, a waiting walk stalls at the dispatcher again if it did): the
    /// counters are credited as if stepped. Call after an idle cycle's [`issue`](Self::issue)
    /// and before the next [`wake`](Self::wake).
    pub fn skip_idle(&mut self, k: u64) {
        let cls = |c: Class| u64::from(self.classes.0[c as usize]) * k;
        let (empty, mem, bp, lat) = (
            cls(Class::Empty),
            cls(Class::MemoryWait),
            cls(Class::Backpressured),
            cls(Class::LatencyWait),
        );
        let c = &mut self.cycles;
        c.busy_context_cycles += u64::from(self.busy_total) * k;
        c.read_port_waits += u64::from(self.queued_total) * k;
        c.empty += empty;
        c.memory_wait += mem;
        c.backpressured += bp;
        c.latency_wait += lat;
        if self.stalled_now {
            c.dispatch_stalls += k;
        }
    }

    /// Phase 2: dispatches a walk (its ops with global addresses) if a context is free;
    /// returns whether it was taken (a refusal counts as a dispatch stall). At most one call
    /// per cycle.
    pub fn dispatch(&mut self, tag: u64, ops: &[u64]) -> bool {
        self.dispatch_with(tag, |v| v.extend_from_slice(ops))
    }

    /// [`dispatch`](Self::dispatch) with the ops written by `fill` straight into the
    /// context's own (emptied) op list, saving a copy per walk.
    pub fn dispatch_with(&mut self, tag: u64, fill: impl FnOnce(&mut Vec<u64>)) -> bool {
        if !self.has_free() {
            self.note_dispatch_stall();
            return false;
        }
        // The walker with the most free contexts, the lowest index on ties.
        let Some((f, best)) = (1..self.by_free.len())
            .rev()
            .find_map(|f| self.by_free[f].first().map(|w| (f, w)))
        else {
            return false;
        };
        let Some(ctx) = self.walkers[best].free.pop() else {
            return false;
        };
        self.by_free[f].remove(best);
        self.by_free[f - 1].insert(best);
        self.activity += 1;
        let c = &mut self.ctxs[ctx as usize];
        c.busy = true;
        c.tag = tag;
        c.ops.clear();
        fill(&mut c.ops);
        c.pc = 0;
        self.remaining[ctx as usize] = 0;
        c.in_issue = false;
        c.waiting_mem = false;
        c.finished = false;
        let wk = &mut self.walkers[best];
        wk.busy += 1;
        wk.reclass(&mut self.classes);
        self.busy_total += 1;
        self.cycles.walks += 1;
        let at = self.now + 1;
        self.schedule(ctx, at);
        true
    }

    /// Phase 3: every walker issues one ready context (if its II allows), and every walker's
    /// cycle is classified (the last phase: retire and dispatch of this cycle come first).
    /// Only walkers with a ready context are visited, in ascending order; the others'
    /// classes come from the running class counts, minus the walkers that issued.
    pub fn issue(&mut self) {
        let now = self.now;
        let (lat, ii) = (self.lat, self.ii);
        let mask = self.wheel.len() - 1;
        let slot = ((now + lat) as usize) & mask;
        let mut issued = 0u32;
        // Issuing walkers by the class they would otherwise have been counted in.
        let mut issued_by_class = [0u32; 4];
        // A context is ready when its key is below the next cycle's (`rings.rs`).
        let ready_below = key(now + 1, 0);
        let step_key = key(now + lat, PHASE_STEP);
        let steps_at = &mut self.steps_due[(now as usize) & mask];
        let caught_up = std::mem::take(steps_at);
        let mut steps_now = 0u32;
        for word in 0..self.has_ready.0.len() {
            let mut bits = self.has_ready.0[word];
            while bits != 0 {
                let w = word * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let wk = &mut self.walkers[w];
                if wk.pos.front >= ready_below || now < wk.next_issue {
                    continue;
                }
                wk.next_issue = now + ii;
                wk.issued_at = now;
                issued_by_class[wk.class as usize] += 1;
                issued += 1;
                // If the run goes on, the context goes back to its walker's ring, ready after
                // the step latency (`rings.rs`).
                let remaining = &mut self.remaining;
                let (ctx, back) = self.rings.issue_head(w, &mut wk.pos, step_key, |ctx| {
                    remaining.get_mut(ctx as usize).is_some_and(|left| {
                        *left -= 1;
                        *left > 0
                    })
                });
                if back {
                    steps_now += 1;
                } else {
                    // The run ends: the context moves on in the pool-wide wake-up order.
                    self.wheel[slot].push(ctx);
                    if wk.pos.len == 0 {
                        self.has_ready.remove(w);
                    }
                }
            }
        }
        self.steps_due[slot] += steps_now;
        self.activity += u64::from(caught_up);
        let idle = |k: Class| u64::from(self.classes.0[k as usize] - issued_by_class[k as usize]);
        let c = &mut self.cycles;
        c.busy_context_cycles += u64::from(self.busy_total);
        c.empty += idle(Class::Empty);
        c.memory_wait += idle(Class::MemoryWait);
        c.backpressured += idle(Class::Backpressured);
        c.latency_wait += idle(Class::LatencyWait);
        c.issuing += u64::from(issued);
        c.slots += u64::from(issued);
        self.issued_count = issued;
        self.activity += u64::from(issued);
    }

    /// The tag of the oldest finished walk, if any.
    pub fn finished_head(&self) -> Option<u64> {
        self.finished.front().map(|&c| self.ctxs[c as usize].tag)
    }

    /// Phase 4: retires the oldest finished walk (the record stage took it this cycle).
    pub fn retire(&mut self) -> Option<u64> {
        let ctx = self.finished.pop_front()?;
        self.activity += 1;
        let c = &mut self.ctxs[ctx as usize];
        c.busy = false;
        c.finished = false;
        let wk = &mut self.walkers[c.walker as usize];
        wk.finished -= 1;
        wk.busy -= 1;
        wk.reclass(&mut self.classes);
        wk.free.push(ctx);
        let (w, f) = (c.walker as usize, wk.free.len());
        self.by_free[f - 1].remove(w);
        self.by_free[f].insert(w);
        self.busy_total -= 1;
        Some(c.tag)
    }
}
#[cfg(test)]
mod tests;
