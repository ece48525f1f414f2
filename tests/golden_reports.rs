//! Golden reports: the JSON report of four cycle-model runs, wall-time fields stripped, must
//! equal the files in `tests/golden/` byte for byte. They pin every cycle count, stage row,
//! FIFO counter, memory statistic and pool counter the report prints, so a change to the
//! simulator's speed (data layout, idle-cycle skipping, parallel studies) cannot change what it
//! reports without failing here.
//!
//! The runs (docs/cycle-model.md §3.1): the default scene and hardware; the same on the default
//! of before issue 29's 32 × 8 pool (`configs/default_48x16.ron`); a small machine
//! (`tests/golden/small_hw.ron`: 4 walkers × 4 contexts, a 16 KiB 2-way cache, DRAM latency
//! 120, 8 MSHRs, an external hit buffer, 2 sphere units); and `scenes/vox_traffic.ron` (skipped
//! with a reason when the shared `.vox` models are missing, a failure under `CI=true`).
//!
//! Regenerate after an intended change of the reports (e.g. new datapath formats):
//! `SVO_BLESS_GOLDEN=1 cargo test --test golden_reports`, then review `git diff tests/golden`.

mod common;

use common::process::{run_sim, Scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Duration;

const LIMIT: Duration = Duration::from_secs(600);

/// Whether a report key holds a wall time or a rate derived from one (the same rule as the
/// byte-identity scripts: `wall`, `_ms`, `_s`, `per_s`, `ms_per`, `mrays`, `seconds`).
fn is_wall_key(k: &str) -> bool {
    k.contains("wall")
        || k.ends_with("_ms")
        || k.ends_with("_s")
        || k.contains("per_s")
        || k.contains("ms_per")
        || k.contains("mrays")
        || k.contains("seconds")
}

/// The report without its wall-time fields.
fn strip(v: Value) -> Value {
    match v {
        Value::Object(m) => Value::Object(
            m.into_iter()
                .filter(|(k, _)| !is_wall_key(k))
                .map(|(k, v)| (k, strip(v)))
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.into_iter().map(strip).collect()),
        v => v,
    }
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `sim args --report-json …` in the repository and compares the stripped report with
/// `tests/golden/NAME.json` (or writes it when `SVO_BLESS_GOLDEN=1`).
fn check(name: &str, args: &[&str]) {
    let t = Scratch::new("golden", name);
    let json = t.p("report.json");
    let mut all: Vec<&str> = args.to_vec();
    // The thread count is in the report's options: fixed so the file does not depend on the
    // machine's cores.
    all.extend(["--threads", "2", "--no-png", "--report-json", &json]);
    let r = run_sim(&all, Some(&repo()), LIMIT);
    assert!(
        r.status.success(),
        "sim {all:?}\n{}\n{}",
        r.stdout,
        r.stderr
    );
    let rep: Value = serde_json::from_str(&std::fs::read_to_string(&json).expect("report"))
        .expect("report is JSON");
    let mut got = serde_json::to_string_pretty(&strip(rep)).expect("serialise");
    got.push('\n');
    let golden = repo().join("tests/golden").join(format!("{name}.json"));
    if std::env::var("SVO_BLESS_GOLDEN").as_deref() == Ok("1") {
        std::fs::write(&golden, &got).expect("write the golden report");
        eprintln!("wrote {}", golden.display());
        return;
    }
    let want = std::fs::read_to_string(&golden).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (regenerate with SVO_BLESS_GOLDEN=1 cargo test --test golden_reports)",
            golden.display()
        )
    });
    if got != want {
        let line = got
            .lines()
            .zip(want.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(got.lines().count().min(want.lines().count()));
        let show = |s: &str| {
            s.lines()
                .skip(line.saturating_sub(3))
                .take(7)
                .collect::<Vec<_>>()
                .join("\n")
        };
        panic!(
            "{name}: the report differs from {} from line {}:\n--- golden\n{}\n--- this run\n{}",
            golden.display(),
            line + 1,
            show(&want),
            show(&got)
        );
    }
}

fn small_hw() -> String {
    Path::new("tests/golden/small_hw.ron").display().to_string()
}

/// The default scene's run of both default reports: 640×384, 3 frames, depth 10.
const DEFAULT_RUN: [&str; 8] = [
    "--width", "640", "--height", "384", "--frames", "3", "--depth", "10",
];

#[test]
fn default_run_report_is_golden() {
    check("default", &DEFAULT_RUN);
}

/// The default hardware before issue 29 moved the pool to 32 walkers of 8 contexts, from its
/// named file: `tests/golden/default_48x16.json` is `default.json` of that time byte for byte
/// (the report does not name the hardware file), so the file reproduces the default of then.
#[test]
fn default_48x16_report_is_golden() {
    let mut args = vec!["--hw", "configs/default_48x16.ron"];
    args.extend(DEFAULT_RUN);
    check("default_48x16", &args);
}

#[test]
fn small_hardware_report_is_golden() {
    let hw = small_hw();
    check(
        "small_hw",
        &[
            "--hw", &hw, "--width", "320", "--height", "192", "--frames", "3", "--depth", "9",
        ],
    );
}

#[test]
fn vox_traffic_report_is_golden() {
    // Relative to the repository, as the golden report records it.
    let Some(scene) = common::skip::vox_scene("scenes/vox_traffic.ron") else {
        return;
    };
    check(
        "vox_traffic",
        &[
            "--scene", scene, "--width", "320", "--height", "192", "--frames", "4",
        ],
    );
}
