//! The walker pool's unit tests: hand-timed walks on one walker (request ports).
//!
//! Pipeline position: tests of `walker_pool.rs` (the walker stage's pool).

use super::*;
use crate::cycle::memory::{MemoryLayout, NodeMemoryConfig, OnChipConfig};

/// On-chip reads of `latency` cycles through one bank of two ports: the memory itself
/// takes two reads a cycle, so only the walker's request ports can delay a read.
fn memory(latency: u32) -> NodeMemory {
    let cfg = NodeMemoryConfig {
        onchip: OnChipConfig {
            levels: crate::svo::MAX_DEPTH + 1,
            max_bytes: u64::MAX,
            latency,
            banks: 1,
            ports_per_bank: 2,
            combine: false,
        },
        ..NodeMemoryConfig::default()
    };
    let layout = MemoryLayout::with_onchip_ranges(16, 4, vec![(0, 16)]).expect("layout");
    NodeMemory::new(cfg, layout).expect("memory")
}

fn ops(v: &[WalkOp]) -> Vec<u64> {
    v.iter().map(|o| o.pack()).collect()
}

/// What [`two_walks`] saw: (tag, cycle) of each retirement, (cycle, reads sent) of each
/// cycle the walker sent, and the pool's counters.
struct Seen {
    retired: Vec<(u64, u64)>,
    sent: Vec<(u64, u32)>,
    cycles: PoolCycles,
}

/// Runs walks A (dispatched in cycle 0) and B (cycle 8) on one walker of two contexts,
/// the record stage always ready.
fn two_walks(read_ports: u32) -> Seen {
    let cfg = PoolConfig {
        walkers: 1,
        contexts_per_walker: 2,
        step_cycles: 1,
        step_latency_cycles: 3,
        read_ports,
        ..PoolConfig::default()
    };
    let mut pool = WalkerPoolModel::new(&cfg).expect("pool");
    let mut mem = memory(5);
    // A: root read, one slot, a child read. B: root read, one slot.
    let a = ops(&[
        WalkOp::Read(FetchKind::Node, 0),
        WalkOp::Issue(1),
        WalkOp::Read(FetchKind::Node, 1),
    ]);
    let b = ops(&[WalkOp::Read(FetchKind::Node, 2), WalkOp::Issue(1)]);
    let (mut retired, mut sent) = (Vec::new(), Vec::new());
    for now in 0..40 {
        pool.wake(now, &mut mem).expect("wake");
        if pool.walker_sent(0) > 0 {
            sent.push((now, pool.walker_sent(0)));
        }
        if let Some(tag) = pool.retire() {
            retired.push((tag, now));
        }
        match now {
            0 => assert!(pool.dispatch(0xA, &a)),
            8 => assert!(pool.dispatch(0xB, &b)),
            _ => {}
        }
        pool.issue();
    }
    Seen {
        retired,
        sent,
        cycles: pool.take_cycles(),
    }
}

/// Hand-timed, L = 5, step latency 3. A: root read in cycle 1 (the cycle after its
/// dispatch), data in 6, its slot issues in 6, the child read in 9, data and done in 14.
/// B, dispatched in 8, sends its root read in 9 too. Unlimited ports: both in 9, B's data
/// in 14, its slot in 14, done in 17. One port: A's read was scheduled first (its slot
/// issued in 6, B's dispatch came in 8), so A sends in 9 and B waits one cycle: sent in
/// 10, data in 15, done in 18; one context-cycle of `read_port_waits`.
#[test]
fn two_reads_of_one_walker_in_one_cycle() {
    let s = two_walks(0);
    assert_eq!(s.retired, vec![(0xA, 14), (0xB, 17)]);
    assert_eq!(s.sent, vec![(1, 1), (9, 2)]);
    assert_eq!((s.cycles.reads, s.cycles.read_port_waits), (3, 0));
    let s = two_walks(1);
    assert_eq!(s.retired, vec![(0xA, 14), (0xB, 18)]);
    assert_eq!(s.sent, vec![(1, 1), (9, 1), (10, 1)]);
    assert_eq!((s.cycles.reads, s.cycles.read_port_waits), (3, 1));
    // Two ports on two contexts: nothing waits, as with unlimited ports.
    let s = two_walks(2);
    assert_eq!(s.retired, vec![(0xA, 14), (0xB, 17)]);
    assert_eq!(s.sent, vec![(1, 1), (9, 2)]);
    assert_eq!(s.cycles.read_port_waits, 0);
}
