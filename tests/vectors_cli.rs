//! `sim vectors` on bad input: a bad `--count`, `--width`, `--frame` or `--depth`, an
//! `--out` that is a file or lies under one, a malformed or missing scene — each a clear
//! error naming the problem, a non-zero exit, and nothing written (the output folder is not
//! even created). Plus the happy path's table and `--help`.

mod common;
mod vector_files;

use common::process::run_sim;
use std::path::Path;
use std::time::Duration;
use vector_files::Tmp;

const TIMEOUT: Duration = Duration::from_secs(120);

/// Every file below `dir`.
fn files_below(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                out.extend(files_below(&p));
            } else {
                out.push(p.display().to_string());
            }
        }
    }
    out
}

/// Runs `sim vectors args`, expects a clean failure whose stderr contains each of `expect`,
/// and that nothing but `keep` exists in `t` afterwards.
fn expect_failure(t: &Tmp, args: &[&str], expect: &[&str], keep: &[&str]) {
    let mut a = vec!["vectors"];
    a.extend_from_slice(args);
    let r = run_sim(&a, None, TIMEOUT);
    let ctx = format!(
        "sim {a:?}\nexit {:?}\nstdout:\n{}\nstderr:\n{}",
        r.status, r.stdout, r.stderr
    );
    assert!(
        r.status.code().is_some_and(|c| c != 0),
        "no clean failure\n{ctx}"
    );
    assert!(!r.stderr.contains("panicked"), "{ctx}");
    for e in expect {
        assert!(
            r.stderr.contains(e),
            "the message does not say {e:?}\n{ctx}"
        );
    }
    let left: Vec<String> = files_below(&t.dir)
        .into_iter()
        .filter(|p| !keep.iter().any(|k| p.ends_with(k)))
        .collect();
    assert!(
        left.is_empty(),
        "files written by a failed run: {left:?}\n{ctx}"
    );
    assert!(
        !t.dir.join("v").exists(),
        "the output folder was created\n{ctx}"
    );
}

#[test]
fn bad_counts() {
    let t = Tmp::new("cli_count");
    let out = t.p("v");
    for bad in ["0", "-3", "abc", "1000001", "99999999999999999999"] {
        let arg = format!("--count={bad}");
        expect_failure(&t, &["--out", &out, &arg], &["--count", bad], &[]);
    }
}

#[test]
fn bad_frame_options() {
    let t = Tmp::new("cli_frame");
    let out = t.p("v");
    expect_failure(
        &t,
        &["--out", &out, "--width", "0"],
        &["--width 0 is out of range"],
        &[],
    );
    expect_failure(
        &t,
        &["--out", &out, "--height", "513"],
        &["--height 513 is out of range"],
        &[],
    );
    expect_failure(
        &t,
        &["--out", &out, "--frame", "48"],
        &["--frame 48 is out of range", "48 frames"],
        &[],
    );
    expect_failure(
        &t,
        &["--out", &out, "--depth", "0"],
        &["--depth 0 is out of range"],
        &[],
    );
    expect_failure(&t, &["--count", "5"], &["--out"], &[]);
}

#[test]
fn unwritable_out() {
    let t = Tmp::new("cli_out");
    let file = t.dir.join("a_file");
    std::fs::write(&file, b"keep me").expect("write a file");
    let f = file.to_str().expect("UTF-8").to_string();
    expect_failure(
        &t,
        &["--out", &f, "--count", "5", "--depth", "3"],
        &["is a file, not a folder"],
        &["a_file"],
    );
    assert_eq!(
        std::fs::read(&file).expect("read"),
        b"keep me",
        "the file was changed"
    );
    let under = format!("{f}/v");
    expect_failure(
        &t,
        &["--out", &under, "--count", "5", "--depth", "3"],
        &["cannot write", &under],
        &["a_file"],
    );
}

#[test]
fn bad_scenes() {
    let t = Tmp::new("cli_scene");
    let out = t.p("v");
    let bad = t.dir.join("bad.ron");
    std::fs::write(&bad, "(resolution: (64, 40) frames: 3)").expect("write a scene");
    let b = bad.to_str().expect("UTF-8").to_string();
    expect_failure(
        &t,
        &["--out", &out, "--scene", &b],
        &[&b, "malformed scene"],
        &["bad.ron"],
    );
    let missing = t.p("missing.ron");
    expect_failure(
        &t,
        &["--out", &out, "--scene", &missing],
        &["cannot read scene file", &missing],
        &["bad.ron"],
    );
}

#[test]
fn help_and_happy_path() {
    let r = run_sim(&["vectors", "--help"], None, TIMEOUT);
    assert!(r.status.success());
    for opt in [
        "--out", "--scene", "--count", "--seed", "--width", "--height", "--depth", "--frame",
    ] {
        assert!(
            r.stdout.contains(opt),
            "--help does not list {opt}:\n{}",
            r.stdout
        );
    }
    let top = run_sim(&["--help"], None, TIMEOUT);
    assert!(top.stdout.contains("vectors"), "{}", top.stdout);
    let t = Tmp::new("cli_happy");
    let out = t.p("v");
    let r = run_sim(
        &[
            "vectors", "--out", &out, "--count", "10", "--depth", "3", "--width", "8", "--height",
            "6",
        ],
        None,
        TIMEOUT,
    );
    assert!(r.status.success(), "{}", r.stderr);
    for unit in [
        "raygen",
        "sphere",
        "sqrt",
        "sorter",
        "transform",
        "reciprocal",
        "walker",
        "hit_record",
        "frame_pixels",
    ] {
        assert!(
            r.stdout.lines().any(|l| l.trim_start().starts_with(unit)),
            "no line for {unit}:\n{}",
            r.stdout
        );
        assert!(t.dir.join("v").join(format!("{unit}.hex")).is_file());
    }
    let leftovers: Vec<String> = files_below(&t.dir)
        .into_iter()
        .filter(|p| p.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}
