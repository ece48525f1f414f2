//! What the two node-cache benches share (tests/node_cache_rtl.rs: `svo_node_cache` with its
//! fill lanes timed by `tb_dram_model.sv`; tests/node_cache_axi_rtl.rs: the same cache behind
//! its AXI4 master and `tb_axi_dram.sv`): the model's configuration per case, the traffic the
//! model is driven with, the data the bench's memory holds (written again here, not read from
//! the bench), the counters compared, and the bench's cache parameters.
//!
//! Pipeline position: none; test harness over tests/common/mem_bench.rs (the closed-loop
//! driver, the log parser and the exact comparison, shared with the on-chip store's bench).

use super::mem_bench::{self, ModelRun, Pool, Req};
use super::SplitMix64;
use rtl_model::cycle::memory::{
    FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, NodeMemoryStats,
};

/// Node words and attribute records of the address space the reads fall in.
pub const NODE_WORDS: u64 = 1 << 22;
pub const ATTR_RECORDS: u64 = 1 << 20;

/// The default configuration with a cache of `size` bytes, `ways` ways, 64-byte lines, `banks`
/// × `ports` lookups, the miss queue and the MSHRs given, DRAM `(latency, bytes_per_cycle)`.
pub fn cfg(
    size: u64,
    ways: u32,
    (banks, ports): (u32, u32),
    miss_queue: u32,
    mshrs: u32,
    (latency, bytes_per_cycle): (u32, u32),
) -> NodeMemoryConfig {
    let mut c = NodeMemoryConfig::default();
    c.cache.size_bytes = size;
    c.cache.ways = ways;
    c.cache.line_bytes = 64;
    c.cache.banks = banks;
    c.cache.ports = ports;
    c.cache.miss_queue = miss_queue;
    c.dram.mshrs = mshrs;
    c.dram.latency = latency;
    c.dram.bytes_per_cycle = bytes_per_cycle;
    c
}

/// The model driven closed loop (`mem_bench::run_closed_loop`) on `cfg` by `pool`, with the
/// RNG derived from `seed` and the case's `name`: 60 % node, 10 % far and 30 % attribute
/// reads, 75 % of them from a hot set (about twice the cache's node lines, 256 records), the
/// rest anywhere in the address space, so that hits, merges, misses, evictions, full MSHRs and
/// full miss queues all happen. Returns the trace with its completions and the model's
/// statistics.
pub fn run_model(
    cfg: &NodeMemoryConfig,
    pool: Pool,
    seed: u64,
    name: &str,
) -> (ModelRun, NodeMemoryStats) {
    let mut rng = SplitMix64::derive(seed, name);
    let layout = MemoryLayout::flat(NODE_WORDS, ATTR_RECORDS).expect("layout");
    let mut mem = NodeMemory::new(cfg.clone(), layout).expect("valid configuration");
    let hot_words = (2 * cfg.cache.size_bytes / 4).max(64);
    let run = mem_bench::run_closed_loop(&mut mem, pool, &mut rng, |rng| {
        let roll = rng.unit();
        let kind = if roll < 0.6 {
            FetchKind::Node
        } else if roll < 0.7 {
            FetchKind::Far
        } else {
            FetchKind::Attr
        };
        let hot = rng.chance(0.75);
        let addr = match (kind, hot) {
            (FetchKind::Attr, true) => rng.below(256),
            (FetchKind::Attr, false) => rng.below(ATTR_RECORDS),
            (_, true) => rng.below(hot_words),
            (_, false) => rng.below(NODE_WORDS),
        } as u32;
        (kind, addr)
    });
    (run, mem.stats())
}

/// The DRAM's word at byte address `a` (tb_dram_model.sv's function, written again here).
fn word_at(a: u64) -> u32 {
    (a as u32).wrapping_mul(0x9E37_79B1) ^ ((a >> 32) as u32).wrapping_mul(0x85EB_CA77)
}

/// The 64 bits a read returns: the node word, or the 8-byte record (lower word first).
pub fn data_of(kind: FetchKind, addr: u32) -> u64 {
    match kind {
        FetchKind::Node | FetchKind::Far => u64::from(word_at(4 * u64::from(addr))),
        FetchKind::Attr => {
            let b = (1u64 << 40) + 8 * u64::from(addr);
            u64::from(word_at(b)) | u64::from(word_at(b + 4)) << 32
        }
    }
}

/// A request as a line of the benches' trace: cycle, requester, kind (0 node, 1 far,
/// 2 attribute record), address.
pub fn trace_line(r: &Req) -> String {
    let kind = match r.kind {
        FetchKind::Node => 0,
        FetchKind::Far => 1,
        FetchKind::Attr => 2,
    };
    format!("{} {} {kind} {}", r.cycle, r.requester, r.addr)
}

/// The counters compared, in the order of the benches' C line.
pub const COUNTERS: &str = "hits, misses, merged, fills, uncached";

/// The model's values of [`COUNTERS`].
pub fn counters(s: &NodeMemoryStats) -> [u64; 5] {
    [
        s.cache_hits,
        s.cache_misses,
        s.cache_merged,
        s.dram_fills,
        s.uncached_reads,
    ]
}

/// The benches' cache and DRAM parameters for `walkers` × `contexts` requesters on `c`.
pub fn params(walkers: u32, contexts: u32, c: &NodeMemoryConfig) -> Vec<(&'static str, u64)> {
    vec![
        ("REQ_PORTS", u64::from(walkers)),
        ("CTX", u64::from(contexts)),
        ("BANKS", u64::from(c.cache.banks)),
        ("PORTS", u64::from(c.cache.ports)),
        ("SETS", c.cache_sets()),
        ("WAYS", u64::from(c.cache.ways)),
        ("LINE_BYTES", u64::from(c.cache.line_bytes)),
        ("HIT_LATENCY", u64::from(c.cache.hit_latency)),
        ("MSHRS", u64::from(c.dram.mshrs)),
        ("MISS_QUEUE", u64::from(c.cache.miss_queue)),
        ("ATTR_CACHED", u64::from(c.cache.attr_cached)),
        ("DRAM_LATENCY", u64::from(c.dram.latency)),
        ("BYTES_PER_CYCLE", u64::from(c.dram.bytes_per_cycle)),
    ]
}
