//! The node cache in RTL (`testbench/rtl/svo_node_cache.v`) against the model's node memory
//! (`rtl_model::cycle::memory::NodeMemory` with no on-chip part), cycle-exact.
//!
//! Per case and seed: random walker contexts read (random kind; addresses from a small hot set
//! and a wide range, so hits, merges, misses, evictions, full MSHRs and full miss queues all
//! happen) from the model, closed loop — a context asks only when it has no read outstanding
//! and a walker makes at most one request a cycle (tests/common/mem_bench.rs, shared with the
//! on-chip store's bench). The requests (cycle, requester, kind,
//! address) are written as a trace; Icarus runs `testbench/tb/tb_node_cache.sv` on it open loop
//! (requests at the recorded cycles, fills timed by `tb_dram_model.sv`, the built-in DRAM
//! model), and its log must equal the model exactly: every completion's (requester,
//! cycle_requested, cycle_done), every data word (a fixed function of the byte address,
//! computed here independently of the bench), and the hit, miss, merged, fill and uncached
//! counters. The seed is printed; a mismatch names the first differing completion.
//!
//! Without `iverilog`/`vvp` the tests skip with a `SKIPPED` line (tests/common/skip.rs); with
//! `CI=true` that is a failure.

mod common;

use common::mem_bench::{self, ModelRun, Pool};
use rtl_model::cycle::memory::{
    FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, NodeMemoryStats,
};
use std::path::{Path, PathBuf};

/// One hardware case: the model's configuration and the pool in front of it.
struct Case {
    name: &'static str,
    cfg: NodeMemoryConfig,
    walkers: u32,
    contexts: u32,
    /// Requests per seed.
    requests: usize,
    /// Chance a walker with a free context asks in a cycle.
    ask: f64,
}

/// Seeds run per case (fixed, printed; `SVO_TEST_SEED` adds its own first).
const SEEDS: [u64; 2] = [0x29_0001, 0x29_0002];

/// The default configuration with a cache of `size` bytes, `ways` ways, 64-byte lines, `banks`
/// × `ports` lookups, the miss queue and the MSHRs given, DRAM `(latency, bytes_per_cycle)`.
fn cfg(
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

fn cases() -> Vec<Case> {
    let default_small = cfg(4096, 4, (4, 2), 32, 8, (60, 128));
    let mut many_mshrs = default_small.clone();
    many_mshrs.dram.mshrs = 256;
    // tests/golden/small_hw.ron: 16 KiB 2-way, DRAM latency 120, 8 MSHRs (the default's rest).
    let small_hw = cfg(16384, 2, (4, 2), 32, 8, (120, 128));
    let mut no_attr = default_small.clone();
    no_attr.cache.attr_cached = false;
    no_attr.cache.miss_queue = 16;
    let mut slow_bus = cfg(4096, 4, (4, 2), 8, 8, (60, 24));
    slow_bus.cache.hit_latency = 1;
    let case = |name, cfg, walkers, contexts, requests, ask| Case {
        name,
        cfg,
        walkers,
        contexts,
        requests,
        ask,
    };
    vec![
        case("default geometry, 4 KiB", default_small, 4, 16, 400, 0.7),
        case(
            "default geometry, 4 KiB, 256 MSHRs",
            many_mshrs,
            4,
            16,
            400,
            0.7,
        ),
        case("small_hw", small_hw, 4, 16, 400, 0.7),
        case(
            "miss_queue 0",
            cfg(4096, 4, (4, 2), 0, 8, (60, 128)),
            2,
            8,
            300,
            0.8,
        ),
        case(
            "1 bank x 1 port",
            cfg(4096, 4, (1, 1), 4, 8, (60, 128)),
            4,
            4,
            300,
            0.8,
        ),
        case(
            "24 B/cycle < 64-byte lines, hit latency 1",
            slow_bus,
            2,
            16,
            300,
            0.7,
        ),
        case("attr_cached false", no_attr, 4, 8, 400, 0.7),
    ]
}

/// Node words and attribute records of the address space the reads fall in.
const NODE_WORDS: u64 = 1 << 22;
const ATTR_RECORDS: u64 = 1 << 20;

/// What the model did for one case and seed: the trace and its completions, and the
/// model's statistics.
fn run_model(case: &Case, seed: u64) -> (ModelRun, NodeMemoryStats) {
    let mut rng = common::SplitMix64::derive(seed, case.name);
    let layout = MemoryLayout::flat(NODE_WORDS, ATTR_RECORDS).expect("layout");
    let mut mem = NodeMemory::new(case.cfg.clone(), layout).expect("valid configuration");
    // Hot set: about twice the cache's node lines, and a few lines of records.
    let hot_words = (2 * case.cfg.cache.size_bytes / 4).max(64);
    let pool = Pool {
        walkers: case.walkers,
        contexts: case.contexts,
        requests: case.requests,
        ask: case.ask,
    };
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
fn data_of(kind: FetchKind, addr: u32) -> u64 {
    match kind {
        FetchKind::Node | FetchKind::Far => u64::from(word_at(4 * u64::from(addr))),
        FetchKind::Attr => {
            let b = (1u64 << 40) + 8 * u64::from(addr);
            u64::from(word_at(b)) | u64::from(word_at(b + 4)) << 32
        }
    }
}

fn kind_code(k: FetchKind) -> u32 {
    match k {
        FetchKind::Node => 0,
        FetchKind::Far => 1,
        FetchKind::Attr => 2,
    }
}

fn counters(s: &NodeMemoryStats) -> [u64; 5] {
    [
        s.cache_hits,
        s.cache_misses,
        s.cache_merged,
        s.dram_fills,
        s.uncached_reads,
    ]
}

/// Compiles the bench for `case` into `dir`.
fn compile(case: &Case, dir: &Path) -> PathBuf {
    let c = &case.cfg;
    mem_bench::compile(
        "tb_node_cache",
        &[
            "tb/tb_node_cache.sv",
            "tb/tb_dram_model.sv",
            "rtl/svo_node_cache.v",
        ],
        &[
            ("REQ_PORTS", u64::from(case.walkers)),
            ("CTX", u64::from(case.contexts)),
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
        ],
        dir,
    )
}

/// Runs the compiled bench on `run`'s trace and returns its log.
fn simulate(vvp: &Path, dir: &Path, run: &ModelRun) -> Result<mem_bench::BenchLog, String> {
    mem_bench::simulate(vvp, dir, run, |r| {
        format!(
            "{} {} {} {}",
            r.cycle,
            r.requester,
            kind_code(r.kind),
            r.addr
        )
    })
}

/// The model's completions with their data, in the bench's order.
fn expected(run: &ModelRun) -> Vec<mem_bench::Line> {
    mem_bench::expected(run, data_of)
}

/// The counters compared, in the order of the bench's C line (its sixth, the hits made on
/// the miss queue's re-check, is coverage only: the model has no counter of its own).
const COUNTERS: &str = "hits, misses, merged, fills, uncached";

/// The miss queue's re-check hits the bench logged (the C line's sixth counter).
fn replay_hits(got: &mem_bench::BenchLog) -> u64 {
    got.counters.get(5).copied().unwrap_or(0)
}

#[test]
fn node_cache_rtl_equals_the_model() {
    if !mem_bench::icarus() {
        return;
    }
    let mut failures = Vec::new();
    for case in cases() {
        let dir = mem_bench::scratch("node_cache_rtl_cases");
        let vvp = compile(&case, &dir);
        let mut total = NodeMemoryStats::default();
        let mut completions = 0;
        let mut replays = 0;
        for seed in mem_bench::seeds(&SEEDS) {
            let (run, stats) = run_model(&case, seed);
            let want = expected(&run);
            completions += want.len();
            let s = &stats;
            total.cache_hits += s.cache_hits;
            total.cache_merged += s.cache_merged;
            total.dram_fills += s.dram_fills;
            total.uncached_reads += s.uncached_reads;
            total.miss_queue_max = total.miss_queue_max.max(s.miss_queue_max);
            total.mshr_full_cycles += s.mshr_full_cycles;
            total.mshr_max_in_use = total.mshr_max_in_use.max(s.mshr_max_in_use);
            let verdict = simulate(&vvp, &dir, &run).and_then(|got| {
                replays += replay_hits(&got);
                mem_bench::compare(&want, &counters(&stats), COUNTERS, &got)
            });
            match verdict {
                Ok(()) => println!(
                    "{}: seed {seed:#x}: {} completions equal",
                    case.name,
                    want.len()
                ),
                Err(e) => {
                    println!("{}: seed {seed:#x}: MISMATCH: {e}", case.name);
                    failures.push(format!("{} (seed {seed:#x}): {e}", case.name));
                }
            }
        }
        println!(
            "{}: {completions} completions; hits {} ({replays} on a miss-queue re-check), \
             merged {}, fills {}, uncached {}, miss queue max {}, MSHRs max {}, \
             MSHR-full cycles {}",
            case.name,
            total.cache_hits,
            total.cache_merged,
            total.dram_fills,
            total.uncached_reads,
            total.miss_queue_max,
            total.mshr_max_in_use,
            total.mshr_full_cycles
        );
        // The traffic reaches what the case is there for.
        assert!(
            total.cache_hits > 0 && total.cache_merged + total.uncached_reads > 0,
            "{}: no hits or merges",
            case.name
        );
        if case.cfg.dram.mshrs < 16 {
            assert!(
                total.mshr_full_cycles > 0
                    && total.miss_queue_max == u64::from(case.cfg.cache.miss_queue),
                "{}: the MSHRs and the miss queue never filled",
                case.name
            );
        }
        if case.cfg.cache.miss_queue >= 32 && case.cfg.dram.mshrs < 16 {
            assert!(
                replays > 0,
                "{}: no miss-queue head hit on its re-check",
                case.name
            );
        }
        if !case.cfg.cache.attr_cached {
            assert!(total.uncached_reads > 0, "{}: no uncached reads", case.name);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        failures.is_empty(),
        "RTL and model differ:\n{}",
        failures.join("\n")
    );
}

/// The check catches a wrong cycle: one completion of the model moved a cycle later must be
/// reported as exactly that completion.
#[test]
fn a_corrupted_completion_is_caught() {
    if !mem_bench::icarus() {
        return;
    }
    let case = cases().swap_remove(0);
    let dir = mem_bench::scratch("node_cache_rtl_corrupt");
    let vvp = compile(&case, &dir);
    let seed = SEEDS[0];
    println!("seed {seed:#x}");
    let (run, stats) = run_model(&case, seed);
    let got = simulate(&vvp, &dir, &run).expect("the bench runs");
    let want = expected(&run);
    mem_bench::assert_late_completion_caught(&want, &counters(&stats), COUNTERS, &got);
    let _ = std::fs::remove_dir_all(&dir);
}
