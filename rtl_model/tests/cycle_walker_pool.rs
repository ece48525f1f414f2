//! The walker pool's per-cycle classification of every walker (issuing, waiting on memory,
//! waiting on its step latency, back-pressured, empty) against a recount from each walker's
//! context counts, cycle by cycle, under random walks, memory and record-stage back-pressure;
//! and the dispatcher's choice (most free contexts, lowest index on ties) against a scan of
//! all walkers. The pool keeps both incrementally; this test recounts them from scratch.
//! With random request ports per walker (`read_ports`, issue 29) it also checks, every cycle,
//! that no walker sends more reads than it has ports, that a walker with reads still queued
//! used every port (the queue never waits behind an idle port), and that the pool's
//! `read_port_waits` grows by the reads left queued.

mod common;

use common::{seed, Rng};
use rtl_model::cycle::hw_config::WalkerPool as PoolConfig;
use rtl_model::cycle::memory::{FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig};
use rtl_model::cycle::walk_op::WalkOp;
use rtl_model::cycle::walker_pool::{PoolCycles, WalkerPoolModel};

/// The walker's class from its counts, as the pool's documentation defines it.
fn recount(pool: &WalkerPoolModel, walkers: usize) -> PoolCycles {
    let mut c = PoolCycles::default();
    for w in 0..walkers {
        let (busy, waiting, finished) = (
            pool.walker_busy(w),
            pool.walker_waiting(w),
            pool.walker_finished(w),
        );
        if pool.walker_issued(w) {
            c.issuing += 1;
        } else if busy == 0 {
            c.empty += 1;
        } else if waiting > 0 {
            c.memory_wait += 1;
        } else if finished == busy {
            c.backpressured += 1;
        } else {
            c.latency_wait += 1;
        }
    }
    c
}

fn random_walk(rng: &mut Rng) -> Vec<u64> {
    let mut ops = vec![WalkOp::Read(FetchKind::Node, rng.below(4096) as u32).pack()];
    for _ in 0..rng.below(6) {
        ops.push(WalkOp::Issue(1 + rng.below(5) as u32).pack());
        if rng.below(3) > 0 {
            // Half on chip (the first 1,024 words), half through the cache or DRAM.
            let kind = if rng.below(8) == 0 {
                FetchKind::Attr
            } else {
                FetchKind::Node
            };
            ops.push(
                WalkOp::Read(
                    kind,
                    rng.below(if kind == FetchKind::Attr { 512 } else { 4096 }) as u32,
                )
                .pack(),
            );
        }
    }
    ops
}

#[test]
fn classification_matches_a_recount_every_cycle() {
    let s = seed(0x5eed_9001);
    println!("seed {s} (SVO_TEST_SEED={s} replays it)");
    let mut rng = Rng::new(s);
    let mut port_waits = 0u64;
    for case in 0..12 {
        let cfg = PoolConfig {
            walkers: 1 + rng.below(70) as u32,
            contexts_per_walker: 1 + rng.below(8) as u32,
            step_cycles: 1 + rng.below(2) as u32,
            step_latency_cycles: 1 + rng.below(4) as u32,
            read_ports: rng.below(3) as u32,
            ..PoolConfig::default()
        };
        let ports = if cfg.read_ports == 0 {
            u32::MAX
        } else {
            cfg.read_ports
        };
        let walkers = cfg.walkers as usize;
        let layout = MemoryLayout::with_onchip_ranges(4096, 512, vec![(0, 1024)]).expect("layout");
        let mut mem = NodeMemory::new(NodeMemoryConfig::default(), layout).expect("memory");
        let mut pool = WalkerPoolModel::new(&cfg).expect("pool");
        let mut to_dispatch = 400u32;
        let mut retired = 0u32;
        let mut now = 0u64;
        while retired < 400 {
            let waits_before = pool.cycles().read_port_waits;
            pool.wake(now, &mut mem).expect("wake");
            let mut queued = 0u64;
            for w in 0..walkers {
                let (sent, q) = (pool.walker_sent(w), pool.walker_queued(w));
                let at = format!("seed {s}, case {case} ({cfg:?}), cycle {now}, walker {w}");
                assert!(sent <= ports, "{at}: {sent} reads sent");
                assert!(q == 0 || sent == ports, "{at}: {q} queued, {sent} sent");
                assert!(q <= pool.walker_waiting(w), "{at}: queued beyond waiting");
                queued += u64::from(q);
            }
            assert_eq!(
                pool.cycles().read_port_waits - waits_before,
                queued,
                "seed {s}, case {case}, cycle {now}: read_port_waits"
            );
            // The record stage takes a walk in about two cycles of three.
            if rng.below(3) > 0 && pool.retire().is_some() {
                retired += 1;
            }
            if to_dispatch > 0 && rng.below(4) > 0 {
                let ops = random_walk(&mut rng);
                let busy: Vec<u32> = (0..walkers).map(|w| pool.walker_busy(w)).collect();
                if pool.dispatch(u64::from(to_dispatch), &ops) {
                    to_dispatch -= 1;
                    // The walker with the most free contexts took it, the lowest on ties.
                    let least = busy.iter().min().copied().unwrap_or(0);
                    let want = busy.iter().position(|&b| b == least);
                    let got = (0..walkers).find(|&w| pool.walker_busy(w) != busy[w]);
                    assert_eq!(got, want, "seed {s}, case {case}, cycle {now}: dispatch");
                }
            }
            let before = *pool.cycles();
            pool.issue();
            let after = *pool.cycles();
            let want = recount(&pool, walkers);
            let got = PoolCycles {
                issuing: after.issuing - before.issuing,
                memory_wait: after.memory_wait - before.memory_wait,
                latency_wait: after.latency_wait - before.latency_wait,
                backpressured: after.backpressured - before.backpressured,
                empty: after.empty - before.empty,
                ..PoolCycles::default()
            };
            assert_eq!(got, want, "seed {s}, case {case} ({cfg:?}), cycle {now}");
            assert_eq!(u64::from(pool.issued_count()), want.issuing);
            now += 1;
            assert!(now < 1_000_000, "seed {s}, case {case}: no progress");
        }
        port_waits += pool.cycles().read_port_waits;
    }
    // The generator must make reads wait for a port, or the port checks say nothing.
    assert!(port_waits > 0, "seed {s}: no read ever waited for a port");
}
