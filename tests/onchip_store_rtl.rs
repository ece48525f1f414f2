//! The on-chip node store in RTL (`testbench/rtl/svo_onchip_store.v`: word-interleaved
//! banks, a port arbitration per bank, same-word combining) against the model's node memory
//! (`rtl_model::cycle::memory::NodeMemory` with every node word on chip), cycle-exact.
//!
//! Per case and seed: random walker contexts read node and far words (from a small hot set,
//! so banks conflict and reads combine, and from the whole store) from the model, closed loop
//! (tests/common/mem_bench.rs). Icarus runs `testbench/tb/tb_onchip_store.sv` on the trace,
//! open loop, and its log must equal the model exactly: every completion's (requester,
//! cycle_requested, cycle_done), every data word (the store's contents, computed here
//! independently of the bench) and the reads, combined reads and port-wait counters. The
//! seed is printed; a mismatch names the first differing completion.
//!
//! Without `iverilog`/`vvp` the tests skip with a `SKIPPED` line (tests/common/skip.rs); with
//! `CI=true` that is a failure.

mod common;

use common::mem_bench::{self, Pool};
use rtl_model::cycle::memory::{FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig};

/// Words of the store (every node word of the address space the reads fall in).
const WORDS: u32 = 4096;

/// Seeds run per case (fixed, printed; `SVO_TEST_SEED` adds its own first).
const SEEDS: [u64; 2] = [0x29_0101, 0x29_0102];

/// The counters the bench logs, in its order.
const COUNTERS: &str = "reads, combined, port_wait";

/// One hardware case: the model's on-chip store and the pool in front of it.
struct Case {
    name: &'static str,
    cfg: NodeMemoryConfig,
    pool: Pool,
    /// Words of the hot set.
    hot: u64,
}

fn store(banks: u32, ports: u32, latency: u32, combine: bool) -> NodeMemoryConfig {
    let mut c = NodeMemoryConfig::default();
    c.onchip.banks = banks;
    c.onchip.ports_per_bank = ports;
    c.onchip.latency = latency;
    c.onchip.combine = combine;
    c
}

fn pool(walkers: u32, contexts: u32, requests: usize, ask: f64) -> Pool {
    Pool {
        walkers,
        contexts,
        requests,
        ask,
    }
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "default banks (16 x 2, latency 3, combine), 4 x 4",
            cfg: store(16, 2, 3, true),
            pool: pool(4, 4, 600, 0.8),
            hot: 48,
        },
        Case {
            name: "default banks, 48 walkers (issue 28's default) of 1 context",
            cfg: store(16, 2, 3, true),
            pool: pool(48, 1, 600, 0.5),
            hot: 64,
        },
        Case {
            name: "4 banks x 2, combine, 8 x 2",
            cfg: store(4, 2, 3, true),
            pool: pool(8, 2, 600, 0.9),
            hot: 16,
        },
        Case {
            name: "4 banks x 1, no combining, latency 2, 4 x 2",
            cfg: store(4, 1, 2, false),
            pool: pool(4, 2, 500, 0.9),
            hot: 32,
        },
        Case {
            name: "1 bank x 2, latency 5, 6 x 2",
            cfg: store(1, 2, 5, true),
            pool: pool(6, 2, 400, 0.7),
            hot: 8,
        },
    ]
}

/// The store's word at address `a` (tb_onchip_store.sv's function, written again here).
fn word_at(a: u32) -> u64 {
    u64::from(a.wrapping_mul(0x9E37_79B1) ^ 0x5A5A_0F0F)
}

fn run_model(case: &Case, seed: u64) -> (mem_bench::ModelRun, [u64; 3]) {
    let mut rng = common::SplitMix64::derive(seed, case.name);
    let layout =
        MemoryLayout::with_onchip_ranges(u64::from(WORDS), 1, vec![(0, WORDS)]).expect("layout");
    let mut mem = NodeMemory::new(case.cfg.clone(), layout).expect("valid configuration");
    let hot = case.hot;
    let run = mem_bench::run_closed_loop(&mut mem, case.pool, &mut rng, |rng| {
        let kind = if rng.chance(0.85) {
            FetchKind::Node
        } else {
            FetchKind::Far
        };
        let addr = if rng.chance(0.7) {
            rng.below(hot)
        } else {
            rng.below(u64::from(WORDS))
        };
        (kind, addr as u32)
    });
    let s = mem.stats();
    (run, [s.onchip_reads, s.onchip_combined, s.port_wait])
}

fn compile(case: &Case, dir: &std::path::Path) -> std::path::PathBuf {
    let c = &case.cfg.onchip;
    mem_bench::compile(
        "tb_onchip_store",
        &["tb/tb_onchip_store.sv", "rtl/svo_onchip_store.v"],
        &[
            ("REQ_PORTS", u64::from(case.pool.walkers)),
            ("CTX", u64::from(case.pool.contexts)),
            ("BANKS", u64::from(c.banks)),
            ("PORTS", u64::from(c.ports_per_bank)),
            ("LATENCY", u64::from(c.latency)),
            ("COMBINE", u64::from(c.combine)),
            ("WORDS", u64::from(WORDS)),
        ],
        dir,
    )
}

fn trace_line(r: &mem_bench::Req) -> String {
    format!("{} {} {}", r.cycle, r.requester, r.addr)
}

#[test]
fn onchip_store_rtl_equals_the_model() {
    if !mem_bench::icarus() {
        return;
    }
    let mut failures = Vec::new();
    for case in cases() {
        let dir = mem_bench::scratch("onchip_store_rtl_cases");
        let vvp = compile(&case, &dir);
        let (mut completions, mut combined, mut waited) = (0, 0, 0);
        for seed in mem_bench::seeds(&SEEDS) {
            let (run, counters) = run_model(&case, seed);
            let want = mem_bench::expected(&run, |_, a| word_at(a));
            completions += want.len();
            combined += counters[1];
            waited += counters[2];
            let verdict = mem_bench::simulate(&vvp, &dir, &run, trace_line)
                .and_then(|got| mem_bench::compare(&want, &counters, COUNTERS, &got));
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
            "{}: {completions} completions, {combined} combined, {waited} request-cycles \
             waiting for a port",
            case.name
        );
        // The traffic reaches what the case is there for: reads wait for ports, and combine
        // where the store combines.
        assert!(waited > 0, "{}: no read waited for a port", case.name);
        assert_eq!(
            combined > 0,
            case.cfg.onchip.combine,
            "{}: combined reads {combined}",
            case.name
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(
        failures.is_empty(),
        "RTL and model differ:\n{}",
        failures.join("\n")
    );
}

/// The check catches a wrong cycle and a wrong word: one completion of the model moved a
/// cycle later, or its data changed, must be reported as exactly that completion.
#[test]
fn a_corrupted_completion_is_caught() {
    if !mem_bench::icarus() {
        return;
    }
    let case = cases().swap_remove(2);
    let dir = mem_bench::scratch("onchip_store_rtl_corrupt");
    let vvp = compile(&case, &dir);
    let seed = SEEDS[0];
    println!("seed {seed:#x}");
    let (run, counters) = run_model(&case, seed);
    let got = mem_bench::simulate(&vvp, &dir, &run, trace_line).expect("the bench runs");
    let want = mem_bench::expected(&run, |_, a| word_at(a));
    let i = mem_bench::assert_late_completion_caught(&want, &counters, COUNTERS, &got);
    let mut wrong = want.clone();
    wrong[i].3 ^= 1;
    let err = mem_bench::compare(&wrong, &counters, COUNTERS, &got)
        .expect_err("a corrupted word is caught");
    println!("{err}");
    assert!(err.starts_with(&format!("completion {i} differs")), "{err}");
    let err = mem_bench::compare(
        &want,
        &[counters[0], counters[1] + 1, counters[2]],
        COUNTERS,
        &got,
    )
    .expect_err("a corrupted counter is caught");
    println!("{err}");
    assert!(
        err.starts_with("counters [reads, combined, port_wait] differ"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
