//! Running the cocotb benches of `testbench/cocotb/` from the tests: the venv with the Python
//! tools of `testbench/requirements.txt` (`SVO_VENV`, default `/opt/svo-venv`, which `.ci/run`
//! creates), `run.py BENCH KEY=VALUE…`, and a bench's closing `N passed, N failed` line.
//!
//! Pipeline position: none; shared by tests/cocotb_units.rs (the unit benches, the register
//! block, FuseSoC) and tests/cocotb_benches.rs (svo_top, the whole accelerator).

use super::skip;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The venv's folder, if it holds the tools (`bin/python`, `bin/fusesoc`, `bin/peakrdl`);
/// else `None` after [`skip::missing`].
pub fn venv() -> Option<PathBuf> {
    let dir = std::env::var_os("SVO_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/opt/svo-venv"));
    let missing: Vec<&str> = ["python", "fusesoc", "peakrdl"]
        .into_iter()
        .filter(|t| !dir.join("bin").join(t).is_file())
        .collect();
    if missing.is_empty() && skip::tools(&["make", "g++", "perl"], "make g++ perl") {
        return Some(dir);
    }
    if !missing.is_empty() {
        skip::missing(
            &format!(
                "the cocotb venv at {} lacks {}",
                dir.display(),
                missing.join(", ")
            ),
            "python3 -m venv /opt/svo-venv && /opt/svo-venv/bin/pip install -r testbench/requirements.txt (or set SVO_VENV); .ci/run does",
        );
    }
    None
}

/// What a run printed (stdout then stderr) and whether it exited 0.
pub fn run(cmd: &mut Command) -> (bool, String) {
    let out = cmd.output().unwrap_or_else(|e| panic!("run {cmd:?}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// `run.py BENCH ENV...` in the venv: (exit 0, output, wall seconds).
pub fn bench(venv: &Path, name: &str, env: &[&str]) -> (bool, String, f64) {
    let t = Instant::now();
    let (ok, text) = run(Command::new(venv.join("bin/python"))
        .arg(repo().join("testbench/cocotb/run.py"))
        .arg(name)
        .args(env)
        .env(
            "SVO_COCOTB_BUILD",
            PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cocotb"),
        ));
    (ok, text, t.elapsed().as_secs_f64())
}

/// The (passed, failed) of the bench's closing line `<prefix>: N passed, N failed`.
pub fn tally(text: &str, prefix: &str) -> (u64, u64) {
    let line = text
        .lines()
        .find(|l| l.starts_with(prefix) && l.ends_with(" failed") && l.contains(" passed, "))
        .unwrap_or_else(|| panic!("no \"{prefix} N passed, N failed\" line:\n{text}"));
    let n: Vec<u64> = line[prefix.len()..]
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect();
    (n[0], n[1])
}
