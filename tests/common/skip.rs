//! What a test needs that the repository does not hold — a tool (iverilog, verilator, yosys,
//! g++, make, the OpenVDB headers) or the shared `.vox` models beside the repository — checked
//! in one place, with one way to skip.
//!
//! When the thing is missing: under `CI=true` the test panics with the reason (CI installs every
//! tool and has `../shared`, so a missing one is a broken machine); otherwise the test skips and
//! writes `SKIPPED: <test>: <reason> (<how to get it>)` straight to the process's stderr. Not
//! with `eprintln!`: libtest captures the print macros of a passing test and shows nothing, so
//! the skip would read as a plain "ok". A write on `std::io::stderr()` bypasses that capture
//! and lands in the terminal output of `cargo test` (tests/skips.rs checks both behaviours).
//!
//! Every test that reads `../shared` or a scene whose assets live there goes through
//! [`shared_vox_dir`] or [`vox_scene`]; tests/skips.rs scans the test sources for any that
//! does not.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Whether missing tools and data fail (`CI=true`) instead of skipping.
pub fn ci() -> bool {
    std::env::var("CI").as_deref() == Ok("true")
}

/// The running test's name: libtest runs each test on a thread named after it.
pub fn test_name() -> String {
    std::thread::current()
        .name()
        .unwrap_or("<unnamed test>")
        .to_string()
}

/// The line a skip writes.
pub fn skipped_line(test: &str, reason: &str, how: &str) -> String {
    format!("SKIPPED: {test}: {reason} ({how})")
}

/// Something the running test needs is missing: panics under `ci`, else writes the
/// `SKIPPED` line to the process's stderr (uncaptured). The caller then returns.
pub fn missing_with(ci: bool, reason: &str, how: &str) {
    let line = skipped_line(&test_name(), reason, how);
    if ci {
        panic!("{line} — but CI=true, so this is a failure");
    }
    // One write of the whole line, so that lines of tests running in parallel do not mix.
    let mut err = std::io::stderr().lock();
    let _ = err.write_all(format!("{line}\n").as_bytes());
    let _ = err.flush();
}

/// [`missing_with`] under this process's `CI`.
pub fn missing(reason: &str, how: &str) {
    missing_with(ci(), reason, how);
}

/// The executable `name` on the `PATH`, if any.
pub fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// Whether every tool of `tools` is on the `PATH`; when not, [`missing`] names the first
/// missing one and the Debian package that brings it.
pub fn tools(tools: &[&str], package: &str) -> bool {
    tools_check(None, tools, package)
}

/// [`tools`] for a test that skips only `part` of itself without them (it runs the rest).
pub fn tools_for(part: &str, tools: &[&str], package: &str) -> bool {
    tools_check(Some(part), tools, package)
}

fn tools_check(part: Option<&str>, tools: &[&str], package: &str) -> bool {
    match tools.iter().find(|t| on_path(t).is_none()) {
        None => true,
        Some(t) => {
            let what = format!("`{t}` not found on PATH");
            let reason = match part {
                Some(p) => format!("{p} skipped (the rest ran): {what}"),
                None => what,
            };
            missing(
                &reason,
                &format!("apt-get install {package}; .ci/run installs it"),
            );
            false
        }
    }
}

/// Whether the header `path` exists; when not, [`missing`] names it and the package.
pub fn header(path: &str, package: &str) -> bool {
    if Path::new(path).is_file() {
        return true;
    }
    missing(
        &format!("{path} not found"),
        &format!("apt-get install {package}; .ci/run installs it"),
    );
    false
}

/// Where the shared MagicaVoxel models are expected: `../shared/data/vox` beside the
/// repository.
pub fn shared_vox_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/vox")
}

/// How to get the shared models.
const SHARED_HOW: &str =
    "put the shared data beside the repository: ../shared/data/vox/*.vox, e.g. ln -s /path/to/shared ../shared";

/// The shared MagicaVoxel models, or `None` after [`missing`] when the folder is absent.
pub fn shared_vox_dir() -> Option<PathBuf> {
    let dir = shared_vox_path();
    if dir.is_dir() {
        return Some(dir);
    }
    missing(
        &format!("the shared .vox models are missing at {}", dir.display()),
        SHARED_HOW,
    );
    None
}

/// [`shared_vox_dir`] for a test that runs without the models but skips `part` of itself:
/// the `SKIPPED` line says which part did not run.
pub fn shared_vox_dir_for(part: &str) -> Option<PathBuf> {
    let dir = shared_vox_path();
    if dir.is_dir() {
        return Some(dir);
    }
    missing(
        &format!(
            "{part} skipped (the rest ran): the shared .vox models are missing at {}",
            dir.display()
        ),
        SHARED_HOW,
    );
    None
}

/// The repository's scene `name` (relative to the repository, e.g. `scenes/vox_traffic.ron`)
/// whose assets are shared `.vox` models: `name` back, or `None` after [`missing`] when the
/// models are absent.
pub fn vox_scene(name: &'static str) -> Option<&'static str> {
    let dir = shared_vox_path();
    if dir.is_dir() {
        return Some(name);
    }
    missing(
        &format!(
            "{name} needs the shared .vox models, missing at {}",
            dir.display()
        ),
        SHARED_HOW,
    );
    None
}

/// [`vox_scene`] as a path in the repository.
pub fn vox_scene_path(name: &'static str) -> Option<PathBuf> {
    vox_scene(name).map(|n| Path::new(env!("CARGO_MANIFEST_DIR")).join(n))
}
