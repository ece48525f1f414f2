//! The `sim stress` command line: runs the cases (all, or those named), prints the table and
//! each case's description, writes `stress.md`, `stress.csv` and `stress.json` with `--out`,
//! and exits non-zero if a case fails (a silently wrong pixel) or ends with another verdict
//! than documented.

use super::cases::all;
use super::measure::{measure, CaseResult, Verdict};
use super::report::{csv, markdown};
use crate::output::writer::{refuse_stdout_folder, write_whole};
use anyhow::{bail, Context, Result};
use rtl_model::datapath::DatapathConfig;
use std::path::PathBuf;

/// Options of `sim stress`.
#[derive(Debug, Clone)]
pub struct StressCommand {
    /// Run only this case (repeatable); default: all. Names as in docs/stability.md.
    pub cases: Vec<String>,
    /// Folder for stress.md, stress.csv and stress.json (created if missing).
    pub out: Option<PathBuf>,
}

/// Runs the named cases (all if `names` is empty) with the default datapath.
pub fn run_cases(names: &[String]) -> Result<Vec<CaseResult>> {
    let specs = all();
    for n in names {
        if !specs.iter().any(|s| s.name == n) {
            let known: Vec<&str> = specs.iter().map(|s| s.name).collect();
            bail!("--case {n}: no such case (known: {})", known.join(", "));
        }
    }
    let cfg = DatapathConfig::default();
    specs
        .iter()
        .filter(|s| names.is_empty() || names.iter().any(|n| n == s.name))
        .map(|s| {
            crate::output::interrupt::check(|| format!("case {}", s.name), String::new)?;
            let input = (s.build)().map_err(|e| anyhow::anyhow!("case {}: {e}", s.name))?;
            measure(s.name, s.what, s.bound, s.expected, &input, &cfg)
                .map_err(|e| anyhow::anyhow!("case {}: {e}", s.name))
        })
        .collect()
}

/// Runs `sim stress`.
pub fn run_command(a: &StressCommand) -> Result<()> {
    if let Some(out) = &a.out {
        if out.exists() && !out.is_dir() {
            bail!("--out {} exists and is not a folder", out.display());
        }
    }
    let results = run_cases(&a.cases)?;
    for r in &results {
        println!("{:<18} {}", r.name, r.what);
    }
    println!();
    print!("{}", markdown(&results));
    if let Some(out) = &a.out {
        refuse_stdout_folder("--out", out)?;
        std::fs::create_dir_all(out)
            .with_context(|| format!("cannot create output folder {}", out.display()))?;
        let json = serde_json::to_string_pretty(&results)?;
        for (name, text) in [
            ("stress.md", markdown(&results)),
            ("stress.csv", csv(&results)),
            ("stress.json", json),
        ] {
            let p = out.join(name);
            write_whole(&p, text.as_bytes())?;
            println!("wrote {}", p.display());
        }
    }
    let failed: Vec<&str> = results
        .iter()
        .filter(|r| r.verdict == Verdict::Fail)
        .map(|r| r.name.as_str())
        .collect();
    let unexpected: Vec<&str> = results
        .iter()
        .filter(|r| r.verdict != r.expected)
        .map(|r| r.name.as_str())
        .collect();
    println!(
        "{} cases: {} pass, {} flagged, {} FAIL",
        results.len(),
        results
            .iter()
            .filter(|r| r.verdict == Verdict::Pass)
            .count(),
        results
            .iter()
            .filter(|r| r.verdict == Verdict::Flagged)
            .count(),
        failed.len()
    );
    if !failed.is_empty() {
        bail!("silently wrong pixels in: {}", failed.join(", "));
    }
    if !unexpected.is_empty() {
        bail!(
            "verdict differs from the documented one in: {}",
            unexpected.join(", ")
        );
    }
    Ok(())
}
