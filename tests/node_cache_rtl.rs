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

use common::cache_bench::{self, cfg, counters, COUNTERS};
use common::mem_bench::{self, ModelRun, Pool};
use rtl_model::cycle::memory::{NodeMemoryConfig, NodeMemoryStats};
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

/// What the model did for one case and seed: the trace and its completions, and the
/// model's statistics (traffic: `cache_bench::run_model`).
fn run_model(case: &Case, seed: u64) -> (ModelRun, NodeMemoryStats) {
    let pool = Pool {
        walkers: case.walkers,
        contexts: case.contexts,
        requests: case.requests,
        ask: case.ask,
    };
    cache_bench::run_model(&case.cfg, pool, seed, case.name)
}

/// Compiles the bench for `case` into `dir`.
fn compile(case: &Case, dir: &Path) -> PathBuf {
    mem_bench::compile(
        "tb_node_cache",
        &[
            "tb/tb_node_cache.sv",
            "tb/tb_dram_model.sv",
            "rtl/svo_node_cache.v",
        ],
        &cache_bench::params(case.walkers, case.contexts, &case.cfg),
        dir,
    )
}

/// Runs the compiled bench on `run`'s trace and returns its log.
fn simulate(vvp: &Path, dir: &Path, run: &ModelRun) -> Result<mem_bench::BenchLog, String> {
    mem_bench::simulate(vvp, dir, run, cache_bench::trace_line)
}

/// The model's completions with their data, in the bench's order.
fn expected(run: &ModelRun) -> Vec<mem_bench::Line> {
    mem_bench::expected(run, cache_bench::data_of)
}

// The bench's C line has a sixth counter after `COUNTERS`, the hits made on the miss queue's
// re-check: coverage only (the model has no counter of its own).

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
