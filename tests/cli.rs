//! Happy paths of the `sim` binary (`CARGO_BIN_EXE_sim`), on the default scene at a tiny size.
//!
//! Checks: `--help` lists the options; a 64x40, 3-frame run prints a line per frame and a
//! summary, writes three 64x40 PNGs, a JSON report with per-frame counters (one ray per pixel)
//! and a binary hit dump that follows `src/output/dump.rs` (header, 40-byte records, misses
//! with instance 65535 and t = +inf); the CSV dump has a header and one line per pixel and
//! frame, agreeing with the binary one; two identical runs give byte-identical PNGs and dumps;
//! `--no-hit-buffer` changes no pixel and reports no reuse, while the hit buffer reuses pixels
//! from the second frame on; `--scene scenes/car.ron` renders like the embedded default; and
//! `sim bench` prints its speed in M rays/s, and with `--model cycle --sample` the sampled
//! model's estimates.
//!
//! This file holds the shared helpers and the run-wide checks; `cli/dumps.rs` reads the hit
//! dumps back, `cli/refusals.rs` has what a run refuses or warns about.

use std::path::{Path, PathBuf};
use std::time::Duration;

mod common;
#[path = "cli/dumps.rs"]
mod dumps;
#[path = "cli/refusals.rs"]
mod refusals;

use common::process::{run_sim, Run};

// ---------------------------------------------------------------------------------------------
// Helpers

const TIMEOUT: Duration = Duration::from_secs(120);
const W: u32 = 64;
const H: u32 = 40;
const FRAMES: u32 = 3;

/// A scratch folder, unique per test and process, removed when dropped.
struct Tmp {
    dir: PathBuf,
}

impl Tmp {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("svo_sim_cli_{test}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the scratch folder");
        Self { dir }
    }

    fn p(&self, name: &str) -> String {
        self.dir
            .join(name)
            .to_str()
            .expect("temporary paths are UTF-8")
            .to_string()
    }

    fn read(&self, name: &str) -> Vec<u8> {
        std::fs::read(self.dir.join(name))
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", self.p(name)))
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Runs and requires success.
fn run_ok(args: &[&str], cwd: &Path) -> Run {
    let r = run_sim(args, Some(cwd), TIMEOUT);
    assert!(
        r.status.success(),
        "sim {args:?} failed ({:?})\nstdout:\n{}\nstderr:\n{}",
        r.status,
        r.stdout,
        r.stderr
    );
    assert!(!r.stderr.contains("panicked"), "{}", r.stderr);
    r
}

const TINY: [&str; 8] = [
    "--width", "64", "--height", "40", "--frames", "3", "--depth", "6",
];

/// The tiny default-scene run with relative outputs `out/`, `report.json` and `dump_name`
/// inside `t` (so two runs in two folders have identical arguments).
fn tiny_run(t: &Tmp, dump_name: &str, extra: &[&str]) -> Run {
    let mut a: Vec<&str> = TINY.to_vec();
    a.extend([
        "--out",
        "out",
        "--report-json",
        "report.json",
        "--dump-hits",
        dump_name,
    ]);
    a.extend_from_slice(extra);
    run_ok(&a, &t.dir)
}

/// The report's per-frame `hit_buffer_reused`.
fn reuses(report: &serde_json::Value) -> Vec<u64> {
    report["frames"]
        .as_array()
        .expect("frames[] in the report")
        .iter()
        .map(|f| f["hit_buffer_reused"].as_u64().expect("hit_buffer_reused"))
        .collect()
}

fn report(t: &Tmp) -> serde_json::Value {
    serde_json::from_slice(&t.read("report.json")).expect("the report is JSON")
}

fn png_names() -> Vec<String> {
    (0..FRAMES)
        .map(|f| format!("out/frame_{f:04}.png"))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Tests

#[test]
fn help_lists_the_options() {
    let t = Tmp::new("help_lists_the_options");
    let r = run_ok(&["--help"], &t.dir);
    for opt in [
        "--scene",
        "--width",
        "--height",
        "--frames",
        "--depth",
        "--out",
        "--report-json",
        "--no-hit-buffer",
        "--dump-hits",
    ] {
        assert!(r.stdout.contains(opt), "--help lacks {opt}:\n{}", r.stdout);
    }
}

/// `--help` opens with what the command does by default: the cycle model, not the reference
/// (it said "with the f64 reference" while the default model was the cycle model).
#[test]
fn help_says_the_default_model_is_the_cycle_model() {
    let t = Tmp::new("help_says_the_default_model");
    let r = run_ok(&["--help"], &t.dir);
    let first = r.stdout.lines().next().unwrap_or("");
    assert!(
        first.contains("cycle-accurate model") && !first.contains("with the f64 reference"),
        "--help's first line: {first}"
    );
}

/// The `wrote … PNGs` line counts and names every PNG the run wrote: with the cycle model
/// `frame_NNNN.png` and `diff_NNNN.png` per frame (it said "wrote 2 PNGs" for 4 files), with
/// the reference only the frames.
#[test]
fn the_png_line_counts_and_names_what_was_written() {
    for (model, per_frame, names) in [
        ("cycle", 2, "frame_0000.png … frame_0001.png (the frames) and diff_0000.png … diff_0001.png (where the model differs from the reference)"),
        ("reference", 1, "frame_0000.png … frame_0001.png (the frames)"),
    ] {
        let t = Tmp::new(&format!("png_line_{model}"));
        let out = t.dir.join("out");
        let out_s = out.display().to_string();
        let r = run_ok(
            &[
                "--model", model, "--width", "16", "--height", "8", "--frames", "2", "--depth",
                "4", "-q", "--out", &out_s,
            ],
            &t.dir,
        );
        let files = std::fs::read_dir(&out).expect("the PNG folder").count();
        assert_eq!(files, 2 * per_frame, "{model}: files in {out_s}");
        let want = format!("wrote {files} PNGs to {out_s}: {names}");
        assert!(
            r.stdout.lines().any(|l| l == want),
            "{model}: no line {want:?} in:\n{}",
            r.stdout
        );
    }
}

#[test]
fn tiny_default_run_writes_everything() {
    let t = Tmp::new("tiny_default_run_writes_everything");
    let r = tiny_run(&t, "hits.bin", &[]);

    // stdout: one line per frame, then a summary.
    for f in 0..FRAMES {
        let want = format!("{f}/{FRAMES}");
        assert!(
            r.stdout
                .lines()
                .any(|l| l.starts_with("frame")
                    && l.split_whitespace().nth(1) == Some(want.as_str())),
            "no line for frame {f}:\n{}",
            r.stdout
        );
    }
    assert!(
        r.stdout.lines().any(|l| l.starts_with("summary:")),
        "no summary line:\n{}",
        r.stdout
    );

    // PNGs.
    for name in png_names() {
        let img =
            image::open(t.dir.join(&name)).unwrap_or_else(|e| panic!("cannot decode {name}: {e}"));
        assert_eq!((img.width(), img.height()), (W, H), "{name}");
    }
    assert!(
        !t.dir.join(format!("out/frame_{FRAMES:04}.png")).exists(),
        "one PNG too many"
    );

    // Report.
    let rep = report(&t);
    let frames = rep["frames"].as_array().expect("frames[]");
    assert_eq!(frames.len(), FRAMES as usize);
    for (f, fr) in frames.iter().enumerate() {
        assert_eq!(
            fr["rays"].as_u64(),
            Some(u64::from(W * H)),
            "frame {f} rays"
        );
        assert!(fr["walker_steps"].is_u64(), "frame {f} walker_steps");
        assert!(fr["hit_buffer_reused"].is_u64(), "frame {f} reuse");
        assert!(
            fr["wall_s"].as_f64().is_some_and(|s| s >= 0.0),
            "frame {f} wall_s"
        );
    }
    assert!(
        rep["summary"]["rays_per_s"]
            .as_f64()
            .is_some_and(|v| v > 0.0),
        "summary.rays_per_s: {}",
        rep["summary"]
    );

    // No temporary files left.
    for dir in [t.dir.clone(), t.dir.join("out")] {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let n = e.file_name().to_string_lossy().into_owned();
            assert!(!n.ends_with(".tmp"), "{n} left in {}", dir.display());
        }
    }
}

#[test]
fn identical_runs_give_identical_files() {
    let a = Tmp::new("identical_runs_a");
    let b = Tmp::new("identical_runs_b");
    tiny_run(&a, "hits.bin", &[]);
    tiny_run(&b, "hits.bin", &[]);
    for name in png_names().iter().map(String::as_str).chain(["hits.bin"]) {
        assert!(a.read(name) == b.read(name), "{name} differs between runs");
    }
}

#[test]
fn hit_buffer_never_changes_a_pixel() {
    let on = Tmp::new("hit_buffer_on");
    let off = Tmp::new("hit_buffer_off");
    tiny_run(&on, "hits.bin", &[]);
    tiny_run(&off, "hits.bin", &["--no-hit-buffer"]);
    assert!(
        on.read("hits.bin") == off.read("hits.bin"),
        "the hit dump differs with and without the hit buffer"
    );
    for name in png_names() {
        assert!(on.read(&name) == off.read(&name), "{name} differs");
    }

    let r_off = reuses(&report(&off));
    assert!(r_off.iter().all(|&n| n == 0), "reuses without: {r_off:?}");
    assert_eq!(
        report(&off)["summary"]["hit_buffer_reused"].as_u64(),
        Some(0)
    );

    // The body is static and the camera still, so frames after the first reuse pixels.
    let r_on = reuses(&report(&on));
    assert_eq!(r_on[0], 0, "nothing to reuse in frame 0: {r_on:?}");
    assert!(r_on[1..].iter().all(|&n| n > 0), "reuses with: {r_on:?}");
}

#[test]
fn scene_file_renders_like_the_default() {
    let def = Tmp::new("scene_file_default");
    let file = Tmp::new("scene_file_car");
    tiny_run(&def, "hits.bin", &[]);
    let mut a: Vec<&str> = vec!["--scene", "scenes/car.ron"];
    a.extend(TINY);
    let (out, rep, dump) = (file.p("out"), file.p("report.json"), file.p("hits.bin"));
    a.extend(["--out", &out, "--report-json", &rep, "--dump-hits", &dump]);
    let r = run_ok(&a, Path::new(env!("CARGO_MANIFEST_DIR")));
    assert!(r.stdout.contains("scenes/car.ron"), "{}", r.stdout);
    assert!(
        def.read("hits.bin") == file.read("hits.bin"),
        "scenes/car.ron renders differently from the embedded default"
    );
    for name in png_names() {
        assert!(def.read(&name) == file.read(&name), "{name} differs");
    }
}

#[test]
fn bench_prints_its_speed() {
    let t = Tmp::new("bench_prints_its_speed");
    let r = run_ok(
        &[
            "bench", "--width", "64", "--height", "40", "--frames", "2", "--depth", "6",
        ],
        &t.dir,
    );
    assert!(r.stdout.contains("M rays/s"), "{}", r.stdout);
}

/// `sim bench --model cycle --sample RATE` times the sampled cycle model and marks its
/// cycles as estimates with their interval; the cycle model's options are refused, before
/// any work, without `--model cycle`.
#[test]
fn bench_times_the_sampled_cycle_model() {
    let t = Tmp::new("bench_sampled");
    let small = [
        "--width", "64", "--height", "40", "--frames", "2", "--depth", "6",
    ];
    let mut a = vec!["bench", "--model", "cycle", "--sample", "0.25"];
    a.extend(small);
    let r = run_ok(&a, &t.dir);
    for want in [
        "cycles are estimates",
        "est cycles",
        "95% CI",
        "estimated from a sample",
    ] {
        assert!(r.stdout.contains(want), "no {want:?} in\n{}", r.stdout);
    }
    for (flag, value) in [("--sample", "0.25"), ("--scaling", "."), ("--hw", "x.ron")] {
        let mut a = vec!["bench", flag, value];
        a.extend(small);
        let r = run_sim(&a, Some(&t.dir), TIMEOUT);
        assert!(
            !r.status.success() && r.stderr.contains(flag) && r.stderr.contains("--model cycle"),
            "bench {flag} without --model cycle: {:?}\n{}",
            r.status,
            r.stderr
        );
        assert!(!r.stdout.contains("assets built"), "{}", r.stdout);
    }
    let mut a = vec!["bench", "--model", "cycle", "--sample", "0"];
    a.extend(small);
    let r = run_sim(&a, Some(&t.dir), TIMEOUT);
    assert!(
        !r.status.success() && r.stderr.contains("--sample 0"),
        "{:?}\n{}",
        r.status,
        r.stderr
    );
}

/// Switches that must never change a record: early termination (a later candidate cannot
/// hold a nearer hit), implicit trees (the same voxels as the memory image), and the thread
/// count (pixels are independent).
#[test]
fn switches_that_must_not_change_records() {
    // The reference's switches (implicit walks exist only in the reference).
    let base = Tmp::new("switch_base");
    tiny_run(&base, "hits.bin", &["--model", "reference"]);
    for (name, extra) in [
        (
            "switch_no_early",
            &["--model", "reference", "--no-early-termination"][..],
        ),
        (
            "switch_implicit",
            &["--model", "reference", "--implicit"][..],
        ),
        (
            "switch_one_thread",
            &["--model", "reference", "--threads", "1"][..],
        ),
    ] {
        let t = Tmp::new(name);
        tiny_run(&t, "hits.bin", extra);
        assert!(
            base.read("hits.bin") == t.read("hits.bin"),
            "{extra:?} changed the hit dump"
        );
    }
}

/// Output into a closed pipe (`sim hardware | head -1`) ends `sim` quietly with the status a
/// shell gives a process ended by SIGPIPE, not with a panic and a backtrace. The reader is
/// closed before `sim` starts (a socket pair whose other end is dropped, which fails writes
/// with EPIPE as a pipe does), so no write can land in a buffer first.
#[cfg(unix)]
#[test]
fn closed_stdout_ends_quietly() {
    use std::os::fd::OwnedFd;
    use std::os::unix::net::UnixStream;
    use std::process::{Command, Stdio};
    let (writer, reader) = UnixStream::pair().expect("a socket pair");
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_sim"))
        .arg("hardware")
        .stdout(Stdio::from(OwnedFd::from(writer)))
        .stderr(Stdio::piped())
        .output()
        .expect("run sim");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(141), "{stderr}");
}

/// `sim hardware --levels`: a Yosys ECP5 netlist's slowest stage by the ECP5 rule, and clear
/// refusals of an unknown rule, a missing top module and a missing file.
#[test]
fn hardware_levels_times_a_netlist_by_the_named_rule() {
    let t = Tmp::new("levels");
    // TRELLIS_FF → LUT4 → CCU2C → TRELLIS_FF: a LUT level, the CCU2C's own LUT, one carry.
    let net = r#"{"modules": {"top": {"cells": {
      "a": {"type": "TRELLIS_FF", "port_directions": {"CLK": "input", "DI": "input", "Q": "output"},
            "connections": {"CLK": [1], "DI": [2], "Q": [3]}},
      "l": {"type": "LUT4", "port_directions": {"A": "input", "Z": "output"},
            "connections": {"A": [3], "Z": [4]}},
      "c": {"type": "CCU2C", "port_directions": {"A0": "input", "S0": "output"},
            "connections": {"A0": [4], "S0": [5]}},
      "b": {"type": "TRELLIS_FF", "port_directions": {"CLK": "input", "DI": "input", "Q": "output"},
            "connections": {"CLK": [1], "DI": [5], "Q": [6]}}},
      "netnames": {"\\acc_q": {"hide_name": 0, "bits": [6]}}}}}"#;
    std::fs::write(t.dir.join("n.json"), net).expect("write the netlist");
    let r = run_ok(
        &[
            "hardware", "--levels", "n.json", "--top", "top", "--rule", "ecp5-6",
        ],
        &t.dir,
    );
    // 150 + 300 + 2 × 729 + 43 = 1,951 ps: 512.6 MHz.
    let line = r
        .stdout
        .lines()
        .find(|l| l.trim_start().starts_with("acc_q"))
        .unwrap_or_else(|| panic!("no acc_q stage:\n{}", r.stdout));
    let f: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(f[1..], ["2", "1", "0", "3", "1.95", "512.6"], "{line}");
    assert!(
        r.stdout.contains("fmax by the rule: 512.6 MHz"),
        "{}",
        r.stdout
    );
    for (args, want) in [
        (
            vec![
                "hardware", "--levels", "n.json", "--top", "top", "--rule", "ecp6",
            ],
            "--rule ecp6: no such clock rule (known: xcup-2, ecp5-6)",
        ),
        (
            vec!["hardware", "--levels", "n.json"],
            "--levels needs --top MODULE",
        ),
        (
            vec!["hardware", "--levels", "n.json", "--top", "nope"],
            "netlist has no module `nope`",
        ),
        (
            vec!["hardware", "--levels", "absent.json", "--top", "top"],
            "reading the netlist absent.json",
        ),
    ] {
        let e = run_sim(&args, Some(&t.dir), TIMEOUT);
        assert!(!e.status.success(), "sim {args:?} succeeded");
        assert!(e.stderr.contains(want), "sim {args:?}: {}", e.stderr);
        assert!(!e.stderr.contains("panicked"), "{}", e.stderr);
    }
}
