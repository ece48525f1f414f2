//! How a test that needs a missing tool or the shared data skips (tests/common/skip.rs): the
//! `SKIPPED` line reaches the terminal output of a test binary that captures output as
//! `cargo test` does, the test passes, and under `CI=true` the same skip is a failure. Each is
//! checked by running this binary again on the ignored [`probe`] test, whose tool cannot exist.
//!
//! And every test source that reads the shared data or a scene whose assets live there goes
//! through the helper: a scan of tests/ (shown finding a direct read in a corrupted source).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A tool that no machine has.
const NO_TOOL: &str = "svo-sim-no-such-tool";

/// Set in the child process that runs [`probe`].
const PROBE_ENV: &str = "SVO_SKIP_PROBE";

/// Needs [`NO_TOOL`]; run only as a child of the tests below (it is ignored otherwise, since
/// on its own it can only skip).
#[test]
#[ignore = "run by a_skip_is_one_visible_line_and_passes and a_skip_fails_under_ci"]
fn probe() {
    assert_eq!(
        std::env::var(PROBE_ENV).as_deref(),
        Ok("1"),
        "run by the tests of tests/skips.rs only"
    );
    if !common::skip::tools(&[NO_TOOL], "no-such-package") {
        return;
    }
    panic!("{NO_TOOL} was found on PATH");
}

/// This test binary, run on [`probe`] alone with output captured (libtest's default), `CI`
/// set to `ci` or removed.
fn run_probe(ci: Option<&str>) -> Output {
    let exe = std::env::current_exe().expect("the test binary's path");
    let mut c = Command::new(exe);
    c.args(["probe", "--exact", "--ignored", "--test-threads=1"])
        .env(PROBE_ENV, "1");
    match ci {
        Some(v) => c.env("CI", v),
        None => c.env_remove("CI"),
    };
    c.output().expect("run the test binary")
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn a_skip_is_one_visible_line_and_passes() {
    let o = run_probe(None);
    let (out, err) = text(&o);
    assert!(
        o.status.success(),
        "the skipping probe failed:\n{out}\n{err}"
    );
    let want = format!(
        "SKIPPED: probe: `{NO_TOOL}` not found on PATH (apt-get install no-such-package; .ci/run installs it)"
    );
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("SKIPPED")).collect();
    assert_eq!(lines, [want.as_str()], "stderr:\n{err}\nstdout:\n{out}");
    assert!(out.contains("test probe ... ok"), "{out}");
}

#[test]
fn a_skip_fails_under_ci() {
    let o = run_probe(Some("true"));
    let (out, err) = text(&o);
    assert!(
        !o.status.success(),
        "the probe passed under CI=true:\n{out}\n{err}"
    );
    assert!(
        out.contains(&format!("SKIPPED: probe: `{NO_TOOL}` not found on PATH"))
            && out.contains("but CI=true, so this is a failure"),
        "the failure does not give the reason:\n{out}\n{err}"
    );
    // Any other value of CI is a local run.
    let o = run_probe(Some("1"));
    assert!(o.status.success(), "{:?}", text(&o));
}

/// The scenes of scenes/ whose assets are the shared models (they name the shared folder in
/// a path).
fn shared_scenes(repo: &Path) -> Vec<String> {
    let marker = concat!("../", "shared", "/");
    let mut v: Vec<String> = std::fs::read_dir(repo.join("scenes"))
        .expect("scenes/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .filter(|p| {
            std::fs::read_to_string(p).is_ok_and(|t| {
                t.lines()
                    .any(|l| !l.trim_start().starts_with("//") && l.contains(marker))
            })
        })
        .filter_map(|p| Some(p.file_name()?.to_str()?.to_string()))
        .collect();
    v.sort();
    v
}

/// Test sources (`name`, text) that reach the shared data without the helper: a code line
/// naming the shared data folder, or a file that names a shared scene and never calls
/// `vox_scene`/`vox_scene_path`/`shared_vox_dir`/`shared_vox_dir_for`. Comment lines are not
/// code.
fn offenders(files: &[(String, String)], scenes: &[String]) -> Vec<String> {
    let folder = concat!("shared", "/data");
    let mut bad = Vec::new();
    for (name, text) in files {
        let code: Vec<&str> = text
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect();
        for l in &code {
            if l.contains(folder) {
                bad.push(format!("{name}: `{}`", l.trim()));
            }
        }
        let checks = code
            .iter()
            .any(|l| l.contains("vox_scene") || l.contains("shared_vox_dir"));
        for s in scenes {
            if !checks && code.iter().any(|l| l.contains(s.as_str())) {
                bad.push(format!("{name}: uses {s} without common::skip"));
            }
        }
    }
    bad
}

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir)
        .expect("read a tests folder")
        .flatten()
    {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn every_test_reaching_the_shared_data_goes_through_the_helper() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes = shared_scenes(repo);
    assert!(
        scenes.iter().any(|s| s == "vox_traffic.ron"),
        "scenes/vox_traffic.ron no longer names the shared models? {scenes:?}"
    );
    let mut paths = Vec::new();
    rust_files(&repo.join("tests"), &mut paths);
    rust_files(&repo.join("rtl_model/tests"), &mut paths);
    let helper = repo.join("tests/common/skip.rs");
    let files: Vec<(String, String)> = paths
        .iter()
        .filter(|p| **p != helper)
        .map(|p| {
            let text = std::fs::read_to_string(p).expect("read a test source");
            (
                p.strip_prefix(repo).unwrap_or(p).display().to_string(),
                text,
            )
        })
        .collect();
    assert!(files.len() > 40, "only {} test sources found", files.len());
    let bad = offenders(&files, &scenes);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The scan finds a direct read of the shared folder and an unchecked shared scene, and
/// accepts the same uses through the helper and in comments.
#[test]
fn the_scan_finds_a_direct_read() {
    let scenes = vec!["vox_traffic.ron".to_string()];
    let folder = concat!("shared", "/data");
    let direct = format!(
        "// the models in ../{folder}/vox\nfn t() {{\n    let d = Path::new(\"../{folder}/vox\");\n}}\n"
    );
    let unchecked = "fn t() {\n    load(\"scenes/vox_traffic.ron\");\n}\n".to_string();
    let checked = "fn t() {\n    let Some(p) = common::skip::vox_scene_path(\"scenes/vox_traffic.ron\") else { return };\n}\n".to_string();
    let files = vec![
        ("direct.rs".to_string(), direct),
        ("unchecked.rs".to_string(), unchecked),
        ("checked.rs".to_string(), checked),
    ];
    assert_eq!(
        offenders(&files, &scenes),
        [
            format!("direct.rs: `let d = Path::new(\"../{folder}/vox\");`"),
            "unchecked.rs: uses vox_traffic.ron without common::skip".to_string(),
        ]
    );
}
