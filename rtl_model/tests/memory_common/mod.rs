//! Helpers shared by the node-memory tests (`cycle_memory_*.rs`): the printed seed, a
//! configuration from the few numbers a test cares about, and one isolated read.

// Each test binary uses a different subset.
#![allow(dead_code)]

use super::common;
use rtl_model::cycle::memory::{
    CacheConfig, Completion, DramConfig, FetchKind, NodeMemory, NodeMemoryConfig, OnChipConfig,
    Source,
};

/// The test's seed (`SVO_TEST_SEED` replays), printed.
pub fn seed(test: &str, default: u64) -> u64 {
    let s = common::seed(default);
    println!("{test}: seed = {s} (SVO_TEST_SEED replays)");
    s
}

/// A configuration from the few numbers a test cares about.
#[allow(clippy::too_many_arguments)]
pub fn config(
    onchip_latency: u32,
    banks: u32,
    ports_per_bank: u32,
    cache_bytes: u64,
    ways: u32,
    line_bytes: u32,
    hit_latency: u32,
    cache_ports: u32,
    dram_latency: u32,
    bytes_per_cycle: u32,
    mshrs: u32,
) -> NodeMemoryConfig {
    NodeMemoryConfig {
        onchip: OnChipConfig {
            levels: 0,
            max_bytes: 0,
            latency: onchip_latency,
            banks,
            ports_per_bank,
            // The arrangement before issue 28: these tests pin its timing.
            combine: false,
        },
        cache: CacheConfig {
            size_bytes: cache_bytes,
            ways,
            line_bytes,
            hit_latency,
            ports: cache_ports,
            attr_cached: true,
            banks: 1,
            miss_queue: 0,
        },
        dram: DramConfig {
            latency: dram_latency,
            bytes_per_cycle,
            mshrs,
            ..DramConfig::default()
        },
    }
}

/// One read, made alone in `cycle` and drained: its completion.
pub fn one(mem: &mut NodeMemory, cycle: u64, addr: u32, kind: FetchKind) -> Completion {
    let id = mem.request(cycle, addr, kind, 0).unwrap();
    let c = mem.drain();
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].id, id);
    c[0]
}

/// Most line fills in flight at once, from the completions: a fill occupies its MSHR over
/// [served, done).
pub fn max_in_flight(done: &[Completion]) -> usize {
    let mut events: Vec<(u64, i32)> = Vec::new();
    for c in done.iter().filter(|c| c.source == Source::Miss) {
        events.push((c.cycle_served, 1));
        events.push((c.cycle_done, -1));
    }
    events.sort(); // frees (-1) sort before allocations at the same cycle
    let (mut cur, mut max) = (0i32, 0i32);
    for (_, d) in events {
        cur += d;
        max = max.max(cur);
    }
    max as usize
}
