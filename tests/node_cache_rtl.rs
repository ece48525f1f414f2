//! The node cache in RTL (`testbench/rtl/svo_node_cache.v`) against the model's node memory
//! (`rtl_model::cycle::memory::NodeMemory` with no on-chip part), cycle-exact.
//!
//! Per case and seed: random walker contexts read (random kind; addresses from a small hot set
//! and a wide range, so hits, merges, misses, evictions, full MSHRs and full miss queues all
//! happen) from the model, closed loop — a context asks only when it has no read outstanding
//! and a walker makes at most one request a cycle. The requests (cycle, requester, kind,
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

use rtl_model::cycle::memory::{
    Completion, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, NodeMemoryStats,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

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

/// One request of the trace.
#[derive(Clone, Copy, Debug)]
struct Req {
    cycle: u64,
    requester: u32,
    kind: FetchKind,
    addr: u32,
}

/// What the model did for one case and seed.
struct ModelRun {
    trace: Vec<Req>,
    done: Vec<Completion>,
    stats: NodeMemoryStats,
}

/// Drives the model closed loop.
fn run_model(case: &Case, seed: u64) -> ModelRun {
    let mut rng = common::SplitMix64::derive(seed, case.name);
    let layout = MemoryLayout::flat(NODE_WORDS, ATTR_RECORDS).expect("layout");
    let mut mem = NodeMemory::new(case.cfg.clone(), layout).expect("valid configuration");
    let n = (case.walkers * case.contexts) as usize;
    let mut busy = vec![false; n];
    // Hot set: about twice the cache's node lines, and a few lines of records.
    let hot_words = (2 * case.cfg.cache.size_bytes / 4).max(64);
    let (mut trace, mut done, mut out) = (Vec::new(), Vec::new(), Vec::new());
    let mut cycle = 0u64;
    loop {
        out.clear();
        mem.tick_into(cycle, &mut out);
        for c in &out {
            busy[c.requester as usize] = false;
        }
        done.extend_from_slice(&out);
        if trace.len() < case.requests {
            for w in 0..case.walkers {
                if !rng.chance(case.ask) {
                    continue;
                }
                let first = rng.below(u64::from(case.contexts)) as u32;
                let free = (0..case.contexts)
                    .map(|i| w * case.contexts + (first + i) % case.contexts)
                    .find(|&r| !busy[r as usize]);
                let Some(requester) = free else { continue };
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
                mem.request(cycle, addr, kind, requester)
                    .expect("request in range and in the present");
                busy[requester as usize] = true;
                trace.push(Req {
                    cycle,
                    requester,
                    kind,
                    addr,
                });
            }
        }
        if trace.len() >= case.requests && mem.outstanding() == 0 {
            break;
        }
        cycle += 1;
        assert!(
            cycle < 10_000_000,
            "{}: the model did not finish",
            case.name
        );
    }
    ModelRun {
        trace,
        done,
        stats: mem.stats(),
    }
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

/// One completion as both sides log it: (cycle_done, requester, cycle_requested, data).
type Line = (u64, u32, u64, u64);

fn kind_code(k: FetchKind) -> u32 {
    match k {
        FetchKind::Node => 0,
        FetchKind::Far => 1,
        FetchKind::Attr => 2,
    }
}

/// The model's completions in the bench's order (done cycle, then requester).
fn expected(run: &ModelRun) -> Vec<Line> {
    let mut v: Vec<Line> = run
        .done
        .iter()
        .map(|c| {
            (
                c.cycle_done,
                c.requester,
                c.cycle_requested,
                data_of(c.kind, c.addr),
            )
        })
        .collect();
    v.sort_unstable();
    v
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

/// What the bench logged.
struct BenchLog {
    done: Vec<Line>,
    counters: [u64; 5],
    /// The part of the hits made by the miss queue's head on its tag re-check (the model
    /// has no counter of its own for them: a coverage figure, not compared).
    replay_hits: u64,
    errors: Vec<String>,
}

fn parse_log(text: &str) -> Result<BenchLog, String> {
    let mut done = Vec::new();
    let mut ctr = None;
    let mut errors = Vec::new();
    let mut end = false;
    let mut replay = 0;
    for line in text.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize| -> Result<u64, String> {
            f.get(i)
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| format!("bench log line {line:?}: field {i} is not a number"))
        };
        match f.first().copied() {
            Some("D") => {
                let data = f
                    .get(4)
                    .and_then(|s| u64::from_str_radix(s, 16).ok())
                    .ok_or_else(|| format!("bench log line {line:?}: bad data"))?;
                done.push((num(2)?, num(3)? as u32, num(1)?, data));
            }
            Some("C") => {
                ctr = Some([num(1)?, num(2)?, num(3)?, num(4)?, num(5)?]);
                replay = num(6)?;
            }
            Some("E") => errors.push(line.to_string()),
            Some("END") => {
                end = true;
                if num(2)? != 0 && errors.is_empty() {
                    errors.push(format!("bench reported {} errors", num(2)?));
                }
            }
            _ => return Err(format!("bench log: unexpected line {line:?}")),
        }
    }
    if !end {
        return Err("bench log has no END line (the simulation did not finish)".into());
    }
    done.sort_unstable();
    Ok(BenchLog {
        done,
        counters: ctr.ok_or("bench log has no counter line")?,
        replay_hits: replay,
        errors,
    })
}

/// Compares the bench with the model: `Err` names the first difference.
fn compare(want: &[Line], want_ctr: [u64; 5], got: &BenchLog) -> Result<(), String> {
    let show = |l: &Line| {
        format!(
            "requester {} requested in cycle {} done in cycle {} data {:#018x}",
            l.1, l.2, l.0, l.3
        )
    };
    for (i, (w, g)) in want.iter().zip(&got.done).enumerate() {
        if w != g {
            return Err(format!(
                "completion {i} differs: model {}, RTL {}",
                show(w),
                show(g)
            ));
        }
    }
    // (A late RTL completion also makes the open-loop trace ask a busy requester: the first
    // differing completion above says more, so the bench's own errors come after it.)
    if let Some(e) = got.errors.first() {
        return Err(format!("the bench flagged an error: {e}"));
    }
    if want.len() != got.done.len() {
        return Err(format!(
            "{} completions in the model, {} in the RTL",
            want.len(),
            got.done.len()
        ));
    }
    if want_ctr != got.counters {
        return Err(format!(
            "counters [hits, misses, merged, fills, uncached] differ: model {want_ctr:?}, RTL {:?}",
            got.counters
        ));
    }
    Ok(())
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("node_cache_rtl_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// Compiles the bench for `case` into `dir`.
fn compile(case: &Case, dir: &Path) -> PathBuf {
    let c = &case.cfg;
    let params = [
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
    ];
    let tb = repo().join("testbench");
    let out = dir.join("tb_node_cache.vvp");
    let mut cmd = Command::new("iverilog");
    cmd.args([
        "-g2012",
        "-Wall",
        "-Wno-sensitivity-entire-array",
        "-s",
        "tb_node_cache",
        "-o",
    ])
    .arg(&out);
    for (k, v) in params {
        cmd.arg(format!("-Ptb_node_cache.{k}={v}"));
    }
    cmd.arg(tb.join("tb/tb_node_cache.sv"))
        .arg(tb.join("tb/tb_dram_model.sv"))
        .arg(tb.join("rtl/svo_node_cache.v"));
    let o = cmd.output().expect("run iverilog");
    assert!(
        o.status.success(),
        "{}: iverilog failed:\n{}",
        case.name,
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// Runs the compiled bench on `run`'s trace and returns its log.
fn simulate(vvp: &Path, dir: &Path, run: &ModelRun) -> Result<BenchLog, String> {
    let mut text = String::new();
    for r in &run.trace {
        let _ = writeln!(
            text,
            "{} {} {} {}",
            r.cycle,
            r.requester,
            kind_code(r.kind),
            r.addr
        );
    }
    let trace = dir.join("trace.txt");
    let log = dir.join("log.txt");
    std::fs::write(&trace, text).expect("write the trace");
    let _ = std::fs::remove_file(&log);
    let o = Command::new("vvp")
        .arg("-n")
        .arg(vvp)
        .arg(format!("+trace={}", trace.display()))
        .arg(format!("+log={}", log.display()))
        .output()
        .expect("run vvp");
    if !o.status.success() {
        return Err(format!(
            "vvp failed:\n{}",
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let text = std::fs::read_to_string(&log).map_err(|e| format!("no bench log: {e}"))?;
    parse_log(&text)
}

fn icarus() -> bool {
    common::skip::tools(&["iverilog", "vvp"], "iverilog")
}

fn seeds() -> Vec<u64> {
    let mut v = Vec::new();
    if std::env::var("SVO_TEST_SEED").is_ok() {
        v.push(common::test_seed());
    }
    v.extend(SEEDS);
    v
}

#[test]
fn node_cache_rtl_equals_the_model() {
    if !icarus() {
        return;
    }
    let mut failures = Vec::new();
    for case in cases() {
        let dir = scratch("cases");
        let vvp = compile(&case, &dir);
        let mut total = NodeMemoryStats::default();
        let mut completions = 0;
        let mut replays = 0;
        for seed in seeds() {
            let run = run_model(&case, seed);
            let want = expected(&run);
            completions += want.len();
            let s = &run.stats;
            total.cache_hits += s.cache_hits;
            total.cache_merged += s.cache_merged;
            total.dram_fills += s.dram_fills;
            total.uncached_reads += s.uncached_reads;
            total.miss_queue_max = total.miss_queue_max.max(s.miss_queue_max);
            total.mshr_full_cycles += s.mshr_full_cycles;
            total.mshr_max_in_use = total.mshr_max_in_use.max(s.mshr_max_in_use);
            let verdict = simulate(&vvp, &dir, &run).and_then(|got| {
                replays += got.replay_hits;
                compare(&want, counters(&run.stats), &got)
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
    if !icarus() {
        return;
    }
    let case = cases().swap_remove(0);
    let dir = scratch("corrupt");
    let vvp = compile(&case, &dir);
    let seed = SEEDS[0];
    println!("seed {seed:#x}");
    let run = run_model(&case, seed);
    let got = simulate(&vvp, &dir, &run).expect("the bench runs");
    let mut want = expected(&run);
    compare(&want, counters(&run.stats), &got).expect("uncorrupted, the RTL equals the model");
    let i = want.len() / 2;
    want[i].0 += 1;
    let err = compare(&want, counters(&run.stats), &got).expect_err("a corrupted cycle is caught");
    println!("{err}");
    assert!(
        err.starts_with(&format!(
            "completion {i} differs: model requester {} requested in cycle {} done in cycle {}",
            want[i].1, want[i].2, want[i].0
        )),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
