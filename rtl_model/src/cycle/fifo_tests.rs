//! Unit tests of the FIFO's driver forms, its batch drive and its back-pressure count
//! (`super`, `fifo.rs`): seeded random streams against the handshake's own forms.

use super::*;
use crate::cycle::clocked::StageStamp;
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

/// `drive_batch` (the commit's one call per FIFO and cycle) against the same pops and
/// pushes driven one by one (`pop_driven`, `push_driven`) on a seeded random stream, with
/// more asked of each side than its ports or contents allow in some cycles: a batch that
/// would not fire must leave the FIFO untouched, and then the one-by-one calls (what the
/// commit falls back to) count and refuse as usual. The same counters, contents and stamps
/// after every edge; both paths taken.
#[test]
fn drive_batch_matches_one_by_one() {
    let seed = 0x5eed_f032u64;
    println!("seed {seed:#x}");
    let mut rng = Rng::new(seed);
    let (mut batched, mut fell_back) = (0u32, 0u32);
    for case in 0..30 {
        let depth = 1 + rng.below(6) as usize;
        let ports = 1 + rng.below(3) as usize;
        let tracked = case % 2 == 0;
        let mut a = Fifo::new_wide(StageId(7), depth, ports).expect("depth in range");
        let mut b = Fifo::new_wide(StageId(7), depth, ports).expect("depth in range");
        let mut next = 0u32;
        let mut pushes = Vec::new();
        for cycle in 0..500 {
            let pops = rng.below(ports as u64 + 2) as usize;
            let n = rng.below(ports as u64 + 2) as u32;
            let items = (next..next + n).map(|p| Stamped::with_history(p, tracked));
            pushes.extend(items.clone());
            if a.drive_batch(pops, &mut pushes) {
                batched += 1;
            } else {
                fell_back += 1;
                assert_eq!(pushes.len(), n as usize, "case {case} cycle {cycle}: kept");
                for _ in 0..pops {
                    let _ = a.pop_driven();
                }
                for item in pushes.drain(..) {
                    let _ = a.push_driven(item);
                }
            }
            for _ in 0..pops {
                let _ = b.pop_driven();
            }
            for item in items {
                let _ = b.push_driven(item);
            }
            next += n;
            assert_eq!(a.stats(), b.stats(), "case {case} cycle {cycle}");
            a.commit();
            b.commit();
            let contents = |f: &Fifo<u32>| -> Vec<(u32, Vec<StageStamp>)> {
                (0..f.occupancy())
                    .filter_map(|i| f.registered(i).map(|s| (s.payload, s.stamps().to_vec())))
                    .collect()
            };
            assert_eq!(contents(&a), contents(&b), "case {case} cycle {cycle}");
        }
    }
    assert!(
        batched > 0 && fell_back > 0,
        "{batched} batched, {fell_back} fell back"
    );
}
