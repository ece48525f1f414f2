//! The two-phase clock (`rtl_model::cycle::clocked`) and the FIFO's documented handshake
//! rules, cycle by cycle.
//!
//! - Evaluation order: a producer and a consumer stage that update their registers in place
//!   around a FIFO (as the pipeline's stages do) give identical traces whichever is evaluated
//!   first; a one-phase (commit-as-you-go) control shows the check has teeth.
//! - The documented handshake corners (depth 1 alternates, depth 2 streams; full with a pop,
//!   empty with a push), and misuse of FIFOs and the clock that must be
//!   refused without panicking.
//! - Stamps record one stage visit at a time.
//!
//! The FIFOs under random back-pressure against a reference model are in
//! `rtl_model/tests/cycle_fifo.rs`.
//!
//! Seeded: the seed is printed; `SVO_TEST_SEED` overrides it to replay a failure.

mod common;

use common::Rng;
use rtl_model::cycle::clocked::{
    Clock, ClockError, Commit, EdgeError, StageId, StampError, Stamped,
};
use rtl_model::cycle::fifo::{forward, Fifo, FifoError, FifoStats, Refusal, MAX_DEPTH};

fn seed(test: &str) -> u64 {
    common::printed_seed(test, 0xF1F0_0000_0000_0001)
}

/// Producer stage: offers its sequence number when its LFSR says valid; advances when the
/// FIFO (registered `ready`, its input) takes the item. Like the pipeline's stages, its
/// registers change in place as it is evaluated; only the FIFO holds its changes for the edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Producer {
    seq: u64,
    lfsr: u64,
}

impl Producer {
    fn valid(&self) -> bool {
        self.lfsr % 3 != 0
    }

    /// One cycle against `fifo`.
    fn eval(&mut self, fifo: &mut Fifo<u64>) {
        let ready = fifo.ready();
        if self.valid() {
            let taken = fifo.try_push(Stamped::new(self.seq)).is_ok();
            assert_eq!(taken, ready, "the stage's view of the handshake");
            self.seq += u64::from(taken);
        }
        self.lfsr = Rng::new(self.lfsr).next();
    }
}

/// Consumer stage: ready when idle and its LFSR agrees; an item keeps it busy for a few
/// cycles and is summed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Consumer {
    busy: u64,
    count: u64,
    sum: u64,
    lfsr: u64,
}

impl Consumer {
    fn ready(&self) -> bool {
        self.busy == 0 && self.lfsr % 4 != 0
    }

    /// One cycle against `fifo`.
    fn eval(&mut self, fifo: &mut Fifo<u64>) {
        let item = if self.ready() {
            fifo.try_pop().expect("one pop per cycle")
        } else {
            None
        };
        match item {
            Some(it) => {
                self.busy = it.payload % 3;
                self.count += 1;
                self.sum = self.sum.wrapping_mul(31).wrapping_add(it.payload);
            }
            None => self.busy = self.busy.saturating_sub(1),
        }
        self.lfsr = Rng::new(self.lfsr).next();
    }
}

type StageTrace = (Vec<(Producer, Consumer, usize)>, FifoStats);

/// Producer → FIFO → consumer for `cycles`; `consumer_first` swaps which stage is evaluated
/// first in every cycle; `one_phase` commits the FIFO right after each stage's evaluation
/// instead of once at the edge (the discipline broken on purpose).
fn run_stages(seed: u64, cycles: u64, consumer_first: bool, one_phase: bool) -> StageTrace {
    let mut clock = Clock::new();
    let mut fifo: Fifo<u64> = Fifo::new(StageId(1), 3).expect("depth is valid");
    let mut prod = Producer { seq: 0, lfsr: seed };
    let mut cons = Consumer {
        busy: 0,
        count: 0,
        sum: 0,
        lfsr: seed ^ 1,
    };
    let mut trace = Vec::new();
    for _ in 0..cycles {
        let mut eval = |producer: bool, fifo: &mut Fifo<u64>| {
            if producer {
                prod.eval(fifo);
            } else {
                cons.eval(fifo);
            }
            if one_phase {
                fifo.commit();
            }
        };
        eval(!consumer_first, &mut fifo);
        eval(consumer_first, &mut fifo);
        if !one_phase {
            clock.edge(&mut [&mut fifo]).expect("edge");
        }
        trace.push((prod, cons, fifo.occupancy()));
    }
    (trace, fifo.stats().clone())
}

#[test]
fn stages_around_a_fifo_do_not_depend_on_evaluation_order() {
    let seed = seed("stages_around_a_fifo_do_not_depend_on_evaluation_order");
    let a = run_stages(seed, 100_000, false, false);
    let b = run_stages(seed, 100_000, true, false);
    assert!(a.1.pops > 10_000, "enough traffic: {:?}", a.1);
    assert!(a.1.full_cycles > 0 && a.1.starved_cycles > 0);
    assert_eq!(a, b);
    // The control: committing as each stage is evaluated makes the order visible, so the
    // equality above is a real check of the single commit point and not a property of the
    // stages.
    assert_ne!(
        run_stages(seed, 1000, false, true).0,
        run_stages(seed, 1000, true, true).0
    );
}

/// Runs `cycles` with the producer always valid and the consumer always ready.
fn saturated_throughput(depth: usize, cycles: u64) -> u64 {
    let mut clock = Clock::new();
    let mut fifo = Fifo::new(StageId(0), depth).expect("depth is valid");
    let mut seq = 0u64;
    for _ in 0..cycles {
        if fifo.try_push(Stamped::new(seq)).is_ok() {
            seq += 1;
        }
        let _ = fifo.try_pop().expect("one pop per cycle");
        clock.edge(&mut [&mut fifo]).expect("edge");
    }
    fifo.stats().pops
}

#[test]
fn handshake_corners_as_documented() {
    // Depth 1 alternates (full blocks the push even while popping); depth 2 streams.
    assert_eq!(saturated_throughput(1, 1000), 500);
    assert_eq!(saturated_throughput(2, 1000), 999);

    // Full, with a pop in the same cycle: the push is still refused.
    let mut clock = Clock::new();
    let mut fifo = Fifo::new(StageId(0), 1).expect("depth is valid");
    assert!(fifo.try_push(Stamped::new(1u8)).is_ok());
    clock.edge(&mut [&mut fifo]).expect("edge");
    let got = fifo.try_pop().expect("pop");
    assert_eq!(got.as_ref().map(|i| i.payload), Some(1));
    assert!(fifo.peek().is_none(), "the head has been handed over");
    assert!(
        fifo.valid() && !fifo.ready(),
        "registered flags hold until the edge"
    );
    let r = fifo
        .try_push(Stamped::new(2))
        .expect_err("full at start of cycle");
    assert_eq!((r.reason, r.item.payload), (Refusal::Full, 2));
    clock.edge(&mut [&mut fifo]).expect("edge");
    assert_eq!(fifo.occupancy(), 0);
    assert_eq!(fifo.stats().full_cycles, 1);

    // Empty, with a push in the same cycle: nothing falls through.
    assert!(fifo.try_push(Stamped::new(3)).is_ok());
    assert!(fifo.try_pop().expect("pop").is_none());
    assert_eq!(fifo.stats().starved_cycles, 1);
    clock.edge(&mut [&mut fifo]).expect("edge");
    assert_eq!(fifo.peek().map(|i| i.payload), Some(3));
    assert_eq!(fifo.stats().max_occupancy, 1);
    // Occupancy 0, 1, 0 in cycles 0, 1, 2.
    assert_eq!(fifo.stats().occupancy_histogram, vec![2, 1]);
}

#[test]
fn misuse_is_refused_without_panicking() {
    assert_eq!(
        Fifo::<u8>::new(StageId(0), 0).err(),
        Some(FifoError::ZeroDepth)
    );
    assert_eq!(
        Fifo::<u8>::new(StageId(0), MAX_DEPTH + 1).err(),
        Some(FifoError::TooDeep(MAX_DEPTH + 1))
    );

    let mut clock = Clock::new();
    let mut f: Fifo<u8> = Fifo::new(StageId(0), 4).expect("depth is valid");
    let mut g: Fifo<u8> = Fifo::new(StageId(1), 4).expect("depth is valid");
    // Two pushes in one cycle: the second comes back, unstamped.
    assert!(f.try_push(Stamped::new(1)).is_ok());
    let r = f.try_push(Stamped::new(2)).expect_err("second push");
    assert_eq!(r.reason, Refusal::AlreadyDriven);
    assert!(r.item.stamps().is_empty());
    // Two pops in one cycle.
    assert!(f.try_pop().expect("first pop").is_none());
    assert_eq!(
        f.try_pop().err(),
        Some(FifoError::PopSideDriven { cycle: 0 })
    );
    // A link onto a side already driven moves nothing.
    assert_eq!(
        forward(&mut f, &mut g).err(),
        Some(FifoError::PopSideDriven { cycle: 0 })
    );
    assert_eq!(f.stats().misuse, 3);
    clock.edge(&mut [&mut f, &mut g]).expect("edge");
    assert_eq!(forward(&mut f, &mut g), Ok(true));
    assert!(g.try_push(Stamped::new(9)).is_err());
    assert_eq!(g.stats().misuse, 1);

    // A part committed outside the edge: the edge is refused and nothing commits.
    g.commit();
    let before = (f.cycle(), f.stats().clone());
    assert_eq!(
        clock.edge(&mut [&mut f, &mut g]),
        Err(EdgeError {
            part: 1,
            cause: ClockError::OutOfStep { part: 2, clock: 1 }
        })
    );
    assert_eq!((f.cycle(), f.stats().clone()), before);
    assert_eq!(clock.now(), 1);
    assert_eq!(
        forward(&mut f, &mut g),
        Err(FifoError::OutOfStep { from: 1, to: 2 })
    );
}

#[test]
fn stamps_record_one_visit_at_a_time() {
    let (a, b) = (StageId(1), StageId(2));
    let mut t = Stamped::new("ray");
    assert_eq!(t.leave(a, 0), Err(StampError::NotInside(a)));
    t.enter(a, 3);
    assert_eq!(t.inside(), Some(a));
    assert_eq!(
        t.leave(a, 2),
        Err(StampError::LeftBeforeEntered {
            stage: a,
            entered: 3,
            left: 2
        })
    );
    assert_eq!(t.leave(b, 5), Err(StampError::NotInside(b)));
    assert_eq!(t.leave(a, 5), Ok(2));
    assert_eq!(t.leave(a, 6), Err(StampError::NotInside(a)), "left already");
    t.enter(b, 5);
    assert_eq!(t.check(), Ok(()));
    let t = t.map(str::len);
    assert_eq!(t.payload, 3);
    assert_eq!(t.latency_in(a), Some(2));
    assert_eq!(t.latency_in(b), None);

    // Entering a stage while still inside another is recorded, and `check` reports it.
    let mut u = Stamped::new(0u8);
    u.enter(a, 1);
    u.enter(b, 2);
    assert_eq!(
        u.check(),
        Err(StampError::Overlap {
            stage: b,
            entered: 2
        })
    );
}

/// An untracked transaction keeps only its latest visit but answers every question about that
/// visit as a tracked one does, and a FIFO counts the same latencies for both.
#[test]
fn untracked_stamps_keep_the_latest_visit() {
    let (a, b) = (StageId(1), StageId(2));
    let mut full = Stamped::new(7u32);
    let mut thin = Stamped::untracked(7u32);
    assert!(full.is_tracked() && !thin.is_tracked());
    assert_eq!(thin.leave(a, 0), Err(StampError::NotInside(a)));
    for t in [&mut full, &mut thin] {
        t.enter(a, 3);
        assert_eq!(t.inside(), Some(a));
        assert_eq!(
            t.leave(a, 2),
            Err(StampError::LeftBeforeEntered {
                stage: a,
                entered: 3,
                left: 2
            })
        );
        assert_eq!(t.leave(a, 5), Ok(2));
        assert_eq!(t.leave(a, 6), Err(StampError::NotInside(a)));
        t.enter(b, 5);
        assert_eq!(t.inside(), Some(b));
    }
    assert_eq!(full.stamps().len(), 2);
    assert!(thin.stamps().is_empty(), "no history kept");
    assert_eq!(thin.last(), full.last());
    assert_eq!(full.last(), Some(full.stamps()[1]));
    assert_eq!(thin.latency_in(b), None, "b is still open");
    assert_eq!(thin.leave(b, 9), Ok(4));
    assert_eq!(full.leave(b, 9), Ok(4));
    assert_eq!(thin.latency_in(b), full.latency_in(b));
    let thin = thin.map(|x| x + 1);
    assert_eq!((thin.payload, thin.is_tracked()), (8, false));
    assert_eq!(thin.check(), Ok(()));

    // Through a FIFO under random back-pressure, tracked and untracked items give the same
    // counters.
    let s = seed("untracked_stamps_keep_the_latest_visit");
    let run = |tracked: bool| {
        let mut clock = Clock::new();
        let mut f = Fifo::new(StageId(4), 3).unwrap();
        let mut rng = Rng::new(s);
        for cycle in 0..2000u64 {
            if rng.chance_percent(75) {
                let _ = f.try_push(Stamped::with_history(cycle, tracked));
            }
            if rng.chance_percent(25) {
                let _ = f.try_pop();
            }
            clock.edge(&mut [&mut f as &mut dyn Commit]).unwrap();
        }
        f.stats().clone()
    };
    let (x, y) = (run(true), run(false));
    assert!(x.latency_sum > 0);
    assert_eq!(x, y);
}
