//! Unit tests of the FIFO's driver forms and its back-pressure count (`super`, `fifo.rs`):
//! seeded random streams against the handshake's own forms.

use super::*;
use crate::cycle::test_rng::TestRng as Rng;

/// The driver's forms (`push_driven`, `pop_driven`) against the handshake's own
/// (`try_push`, `try_pop`) on one seeded random stream of pushes and pops, wide and
/// narrow, full and empty: the same items out in the same order, and the same counters
/// after every edge.
#[test]
fn driven_forms_match_try_forms() {
    let seed = 0x5eed_f030u64;
    println!("seed {seed:#x}");
    let mut rng = Rng::new(seed);
    for case in 0..30 {
        let depth = 1 + rng.below(6) as usize;
        let ports = 1 + rng.below(3) as usize;
        let mut a = Fifo::new_wide(StageId(7), depth, ports).expect("depth in range");
        let mut b = Fifo::new_wide(StageId(7), depth, ports).expect("depth in range");
        let mut got_a = Vec::new();
        let mut next = 0u32;
        for cycle in 0..500 {
            // Up to one more push and pop than the ports: refusals and misuse included.
            for _ in 0..rng.below(ports as u64 + 2) {
                got_a.push(a.try_pop().ok().flatten().map(|s| s.payload));
                let left = b.pop_driven().unwrap_or(false);
                assert_eq!(
                    left,
                    got_a.last().is_some_and(Option::is_some),
                    "case {case} cycle {cycle}: pop"
                );
            }
            for _ in 0..rng.below(ports as u64 + 2) {
                let ra = a.try_push(Stamped::untracked(next)).map_err(|r| r.reason);
                let rb = b.push_driven(Stamped::untracked(next));
                assert_eq!(ra, rb, "case {case} cycle {cycle}: push");
                next += 1;
            }
            assert_eq!(a.stats(), b.stats(), "case {case} cycle {cycle}");
            a.commit();
            b.commit();
            let heads: Vec<u32> = (0..a.occupancy())
                .filter_map(|i| a.registered(i).map(|s| s.payload))
                .collect();
            let heads_b: Vec<u32> = (0..b.occupancy())
                .filter_map(|i| b.registered(i).map(|s| s.payload))
                .collect();
            assert_eq!(heads, heads_b, "case {case} cycle {cycle}: contents");
        }
        assert!(
            got_a.iter().flatten().count() > 0,
            "case {case} moved nothing"
        );
    }
}

/// `note_full` counts as a refused offer would: a driver that offers only what the FIFO
/// takes and reports a held item (`note_full`, only when no room is left)
/// against one that offers everything with `try_push`, on a seeded random stream — the
/// same counters after every edge, and `skip_idle` after a cycle in which only a held
/// item was reported (neither side driven) credits the full cycles too.
#[test]
fn note_full_counts_as_a_refused_offer() {
    let seed = 0x5eed_f031u64;
    println!("seed {seed:#x}");
    let mut rng = Rng::new(seed);
    for case in 0..30 {
        let depth = 1 + rng.below(6) as usize;
        let ports = 1 + rng.below(3) as usize;
        let mut a = Fifo::new_wide(StageId(7), depth, ports).expect("depth in range");
        let mut b = Fifo::new_wide(StageId(7), depth, ports).expect("depth in range");
        let mut next = 0u32;
        let mut full_seen = false;
        for cycle in 0..500 {
            // Pops rarer than offers: the FIFO is often full.
            for _ in 0..rng.below(ports as u64 + 1) / 2 + rng.below(2) {
                if a.pops_now < ports {
                    let _ = a.try_pop();
                    let _ = b.pop_driven();
                }
            }
            let offers = rng.below(ports as u64 + 1) as usize;
            for _ in 0..offers.min(ports) {
                let _ = a.try_push(Stamped::untracked(next));
                next += 1;
            }
            let mut pushed = 0;
            while pushed < offers && b.can_push() {
                b.push_driven(Stamped::untracked(0))
                    .expect("can_push said yes");
                pushed += 1;
            }
            // `offers` ≤ `ports`: a held item here found no room, never only no port.
            if pushed < offers {
                b.note_full().expect("no room left");
            }
            let (sa, sb) = (a.stats(), b.stats());
            assert_eq!(sa.full_cycles, sb.full_cycles, "case {case} cycle {cycle}");
            assert_eq!(sa.pushes, sb.pushes, "case {case} cycle {cycle}: pushes");
            full_seen |= sa.full_cycles > 0;
            a.commit();
            b.commit();
        }
        assert!(full_seen, "case {case} never full");
    }
    // A full FIFO whose consumer is stalled and whose producer holds an item: only
    // `note_full` drives it, and the idle skip repeats that cycle.
    let mut f = Fifo::new(StageId(7), 1).expect("depth 1");
    assert_eq!(f.note_full(), Err(FifoError::NotFull { cycle: 0, room: 1 }));
    assert_eq!(f.stats().full_cycles, 0, "a refused note counts nothing");
    f.push_driven(Stamped::untracked(1u32)).expect("room");
    f.commit();
    f.note_full().expect("full");
    f.note_full().expect("full");
    f.commit();
    assert_eq!(f.stats().full_cycles, 1, "once a cycle");
    f.skip_idle(5);
    assert_eq!(f.stats().full_cycles, 6, "skip_idle repeats the held cycle");
}
