//! The end-to-end frame (`tb_frame.sv`): every pixel's hit-buffer word equals the model's and
//! the frame takes the cycle model's cycles, in both simulators, for both hit-buffer write
//! paths (each write in the model's cycle), with hit-buffer reuse in a second frame and under
//! random memory stalls; the model's cycles are required, and one corrupted pixel is exactly
//! one failure.
//!
//! Pipeline position: the whole RTL pipeline of one frame against the cycle model's run of the
//! same frame (`sim --report-json`, `--transaction-log`) on `testbench/hw/frame_hw.ron`.

use super::common::process::run_sim;
use super::common::report::ModelReport;
use super::vector_files::{corrupt_field, repo, Tmp};
use super::{icarus, numbers, run_sh, simulators, SEED};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The hardware of the end-to-end frame (tb_frame.sv), one file for the model and the RTL:
/// testbench/hw/frame_hw.ron (one walker with one context, one walk-issue lane, the default's
/// two hit-buffer write paths, every node and attribute read taking `FRAME_MEM_LATENCY`
/// cycles); tb_frame reads it as testbench/hw/frame_hw_pkg.sv.
pub(super) fn frame_hw() -> String {
    std::fs::read_to_string(repo().join("testbench/hw/frame_hw.ron"))
        .expect("read testbench/hw/frame_hw.ron")
}

/// `frame_hw()` with one hit-buffer write path.
fn frame_hw_one_path() -> String {
    let hw = frame_hw();
    let two = "hit_buffer: (write_ports: 2, record_writes: 2)";
    assert!(hw.contains(two), "frame_hw.ron no longer names {two}");
    hw.replace(two, "hit_buffer: (write_ports: 1, record_writes: 1)")
}

/// The hardware package of `hw_ron` (`sim hardware --sv-package`), written into `t`.
pub(super) fn hw_package(t: &Tmp, name: &str, hw_ron: &str) -> PathBuf {
    let ron = t.dir.join(format!("{name}.ron"));
    std::fs::write(&ron, hw_ron).expect("write a hardware RON");
    let pkg = t.dir.join(format!("{name}_pkg.sv"));
    let (r, p) = (ron.display().to_string(), pkg.display().to_string());
    let args = ["hardware", "--hw", &r, "--sv-package", &p];
    let out = run_sim(&args, None, Duration::from_secs(120));
    assert!(out.status.success(), "sim {args:?}: {}", out.stderr);
    pkg
}
const FRAME_MEM_LATENCY: u64 = 3;

/// The vectors of `scene`'s 16 × 10 frame at depth 4 (32 rows a stage, the suite's seed),
/// written into `t`'s folder `name`: the small end-to-end frames of the frame tests.
fn small_frame_vectors(t: &Tmp, scene: &str, name: &str) -> PathBuf {
    let (out, scene) = (t.p(name), repo().join(scene).display().to_string());
    let args = [
        "vectors", "--out", &out, "--count", "32", "--seed", SEED, "--width", "16", "--height",
        "10", "--depth", "4", "--scene", &scene,
    ];
    let r = run_sim(&args, None, Duration::from_secs(300));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
    t.dir.join(name)
}

/// The cycle model's cycles for frame 0 of `scene` (`None`: the default) at this size and
/// depth on `frame_hw()`, from `sim --report-json` (the test's own run of the model).
fn model_frame_cycles(t: &Tmp, scene: Option<&str>, width: &str, height: &str, depth: &str) -> u64 {
    model_frame(t, &frame_hw(), scene, width, height, depth, None)
}

/// The cycle model's cycles for frame 0 of `scene` on hardware `hw` (RON), and with `txlog`
/// its transaction log of every pixel (`sim --transaction-log`).
fn model_frame(
    t: &Tmp,
    hw_ron: &str,
    scene: Option<&str>,
    width: &str,
    height: &str,
    depth: &str,
    txlog: Option<&Path>,
) -> u64 {
    let tag = format!("{width}x{height}_{}_{}", scene.is_some(), hw_ron.len());
    let hw = t
        .dir
        .join(format!("frame_hw_{tag}_{}.ron", txlog.is_some()));
    std::fs::write(&hw, hw_ron).expect("write the frame's hardware RON");
    let rep = t.p(&format!("frame_{tag}_{}_report.json", txlog.is_some()));
    let hw = hw.display().to_string();
    let scene = scene.map(|s| repo().join(s).display().to_string());
    let log = txlog.map(|p| p.display().to_string());
    let mut args = vec![
        "--width",
        width,
        "--height",
        height,
        "--depth",
        depth,
        "--frames",
        "1",
        "--hw",
        &hw,
        "--no-prune",
        "--report-json",
        &rep,
    ];
    if let Some(p) = &scene {
        args.extend(["--scene", p.as_str()]);
    }
    if let Some(l) = &log {
        args.extend(["--transaction-log", l.as_str(), "--log-count", "1000000"]);
    }
    let r = run_sim(&args, None, Duration::from_secs(300));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
    ModelReport::read(&rep).frame(0, "cycles")
}

/// Every pixel's hit-buffer write cycle in a model transaction log (`sim --transaction-log`).
fn model_write_cycles(log: &Path) -> std::collections::BTreeMap<u64, u64> {
    let text = std::fs::read_to_string(log).expect("read the transaction log");
    let mut out = std::collections::BTreeMap::new();
    for line in text.lines() {
        let j: serde_json::Value = serde_json::from_str(line).expect("a transaction-log line");
        let pixel = j["pixel"].as_u64().expect("a pixel");
        let write = j["stages"]
            .as_array()
            .and_then(|a| a.iter().find(|s| s["stage"] == "write"))
            .and_then(|s| s["entered"].as_u64())
            .unwrap_or_else(|| panic!("pixel {pixel}: no write stage in the log"));
        out.insert(pixel, write);
    }
    out
}

/// Every pixel's write cycle as tb_frame printed it (`+write_log`: "write P C PATH").
fn rtl_write_cycles(text: &str) -> std::collections::BTreeMap<u64, u64> {
    text.lines()
        .filter(|l| l.starts_with("write "))
        .map(|l| {
            let n = numbers(l);
            (n[0], n[1])
        })
        .collect()
}

/// One frame run: (pixels equal, pixels, RTL cycles, passed, failed, everything printed).
fn frame_run(sim: &str, dir: &Path, args: &str) -> (u64, u64, u64, u64, u64, String) {
    frame_run_with(sim, dir, args, None)
}

/// [`frame_run`] on the hardware package `pkg` (run.sh's `FRAME_HW_PKG`; `None`: the
/// committed testbench/hw/frame_hw_pkg.sv).
fn frame_run_with(
    sim: &str,
    dir: &Path,
    args: &str,
    pkg: Option<&Path>,
) -> (u64, u64, u64, u64, u64, String) {
    let d = dir.to_string_lossy();
    let pkg = pkg.map(|p| p.display().to_string());
    let mut env = vec![("FRAME_ARGS", args)];
    if let Some(p) = &pkg {
        env.push(("FRAME_HW_PKG", p.as_str()));
    }
    let (_, text) = run_sh(&["--sim", sim, &d, "frame"], &env);
    let summary = text.lines().find(|l| l.starts_with("frame: ")).map(numbers);
    let last = text
        .lines()
        .rev()
        .find(|l| l.ends_with(" failed") && l.contains(" passed, "))
        .map(numbers);
    match (summary, last) {
        (Some(s), Some(l)) if s.len() >= 3 && l.len() == 2 => (s[0], s[1], s[2], l[0], l[1], text),
        _ => panic!("frame ({sim}): no \"frame: …\" and \"N passed, N failed\" lines:\n{text}"),
    }
}

/// The end-to-end frame in both simulators: every pixel's hit-buffer word (and candidates,
/// walks, hit, t, voxel) equals frame_pixels.hex and the frame takes the cycle model's cycles
/// exactly. Verilator runs the 32 × 24 frame at depth 5 (about 2 s once built),
/// Icarus the golden set's 16 × 10 frame at depth 4 (Icarus runs this top at a few hundred
/// cycles a second, so the 32 × 24 frame would take minutes there) and scenes/moving_camera.ron
/// at 16 × 10 (3 instances in the 8 lanes; 135 of its pixels have no candidate and take the
/// frame's miss word).
#[test]
fn frame_end_to_end_matches_pixels_and_model_cycles() {
    let sims = simulators();
    if sims.is_empty() {
        return;
    }
    let t = Tmp::new("rtl_frame");
    let golden = repo().join("vectors");
    let mut jobs: Vec<(&str, PathBuf, u64)> = Vec::new();
    for &sim in &sims {
        if sim == "icarus" {
            jobs.push((
                sim,
                golden.clone(),
                model_frame_cycles(&t, None, "16", "10", "4"),
            ));
            let mc = "scenes/moving_camera.ron";
            let dir = small_frame_vectors(&t, mc, "mc");
            let cycles = model_frame_cycles(&t, Some(mc), "16", "10", "4");
            jobs.push((sim, dir, cycles));
        } else {
            let args = [
                "vectors",
                "--out",
                &t.p("v32"),
                "--count",
                "32",
                "--seed",
                SEED,
                "--width",
                "32",
                "--height",
                "24",
                "--depth",
                "5",
            ];
            let r = run_sim(&args, None, Duration::from_secs(300));
            assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
            jobs.push((
                sim,
                t.dir.join("v32"),
                model_frame_cycles(&t, None, "32", "24", "5"),
            ));
        }
    }
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|(sim, dir, model)| {
                s.spawn(move || {
                    let start = std::time::Instant::now();
                    let args = format!("+model_cycles={model} +latency={FRAME_MEM_LATENCY}");
                    let r = frame_run(sim, dir, &args);
                    (*sim, *model, r, start.elapsed().as_secs_f64())
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("frame thread"))
            .collect()
    });
    for (sim, model, (equal, pixels, rtl, passed, failed, text), secs) in results {
        println!(
            "frame {sim} ({pixels} pixels): {equal}/{pixels} pixels equal, RTL {rtl} cycles, model {model} cycles, {passed} passed, {failed} failed, {secs:.1} s (build included)"
        );
        assert_eq!((equal, failed), (pixels, 0), "frame ({sim}):\n{text}");
        assert_eq!(rtl, model, "frame ({sim}): RTL cycles:\n{text}");
        assert_eq!(passed, pixels + 1, "frame ({sim}):\n{text}");
    }
}

/// One bit of one pixel's expected hit-buffer word flipped: exactly that pixel fails.
#[test]
fn one_corrupted_frame_pixel_is_exactly_one_failure() {
    if !icarus() {
        return;
    }
    let golden = repo().join("vectors");
    let t = Tmp::new("corrupt_frame");
    for e in std::fs::read_dir(&golden).expect("list the golden set") {
        let p = e.expect("a golden file").path();
        if p.is_file() {
            std::fs::copy(&p, t.dir.join(p.file_name().expect("a file name")))
                .expect("copy a golden file");
        }
    }
    let (row, pixels) = corrupt_field(&t.dir, "frame_pixels", "word", 77, |w| w / 3);
    let model = model_frame_cycles(&t, None, "16", "10", "4");
    let (equal, _, _, passed, failed, text) = frame_run(
        "icarus",
        &t.dir,
        &format!("+model_cycles={model} +latency={FRAME_MEM_LATENCY}"),
    );
    println!("frame: one bit of pixel {row}'s word flipped: {equal}/{pixels} equal, {passed} passed, {failed} failed");
    // Every other pixel and the cycles pass.
    assert_eq!((passed, failed), (pixels, 1), "{text}");
    assert!(
        text.contains(&format!("pixel {row}: word")),
        "the failure does not name pixel {row}'s word:\n{text}"
    );
}

/// The frame's cycles are checked, never skipped: a frame run without `+model_cycles` fails
/// on its cycles row, and with the model's figure off by one fails there too, naming both;
/// every pixel passes in both runs. The frame is scenes/moving_camera.ron at 16 × 10 (694
/// cycles, about 10 s each in Icarus, against 7,620 for the golden set's frame).
#[test]
fn frame_cycles_are_required_and_checked() {
    if !icarus() {
        return;
    }
    let t = Tmp::new("frame_cycles");
    let mc = "scenes/moving_camera.ron";
    let golden = small_frame_vectors(&t, mc, "mc");
    let model = model_frame_cycles(&t, Some(mc), "16", "10", "4");
    let runs = [
        format!("+latency={FRAME_MEM_LATENCY}"),
        format!("+model_cycles={} +latency={FRAME_MEM_LATENCY}", model + 1),
    ];
    let results: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = runs
            .iter()
            .map(|args| {
                let golden = &golden;
                s.spawn(move || frame_run("icarus", golden, args))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("frame thread"))
            .collect()
    });
    let expected = [
        "FAIL frame: no +model_cycles=N given".to_string(),
        format!(
            "FAIL frame: {model} cycles, the cycle model's {}",
            model + 1
        ),
    ];
    for ((args, want), (equal, pixels, rtl, passed, failed, text)) in
        runs.iter().zip(&expected).zip(results)
    {
        println!("frame with \"{args}\": {equal}/{pixels} equal, RTL {rtl} cycles, {passed} passed, {failed} failed");
        assert_eq!(
            (equal, passed, failed),
            (pixels, pixels, 1),
            "{args}:\n{text}"
        );
        assert_eq!(rtl, model, "{args}: RTL cycles:\n{text}");
        assert!(
            text.contains(want.as_str()),
            "{args}: no \"{want}\":\n{text}"
        );
    }
}

/// The hit buffer's write paths, write by write: on scenes/moving_camera.ron at 16 × 10 (135 of
/// 160 pixels without a candidate, so the check stage's words and the records meet at the
/// write port), every pixel is written in the cycle the cycle model's transaction log gives,
/// for both write-path designs — one path (`WRITE_PORTS = 1`: the record first), and the
/// default's two banks with the check's word first and two records a cycle. The two designs
/// write 51 of the pixels in different cycles, so each log is a check of its own design: the
/// two-path RTL against the one-path log is shown failing on exactly those pixels.
#[test]
fn frame_writes_land_in_the_models_cycles_for_both_write_paths() {
    let Some(&sim) = simulators().first() else {
        return;
    };
    let t = Tmp::new("frame_writes");
    let mc = "scenes/moving_camera.ron";
    let dir = small_frame_vectors(&t, mc, "mc");
    let one_path = frame_hw_one_path();
    let designs = [
        ("two banks, check first", frame_hw(), None),
        (
            "one path",
            one_path.clone(),
            Some(hw_package(&t, "one_path", &one_path)),
        ),
    ];
    let mut logs = Vec::new();
    for (i, (name, hw, pkg)) in designs.iter().enumerate() {
        let log = t.dir.join(format!("{i}.jsonl"));
        let model = model_frame(&t, hw, Some(mc), "16", "10", "4", Some(&log));
        let want = model_write_cycles(&log);
        let (equal, pixels, rtl, _, failed, text) = frame_run_with(
            sim,
            &dir,
            &format!("+model_cycles={model} +latency={FRAME_MEM_LATENCY} +write_log"),
            pkg.as_deref(),
        );
        let got = rtl_write_cycles(&text);
        let differ: Vec<_> = want.iter().filter(|(p, c)| got.get(p) != Some(c)).collect();
        println!(
            "frame writes ({sim}, {name}): {equal}/{pixels} pixels equal, RTL {rtl} cycles, model {model}; {} of {} pixels written in the model's cycle",
            want.len() - differ.len(),
            want.len()
        );
        assert_eq!((equal, failed, rtl), (pixels, 0, model), "{name}:\n{text}");
        assert_eq!(want.len() as u64, pixels, "{name}: the log misses pixels");
        assert!(
            differ.is_empty(),
            "{name}: (pixel, model cycle) written elsewhere: {differ:?}"
        );
        logs.push((want, got));
    }
    // The two-path RTL against the one-path model: it fails exactly where the designs differ.
    let (two, one) = (&logs[0], &logs[1]);
    let designs_differ = two
        .0
        .iter()
        .filter(|(p, c)| one.0.get(p) != Some(c))
        .count();
    let wrong = one
        .0
        .iter()
        .filter(|(p, c)| two.1.get(p) != Some(c))
        .count();
    println!(
        "frame writes: the designs write {designs_differ} pixels in different cycles; the two-path RTL against the one-path log: {wrong} pixels differ"
    );
    assert!(
        designs_differ > 0,
        "the scene does not tell the designs apart"
    );
    assert_eq!(wrong, designs_differ);
}

/// Two frames through svo_core with the hit buffer kept: scenes/static_single.ron at 16 × 10
/// (a still camera and a still instance). Frame 1 runs after a reset of the pipeline with
/// buffer_valid 1 and nothing dirty; its pixels are the words of frame 0 read back through the
/// reuse rule, and it takes the model's frame-1 cycles, reusing as many words as the model
/// (`hit_buffer_reused`) and walking as many rays (`walks`). Shown failing: with the camera
/// flagged dirty nothing is reused, every ray is walked again, and the frame fails on its
/// cycles alone (the words come out the same).
#[test]
fn frame_reuses_the_hit_buffer_in_the_second_frame() {
    let Some(&sim) = simulators().first() else {
        return;
    };
    let t = Tmp::new("frame_reuse");
    let st = "scenes/static_single.ron";
    let dir = small_frame_vectors(&t, st, "st");
    let scene = repo().join(st).display().to_string();
    let hw = repo()
        .join("testbench/hw/frame_hw.ron")
        .display()
        .to_string();
    let rep = t.p("st_report.json");
    let args = [
        "--width",
        "16",
        "--height",
        "10",
        "--depth",
        "4",
        "--frames",
        "2",
        "--hw",
        &hw,
        "--no-prune",
        "--scene",
        &scene,
        "--report-json",
        &rep,
    ];
    let r = run_sim(&args, None, Duration::from_secs(300));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
    let report = ModelReport::read(&rep);
    let f = |i: usize, k: &str| report.frame(i, k);
    let (c0, c1, reused, walks) = (
        f(0, "cycles"),
        f(1, "cycles"),
        f(1, "hit_buffer_reused"),
        f(1, "walks"),
    );
    assert!(reused > 0, "the model reused nothing in frame 1");
    let run = |extra: &str| {
        let a = format!(
            "+model_cycles={c0} +latency={FRAME_MEM_LATENCY} +frames=2 +model_cycles1={c1} {extra}"
        );
        let d = dir.to_string_lossy();
        let (_, text) = run_sh(&["--sim", sim, &d, "frame"], &[("FRAME_ARGS", &a)]);
        let line = |start: &str| {
            text.lines()
                .find(|l| l.starts_with(start))
                .map(numbers)
                .unwrap_or_else(|| panic!("no \"{start}\" line:\n{text}"))
        };
        let (f0, f1) = (line("frame: "), line("frame 1: "));
        let last = text
            .lines()
            .rev()
            .find(|l| l.ends_with(" failed") && l.contains(" passed, "))
            .map(numbers)
            .unwrap_or_else(|| panic!("no closing line:\n{text}"));
        (f0, f1, last, text)
    };
    let (f0, f1, last, text) = run("");
    println!("frame reuse ({sim}): frame 0 {}/{} equal, {} cycles (model {c0}); frame 1 {}/{} equal, {} cycles (model {c1}), {} reused (model {reused}), {} walked (model {walks}); {} passed, {} failed",
        f0[0], f0[1], f0[2], f1[1], f1[2], f1[3], f1[5], f1[6], last[0], last[1]);
    assert_eq!(
        (f0[0], f0[2], f1[1], f1[3]),
        (f0[1], c0, f1[2], c1),
        "{text}"
    );
    assert_eq!((f1[5], f1[6]), (reused, walks), "{text}");
    assert_eq!(last, vec![2 * f0[1] + 2, 0], "{text}");
    // The camera flagged dirty: the same words, every ray walked, the cycles row fails.
    let (_, f1, last, text) = run("+f1_camera_dirty=1");
    println!(
        "frame reuse with the camera dirty: frame 1 {} cycles, {} reused; {} passed, {} failed",
        f1[3], f1[5], last[0], last[1]
    );
    assert_eq!((f1[1], f1[5], last[1]), (f1[2], 0, 1), "{text}");
    assert!(
        text.contains(&format!(
            "FAIL frame: {} cycles, the cycle model's {c1}",
            f1[3]
        )),
        "{text}"
    );
}

/// Random memory stalls under svo_core: the node memory holds its request ready low in 30 % of
/// cycles and answers each read 0–6 cycles late (`+mem_stall=30 +mem_jitter=6`, seeded). The
/// frame still writes every pixel once and right (none lost, none repeated, no deadlock), in
/// more cycles than the model's fixed-latency figure; the stalls are counted so that a run that
/// never stalled shows it. The deadlock check is shown failing: the same run cut off at 300
/// cycles fails on the unfinished frame and each pixel never written.
#[test]
fn frame_survives_random_memory_stalls() {
    let Some(&sim) = simulators().first() else {
        return;
    };
    let t = Tmp::new("frame_stalls");
    let mc = "scenes/moving_camera.ron";
    let dir = small_frame_vectors(&t, mc, "mc");
    let model = model_frame_cycles(&t, Some(mc), "16", "10", "4");
    for seed in [1, 2, 3] {
        let a = format!(
            "+model_cycles={model} +latency={FRAME_MEM_LATENCY} +mem_stall=30 +mem_jitter=6 +seed={seed}"
        );
        let (equal, pixels, rtl, passed, failed, text) = frame_run(sim, &dir, &a);
        let line = text
            .lines()
            .find(|l| l.starts_with("frame: random stalls"))
            .unwrap_or_else(|| panic!("no stall line:\n{text}"));
        let n = numbers(line);
        println!("frame with stalls ({sim}, seed {seed}): {equal}/{pixels} pixels equal, RTL {rtl} cycles (model {model} without stalls); {line}");
        assert_eq!(
            (equal, passed, failed),
            (pixels, pixels + 1, 0),
            "seed {seed}:\n{text}"
        );
        assert!(
            n[1] > 0 && n[2] > 0,
            "seed {seed}: no stall happened: {line}"
        );
        assert!(
            rtl > model,
            "seed {seed}: stalls cost nothing? {rtl} vs {model}"
        );
    }
    // Cut off before the end: the frame fails, naming the unfinished frame and the pixels.
    let a = format!(
        "+model_cycles={model} +latency={FRAME_MEM_LATENCY} +mem_stall=30 +mem_jitter=6 +seed=1 +max_cycles=300"
    );
    let (_, pixels, _, passed, failed, text) = frame_run(sim, &dir, &a);
    let unwritten = pixels - passed;
    println!("frame with stalls cut at 300 cycles: {passed} passed, {failed} failed");
    assert!(text.contains("FAIL frame: with stalls,"), "{text}");
    assert!(text.contains("never written"), "{text}");
    assert_eq!(failed, unwritten + 1, "{text}");
}
