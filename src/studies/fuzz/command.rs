//! `sim fuzz`: the seeded mutation fuzzer of the input parsers — runs N mutated inputs per
//! target, prints a table of outcomes (accepted, rejected by kind, panics, hangs, slowest
//! input, peak memory), saves every panicking or hanging input with `--save`, and exits
//! non-zero if any input panicked or hung. `--replay FILE` runs one saved input again.
//!
//! Pipeline position: none — a check of what stands in front of the pipeline (docs/fuzz.md).

use super::corpus::seeds;
use super::runner::{peak_rss_bytes, run, FuzzOptions, TargetReport};
use super::targets::Target;
use crate::output::writer::write_whole;
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Most inputs per target one run accepts (about a day at the slowest target's pace).
pub const MAX_INPUTS: u64 = 100_000_000;

/// Options of `sim fuzz`.
#[derive(Clone, Debug)]
pub struct FuzzCommand {
    /// Targets to fuzz (all if empty).
    pub targets: Vec<Target>,
    /// Mutated inputs per target.
    pub inputs: u64,
    /// Seed of the mutations.
    pub seed: u64,
    /// Time limit per input.
    pub time_limit: Duration,
    /// Folder of `.vox` seed models (the shared models); skipped with a note if absent.
    pub vox_dir: PathBuf,
    /// Leave out `.vox` seeds larger than this many bytes.
    pub max_vox_bytes: u64,
    /// Folder to save panicking or hanging inputs into.
    pub save: Option<PathBuf>,
    /// Run this one input (with the first of `targets`) instead of fuzzing.
    pub replay: Option<PathBuf>,
    /// No progress line.
    pub quiet: bool,
}

/// Everything a fuzz run found, for the caller to judge.
#[derive(Debug)]
pub struct FuzzSummary {
    /// Per target.
    pub reports: Vec<(Target, TargetReport)>,
    /// Peak resident size of the process, bytes.
    pub peak_rss: Option<u64>,
    /// Wall time of the whole run.
    pub wall: Duration,
}

impl FuzzSummary {
    /// Inputs that panicked, over all targets.
    pub fn panics(&self) -> usize {
        self.reports.iter().map(|(_, r)| r.panics.len()).sum()
    }

    /// Inputs that hung (0 or 1: the run stops at the first).
    pub fn hangs(&self) -> usize {
        self.reports
            .iter()
            .filter(|(_, r)| r.hang.is_some())
            .count()
    }

    /// Inputs run, over all targets.
    pub fn inputs(&self) -> u64 {
        self.reports.iter().map(|(_, r)| r.inputs).sum()
    }
}

fn check(c: &FuzzCommand) -> Result<()> {
    if c.inputs > MAX_INPUTS {
        bail!(
            "--inputs {}: at most {MAX_INPUTS} per target in one run",
            c.inputs
        );
    }
    if c.time_limit.is_zero() {
        bail!("--time-limit-ms must be positive");
    }
    if let Some(s) = &c.save {
        if s.exists() && !s.is_dir() {
            bail!("--save {} exists and is not a folder", s.display());
        }
    }
    Ok(())
}

/// Runs the fuzzer as `c` says and returns what it found (the caller prints and judges).
pub fn fuzz(c: &FuzzCommand) -> Result<FuzzSummary> {
    check(c)?;
    let targets = if c.targets.is_empty() {
        Target::ALL.to_vec()
    } else {
        c.targets.clone()
    };
    let vox_dir = c.vox_dir.is_dir().then_some(c.vox_dir.as_path());
    if vox_dir.is_none() && targets.contains(&Target::Vox) && !c.quiet {
        eprintln!(
            "note: {} is not a folder; the .vox target uses its two built-in seeds only",
            c.vox_dir.display()
        );
    }
    let mut corpus = Vec::new();
    for t in &targets {
        corpus.push((*t, seeds(*t, vox_dir, c.max_vox_bytes)?));
    }
    let opts = FuzzOptions {
        inputs: c.inputs,
        seed: c.seed,
        time_limit: c.time_limit,
    };
    let start = Instant::now();
    let mut last = Instant::now();
    let quiet = c.quiet;
    let reports = run(&corpus, &opts, |t, done, total| {
        if !quiet && (done == total || last.elapsed() >= Duration::from_secs(2)) {
            last = Instant::now();
            eprint!("\r{:<9} {done}/{total} inputs   ", t.name());
            if done == total {
                eprintln!();
            }
            let _ = std::io::stderr().flush();
        }
    })
    .context("cannot start the fuzz worker thread")?;
    Ok(FuzzSummary {
        reports,
        peak_rss: peak_rss_bytes(),
        wall: start.elapsed(),
    })
}

/// The outcome table and the findings, as `sim fuzz` prints them.
pub fn summary_text(s: &FuzzSummary, seed: u64) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{:<9} {:>9} {:>9} {:>9} {:>6} {:>6} {:>6} {:>10} {:>9}",
        "target", "inputs", "accepted", "rejected", "kinds", "panics", "hangs", "slowest", "mean"
    );
    for (t, r) in &s.reports {
        let mean_us = if r.inputs > 0 {
            r.total.as_secs_f64() * 1e6 / r.inputs as f64
        } else {
            0.0
        };
        let _ = writeln!(
            o,
            "{:<9} {:>9} {:>9} {:>9} {:>6} {:>6} {:>6} {:>8.1}ms {:>7.0}µs",
            t.name(),
            r.inputs,
            r.accepted,
            r.rejected,
            r.error_kinds.len(),
            r.panics.len(),
            usize::from(r.hang.is_some()),
            r.slowest.as_secs_f64() * 1e3,
            mean_us
        );
    }
    let _ = writeln!(
        o,
        "{} inputs, {} panics, {} hangs, seed {seed}, {:.1} s{}",
        s.inputs(),
        s.panics(),
        s.hangs(),
        s.wall.as_secs_f64(),
        s.peak_rss
            .map(|b| format!(", peak resident memory {:.0} MiB", b as f64 / 1048576.0))
            .unwrap_or_default()
    );
    for (t, r) in &s.reports {
        for seed_err in &r.seeds_rejected {
            let _ = writeln!(
                o,
                "warning: {} seed rejected unmutated: {seed_err}",
                t.name()
            );
        }
        let mut kinds: Vec<_> = r.error_kinds.iter().collect();
        kinds.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        if !kinds.is_empty() {
            let _ = writeln!(o, "{}: most frequent rejections", t.name());
            for (k, n) in kinds.iter().take(5) {
                let _ = writeln!(o, "  {n:>7}  {k}");
            }
        }
        for f in r.panics.iter().chain(&r.hang) {
            let _ = writeln!(o, "FOUND {} input {}: {}", t.name(), f.index, f.message);
        }
    }
    o
}

/// Saves every panicking or hanging input as `TARGET-INDEX.bin` with the message beside it
/// in `TARGET-INDEX.txt`; returns the files written.
pub fn save_findings(s: &FuzzSummary, dir: &std::path::Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (t, r) in &s.reports {
        for f in r.panics.iter().chain(&r.hang) {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
            let stem = format!("{}-{}", t.name(), f.index);
            let bin = dir.join(format!("{stem}.bin"));
            write_whole(&bin, &f.input)?;
            let txt = dir.join(format!("{stem}.txt"));
            write_whole(&txt, format!("{}\n", f.message).as_bytes())?;
            written.push(bin);
        }
    }
    Ok(written)
}

/// Runs `sim fuzz`: prints the table, saves findings, and fails if any input panicked or hung.
pub fn run_command(c: &FuzzCommand) -> Result<()> {
    if let Some(file) = &c.replay {
        let target = match c.targets.as_slice() {
            [t] => *t,
            _ => bail!("--replay needs exactly one --target"),
        };
        // A replayed input is one the fuzzer saved: never above the largest input a target
        // takes (the `.vox` default cap; RON files have the smaller configuration cap).
        let cap = match target {
            Target::Vox => crate::input::Cap::vox(crate::input::DEFAULT_VOX_CAP_BYTES),
            _ => crate::input::Cap::config("fuzz replay"),
        };
        let input = crate::input::read_bytes(file, cap)?;
        return match target.run(&input) {
            Ok(()) => {
                println!("{}: accepted", file.display());
                Ok(())
            }
            Err(e) => {
                println!("{}: rejected: {e}", file.display());
                Ok(())
            }
        };
    }
    let s = fuzz(c)?;
    print!("{}", summary_text(&s, c.seed));
    if let Some(dir) = &c.save {
        for p in save_findings(&s, dir)? {
            println!("saved {}", p.display());
        }
    }
    if s.panics() + s.hangs() > 0 {
        bail!(
            "{} of {} inputs panicked or hung (replay one with --replay FILE --target T)",
            s.panics() + s.hangs(),
            s.inputs()
        );
    }
    Ok(())
}
