//! The node memory's issue-28 mechanisms on hand-built request patterns where each must
//! matter, with every expected cycle derived by hand in the comments: hit under miss (the miss
//! queue), MSHR merging in the miss queue, the tag re-check of a queued miss, line-interleaved
//! cache banks, and combining of same-word reads at an on-chip bank. Each test also runs the
//! arrangement before issue 28 (no miss queue, one bank, no combining) on the same pattern, so
//! the difference is pinned.
//!
//! Random stress of the same mechanisms is in `cycle_memory_stress.rs`.

mod common;
mod memory_common;
use memory_common::config;

use rtl_model::cycle::memory::{
    Completion, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, Source,
};
use std::collections::BTreeMap;

/// Completions by requester.
fn by_requester(done: &[Completion]) -> BTreeMap<u32, Completion> {
    done.iter().map(|c| (c.requester, *c)).collect()
}

/// 64 KiB, 4 ways, 64-byte lines, hit 4, one lookup port; DRAM latency 10, 64 B/cycle (a
/// fill is 10 + 1 cycles), one MSHR; no on-chip store.
fn one_mshr(miss_queue: u32) -> NodeMemoryConfig {
    let mut cfg = config(3, 1, 1, 1 << 16, 4, 64, 4, 1, 10, 64, 1);
    cfg.cache.miss_queue = miss_queue;
    cfg
}

fn flat() -> MemoryLayout {
    MemoryLayout::flat(1 << 16, 16).unwrap()
}

#[test]
fn a_hit_behind_a_miss_completes_before_it() {
    // Line 0 (word 0) is cached. Cycle 0: r0 misses line 1 (word 16), r1 misses line 2
    // (word 32), r2 hits line 0. One port: lookups in cycles 0, 1, 2.
    //   r0: MSHR at 0, fill done 0 + 10 + 1 = 11.
    //   With the miss queue: r1 finds no MSHR in cycle 1 and waits in the queue; r2 hits in
    //   cycle 2, done 2 + 4 = 6; in cycle 11 r0's fill frees the MSHR, r1 takes it: done
    //   11 + 11 = 22, served (looked up) 1, 10 cycles in the queue.
    //   Blocking (before issue 28): r1 stalls the pipeline from cycle 1 until the MSHR frees
    //   in 11: served 11, done 22; r2 is looked up in 12, done 16.
    let run = |miss_queue| {
        let mut mem = NodeMemory::new(one_mshr(miss_queue), flat()).unwrap();
        mem.warm(FetchKind::Node, 0);
        for (r, addr) in [(0, 16), (1, 32), (2, 0)] {
            mem.request(0, addr, FetchKind::Node, r).unwrap();
        }
        let done = by_requester(&mem.drain());
        (done, mem.stats())
    };
    let (q, s) = run(4);
    let got: Vec<(u64, u64)> = q.values().map(|c| (c.cycle_served, c.cycle_done)).collect();
    assert_eq!(got, vec![(0, 11), (1, 22), (2, 6)], "hit under miss");
    assert_eq!(q[&2].source, Source::CacheHit);
    assert_eq!(
        (s.miss_queued, s.miss_queue_wait, s.miss_queue_max),
        (1, 10, 1)
    );
    assert_eq!((s.mshr_full_cycles, s.mshr_wait), (0, 0));
    let (b, s) = run(0);
    let got: Vec<(u64, u64)> = b.values().map(|c| (c.cycle_served, c.cycle_done)).collect();
    assert_eq!(got, vec![(0, 11), (11, 22), (12, 16)], "blocking");
    // Stalled cycles 1 ..= 10 with r1 and r2 waiting: 10 cycles, 20 request-cycles; r2 waits
    // one more cycle for the port in 11.
    assert_eq!(
        (s.mshr_full_cycles, s.mshr_wait, s.miss_queued),
        (10, 20, 0)
    );
}

#[test]
fn queued_misses_to_one_line_merge() {
    // Cycle 0: r0 misses line 1 (MSHR, done 11); r1 and r2 miss line 2, looked up in cycles
    // 1 and 2, neither finds an MSHR or a fill of line 2: both queue. Cycle 11: r1 takes the
    // freed MSHR (done 22) and r2, now at the head, merges into that fill (done 22).
    let mut mem = NodeMemory::new(one_mshr(4), flat()).unwrap();
    for (r, addr) in [(0, 16), (1, 32), (2, 33)] {
        mem.request(0, addr, FetchKind::Node, r).unwrap();
    }
    let done = by_requester(&mem.drain());
    let got: Vec<(u64, u64, Source)> = done
        .values()
        .map(|c| (c.cycle_served, c.cycle_done, c.source))
        .collect();
    assert_eq!(
        got,
        vec![
            (0, 11, Source::Miss),
            (1, 22, Source::Miss),
            (2, 22, Source::Merged)
        ]
    );
    let s = mem.stats();
    assert_eq!((s.dram_fills, s.cache_misses, s.cache_merged), (2, 2, 1));
    // r1 waited 11 − 1, r2 11 − 2.
    assert_eq!(
        (s.miss_queued, s.miss_queue_wait, s.miss_queue_max),
        (2, 19, 2)
    );
}

#[test]
fn a_queued_miss_whose_line_arrived_meanwhile_hits() {
    // One MSHR, one lookup port. Cycle 0: r0 misses line 1 (word 16; MSHR, done 11); r1
    // misses line 2 (word 32), r2 line 3 (word 48), r3 and r4 line 2 again (words 33, 34),
    // looked up in cycles 1 to 4: line 2 is not in flight then (r1 only waits in the queue),
    // so all four queue. Cycle 11: r1 takes the freed MSHR (fill of line 2, done 22); r2
    // finds none. Cycle 22: line 2 is installed and r2 takes the MSHR (done 33); r3, now at
    // the head, finds line 2 in the tags: a hit through the bank's one port, served 22, done
    // 22 + 4 = 26; r4 hits too but the port is taken: served 23, done 27. Without the tag
    // re-check r3 would wait for r2's fill (33) and fetch line 2 again (done 44), r4 merging
    // into that fill.
    let mut mem = NodeMemory::new(one_mshr(4), flat()).unwrap();
    for (r, addr) in [(0, 16), (1, 32), (2, 48), (3, 33), (4, 34)] {
        mem.request(0, addr, FetchKind::Node, r).unwrap();
    }
    let done = by_requester(&mem.drain());
    let got: Vec<(u64, u64, Source)> = done
        .values()
        .map(|c| (c.cycle_served, c.cycle_done, c.source))
        .collect();
    assert_eq!(
        got,
        vec![
            (0, 11, Source::Miss),
            (1, 22, Source::Miss),
            (2, 33, Source::Miss),
            (22, 26, Source::CacheHit),
            (23, 27, Source::CacheHit)
        ],
        "queued misses re-check the tags"
    );
    let s = mem.stats();
    assert_eq!(
        (s.dram_fills, s.cache_misses, s.cache_hits, s.cache_lookups),
        (3, 3, 2, 5)
    );
    // r1 waited 11 − 1, r2 22 − 2, r3 22 − 3, r4 23 − 4.
    assert_eq!((s.miss_queued, s.miss_queue_wait), (4, 68));
}

#[test]
fn a_full_miss_queue_stalls_the_bank() {
    // A one-entry queue. Cycle 0: r0 misses line 1 (MSHR, done 11), r1 and r2 miss line 2,
    // r3 misses line 3 (word 48). Cycle 1: r1 queues. Cycle 2: r2 finds no MSHR, no fill of
    // line 2 and the queue full: the pipeline stalls (r2 and r3 wait) through cycle 10. Cycle
    // 11: r0's fill frees the MSHR, r1 takes it (done 22), then r2 is looked up again and
    // merges into that fill (done 22); r3 waits for the port. Cycle 12: r3 queues; cycle 22:
    // r1's fill frees the MSHR and r3 takes it, done 22 + 11 = 33.
    let mut mem = NodeMemory::new(one_mshr(1), flat()).unwrap();
    for (r, addr) in [(0, 16), (1, 32), (2, 33), (3, 48)] {
        mem.request(0, addr, FetchKind::Node, r).unwrap();
    }
    let done = by_requester(&mem.drain());
    let got: Vec<(u64, u64)> = done
        .values()
        .map(|c| (c.cycle_served, c.cycle_done))
        .collect();
    assert_eq!(got, vec![(0, 11), (1, 22), (11, 22), (12, 33)]);
    let s = mem.stats();
    // Stalled in cycles 2 ..= 10 (r2 and r3 waiting): 9 cycles, 18 request-cycles; r3 then
    // waits for the port in 11.
    assert_eq!((s.mshr_full_cycles, s.mshr_wait), (9, 18));
    assert_eq!(s.miss_queued, 2);
}

#[test]
fn cache_bank_conflicts_serialise_and_other_banks_run_in_parallel() {
    // Lines 0, 1 and 2 cached (words 0, 16, 32); one lookup port per bank, hit 4. Cycle 0:
    // r0 line 0, r1 line 2, r2 line 1.
    //   2 banks (line mod 2): bank 0 has r0 then r1 (cycles 0, 1), bank 1 has r2 (cycle 0):
    //   done 4, 5, 4; r1 waited one cycle.
    //   1 bank: cycles 0, 1, 2: done 4, 5, 6; 1 + 2 request-cycles of waiting.
    let run = |banks| {
        let mut cfg = config(3, 1, 1, 1 << 16, 4, 64, 4, 1, 10, 64, 4);
        cfg.cache.banks = banks;
        let mut mem = NodeMemory::new(cfg, flat()).unwrap();
        for w in [0, 16, 32] {
            mem.warm(FetchKind::Node, w);
        }
        for (r, addr) in [(0, 0), (1, 32), (2, 16)] {
            mem.request(0, addr, FetchKind::Node, r).unwrap();
        }
        let done = by_requester(&mem.drain());
        let s = mem.stats();
        (
            done.values().map(|c| c.cycle_done).collect::<Vec<_>>(),
            s.cache_port_wait,
            s.port_conflict_cycles,
        )
    };
    assert_eq!(run(2), (vec![4, 5, 4], 1, 1), "two banks");
    assert_eq!(run(1), (vec![4, 5, 6], 3, 2), "one bank");
}

#[test]
fn same_word_reads_at_an_onchip_bank_share_one_port_read() {
    // Everything on chip, one bank with one port, latency 3. Cycle 0: r0 word 0, r1 word 4,
    // r2 word 0; cycle 1: r3 word 4; cycle 5: r4 word 0.
    //   Combining: r0 read in cycle 0 (done 3), r2 joins it (3); r1 waits to cycle 1 (4), r3
    //   arrives in cycle 1 while word 4 is being read: joins it (4); r4 in cycle 5 finds
    //   nothing queued: its own read (8). Two reads combined (r2, r3).
    //   Without: r0 0, r1 1, r2 2, r3 3, r4 5: done 3, 4, 5, 6, 8.
    let run = |combine| {
        let mut cfg = config(3, 1, 1, 1 << 16, 4, 64, 4, 1, 10, 64, 4);
        cfg.onchip.combine = combine;
        let layout = MemoryLayout::with_onchip_ranges(1 << 12, 16, vec![(0, 1 << 12)]).unwrap();
        let mut mem = NodeMemory::new(cfg, layout).unwrap();
        for (c, r, addr) in [(0, 0, 0), (0, 1, 4), (0, 2, 0), (1, 3, 4), (5, 4, 0)] {
            mem.request(c, addr, FetchKind::Node, r).unwrap();
        }
        let done = by_requester(&mem.drain());
        let s = mem.stats();
        (
            done.values().map(|c| c.cycle_done).collect::<Vec<_>>(),
            s.onchip_combined,
            s.port_wait,
        )
    };
    assert_eq!(run(true), (vec![3, 4, 3, 4, 8], 2, 1), "combining");
    assert_eq!(
        run(false),
        (vec![3, 4, 5, 6, 8], 0, 1 + 2 + 2),
        "one read per port"
    );
}
