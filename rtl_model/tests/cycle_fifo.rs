//! FIFOs and the two-phase clock under random back-pressure.
//!
//! - One million items through one FIFO, and one million through a chain of three FIFOs of
//!   different depths, with random producer valid and consumer ready each cycle (in phases of
//!   different rates, some with AXI-style sticky valid): every item comes out exactly once and
//!   in order, occupancy never exceeds depth, every handshake and every counter equals an
//!   independent reference model (a `VecDeque` with the same rules), and the cycle stamps match
//!   the cycles the reference saw.
//! - Evaluation order: the same chain and stimulus with its parts evaluated in opposite (and
//!   random) orders gives identical traces.
//!
//! The two-phase clock's own evaluation-order tests, the documented handshake corners, misuse
//! and stamps are in `rtl_model/tests/cycle_clocked.rs`.
//!
//! Seeded: the seed is printed; `SVO_TEST_SEED` overrides it to replay a failure.

mod common;

use std::collections::VecDeque;
use std::time::Instant;

use common::Rng;
use rtl_model::cycle::clocked::{Clock, StageId, Stamped};
use rtl_model::cycle::fifo::{forward, Fifo, FifoStats, Refusal};

const MILLION: u64 = 1_000_000;

fn seed(test: &str) -> u64 {
    common::printed_seed(test, 0xF1F0_0000_0000_0001)
}

/// Rates of one stimulus phase: producer valid %, consumer ready %, sticky valid (once
/// raised, held until accepted, as AXI requires of a producer). The set covers long full
/// stretches (ready 0–10 %), long empty ones (valid 0–10 %) and balanced traffic.
const PHASES: [(u64, u64, bool); 10] = [
    (50, 50, false),
    (90, 10, false),
    (10, 90, false),
    (100, 100, false),
    (100, 0, false),
    (0, 100, false),
    (70, 70, true),
    (95, 40, true),
    (30, 95, true),
    (60, 55, false),
];
/// Cycles per phase before the next phase is drawn.
const PHASE_CYCLES: u64 = 5_000;

/// The stimulus: per cycle, whether the producer is valid and the consumer ready.
struct Stimulus {
    rng: Rng,
    phase: (u64, u64, bool),
    left_in_phase: u64,
    /// The producer offered last cycle and was refused (sticky valid holds it up).
    refused: bool,
}

impl Stimulus {
    fn new(seed: u64) -> Self {
        Self {
            rng: Rng::new(seed),
            phase: PHASES[0],
            left_in_phase: 0,
            refused: false,
        }
    }
    fn draw(&mut self) -> (bool, bool) {
        if self.left_in_phase == 0 {
            self.phase = PHASES[(self.rng.next() % PHASES.len() as u64) as usize];
            self.left_in_phase = PHASE_CYCLES;
        }
        self.left_in_phase -= 1;
        let (pv, pr, sticky) = self.phase;
        let valid = (sticky && self.refused) || self.rng.chance_percent(pv);
        let ready = self.rng.chance_percent(pr);
        (valid, ready)
    }
}

/// The reference FIFO: a `VecDeque` of (sequence number, entry cycle) with the documented
/// rules, written independently of the library (no shared code).
struct RefFifo {
    depth: usize,
    q: VecDeque<(u64, u64)>,
    stats: FifoStats,
}

impl RefFifo {
    fn new(depth: usize) -> Self {
        Self {
            depth,
            q: VecDeque::new(),
            stats: FifoStats {
                occupancy_histogram: vec![0; depth + 1],
                ..FifoStats::default()
            },
        }
    }
    fn ready(&self) -> bool {
        self.q.len() < self.depth
    }
    fn valid(&self) -> bool {
        !self.q.is_empty()
    }
    fn head(&self) -> Option<u64> {
        self.q.front().map(|&(s, _)| s)
    }
    /// One cycle: `offer` is the producer's item if valid, `ask` the consumer's ready.
    /// Decisions use the start-of-cycle length only. Returns (pushed, popped (seq, entered)).
    fn cycle(&mut self, now: u64, offer: Option<u64>, ask: bool) -> (bool, Option<(u64, u64)>) {
        let (ready, valid, occ) = (self.ready(), self.valid(), self.q.len());
        let s = &mut self.stats;
        s.cycles += 1;
        s.occupancy_sum += occ as u64;
        s.occupancy_histogram[occ] += 1;
        if offer.is_some() && !ready {
            s.full_cycles += 1;
        }
        if ask && !valid {
            s.starved_cycles += 1;
        }
        let popped = if ask && valid {
            self.q.pop_front()
        } else {
            None
        };
        if let Some((_, entered)) = popped {
            s.pops += 1;
            s.latency_sum += now - entered;
            s.latency_max = s.latency_max.max(now - entered);
        }
        let pushed = match offer {
            Some(seq) if ready => {
                self.q.push_back((seq, now));
                s.pushes += 1;
                true
            }
            _ => false,
        };
        s.max_occupancy = s.max_occupancy.max(self.q.len() as u64);
        (pushed, popped)
    }
}

/// One FIFO of `depth`, `n` items, with the stimulus of `seed`. The push and pop sides are
/// driven in a random order each cycle. Returns the cycles taken.
fn run_single(seed: u64, depth: usize, n: u64) -> u64 {
    let stage = StageId(7);
    let mut stim = Stimulus::new(seed);
    let mut order = Rng::new(seed ^ 0xA5A5);
    let mut clock = Clock::new();
    let mut fifo: Fifo<u64> = Fifo::new(stage, depth).expect("depth is valid");
    let mut model = RefFifo::new(depth);
    let mut next_in = 0u64; // next sequence number the producer offers
    let mut held: Option<Stamped<u64>> = None; // a refused item, offered again later
    let mut next_out = 0u64;
    while next_out < n {
        let now = clock.now();
        let (mut valid, ready) = stim.draw();
        valid &= next_in < n;
        assert_eq!(fifo.ready(), model.ready(), "ready at cycle {now}");
        assert_eq!(fifo.valid(), model.valid(), "valid at cycle {now}");
        assert_eq!(fifo.occupancy(), model.q.len(), "occupancy at cycle {now}");
        assert_eq!(fifo.peek().map(|i| i.payload), model.head());

        let mut pushed = false;
        let mut popped = None;
        let push = |fifo: &mut Fifo<u64>, held: &mut Option<Stamped<u64>>, pushed: &mut bool| {
            if !valid {
                return;
            }
            let item = held.take().unwrap_or_else(|| Stamped::new(next_in));
            assert_eq!(item.payload, next_in);
            match fifo.try_push(item) {
                Ok(()) => *pushed = true,
                Err(r) => {
                    assert_eq!(r.reason, Refusal::Full, "cycle {now}");
                    assert!(r.item.stamps().is_empty(), "a refused item is not stamped");
                    *held = Some(r.item);
                }
            }
        };
        let pop = |fifo: &mut Fifo<u64>, popped: &mut Option<Stamped<u64>>| {
            if ready {
                *popped = fifo.try_pop().expect("one pop per cycle");
            }
        };
        if order.next() & 1 == 0 {
            push(&mut fifo, &mut held, &mut pushed);
            pop(&mut fifo, &mut popped);
        } else {
            pop(&mut fifo, &mut popped);
            push(&mut fifo, &mut held, &mut pushed);
        }
        // Registered signals do not move before the edge, whatever happened this cycle.
        assert_eq!(fifo.ready(), model.ready());
        assert_eq!(fifo.valid(), model.valid());

        let (ref_pushed, ref_popped) = model.cycle(now, valid.then_some(next_in), ready);
        assert_eq!(pushed, ref_pushed, "push handshake at cycle {now}");
        if pushed {
            next_in += 1;
        }
        match (popped, ref_popped) {
            (None, None) => {}
            (Some(item), Some((seq, entered))) => {
                assert_eq!(item.payload, next_out, "order at cycle {now}");
                assert_eq!(item.payload, seq);
                let st = item.stamps();
                assert_eq!(st.len(), 1);
                assert_eq!(st[0].stage, stage);
                assert_eq!((st[0].entered, st[0].left), (entered, Some(now)));
                assert!(now > entered, "registered FIFO: exit ≥ entry + 1");
                assert_eq!(item.check(), Ok(()));
                next_out += 1;
            }
            (a, b) => panic!("pop handshake at cycle {now}: {a:?} vs reference {b:?}"),
        }
        clock.edge(&mut [&mut fifo]).expect("edge");
        assert!(fifo.occupancy() <= depth);
    }
    let s = fifo.stats();
    assert_eq!(s, model.stats, "counters against the reference");
    assert_eq!(s.pushes, n);
    assert_eq!(s.pops, n);
    assert_eq!(s.pushes, s.pops + fifo.occupancy() as u64);
    assert_eq!(s.cycles, clock.now());
    assert_eq!(s.occupancy_histogram.iter().sum::<u64>(), s.cycles);
    assert_eq!(s.misuse, 0);
    assert!(s.max_occupancy <= depth as u64);
    clock.now()
}

#[test]
fn million_items_through_one_fifo() {
    let seed = seed("million_items_through_one_fifo");
    let t = Instant::now();
    let cycles = run_single(seed, 5, MILLION);
    println!(
        "depth 5: {MILLION} items in {cycles} cycles, {:.2} s",
        t.elapsed().as_secs_f64()
    );
    // The small depths, where the registered ready costs the most, on fewer items.
    for depth in [1, 2, 3] {
        let t = Instant::now();
        let cycles = run_single(seed.wrapping_add(depth as u64), depth, 100_000);
        println!(
            "depth {depth}: 100000 items in {cycles} cycles, {:.2} s",
            t.elapsed().as_secs_f64()
        );
    }
}

/// Trace of a chain run: each item's payload and stamps as it reached the sink, the counters
/// of each FIFO, and the cycles taken.
type ChainTrace = (Vec<Stamped<u64>>, Vec<FifoStats>, u64);

/// How the parts of a chain are driven within a cycle.
#[derive(Clone, Copy)]
enum Order {
    /// Source, links upstream first, sink.
    Forward,
    /// Sink, links downstream first, source.
    Reverse,
    /// A random permutation each cycle.
    Random,
}

/// Source → FIFO 0 → FIFO 1 → FIFO 2 → sink, `n` items, every handshake checked against three
/// reference FIFOs. With `keep`, the sink's items are returned for order comparisons.
fn run_chain(seed: u64, depths: [usize; 3], n: u64, order: Order, keep: bool) -> ChainTrace {
    let mut stim = Stimulus::new(seed);
    let mut perm_rng = Rng::new(seed ^ 0x5A5A);
    let mut clock = Clock::new();
    let mut fifos: Vec<Fifo<u64>> = (0..3)
        .map(|k| Fifo::new(StageId(k as u16), depths[k]).expect("depth is valid"))
        .collect();
    let mut models: Vec<RefFifo> = depths.iter().map(|&d| RefFifo::new(d)).collect();
    let mut next_in = 0u64;
    let mut held: Option<Stamped<u64>> = None;
    let mut next_out = 0u64;
    let mut out = Vec::new();
    let capacity: usize = depths.iter().sum();
    while next_out < n {
        let now = clock.now();
        let (mut valid, ready) = stim.draw();
        valid &= next_in < n;
        for (f, m) in fifos.iter().zip(&models) {
            assert_eq!(
                (f.ready(), f.valid()),
                (m.ready(), m.valid()),
                "cycle {now}"
            );
            assert_eq!(f.occupancy(), m.q.len());
        }

        // Actions: 0 = source push, 1 = link 0→1, 2 = link 1→2, 3 = sink pop.
        let mut actions = [0usize, 1, 2, 3];
        match order {
            Order::Forward => {}
            Order::Reverse => actions.reverse(),
            Order::Random => {
                for i in (1..4).rev() {
                    let j = (perm_rng.next() % (i as u64 + 1)) as usize;
                    actions.swap(i, j);
                }
            }
        }
        let mut pushed = false;
        let mut moved = [false; 2];
        let mut popped = None;
        for a in actions {
            match a {
                0 if valid => {
                    let item = held.take().unwrap_or_else(|| Stamped::new(next_in));
                    match fifos[0].try_push(item) {
                        Ok(()) => pushed = true,
                        Err(r) => {
                            assert_eq!(r.reason, Refusal::Full);
                            held = Some(r.item);
                        }
                    }
                }
                1 | 2 => {
                    let (up, down) = fifos.split_at_mut(a);
                    moved[a - 1] = forward(&mut up[a - 1], &mut down[0]).expect("link");
                }
                3 if ready => popped = fifos[2].try_pop().expect("one pop per cycle"),
                _ => {}
            }
        }

        // The reference: all decisions from start-of-cycle state, then applied.
        let offers = [valid.then_some(next_in), models[0].head(), models[1].head()];
        let asks = [models[1].ready(), models[2].ready(), ready];
        let mut ref_pushed = [false; 3];
        let mut ref_popped = [None; 3];
        for k in 0..3 {
            (ref_pushed[k], ref_popped[k]) = models[k].cycle(now, offers[k], asks[k]);
        }
        assert_eq!(pushed, ref_pushed[0], "source push at cycle {now}");
        assert_eq!(
            moved,
            [ref_pushed[1], ref_pushed[2]],
            "links at cycle {now}"
        );
        // A link moves exactly what the upstream reference popped.
        for k in 0..2 {
            assert_eq!(ref_pushed[k + 1], ref_popped[k].is_some());
        }
        if pushed {
            next_in += 1;
        }
        match (popped, ref_popped[2]) {
            (None, None) => {}
            (Some(item), Some((seq, entered))) => {
                assert_eq!(item.payload, next_out, "order at cycle {now}");
                assert_eq!(item.payload, seq);
                let st = item.stamps();
                assert_eq!(st.len(), 3, "one visit per FIFO");
                for (k, s) in st.iter().enumerate() {
                    assert_eq!(s.stage, StageId(k as u16));
                    let left = s.left.expect("every visit closed");
                    assert!(left > s.entered, "exit ≥ entry + 1 in FIFO {k}");
                    if k + 1 < st.len() {
                        assert_eq!(Some(st[k + 1].entered), s.left, "hand-over cycle");
                    }
                }
                assert_eq!((st[2].entered, st[2].left), (entered, Some(now)));
                assert_eq!(item.check(), Ok(()));
                next_out += 1;
                if keep {
                    out.push(item);
                }
            }
            (a, b) => panic!("sink pop at cycle {now}: {a:?} vs reference {b:?}"),
        }

        let [a, b, c] = &mut fifos[..] else {
            unreachable!("three FIFOs")
        };
        clock.edge(&mut [a, b, c]).expect("edge");
        let inside: usize = fifos.iter().map(Fifo::occupancy).sum();
        assert!(inside <= capacity);
        for (f, d) in fifos.iter().zip(depths) {
            assert!(f.occupancy() <= d);
        }
        // Items inside the chain are exactly those pushed and not yet out.
        assert_eq!(inside as u64, next_in - next_out);
    }
    let stats: Vec<FifoStats> = fifos.iter().map(|f| f.stats().clone()).collect();
    for (k, (s, m)) in stats.iter().zip(&models).enumerate() {
        assert_eq!(*s, m.stats, "FIFO {k} counters against the reference");
        assert_eq!(s.pushes, s.pops + fifos[k].occupancy() as u64);
        assert_eq!(s.pushes, n);
        assert_eq!(s.misuse, 0);
        assert_eq!(s.cycles, clock.now());
    }
    (out, stats, clock.now())
}

#[test]
fn million_items_through_a_chain_of_three() {
    let seed = seed("million_items_through_a_chain_of_three");
    let t = Instant::now();
    let depths = [4, 1, 9];
    let (_, stats, cycles) = run_chain(seed, depths, MILLION, Order::Random, false);
    println!(
        "depths {depths:?}: {MILLION} items in {cycles} cycles, {:.2} s",
        t.elapsed().as_secs_f64()
    );
    for (k, s) in stats.iter().enumerate() {
        println!(
            "  FIFO {k}: full {} starved {} max occupancy {} mean occupancy {:.2} mean latency {:.2}",
            s.full_cycles,
            s.starved_cycles,
            s.max_occupancy,
            s.mean_occupancy(),
            s.mean_latency()
        );
    }
}

#[test]
fn chain_results_do_not_depend_on_evaluation_order() {
    let seed = seed("chain_results_do_not_depend_on_evaluation_order");
    let depths = [2, 3, 1];
    let a = run_chain(seed, depths, 50_000, Order::Forward, true);
    let b = run_chain(seed, depths, 50_000, Order::Reverse, true);
    let c = run_chain(seed, depths, 50_000, Order::Random, true);
    assert_eq!(a, b);
    assert_eq!(a, c);
}

/// `skip_idle(k)` equals `k` edges in which the sides are driven as in the last one and
/// nothing moves: starved, full and idle FIFOs alike.
#[test]
fn skipping_idle_cycles_equals_stepping_them() {
    use rtl_model::cycle::clocked::{Clock, Commit, StageId, Stamped};
    for (items, ask_pop, offer) in [(0usize, true, false), (2, false, true), (1, false, false)] {
        let make = || {
            let mut clock = Clock::new();
            let mut f: Fifo<u32> = Fifo::new(StageId(3), 2).unwrap();
            for i in 0..items {
                f.try_push(Stamped::new(i as u32)).unwrap();
                clock.edge(&mut [&mut f as &mut dyn Commit]).unwrap();
            }
            (clock, f)
        };
        let idle = |clock: &mut Clock, f: &mut Fifo<u32>| {
            if ask_pop {
                assert_eq!(f.try_pop().unwrap().map(|s| s.payload), None);
            }
            if offer {
                assert!(f.try_push(Stamped::new(9)).is_err());
            }
            clock.edge(&mut [f as &mut dyn Commit]).unwrap();
        };
        let (mut c1, mut stepped) = make();
        let (mut c2, mut skipped) = make();
        for _ in 0..8 {
            idle(&mut c1, &mut stepped);
        }
        idle(&mut c2, &mut skipped);
        skipped.skip_idle(7);
        c2.skip(7);
        assert_eq!(stepped.stats(), skipped.stats(), "{items} items");
        assert_eq!((stepped.cycle(), c1.now()), (skipped.cycle(), c2.now()));
        // And both go on alike.
        idle(&mut c1, &mut stepped);
        idle(&mut c2, &mut skipped);
        assert_eq!(stepped.stats(), skipped.stats());
    }
}

/// Items a wide FIFO of `depth` entries and `ports` ports passes per cycle when its producer
/// pushes and its consumer pops as many as it lets them, every cycle, over `cycles` cycles.
fn wide_throughput(depth: usize, ports: usize, cycles: u64) -> f64 {
    let mut clock = Clock::new();
    let mut fifo: Fifo<u64> = Fifo::new_wide(StageId(3), depth, ports).expect("valid FIFO");
    let mut next = 0u64;
    let mut out = 0u64;
    for _ in 0..cycles {
        while fifo.can_pop() {
            fifo.try_pop().expect("a pop").expect("an item");
            out += 1;
        }
        while fifo.can_push() {
            fifo.try_push(Stamped::new(next)).expect("room");
            next += 1;
        }
        clock.edge(&mut [&mut fifo]).expect("edge");
    }
    out as f64 / cycles as f64
}

/// A push is taken against the registered occupancy (a space a pop frees is usable from the
/// next cycle), so a FIFO passes at most half its depth a cycle however many ports it has:
/// the walk section's default 4-deep FIFOs carry two walks a cycle, the ceiling that made a
/// third or fourth walk-issue lane useless until their depth grew (docs/cycle-model.md §3.7).
#[test]
fn a_wide_fifo_passes_half_its_depth_a_cycle() {
    let rate = |d, p| wide_throughput(d, p, 10_000);
    for (depth, ports, want) in [
        (4, 2, 2.0),
        (4, 4, 2.0),
        (4, 8, 2.0),
        (8, 4, 4.0),
        (16, 8, 8.0),
    ] {
        let got = rate(depth, ports);
        assert!(
            (got - want).abs() < 0.01,
            "depth {depth}, {ports} ports: {got} items a cycle, expected {want}"
        );
    }
    // A port-bound FIFO: deep enough, the ports decide.
    assert!((rate(64, 2) - 2.0).abs() < 0.01);
}

/// `Fifo::registered`, what the cycle model's stage kernels read (issue 30): the items inside
/// at the start of the cycle, head first, unchanged by this cycle's pushes, and past the ones
/// already handed out by a pop.
#[test]
fn registered_items_are_the_start_of_cycle_contents() {
    let mut clock = Clock::new();
    let mut f = Fifo::new_wide(StageId(1), 4, 2).unwrap();
    for v in [10u32, 11] {
        f.try_push(Stamped::untracked(v)).unwrap();
    }
    // Pushed this cycle: not visible before the edge.
    assert!(f.registered(0).is_none());
    clock.edge(&mut [&mut f]).unwrap();
    f.try_push(Stamped::untracked(12)).unwrap();
    let at = |f: &Fifo<u32>, i| f.registered(i).map(|s| s.payload);
    assert_eq!(
        (at(&f, 0), at(&f, 1), at(&f, 2)),
        (Some(10), Some(11), None)
    );
    // A pop hands out the head: index 0 is still the head of the start of the cycle, gone.
    assert_eq!(f.try_pop().unwrap().map(|s| s.payload), Some(10));
    assert_eq!((at(&f, 0), at(&f, 1)), (None, Some(11)));
}
