//! The walker pool's within-cycle orders (wake-up, send queue, round robin, retire, dispatch)
//! against a reference pool written here from the pool's module doc alone, cycle by cycle:
//! every context woken through one wheel of (cycle, context) in push order, every ready
//! queue a plain FIFO. The pool keeps runs that go on in per-walker rings instead of its
//! wheel (issue 30); any order that differs moves a read, a slot or a retirement.
//!
//! Both pools drive their own node memory of the same configuration, so a read requested in
//! another order or cycle shows up as a different completion and then a different cycle.
//! Random configurations include a step latency of 1 (a walk dispatched in the cycle before
//! joins the ready queue before a step that ends now) and initiation intervals above 1, and
//! random walks include empty and back-to-back issue runs and walks that start with a run.
//!
//! The pool's response and request registers (`walker_pool.response_register_cycles`,
//! `request_register_cycles`, issue 29) are checked twice: the reference pool states them
//! (a completion is seen in the cycle after the memory's; a read picked in C reaches the memory
//! in C + 1, before anything else of that cycle, in pick order), and
//! `registers_are_one_cycle_more_latency_on_a_memory_without_contention` compares a pool
//! with them against a pool without them on a memory one or two cycles slower, where nothing
//! but latency can tell them apart.

mod common;

use std::collections::{BTreeMap, VecDeque};

use common::{seed, Rng};
use rtl_model::cycle::hw_config::WalkerPool as PoolConfig;
use rtl_model::cycle::memory::{
    Completion, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, OnChipConfig,
};
use rtl_model::cycle::walk_op::WalkOp;
use rtl_model::cycle::walker_pool::WalkerPoolModel;

/// One context of the reference pool.
#[derive(Clone, Default)]
struct RefCtx {
    tag: u64,
    ops: Vec<u64>,
    pc: usize,
    /// Slots left in the run it is in (`None`: not in a run).
    run: Option<u32>,
    waiting: bool,
}

/// The reference pool: the module doc's rules, one step at a time.
struct RefPool {
    r: usize,
    lat: u64,
    ii: u64,
    ports: u32,
    ctxs: Vec<RefCtx>,
    ready: Vec<VecDeque<usize>>,
    free: Vec<Vec<usize>>,
    busy: Vec<u32>,
    waiting: Vec<u32>,
    next_issue: Vec<u64>,
    send: Vec<VecDeque<(usize, FetchKind, u32)>>,
    sent: Vec<u32>,
    issued: Vec<bool>,
    /// Contexts due per cycle, in the order they were put there.
    due: BTreeMap<u64, Vec<usize>>,
    finished: VecDeque<usize>,
    reads: u64,
    slots: u64,
    port_waits: u64,
    now: u64,
    /// `response_register_cycles` 1 and the completions it holds (the memory's last cycle's).
    resp_reg: bool,
    held: Vec<Completion>,
    /// `request_register_cycles` 1 and the reads it holds (picked in the last cycle).
    req_reg: bool,
    picked: Vec<(usize, FetchKind, u32)>,
}

impl RefPool {
    fn new(cfg: &PoolConfig) -> Self {
        let (w, r) = (cfg.walkers as usize, cfg.contexts_per_walker as usize);
        Self {
            r,
            lat: u64::from(cfg.step_latency_cycles.max(1)),
            ii: u64::from(cfg.step_cycles.max(1)),
            ports: if cfg.read_ports == 0 {
                u32::MAX
            } else {
                cfg.read_ports
            },
            ctxs: vec![RefCtx::default(); w * r],
            ready: vec![VecDeque::new(); w],
            // Lowest context first; a freed context is taken next.
            free: (0..w)
                .map(|wi| (0..r).rev().map(|k| wi * r + k).collect())
                .collect(),
            busy: vec![0; w],
            waiting: vec![0; w],
            next_issue: vec![0; w],
            send: vec![VecDeque::new(); w],
            sent: vec![0; w],
            issued: vec![false; w],
            due: BTreeMap::new(),
            finished: VecDeque::new(),
            reads: 0,
            slots: 0,
            port_waits: 0,
            now: 0,
            resp_reg: cfg.response_register_cycles == 1,
            held: Vec::new(),
            req_reg: cfg.request_register_cycles == 1,
            picked: Vec::new(),
        }
    }

    /// The port sends a read: to the memory now, or into the request register.
    fn send_read(&mut self, ctx: usize, kind: FetchKind, addr: u32, mem: &mut NodeMemory) {
        if self.req_reg {
            self.picked.push((ctx, kind, addr));
        } else {
            mem.request(self.now, addr, kind, ctx as u32)
                .expect("reference read");
            self.reads += 1;
        }
    }

    fn read(&mut self, ctx: usize, kind: FetchKind, addr: u32, mem: &mut NodeMemory) {
        let w = ctx / self.r;
        if self.sent[w] < self.ports {
            self.sent[w] += 1;
            self.send_read(ctx, kind, addr, mem);
        } else {
            self.send[w].push_back((ctx, kind, addr));
        }
    }

    fn advance(&mut self, ctx: usize, mem: &mut NodeMemory) {
        let w = ctx / self.r;
        loop {
            let c = &mut self.ctxs[ctx];
            match c.run {
                Some(0) => {
                    c.run = None;
                    c.pc += 1;
                }
                Some(_) => {
                    self.ready[w].push_back(ctx);
                    return;
                }
                None => {}
            }
            let Some(&op) = c.ops.get(c.pc) else {
                self.finished.push_back(ctx);
                return;
            };
            match WalkOp::unpack(op) {
                WalkOp::Issue(n) => c.run = Some(n),
                WalkOp::Read(kind, addr) => {
                    c.pc += 1;
                    c.waiting = true;
                    self.waiting[w] += 1;
                    self.read(ctx, kind, addr, mem);
                    return;
                }
            }
        }
    }

    fn wake(&mut self, now: u64, mem: &mut NodeMemory, done: &mut Vec<Completion>) {
        self.now = now;
        mem.catch_up(now);
        for (ctx, kind, addr) in std::mem::take(&mut self.picked) {
            mem.request(now, addr, kind, ctx as u32)
                .expect("reference registered read");
            self.reads += 1;
        }
        self.sent.iter_mut().for_each(|s| *s = 0);
        for w in 0..self.send.len() {
            while self.sent[w] < self.ports {
                let Some((ctx, kind, addr)) = self.send[w].pop_front() else {
                    break;
                };
                self.sent[w] += 1;
                self.send_read(ctx, kind, addr, mem);
            }
        }
        for ctx in self.due.remove(&now).unwrap_or_default() {
            self.advance(ctx, mem);
        }
        done.clear();
        mem.tick_into(now, done);
        if self.resp_reg {
            // Seen now: the memory's last cycle's; latched: this cycle's.
            let fresh = std::mem::take(done);
            *done = std::mem::replace(&mut self.held, fresh);
        }
        for comp in done.iter() {
            let ctx = comp.requester as usize;
            if self.ctxs[ctx].waiting {
                self.ctxs[ctx].waiting = false;
                self.waiting[ctx / self.r] -= 1;
                self.advance(ctx, mem);
            }
        }
        self.port_waits += self.send.iter().map(|q| q.len() as u64).sum::<u64>();
    }

    fn retire(&mut self) -> Option<u64> {
        let ctx = self.finished.pop_front()?;
        let w = ctx / self.r;
        self.busy[w] -= 1;
        self.free[w].push(ctx);
        Some(self.ctxs[ctx].tag)
    }

    fn dispatch(&mut self, tag: u64, ops: &[u64]) -> bool {
        // Most free contexts, the lowest walker on ties.
        let Some(w) = (0..self.free.len())
            .filter(|&w| !self.free[w].is_empty())
            .max_by_key(|&w| (self.free[w].len(), std::cmp::Reverse(w)))
        else {
            return false;
        };
        let ctx = self.free[w].pop().expect("a free context");
        self.busy[w] += 1;
        self.ctxs[ctx] = RefCtx {
            tag,
            ops: ops.to_vec(),
            ..RefCtx::default()
        };
        self.due.entry(self.now + 1).or_default().push(ctx);
        true
    }

    fn issue(&mut self) {
        let now = self.now;
        for w in 0..self.ready.len() {
            self.issued[w] = false;
            if now < self.next_issue[w] {
                continue;
            }
            let Some(ctx) = self.ready[w].pop_front() else {
                continue;
            };
            self.issued[w] = true;
            self.next_issue[w] = now + self.ii;
            self.slots += 1;
            if let Some(n) = self.ctxs[ctx].run.as_mut() {
                *n -= 1;
            }
            self.due.entry(now + self.lat).or_default().push(ctx);
        }
    }
}

/// A walk: usually a root read first, then runs and reads; sometimes a run first, an empty
/// run, or two runs back to back.
fn random_walk(rng: &mut Rng) -> Vec<u64> {
    let mut ops = Vec::new();
    for _ in 0..1 + rng.below(6) {
        match rng.below(8) {
            0 => ops.push(WalkOp::Issue(0).pack()),
            1..=4 => ops.push(WalkOp::Issue(1 + rng.below(6) as u32).pack()),
            _ => {
                let kind = match rng.below(6) {
                    0 => FetchKind::Attr,
                    1 => FetchKind::Far,
                    _ => FetchKind::Node,
                };
                let top = if kind == FetchKind::Attr { 512 } else { 4096 };
                ops.push(WalkOp::Read(kind, rng.below(top) as u32).pack());
            }
        }
    }
    ops
}

fn memory() -> NodeMemory {
    let layout = MemoryLayout::with_onchip_ranges(4096, 512, vec![(0, 1024)]).expect("layout");
    NodeMemory::new(NodeMemoryConfig::default(), layout).expect("memory")
}

#[test]
fn orders_match_a_reference_pool_every_cycle() {
    let s = seed(0x5eed_3030);
    println!("seed {s} (SVO_TEST_SEED={s} replays it)");
    let mut rng = Rng::new(s);
    let mut done = Vec::new();
    let mut total_slots = 0;
    for case in 0..40 {
        let cfg = PoolConfig {
            walkers: 1 + rng.below(6) as u32,
            contexts_per_walker: 1 + rng.below(6) as u32,
            step_cycles: 1 + rng.below(3) as u32,
            step_latency_cycles: 1 + rng.below(5) as u32,
            read_ports: rng.below(3) as u32,
            response_register_cycles: rng.below(2) as u32,
            request_register_cycles: rng.below(2) as u32,
            ..PoolConfig::default()
        };
        let walkers = cfg.walkers as usize;
        let (mut mem, mut ref_mem) = (memory(), memory());
        let mut pool = WalkerPoolModel::new(&cfg).expect("pool");
        let mut oracle = RefPool::new(&cfg);
        let mut to_dispatch = 150u64;
        let mut retired = 0u64;
        let mut now = 0u64;
        while retired < 150 {
            let at = format!("seed {s}, case {case} ({cfg:?}), cycle {now}");
            pool.wake(now, &mut mem).expect("wake");
            oracle.wake(now, &mut ref_mem, &mut done);
            for w in 0..walkers {
                let got = (
                    pool.walker_sent(w),
                    pool.walker_queued(w),
                    pool.walker_waiting(w),
                );
                let want = (
                    oracle.sent[w],
                    oracle.send[w].len() as u32,
                    oracle.waiting[w],
                );
                assert_eq!(got, want, "{at}, walker {w}: (sent, queued, waiting)");
            }
            if rng.below(3) > 0 {
                let got = pool.retire();
                assert_eq!(got, oracle.retire(), "{at}: retired walk");
                retired += u64::from(got.is_some());
            }
            if to_dispatch > 0 && rng.below(3) > 0 {
                let ops = random_walk(&mut rng);
                let taken = pool.dispatch(to_dispatch, &ops);
                assert_eq!(taken, oracle.dispatch(to_dispatch, &ops), "{at}: dispatch");
                to_dispatch -= u64::from(taken);
            }
            pool.issue();
            oracle.issue();
            for w in 0..walkers {
                let got = (pool.walker_issued(w), pool.walker_busy(w));
                let want = (oracle.issued[w], oracle.busy[w]);
                assert_eq!(got, want, "{at}, walker {w}: (issued, busy)");
            }
            now += 1;
            assert!(now < 1_000_000, "seed {s}, case {case}: no progress");
        }
        let c = pool.take_cycles();
        let want = (oracle.reads, oracle.slots, oracle.port_waits);
        assert_eq!(
            (c.reads, c.slots, c.read_port_waits),
            want,
            "seed {s}, case {case}: (reads, slots, read_port_waits)"
        );
        total_slots += c.slots;
    }
    assert!(total_slots > 0, "seed {s}: no slot ever issued");
}

/// A node memory no read ever waits in: every node word on chip in one bank of 64 ports
/// (more than the walkers of these tests can send in a cycle), no combining, `latency` cycles.
fn uncontended(latency: u32) -> NodeMemory {
    let cfg = NodeMemoryConfig {
        onchip: OnChipConfig {
            levels: rtl_model::svo::MAX_DEPTH + 1,
            max_bytes: u64::MAX,
            latency,
            banks: 1,
            ports_per_bank: 64,
            combine: false,
        },
        ..NodeMemoryConfig::default()
    };
    let layout = MemoryLayout::with_onchip_ranges(4096, 512, vec![(0, 4096)]).expect("layout");
    NodeMemory::new(cfg, layout).expect("memory")
}

/// A walk of on-chip node reads and issue runs only.
fn onchip_walk(rng: &mut Rng) -> Vec<u64> {
    (0..1 + rng.below(6))
        .map(|_| match rng.below(2) {
            0 => WalkOp::Issue(1 + rng.below(6) as u32).pack(),
            _ => WalkOp::Read(FetchKind::Node, rng.below(4096) as u32).pack(),
        })
        .collect()
}

/// The registers' independent statement: on a memory where no read waits, a register stage
/// is one more cycle of read latency as a context sees it and nothing else. A pool with
/// response register `a` and request register `b` on a memory of latency L must retire the
/// same walks in the same cycles, send and queue the same reads per walker and cycle, and
/// issue the same slots as a pool without registers on a memory of latency L + a + b.
#[test]
fn registers_are_one_cycle_more_latency_on_a_memory_without_contention() {
    let s = seed(0x5eed_2929);
    println!("seed {s} (SVO_TEST_SEED={s} replays it)");
    let mut rng = Rng::new(s);
    for case in 0..40 {
        let (resp, req) = [(1, 0), (0, 1), (1, 1)][case % 3];
        let base = PoolConfig {
            walkers: 1 + rng.below(6) as u32,
            contexts_per_walker: 1 + rng.below(6) as u32,
            step_cycles: 1 + rng.below(3) as u32,
            step_latency_cycles: 1 + rng.below(5) as u32,
            read_ports: rng.below(3) as u32,
            ..PoolConfig::default()
        };
        let cfg = PoolConfig {
            response_register_cycles: resp,
            request_register_cycles: req,
            ..base.clone()
        };
        let latency = 1 + rng.below(5) as u32;
        let walkers = cfg.walkers as usize;
        let (mut mem, mut slow_mem) = (uncontended(latency), uncontended(latency + resp + req));
        let mut pool = WalkerPoolModel::new(&cfg).expect("pool");
        let mut slow = WalkerPoolModel::new(&base).expect("pool");
        let mut to_dispatch = 150u64;
        let mut retired = 0u64;
        let mut now = 0u64;
        while retired < 150 {
            let at = format!("seed {s}, case {case} ({cfg:?}, latency {latency}), cycle {now}");
            pool.wake(now, &mut mem).expect("wake");
            slow.wake(now, &mut slow_mem).expect("wake");
            for w in 0..walkers {
                let state = |p: &WalkerPoolModel| {
                    (p.walker_sent(w), p.walker_queued(w), p.walker_waiting(w))
                };
                assert_eq!(
                    state(&pool),
                    state(&slow),
                    "{at}, walker {w}: (sent, queued, waiting)"
                );
            }
            if rng.below(3) > 0 {
                let got = pool.retire();
                assert_eq!(got, slow.retire(), "{at}: retired walk");
                retired += u64::from(got.is_some());
            }
            if to_dispatch > 0 && rng.below(3) > 0 {
                let ops = onchip_walk(&mut rng);
                let taken = pool.dispatch(to_dispatch, &ops);
                assert_eq!(taken, slow.dispatch(to_dispatch, &ops), "{at}: dispatch");
                to_dispatch -= u64::from(taken);
            }
            pool.issue();
            slow.issue();
            for w in 0..walkers {
                let got = (pool.walker_issued(w), pool.walker_busy(w));
                let want = (slow.walker_issued(w), slow.walker_busy(w));
                assert_eq!(got, want, "{at}, walker {w}: (issued, busy)");
            }
            now += 1;
            assert!(now < 1_000_000, "seed {s}, case {case}: no progress");
        }
        let (c, d) = (pool.take_cycles(), slow.take_cycles());
        assert_eq!(
            (c.reads, c.slots, c.read_port_waits),
            (d.reads, d.slots, d.read_port_waits),
            "seed {s}, case {case}: (reads, slots, read_port_waits)"
        );
    }
}
