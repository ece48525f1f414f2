//! Bad command lines of the `sim` binary: depth 0/21/256, resolution 0 / too large and zero
//! frames or threads on the command line; unreadable scene paths; output paths in missing
//! folders or onto an existing file; and a depth too deep for memory (refused or rendered,
//! never a panic, never slow).
//!
//! What a failure must look like (exit code, message, nothing half-written) is checked by
//! `tests/common/bad_input.rs`. Bad scene files are in `tests/bad_input_scene.rs`, `.vox`
//! assets in `tests/bad_input_vox.rs`.

use std::path::PathBuf;
use std::time::Instant;

mod common;
use common::bad_input::{args, expect_failure, files_below, small_default, Tmp, TIMEOUT};
use common::process::run_sim;

// ---------------------------------------------------------------------------------------------
// 1. Depth out of range

#[test]
fn depth_zero_on_command_line() {
    let t = Tmp::new("depth_zero_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "0",
    ]);
    expect_failure(&t, &a, &["--depth", "depth 0", "out of range"]);
}

#[test]
fn depth_21_on_command_line() {
    let t = Tmp::new("depth_21_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "21",
    ]);
    expect_failure(&t, &a, &["--depth", "depth 21", "out of range"]);
}

#[test]
fn depth_256_on_command_line() {
    let t = Tmp::new("depth_256_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "256",
    ]);
    expect_failure(&t, &a, &["--depth", "256"]);
}

// ---------------------------------------------------------------------------------------------
// 2. Resolution

#[test]
fn width_zero_on_command_line() {
    let t = Tmp::new("width_zero_on_command_line");
    let a = args(&[
        "--width", "0", "--height", "24", "--frames", "1", "--depth", "5",
    ]);
    expect_failure(&t, &a, &["command line", "resolution 0x24", "out of range"]);
}

#[test]
fn height_zero_on_command_line() {
    let t = Tmp::new("height_zero_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "0", "--frames", "1", "--depth", "5",
    ]);
    expect_failure(&t, &a, &["command line", "resolution 32x0", "out of range"]);
}

#[test]
fn huge_resolution_on_command_line() {
    let t = Tmp::new("huge_resolution_on_command_line");
    let a = args(&[
        "--width", "100000", "--height", "100000", "--frames", "1", "--depth", "5",
    ]);
    expect_failure(
        &t,
        &a,
        &["command line", "resolution 100000x100000", "out of range"],
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Frames and threads

#[test]
fn frames_zero_on_command_line() {
    let t = Tmp::new("frames_zero_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "0", "--depth", "5",
    ]);
    expect_failure(&t, &a, &["--frames 0", "out of range"]);
}

#[test]
fn threads_zero() {
    let t = Tmp::new("threads_zero");
    let a = small_default(&["--threads", "0"]);
    expect_failure(&t, &a, &["--threads 0", "out of range"]);
}

// ---------------------------------------------------------------------------------------------
// 4. Unreadable scene paths

#[test]
fn scene_path_does_not_exist() {
    let t = Tmp::new("scene_path_does_not_exist");
    let missing = t.p("no_such_scene.ron");
    expect_failure(
        &t,
        &args(&["--scene", &missing]),
        &["cannot read scene file", &missing],
    );
}

#[test]
fn scene_path_is_a_directory() {
    let t = Tmp::new("scene_path_is_a_directory");
    let dir = t.p("a_folder.ron");
    std::fs::create_dir_all(&dir).unwrap();
    expect_failure(
        &t,
        &args(&["--scene", &dir]),
        &["cannot read scene file", &dir],
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Output paths

#[test]
fn report_json_in_missing_folder() {
    let t = Tmp::new("report_json_in_missing_folder");
    let report = t.p("no_such_folder/report.json");
    let a = small_default(&["--report-json", &report]);
    expect_failure(&t, &a, &["--report-json", &report, "does not exist"]);
    assert!(!t.dir.join("out").exists() || files_below(&t.dir.join("out")).is_empty());
}

#[test]
fn dump_hits_in_missing_folder() {
    let t = Tmp::new("dump_hits_in_missing_folder");
    let dump = t.p("no_such_folder/hits.bin");
    let a = small_default(&["--dump-hits", &dump]);
    expect_failure(&t, &a, &["--dump-hits", &dump, "does not exist"]);
}

#[test]
fn out_is_an_existing_file() {
    let t = Tmp::new("out_is_an_existing_file");
    let out = t.write("out_file", "not a folder");
    let a = small_default(&["--out", &out]);
    expect_failure(&t, &a, &[&out]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "not a folder");
}

// ---------------------------------------------------------------------------------------------
// 6. A depth too large for memory

#[test]
fn depth_too_large_for_memory_is_refused_or_rendered() {
    let t = Tmp::new("depth_too_large_for_memory");
    // The reference walks depth-16 SDF assets implicitly; the fixed-point and cycle models
    // refuse them (tests/cycle_cli.rs).
    let mut a = args(&[
        "--width",
        "32",
        "--height",
        "24",
        "--frames",
        "1",
        "--depth",
        "16",
        "--model",
        "reference",
    ]);
    for (flag, name) in [
        ("--out", "out"),
        ("--report-json", "report.json"),
        ("--dump-hits", "hits.bin"),
    ] {
        a.push(flag.into());
        a.push(t.p(name));
    }
    let start = Instant::now();
    let r = run_sim(&a, None, TIMEOUT);
    let ctx = format!(
        "sim {a:?}\nexit: {:?} after {:.1} s\nstdout:\n{}\nstderr:\n{}",
        r.status,
        start.elapsed().as_secs_f64(),
        r.stdout,
        r.stderr
    );
    assert!(
        r.status.code().is_some(),
        "sim was killed by a signal\n{ctx}"
    );
    assert!(!r.stderr.contains("panicked"), "sim panicked\n{ctx}");
    if r.status.success() {
        assert!(t.dir.join("out/frame_0000.png").is_file(), "no PNG\n{ctx}");
        assert!(t.dir.join("report.json").is_file(), "no report\n{ctx}");
        assert!(t.dir.join("hits.bin").is_file(), "no dump\n{ctx}");
    } else {
        assert!(
            r.stderr.contains("depth 16") && r.stderr.contains("GiB"),
            "the refusal does not say which depth and how much memory\n{ctx}"
        );
        assert!(!t.dir.join("report.json").exists(), "report left\n{ctx}");
        assert!(!t.dir.join("hits.bin").exists(), "dump left\n{ctx}");
        let left: Vec<PathBuf> = files_below(&t.dir)
            .into_iter()
            .filter(|p| {
                let n = p.file_name().unwrap().to_string_lossy();
                n.ends_with(".png") || n.ends_with(".tmp")
            })
            .collect();
        assert!(left.is_empty(), "files left behind: {left:?}\n{ctx}");
    }
}
