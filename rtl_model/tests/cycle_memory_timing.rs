//! Node-memory model (`rtl_model::cycle::memory`) against checks that share no code with it:
//! when reads complete.
//!
//! - Exact latencies of isolated reads (on chip, hit, cold miss with and without a line that
//!   is a multiple of the bus width, merged misses, uncached attributes).
//! - Port conflicts, the MSHR limit, the per-cycle byte budget and saturation of a streaming
//!   pattern.
//! - On-chip banks against a cycle-by-cycle queue oracle, with the statistics window split and
//!   ticks skipping cycles.
//!
//! What the memories hold is in `cycle_memory_contents.rs`, random stress, determinism and
//! refusals in `cycle_memory_stress.rs`. Run with `-- --nocapture` to see seeds;
//! `SVO_TEST_SEED` replays.

mod common;
mod memory_common;
use common::Rng;
use memory_common::{config, max_in_flight, one, seed};
use std::collections::{BTreeMap, HashMap};

use rtl_model::cycle::memory::{
    Completion, FetchKind, MemoryLayout, NodeMemory, RequestId, Source,
};

// ---------------------------------------------------------------------------------------
// Exact latencies.

#[test]
fn isolated_reads_take_exactly_their_latency() {
    for &(onchip_lat, hit_lat, dram_lat, bpc, line) in &[
        (3u32, 4u32, 60u32, 64u32, 64u32),
        (1, 1, 1, 1, 8),
        (2, 5, 30, 24, 64), // a line is not a multiple of the bus: ⌈64/24⌉ = 3 beats
        (4, 2, 100, 16, 128), // 8 beats
    ] {
        let mut cfg = config(
            onchip_lat, 1, 2, 8192, 4, line, hit_lat, 2, dram_lat, bpc, 8,
        );
        cfg.cache.attr_cached = true;
        let layout = MemoryLayout::with_onchip_ranges(1 << 20, 1 << 13, vec![(0, 100)]).unwrap();
        let mut mem = NodeMemory::new(cfg, layout).unwrap();
        let beats = u64::from(line.div_ceil(bpc));
        let c = one(&mut mem, 10, 50, FetchKind::Node);
        assert_eq!(
            (c.source, c.cycle_done),
            (Source::OnChip { bank: 0 }, 10 + u64::from(onchip_lat))
        );
        let t = mem.now() + 7;
        let c = one(&mut mem, t, 5000, FetchKind::Node);
        assert_eq!(c.source, Source::Miss);
        assert_eq!(c.cycle_done, t + u64::from(dram_lat) + beats, "cold miss");
        let t = mem.now() + 3;
        let c = one(&mut mem, t, 5001, FetchKind::Far); // same line
        assert_eq!(
            (c.source, c.cycle_done),
            (Source::CacheHit, t + u64::from(hit_lat))
        );
        // Regions are separate: record 2500 sits at the same byte offset in the attribute
        // array as node word 5000 (cached above) in node memory, yet it misses.
        let t = mem.now();
        let c = one(&mut mem, t, 2500, FetchKind::Attr);
        assert_eq!(
            (c.source, c.cycle_done),
            (Source::Miss, t + u64::from(dram_lat) + beats)
        );
        let t = mem.now();
        let c = one(&mut mem, t, 2501, FetchKind::Attr);
        let same_line = (8 * 2500) / line == (8 * 2501) / line;
        assert_eq!(c.source == Source::CacheHit, same_line);
    }
}

#[test]
fn misses_to_one_line_merge_and_complete_together() {
    let cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 60, 64, 4);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 20, 16).unwrap()).unwrap();
    let a = mem.request(0, 1600, FetchKind::Node, 3).unwrap(); // line 100
    let b = mem.request(0, 1601, FetchKind::Node, 1).unwrap(); // same line, same cycle
    let c = mem.request(5, 1615, FetchKind::Far, 2).unwrap(); // same line, later
    let d = mem.request(61, 1602, FetchKind::Node, 0).unwrap(); // the fill completes at 61
    let done: HashMap<RequestId, Completion> = mem.drain().into_iter().map(|c| (c.id, c)).collect();
    assert_eq!(done.len(), 4);
    // Requester 1 is served first in cycle 0, so it issues the fill.
    assert_eq!((done[&b].source, done[&b].cycle_done), (Source::Miss, 61));
    assert_eq!((done[&a].source, done[&a].cycle_done), (Source::Merged, 61));
    assert_eq!((done[&c].source, done[&c].cycle_done), (Source::Merged, 61));
    assert_eq!(
        (done[&d].source, done[&d].cycle_done),
        (Source::CacheHit, 65)
    );
    let s = mem.stats();
    assert_eq!(
        (s.cache_misses, s.cache_merged, s.cache_hits, s.dram_fills),
        (1, 2, 1, 1)
    );
    assert_eq!(s.dram_bytes, 64);
}

#[test]
fn uncached_attributes_bypass_the_cache() {
    let mut cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 20, 64, 4);
    cfg.cache.attr_cached = false;
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1024, 1024).unwrap()).unwrap();
    let c1 = one(&mut mem, 0, 9, FetchKind::Attr);
    let t = mem.now();
    let c2 = one(&mut mem, t, 9, FetchKind::Attr);
    assert_eq!((c1.source, c2.source), (Source::Miss, Source::Miss));
    let s = mem.stats();
    assert_eq!((s.uncached_reads, s.cache_lookups, s.dram_fills), (2, 0, 2));
}

// ---------------------------------------------------------------------------------------
// Ports, MSHRs, bandwidth.

#[test]
fn three_reads_on_a_dual_port_bram_one_waits() {
    let cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 60, 64, 4);
    let layout = MemoryLayout::with_onchip_ranges(1 << 16, 16, vec![(0, 4096)]).unwrap();
    let mut mem = NodeMemory::new(cfg, layout).unwrap();
    // Made in the order 2, 0, 1: served by requester id.
    let r2 = mem.request(5, 30, FetchKind::Node, 2).unwrap();
    let r0 = mem.request(5, 10, FetchKind::Node, 0).unwrap();
    let r1 = mem.request(5, 20, FetchKind::Far, 1).unwrap();
    let mut at7 = Vec::new();
    mem.tick_into(7, &mut at7);
    assert!(at7.is_empty());
    let mut at8 = Vec::new();
    mem.tick_into(8, &mut at8);
    assert_eq!(at8.iter().map(|c| c.id).collect::<Vec<_>>(), vec![r0, r1]);
    let mut at9 = Vec::new();
    mem.tick_into(9, &mut at9);
    assert_eq!(at9.len(), 1);
    assert_eq!(
        (at9[0].id, at9[0].cycle_served, at9[0].cycle_done),
        (r2, 6, 9)
    );
    let s = mem.stats();
    assert_eq!(
        (s.port_wait, s.port_conflict_cycles, s.onchip_reads),
        (1, 1, 3)
    );

    // Banks: with two banks, words 0 and 2 share bank 0 (one port each here), word 1 does not.
    let cfg = config(3, 2, 1, 8192, 4, 64, 4, 2, 60, 64, 4);
    let layout = MemoryLayout::with_onchip_ranges(1 << 16, 16, vec![(0, 4096)]).unwrap();
    let mut mem = NodeMemory::new(cfg, layout).unwrap();
    for (req, addr) in [(0u32, 0u32), (1, 1), (2, 2)] {
        mem.request(0, addr, FetchKind::Node, req).unwrap();
    }
    let done: Vec<(u32, u64)> = mem.drain().iter().map(|c| (c.addr, c.cycle_done)).collect();
    assert_eq!(done, vec![(0, 3), (1, 3), (2, 4)]);

    // The cache has its own lookup ports: three hits to a 2-port cache, one waits.
    let cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 10, 64, 4);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 16, 16).unwrap()).unwrap();
    one(&mut mem, 0, 100, FetchKind::Node);
    let t = mem.now();
    for r in 0..3 {
        mem.request(t, 100 + r, FetchKind::Node, r).unwrap();
    }
    let done: Vec<u64> = mem.drain().iter().map(|c| c.cycle_done - t).collect();
    assert_eq!(done, vec![4, 4, 5]);
}

#[test]
fn more_misses_than_mshrs_stall_and_none_is_lost() {
    let cfg = config(3, 1, 2, 1 << 16, 4, 64, 4, 2, 10, 64, 2);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 20, 16).unwrap()).unwrap();
    // Ten different lines in one cycle, two MSHRs.
    let ids: Vec<RequestId> = (0..10)
        .map(|i| mem.request(0, i * 16, FetchKind::Node, i).unwrap())
        .collect();
    let done = mem.drain();
    let got: Vec<RequestId> = {
        let mut v: Vec<RequestId> = done.iter().map(|c| c.id).collect();
        v.sort();
        v
    };
    assert_eq!(got, ids, "every request completes exactly once");
    // Pairs: fills of (0, 1) complete at 11 and 12; the third is served at 11, and so on.
    let by_req: BTreeMap<u32, &Completion> = done.iter().map(|c| (c.requester, c)).collect();
    assert_eq!((by_req[&0].cycle_served, by_req[&0].cycle_done), (0, 11));
    assert_eq!((by_req[&1].cycle_served, by_req[&1].cycle_done), (0, 12));
    assert_eq!((by_req[&2].cycle_served, by_req[&2].cycle_done), (11, 22));
    assert_eq!((by_req[&3].cycle_served, by_req[&3].cycle_done), (12, 23));
    assert_eq!(max_in_flight(&done), 2);
    let s = mem.stats();
    println!("{s:?}");
    assert_eq!(s.mshr_max_in_use, 2);
    assert_eq!(s.cache_misses, 10);
    // From cycle 1 the pipeline is blocked until the last read gets its MSHR in cycle 45
    // (cycle 0 ran out of lookup ports instead).
    assert_eq!(s.mshr_full_cycles, 44);
    assert_eq!(s.port_wait, 8);
    assert!(s.mshr_wait > s.mshr_full_cycles);
    let waited: u64 = done
        .iter()
        .map(|c| c.cycle_served - c.cycle_requested)
        .sum();
    assert_eq!(waited, s.mshr_wait + s.port_wait);
}

#[test]
fn dram_never_exceeds_its_byte_budget_and_saturates_when_streaming() {
    // Budget: 24 B/cycle with 64-byte lines (fills share cycles), lots of MSHRs.
    for &(bpc, line) in &[(24u32, 64u32), (64, 64), (16, 128), (100, 32)] {
        let cfg = config(3, 1, 2, 1 << 16, 4, line, 4, 2, 40, bpc, 256);
        let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 24, 16).unwrap()).unwrap();
        let words = u64::from(line / 4);
        for i in 0..3000u64 {
            mem.request(i / 2, (i * words) as u32, FetchKind::Node, (i % 2) as u32)
                .unwrap();
        }
        let done = mem.drain();
        let s = mem.stats();
        assert!(s.dram_max_bytes_in_cycle <= u64::from(bpc));
        assert!(s.dram_bytes <= s.window_cycles * u64::from(bpc));
        assert_eq!(s.dram_bytes, 3000 * u64::from(line));
        // Independently: the n-th fill cannot finish before n lines fit through the bus after
        // the first data could arrive.
        let mut dones: Vec<u64> = done.iter().map(|c| c.cycle_done).collect();
        dones.sort();
        for (n, &d) in dones.iter().enumerate() {
            let bytes = (n as u64 + 1) * u64::from(line);
            assert!(d >= 40 + bytes.div_ceil(u64::from(bpc)), "fill {n} at {d}");
        }
        println!(
            "bus {bpc} B/cycle, line {line}: {:.1} % of peak, busy {:.1} %",
            s.dram_bandwidth_pct(),
            s.dram_busy_pct()
        );
    }

    // Saturation: one new line per cycle at 64 B/cycle, more MSHRs than latency × rate.
    let cfg = config(3, 1, 2, 1 << 16, 4, 64, 4, 2, 60, 64, 128);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 24, 16).unwrap()).unwrap();
    for i in 0..4096u32 {
        mem.request(u64::from(i), i * 16, FetchKind::Node, 0)
            .unwrap();
    }
    mem.drain();
    let s = mem.stats();
    println!(
        "streaming: {:.2} % of peak over {} cycles",
        s.dram_bandwidth_pct(),
        s.window_cycles
    );
    assert!(s.dram_bandwidth_pct() > 95.0);
    assert!(s.dram_bandwidth_pct() <= 100.0);

    // Little's law: 16 MSHRs over 60 + 1 cycles carry at most 16 lines per 61 cycles.
    let cfg = config(3, 1, 2, 1 << 16, 4, 64, 4, 2, 60, 64, 16);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 24, 16).unwrap()).unwrap();
    for i in 0..4096u32 {
        mem.request(u64::from(i), i * 16, FetchKind::Node, 0)
            .unwrap();
    }
    mem.drain();
    let pct = mem.stats().dram_bandwidth_pct();
    println!(
        "16 MSHRs: {pct:.2} % of peak (bound {:.2} %)",
        100.0 * 16.0 / 61.0
    );
    assert!(pct <= 100.0 * 16.0 / 61.0 + 0.5 && pct > 20.0);
}

// ---------------------------------------------------------------------------------------
// On-chip banks against an oracle.

/// On-chip banks against a cycle-by-cycle oracle: per bank a queue served `ports` reads per
/// cycle in (cycle, requester, id) order. Checks every read's service cycle, and the port-wait
/// and port-conflict counts, also when the statistics window is split at random cycles and
/// when ticks skip many cycles.
#[test]
fn onchip_banks_agree_with_a_per_cycle_queue_oracle() {
    let s = seed(
        "onchip_banks_agree_with_a_per_cycle_queue_oracle",
        0xba4c_5107,
    );
    let mut rng = Rng::new(s);
    for case in 0..40 {
        let banks = 1 + rng.below(6) as u32;
        let ports = 1 + rng.below(2) as u32;
        let latency = 1 + rng.below(5) as u32;
        let cfg = config(latency, banks, ports, 8192, 4, 64, 4, 2, 60, 64, 4);
        let layout = MemoryLayout::with_onchip_ranges(1 << 12, 16, vec![(0, 1 << 12)]).unwrap();
        let mut mem = NodeMemory::new(cfg, layout).unwrap();
        // Bursts (hot banks, long queues) and quiet stretches (skipped cycles).
        let mut reqs: Vec<(u64, u32, u32, u64)> = Vec::new(); // (cycle, requester, addr, id)
        let mut cycle = 0u64;
        for _ in 0..60 {
            cycle += if rng.below(4) == 0 {
                5 + rng.below(40)
            } else {
                rng.below(2)
            };
            let hot = rng.below(u64::from(banks)) as u32;
            let mut requesters: Vec<u32> = (0..16).collect();
            for _ in 0..rng.below(7) {
                let k = rng.below(requesters.len() as u64) as usize;
                let requester = requesters.swap_remove(k);
                let addr = if rng.below(2) == 0 {
                    hot + banks * rng.below(50) as u32
                } else {
                    rng.below(1 << 12) as u32
                };
                reqs.push((cycle, requester, addr, 0));
            }
        }
        // Make them in cycle order, ticking now and then, and split the statistics window.
        let mut windows = Vec::new();
        let mut done: Vec<Completion> = Vec::new();
        for r in reqs.iter_mut() {
            if r.0 > mem.now() && rng.below(3) == 0 {
                mem.tick_into(r.0, &mut done);
                if rng.below(3) == 0 {
                    windows.push(mem.reset_stats());
                }
            }
            r.3 = mem.request(r.0, r.2, FetchKind::Node, r.1).unwrap().0;
        }
        done.extend(mem.drain());
        windows.push(mem.stats());

        // The oracle.
        let mut order = reqs.clone();
        order.sort_by_key(|&(c, req, _, id)| (c, req, id));
        let mut queues: Vec<std::collections::VecDeque<(u64, u64)>> =
            vec![Default::default(); banks as usize]; // (id, request cycle)
        let mut served: HashMap<u64, u64> = HashMap::new();
        let (mut wait, mut conflicts) = (0u64, 0u64);
        let mut next = 0;
        let mut k = 0u64;
        while served.len() < order.len() {
            while next < order.len() && order[next].0 == k {
                let (_, _, addr, id) = order[next];
                queues[(addr % banks) as usize].push_back((id, k));
                next += 1;
            }
            let mut left_any = false;
            for q in queues.iter_mut() {
                for _ in 0..ports {
                    if let Some((id, _)) = q.pop_front() {
                        served.insert(id, k);
                    }
                }
                wait += q.len() as u64;
                left_any |= !q.is_empty();
            }
            conflicts += u64::from(left_any);
            k += 1;
        }
        let what = format!("seed {s}, case {case}: {banks} banks × {ports} ports");
        assert_eq!(done.len(), reqs.len(), "{what}");
        for c in &done {
            assert_eq!(
                Some(&c.cycle_served),
                served.get(&c.id.0),
                "{what}: read {}",
                c.id.0
            );
            assert_eq!(c.cycle_done, c.cycle_served + u64::from(latency), "{what}");
        }
        let total = |f: fn(&rtl_model::cycle::memory::NodeMemoryStats) -> u64| -> u64 {
            windows.iter().map(f).sum()
        };
        assert_eq!(total(|w| w.port_wait), wait, "{what}: port wait");
        assert_eq!(
            total(|w| w.port_conflict_cycles),
            conflicts,
            "{what}: conflict cycles"
        );
        assert_eq!(total(|w| w.onchip_reads), reqs.len() as u64, "{what}");
    }
}
