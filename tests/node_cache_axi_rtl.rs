//! The node cache on AXI4 (`testbench/rtl/svo_node_cache_axi.v`: svo_node_cache with its fills
//! as one-beat INCR bursts on FILL_LANES read ports) against the model's node memory
//! (`rtl_model::cycle::memory::NodeMemory`, no on-chip part), with the AXI4 slave
//! `testbench/tb/tb_axi_dram.sv` timed as the model's built-in DRAM bus.
//!
//! Per case and seed, as tests/node_cache_rtl.rs: the model driven closed loop into a trace
//! (tests/common/mem_bench.rs), Icarus runs `tb/tb_node_cache_axi.sv` on it open loop, and every
//! completion (requester, cycle requested, cycle done, data) and the hit, miss, merged, fill and
//! uncached counters must equal the model's; AXI_ERROR must stay low. The stall run pauses the
//! slave's ARREADY and R beats at random (seeded): the bench then replays the trace elastically
//! and every requester's reads must return the model's data in order, none lost or repeated.
//! An SLVERR fill must raise AXI_ERROR. The seed is printed; a mismatch names the first
//! differing completion.
//!
//! Without `iverilog`/`vvp` the tests skip with a `SKIPPED` line (tests/common/skip.rs); with
//! `CI=true` that is a failure.

mod common;

use common::cache_bench::{self, cfg, counters, data_of, COUNTERS};
use common::mem_bench::{self, BenchLog, Line, ModelRun, Pool};
use rtl_model::cycle::memory::{NodeMemoryConfig, NodeMemoryStats};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One hardware case: the model's configuration and the pool in front of it.
struct Case {
    name: &'static str,
    cfg: NodeMemoryConfig,
    walkers: u32,
    contexts: u32,
    /// Requests per seed.
    requests: usize,
}

/// Seeds run per case (fixed, printed; `SVO_TEST_SEED` adds its own first).
const SEEDS: [u64; 2] = [0x29_a001, 0x29_a002];

fn cases() -> Vec<Case> {
    let case = |name, cfg, walkers, contexts, requests| Case {
        name,
        cfg,
        walkers,
        contexts,
        requests,
    };
    let mut slow_bus = cfg(4096, 4, (4, 2), 8, 8, (60, 24));
    slow_bus.cache.hit_latency = 1;
    vec![
        // The default's geometry at test size: 2 AXI ports of 512 bits at 128 B/cycle.
        case(
            "default geometry, 4 KiB",
            cfg(4096, 4, (4, 2), 32, 8, (60, 128)),
            4,
            16,
            400,
        ),
        // Many fills issued in one cycle: ARs queue behind each other on the 2 ports.
        case(
            "default geometry, 4 KiB, 256 MSHRs",
            cfg(4096, 4, (4, 2), 32, 256, (60, 128)),
            4,
            16,
            400,
        ),
        // tests/golden/small_hw.ron: 16 KiB 2-way, DRAM latency 120.
        case(
            "small_hw",
            cfg(16384, 2, (4, 2), 32, 8, (120, 128)),
            4,
            16,
            300,
        ),
        case(
            "1 KiB 2-way, 1 bank x 1 port",
            cfg(1024, 2, (1, 1), 4, 8, (60, 128)),
            2,
            8,
            300,
        ),
        // One AXI port; the bus slower than a line a cycle.
        case("24 B/cycle, hit latency 1", slow_bus, 2, 16, 300),
        // The smallest latency the AXI mapping allows (RLAST the cycle after the AR).
        case(
            "DRAM latency 3",
            cfg(4096, 4, (4, 2), 8, 8, (3, 128)),
            2,
            8,
            300,
        ),
    ]
}

/// What the model did for one case and seed (traffic: `cache_bench::run_model`, as
/// tests/node_cache_rtl.rs drives it).
fn run_model(case: &Case, seed: u64) -> (ModelRun, NodeMemoryStats) {
    let pool = Pool {
        walkers: case.walkers,
        contexts: case.contexts,
        requests: case.requests,
        ask: 0.7,
    };
    cache_bench::run_model(&case.cfg, pool, seed, case.name)
}

/// The bench's C line after the compared counters (coverage and the error flag).
struct Extra {
    ar_queued: u64,
    ar_stalls: u64,
    r_stalls: u64,
    axi_error: u64,
}

fn extra(got: &BenchLog) -> Extra {
    let c = |i: usize| got.counters.get(i).copied().unwrap_or(0);
    Extra {
        ar_queued: c(6),
        ar_stalls: c(7),
        r_stalls: c(8),
        axi_error: c(9),
    }
}

/// Compiles the bench for `case` into `dir`.
fn compile(case: &Case, dir: &Path) -> PathBuf {
    mem_bench::compile(
        "tb_node_cache_axi",
        &[
            "tb/tb_node_cache_axi.sv",
            "tb/tb_axi_dram.sv",
            "tb/tb_dram_model.sv",
            "rtl/svo_node_cache_axi.v",
            "rtl/svo_node_cache.v",
        ],
        &cache_bench::params(case.walkers, case.contexts, &case.cfg),
        dir,
    )
}

/// Runs the compiled bench on `run`'s trace with the extra plusargs `args`.
fn simulate(vvp: &Path, dir: &Path, run: &ModelRun, args: &[String]) -> Result<BenchLog, String> {
    mem_bench::simulate_with(vvp, dir, run, args, cache_bench::trace_line)
}

/// The stall run's check: per requester, the RTL's reads (in completion order) return the
/// model's data of that requester's reads (in request order), none lost, none repeated, and
/// the bench flagged nothing. Returns the completions checked.
fn compare_in_order(want: &[Line], got: &BenchLog) -> Result<usize, String> {
    if let Some(e) = got.errors.first() {
        return Err(format!("the bench flagged an error: {e}"));
    }
    let mut model: BTreeMap<u32, Vec<&Line>> = BTreeMap::new();
    for l in want {
        model.entry(l.1).or_default().push(l);
    }
    for v in model.values_mut() {
        v.sort_by_key(|l| l.2);
    }
    let mut rtl: BTreeMap<u32, Vec<&Line>> = BTreeMap::new();
    for l in &got.done {
        rtl.entry(l.1).or_default().push(l);
    }
    for v in rtl.values_mut() {
        v.sort_by_key(|l| l.0);
    }
    for (r, m) in &model {
        let g = rtl.get(r).map(Vec::as_slice).unwrap_or(&[]);
        for (i, (w, x)) in m.iter().zip(g).enumerate() {
            if w.3 != x.3 {
                return Err(format!(
                    "requester {r}, read {i} (model: requested in cycle {}): RTL data {:#018x}, \
                     model {:#018x}",
                    w.2, x.3, w.3
                ));
            }
        }
        if m.len() != g.len() {
            return Err(format!(
                "requester {r}: {} reads completed in the model, {} in the RTL",
                m.len(),
                g.len()
            ));
        }
    }
    if let Some(r) = rtl.keys().find(|r| !model.contains_key(r)) {
        return Err(format!("requester {r} completed reads it never made"));
    }
    Ok(want.len())
}

#[test]
fn node_cache_axi_rtl_equals_the_model() {
    if !mem_bench::icarus() {
        return;
    }
    let mut failures = Vec::new();
    for case in cases() {
        let dir = mem_bench::scratch("node_cache_axi_rtl_cases");
        let vvp = compile(&case, &dir);
        let (mut completions, mut equal, mut queued, mut fills) = (0, 0, 0, 0);
        for seed in mem_bench::seeds(&SEEDS) {
            let (run, stats) = run_model(&case, seed);
            let want = mem_bench::expected(&run, data_of);
            completions += want.len();
            fills += stats.dram_fills;
            let verdict = simulate(&vvp, &dir, &run, &[]).and_then(|got| {
                let x = extra(&got);
                queued += x.ar_queued;
                mem_bench::compare(&want, &counters(&stats), COUNTERS, &got)?;
                if x.axi_error != 0 {
                    return Err("AXI_ERROR raised without an error response".into());
                }
                // The contract's premise: no AR ever waited on ARREADY, no beat was held.
                if x.ar_stalls + x.r_stalls != 0 {
                    return Err(format!(
                        "the slave stalled without pauses: {} AR, {} R port-cycles",
                        x.ar_stalls, x.r_stalls
                    ));
                }
                Ok(())
            });
            match verdict {
                Ok(()) => {
                    equal += want.len();
                    println!(
                        "{}: seed {seed:#x}: {} completions equal",
                        case.name,
                        want.len()
                    );
                }
                Err(e) => {
                    println!("{}: seed {seed:#x}: MISMATCH: {e}", case.name);
                    failures.push(format!("{} (seed {seed:#x}): {e}", case.name));
                }
            }
        }
        println!(
            "{}: {equal}/{completions} completions equal; {fills} fills, {queued} of them \
             with their AR queued past the cycle after issue",
            case.name
        );
        if case.cfg.dram.mshrs > 16 {
            assert!(queued > 0, "{}: no AR ever queued", case.name);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        failures.is_empty(),
        "RTL and model differ:\n{}",
        failures.join("\n")
    );
}

/// Pauses on ARREADY and R (seeded): every read still returns the model's data, in order per
/// requester, none lost or repeated. Then an SLVERR response raises AXI_ERROR.
#[test]
fn stalls_keep_the_data_and_an_error_response_is_flagged() {
    if !mem_bench::icarus() {
        return;
    }
    let case = cases().swap_remove(0);
    let dir = mem_bench::scratch("node_cache_axi_rtl_stall");
    let vvp = compile(&case, &dir);
    for seed in mem_bench::seeds(&SEEDS[..1]) {
        let (run, stats) = run_model(&case, seed);
        let want = mem_bench::expected(&run, data_of);
        let slave_seed = seed as u32;
        let args = [
            "+elastic".to_string(),
            "+pause_ar=30".to_string(),
            "+pause_r=30".to_string(),
            format!("+seed={slave_seed}"),
        ];
        let got = simulate(&vvp, &dir, &run, &args).expect("the bench runs");
        let x = extra(&got);
        let n = compare_in_order(&want, &got).unwrap_or_else(|e| panic!("seed {seed:#x}: {e}"));
        let last = |v: &[Line]| v.iter().map(|l| l.0).max().unwrap_or(0);
        println!(
            "stall run, seed {seed:#x}, slave seed {slave_seed}: {n}/{} completions with the \
             model's data in order; {} AR stall and {} R stall port-cycles; last completion in \
             cycle {} (model {}); {} fills (model {})",
            want.len(),
            x.ar_stalls,
            x.r_stalls,
            last(&got.done),
            last(&want),
            got.counters.get(3).copied().unwrap_or(0),
            stats.dram_fills
        );
        assert!(x.ar_stalls > 0 && x.r_stalls > 0, "no stalls injected");
        assert_eq!(x.axi_error, 0, "AXI_ERROR without an error response");

        // Fill 10 answers SLVERR: the flag rises, the reads still complete (exact mode).
        let got = simulate(&vvp, &dir, &run, &["+slverr=10".to_string()]).expect("the bench runs");
        assert_eq!(extra(&got).axi_error, 1, "SLVERR on fill 10 not flagged");
        mem_bench::compare(&want, &counters(&stats), COUNTERS, &got)
            .expect("an error response still delivers its fill");
        println!("SLVERR on fill 10: AXI_ERROR set, all reads completed");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Both checks catch a corruption: a model completion a cycle late (exact comparison) and one
/// wrong data word (the stall run's comparison), each reported as exactly that completion.
#[test]
fn corruptions_are_caught() {
    if !mem_bench::icarus() {
        return;
    }
    let case = cases().swap_remove(0);
    let dir = mem_bench::scratch("node_cache_axi_rtl_corrupt");
    let vvp = compile(&case, &dir);
    let seed = SEEDS[0];
    println!("seed {seed:#x}");
    let (run, stats) = run_model(&case, seed);
    let got = simulate(&vvp, &dir, &run, &[]).expect("the bench runs");
    let want = mem_bench::expected(&run, data_of);
    mem_bench::assert_late_completion_caught(&want, &counters(&stats), COUNTERS, &got);

    compare_in_order(&want, &got).expect("uncorrupted, the data agree");
    let i = want.len() / 2;
    let mut bad = want.clone();
    bad[i].3 ^= 1 << 7;
    let (r, requested) = (bad[i].1, bad[i].2);
    let k = want.iter().filter(|l| l.1 == r && l.2 < requested).count();
    let err = compare_in_order(&bad, &got).expect_err("a corrupted word is caught");
    println!("{err}");
    assert!(
        err.starts_with(&format!(
            "requester {r}, read {k} (model: requested in cycle {requested}): RTL data {:#018x}, \
             model {:#018x}",
            want[i].3, bad[i].3
        )),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
