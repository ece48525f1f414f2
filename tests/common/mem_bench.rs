//! Shared by the node-memory RTL benches (tests/onchip_store_rtl.rs and the cache's): the
//! model driven closed loop into a request trace, the Icarus bench run open loop on it, and
//! the comparison of the bench's completion log with the model's completions.
//!
//! A bench log is lines "D cycle_requested cycle_done requester data(hex)" per completion,
//! "C n1 n2 …" (the bench's counters), "E …" (a protocol error the bench found) and
//! "END cycle errors". The data word of a completion is computed on the Rust side from its
//! address by a function the bench does not share.

use rtl_model::cycle::memory::{Completion, FetchKind, NodeMemory};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use super::SplitMix64;

/// One request of a trace.
#[derive(Clone, Copy, Debug)]
pub struct Req {
    pub cycle: u64,
    pub requester: u32,
    pub kind: FetchKind,
    pub addr: u32,
}

/// What the model did on one trace.
pub struct ModelRun {
    pub trace: Vec<Req>,
    pub done: Vec<Completion>,
}

/// The pool in front of the memory: `walkers` request ports of `contexts` requesters each.
#[derive(Clone, Copy, Debug)]
pub struct Pool {
    pub walkers: u32,
    pub contexts: u32,
    /// Requests in the trace.
    pub requests: usize,
    /// Chance a walker with a free context asks in a cycle.
    pub ask: f64,
}

/// Drives `mem` closed loop, as the walker pool does: a walker asks at most once a cycle,
/// for a context with no read outstanding; `pick` chooses the read's kind and address.
pub fn run_closed_loop(
    mem: &mut NodeMemory,
    pool: Pool,
    rng: &mut SplitMix64,
    mut pick: impl FnMut(&mut SplitMix64) -> (FetchKind, u32),
) -> ModelRun {
    let n = (pool.walkers * pool.contexts) as usize;
    let mut busy = vec![false; n];
    let (mut trace, mut done, mut out) = (Vec::new(), Vec::new(), Vec::new());
    let mut cycle = 0u64;
    loop {
        out.clear();
        mem.tick_into(cycle, &mut out);
        for c in &out {
            busy[c.requester as usize] = false;
        }
        done.extend_from_slice(&out);
        if trace.len() < pool.requests {
            for w in 0..pool.walkers {
                if !rng.chance(pool.ask) {
                    continue;
                }
                let first = rng.below(u64::from(pool.contexts)) as u32;
                let free = (0..pool.contexts)
                    .map(|i| w * pool.contexts + (first + i) % pool.contexts)
                    .find(|&r| !busy[r as usize]);
                let Some(requester) = free else { continue };
                let (kind, addr) = pick(rng);
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
        if trace.len() >= pool.requests && mem.outstanding() == 0 {
            break;
        }
        cycle += 1;
        assert!(cycle < 10_000_000, "the model did not finish");
    }
    ModelRun { trace, done }
}

/// One completion as both sides log it: (cycle_done, requester, cycle_requested, data).
pub type Line = (u64, u32, u64, u64);

/// The model's completions with their data, in the bench's order (done cycle, requester).
pub fn expected(run: &ModelRun, data: impl Fn(FetchKind, u32) -> u64) -> Vec<Line> {
    let mut v: Vec<Line> = run
        .done
        .iter()
        .map(|c| {
            (
                c.cycle_done,
                c.requester,
                c.cycle_requested,
                data(c.kind, c.addr),
            )
        })
        .collect();
    v.sort_unstable();
    v
}

/// What a bench logged.
pub struct BenchLog {
    pub done: Vec<Line>,
    pub counters: Vec<u64>,
    pub errors: Vec<String>,
}

/// Reads a bench log.
pub fn parse_log(text: &str) -> Result<BenchLog, String> {
    let mut done = Vec::new();
    let mut counters = None;
    let mut errors = Vec::new();
    let mut end = false;
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
            Some("C") => counters = Some((1..f.len()).map(num).collect::<Result<Vec<_>, _>>()?),
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
        counters: counters.ok_or("bench log has no counter line")?,
        errors,
    })
}

/// Compares a bench with the model: `Err` names the first difference. `names` are the
/// counters' names, in the order of the log's C line; counters the bench logs after them are
/// not compared.
pub fn compare(
    want: &[Line],
    want_counters: &[u64],
    names: &str,
    got: &BenchLog,
) -> Result<(), String> {
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
    // A late RTL completion also makes the open-loop trace ask a busy requester: the first
    // differing completion says more, so the bench's own errors come after it.
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
    // The bench may log more counters than are compared (coverage figures after them).
    let got_counters = got
        .counters
        .get(..want_counters.len())
        .unwrap_or(&got.counters);
    if want_counters != got_counters {
        return Err(format!(
            "counters [{names}] differ: model {want_counters:?}, RTL {got_counters:?}"
        ));
    }
    Ok(())
}

/// Shows the comparison failing: the model's completion `i` (the middle one) moved a cycle
/// later must be reported as exactly that completion. `want` and `counters` must equal the
/// bench's `got` uncorrupted. Returns `i`.
pub fn assert_late_completion_caught(
    want: &[Line],
    counters: &[u64],
    names: &str,
    got: &BenchLog,
) -> usize {
    compare(want, counters, names, got).expect("uncorrupted, the RTL equals the model");
    let i = want.len() / 2;
    let mut late = want.to_vec();
    late[i].0 += 1;
    let err = compare(&late, counters, names, got).expect_err("a corrupted cycle is caught");
    println!("{err}");
    assert!(
        err.starts_with(&format!(
            "completion {i} differs: model requester {} requested in cycle {} done in cycle {}",
            late[i].1, late[i].2, late[i].0
        )),
        "{err}"
    );
    i
}

/// The repository.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh scratch folder for one bench.
pub fn scratch(name: &str) -> PathBuf {
    let d =
        PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// Compiles the bench `top` (files relative to testbench/) with `params` into `dir`.
pub fn compile(top: &str, files: &[&str], params: &[(&str, u64)], dir: &Path) -> PathBuf {
    let tb = repo().join("testbench");
    let out = dir.join(format!("{top}.vvp"));
    let mut cmd = Command::new("iverilog");
    cmd.args([
        "-g2012",
        "-Wall",
        "-Wno-sensitivity-entire-array",
        "-s",
        top,
        "-o",
    ])
    .arg(&out)
    // The benches' shared parts (`include "tb_*.svh") live beside them.
    .arg(format!("-I{}", tb.join("tb").display()));
    for (k, v) in params {
        cmd.arg(format!("-P{top}.{k}={v}"));
    }
    for f in files {
        cmd.arg(tb.join(f));
    }
    let o = cmd.output().expect("run iverilog");
    assert!(
        o.status.success(),
        "iverilog failed on {top}:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// Runs a compiled bench on a trace (one line per request, written by `line`) and returns
/// its log.
pub fn simulate(
    vvp: &Path,
    dir: &Path,
    run: &ModelRun,
    line: impl Fn(&Req) -> String,
) -> Result<BenchLog, String> {
    simulate_with(vvp, dir, run, &[], line)
}

/// [`simulate`] with extra plusargs (`+name=value`) for the bench.
pub fn simulate_with(
    vvp: &Path,
    dir: &Path,
    run: &ModelRun,
    args: &[String],
    line: impl Fn(&Req) -> String,
) -> Result<BenchLog, String> {
    let mut text = String::new();
    for r in &run.trace {
        let _ = writeln!(text, "{}", line(r));
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
        .args(args)
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

/// Whether Icarus is here (else the test skips with its reason; a failure under CI=true).
pub fn icarus() -> bool {
    super::skip::tools(&["iverilog", "vvp"], "iverilog")
}

/// The seeds a bench runs: `SVO_TEST_SEED` first when set, then `fixed`.
pub fn seeds(fixed: &[u64]) -> Vec<u64> {
    let mut v = Vec::new();
    if std::env::var("SVO_TEST_SEED").is_ok() {
        v.push(super::test_seed());
    }
    v.extend_from_slice(fixed);
    v
}
