//! The block-RAM model: READ_FIRST read-during-write, the port limit per cycle, collision
//! counting, order independence within a cycle, and a long seeded random run against a
//! reference model written here (a plain array whose writes are applied at the edge).

mod common;

use common::Rng;
use rtl_model::cycle::bram::{Bram, BramError, DirtyRegisters};
use rtl_model::cycle::clocked::Clock;

#[test]
fn read_first_returns_the_old_value_until_the_edge() {
    let mut clock = Clock::new();
    let mut m = Bram::new(16, 2, 0u32).unwrap();
    m.write(3, 7).unwrap();
    assert_eq!(m.read(3).unwrap(), 0, "same cycle: old data");
    clock.edge(&mut [&mut m]).unwrap();
    assert_eq!(m.read(3).unwrap(), 7, "after the edge: new data");
    assert_eq!(m.stats().read_write_collisions, 1);
}

#[test]
fn ports_limit_accesses_per_cycle() {
    let mut clock = Clock::new();
    let mut m = Bram::new(8, 2, 0u8).unwrap();
    m.read(0).unwrap();
    m.write(1, 5).unwrap();
    assert_eq!(m.read(2), Err(BramError::PortsBusy { ports: 2, cycle: 0 }));
    assert_eq!(m.stats().port_conflicts, 1);
    clock.edge(&mut [&mut m]).unwrap();
    assert_eq!(m.free_ports(), 2);
    assert_eq!(m.read(1).unwrap(), 5);
    assert_eq!(m.stats().full_cycles, 1);
}

#[test]
fn refusals_never_panic() {
    let mut m = Bram::new(4, 2, 0i64).unwrap();
    assert!(matches!(m.read(4), Err(BramError::Address { .. })));
    m.write(1, 1).unwrap();
    assert!(matches!(
        m.write(1, 2),
        Err(BramError::WriteCollision { .. })
    ));
    assert!(Bram::new(0, 1, 0u8).is_err());
    assert!(Bram::new(1, 0, 0u8).is_err());
    assert_eq!(m.stats().errors, 2);
}

#[test]
fn order_within_a_cycle_does_not_matter() {
    let run = |write_first: bool| {
        let mut clock = Clock::new();
        let mut m = Bram::new(4, 2, 10u32).unwrap();
        let mut seen = Vec::new();
        for c in 0..50u32 {
            let addr = (c % 4) as usize;
            if write_first {
                m.write(addr, c).unwrap();
                seen.push(m.read(addr).unwrap());
            } else {
                seen.push(m.read(addr).unwrap());
                m.write(addr, c).unwrap();
            }
            clock.edge(&mut [&mut m]).unwrap();
        }
        seen
    };
    assert_eq!(run(true), run(false));
}

#[test]
fn random_accesses_match_a_reference_model() {
    let seed = common::seed(0xb7a3_0001);
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    let depth = 64;
    let ports = 2u8;
    let mut clock = Clock::new();
    let mut m = Bram::new(depth, ports, 0u64).unwrap();
    let mut model = vec![0u64; depth];
    let (mut reads, mut writes, mut refused) = (0u64, 0u64, 0u64);
    for cycle in 0..200_000u64 {
        let mut pending: Vec<(usize, u64)> = Vec::new();
        let mut used = 0u8;
        for _ in 0..rng.below(4) {
            let addr = rng.below(depth as u64) as usize;
            if rng.below(2) == 0 {
                let r = m.read(addr);
                if used < ports {
                    used += 1;
                    reads += 1;
                    assert_eq!(r, Ok(model[addr]), "seed {seed} cycle {cycle}");
                } else {
                    refused += 1;
                    assert!(r.is_err());
                }
            } else {
                let v = rng.next();
                let r = m.write(addr, v);
                if pending.iter().any(|&(a, _)| a == addr) {
                    assert!(
                        matches!(r, Err(BramError::WriteCollision { .. })),
                        "seed {seed} cycle {cycle}"
                    );
                } else if used < ports {
                    used += 1;
                    writes += 1;
                    assert_eq!(r, Ok(()));
                    pending.push((addr, v));
                } else {
                    refused += 1;
                    assert!(r.is_err());
                }
            }
        }
        clock.edge(&mut [&mut m]).unwrap();
        for (a, v) in pending {
            model[a] = v;
        }
    }
    let st = m.stats();
    assert_eq!(
        (st.reads, st.writes, st.port_conflicts),
        (reads, writes, refused)
    );
    assert_eq!(st.cycles, 200_000);
    for (a, v) in model.iter().enumerate() {
        assert_eq!(m.peek(a), Some(v));
    }
    println!(
        "{reads} reads, {writes} writes, {refused} refused, {} collisions",
        st.read_write_collisions
    );
}

#[test]
fn dirty_flags_take_effect_at_the_edge() {
    let mut clock = Clock::new();
    let mut d = DirtyRegisters::new(2);
    assert!(d.camera() && d.instance(0) && d.instance(1) && d.instance(7));
    d.load(false, vec![false, true]);
    assert!(d.camera(), "not before the edge");
    clock.edge(&mut [&mut d]).unwrap();
    assert!(!d.camera() && !d.instance(0) && d.instance(1));
    assert!(d.instance(5), "an unknown instance reads as dirty");
}
