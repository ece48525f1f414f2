//! The RTL walker against its vectors: every row of the golden and the large sets at the
//! model's per-row cycles at three node-memory latencies, and one corrupted value is exactly
//! one failure.
//!
//! Pipeline position: the walk section's walker (`testbench/tb_walker.sv`), with its own memory
//! images, run through `testbench/run.sh`.

use super::common::process::run_sim;
use super::vector_files::{corrupt_field, manifest, repo, Tmp};
use super::{icarus, numbers, run_sh, simulators, COUNT, SEED};
use std::path::Path;
use std::time::Duration;

/// One walker run: (memory latency, passed, failed, rows whose cycles equal the model's).
fn walker_runs(
    sim: &str,
    dir: &Path,
    latencies: &str,
    args: &str,
) -> (Vec<(u64, u64, u64, u64)>, String) {
    let d = dir.to_string_lossy();
    let (_, text) = run_sh(
        &["--sim", sim, &d, "walker"],
        &[("WALKER_LATENCIES", latencies), ("WALKER_ARGS", args)],
    );
    let mut runs = Vec::new();
    let mut pending: Option<(u64, u64)> = None;
    for l in text.lines() {
        if let Some(rest) = l.split("memory latency ").nth(1) {
            let lat = numbers(rest)[0];
            let timed = numbers(l.split("): ").nth(1).unwrap_or(""))[0];
            pending = Some((lat, timed));
        } else if l.ends_with(" failed") && l.contains(" passed, ") {
            let n = numbers(l);
            let (lat, timed) = pending.take().unwrap_or((0, 0));
            runs.push((lat, n[0], n[1], timed));
        }
    }
    (runs, text)
}

/// Every run passed every row of `rows`, each at the model's cycles, at the given latencies.
fn assert_walker(runs: &[(u64, u64, u64, u64)], rows: u64, lats: &[u64], what: &str, text: &str) {
    let got: Vec<u64> = runs.iter().map(|r| r.0).collect();
    assert_eq!(got, lats, "{what}: runs\n{text}");
    for &(lat, passed, failed, timed) in runs {
        println!("walker {what}: memory latency {lat}: {passed} passed, {failed} failed, {timed} of {rows} at the model's cycles");
        assert_eq!(
            (passed, failed, timed),
            (rows, 0, rows),
            "{what} at latency {lat}:\n{text}"
        );
    }
}

fn model_mem_latencies() -> Vec<u64> {
    let hw = rtl_model::cycle::hw_config::HwConfig::default();
    vec![
        1,
        u64::from(hw.node_memory.onchip.latency),
        u64::from(hw.node_memory.dram.latency),
    ]
}

/// The golden walker set at all three latencies, in every simulator present.
#[test]
fn walker_golden_set_passes_at_the_models_cycles() {
    let dir = repo().join("vectors");
    let depth = manifest(&dir, "walker")["depth"].as_u64().expect("depth");
    for sim in simulators() {
        let (runs, text) = walker_runs(sim, &dir, "0 1 2", "");
        assert_walker(&runs, depth, &model_mem_latencies(), sim, &text);
    }
}

/// The large walker sets: the default car (10,000 rows besides the adversarial ones, half
/// from a 96 × 64 frame) at memory latency 1 and the on-chip latency on every row and at the
/// DRAM latency on its first 2,000 rows (the adversarial walks and 1,755 of the frame's), and
/// scenes/vox_traffic.ron (4,000 more, half from its frame) at latency 1 on every row and at
/// the DRAM latency on 1,000 of its frame's walks. Two threads.
#[test]
fn walker_large_sets_pass_at_the_models_cycles() {
    if !icarus() {
        return;
    }
    // The traffic scene's assets are the shared .vox models.
    let Some(traffic) = super::common::skip::vox_scene_path("scenes/vox_traffic.ron") else {
        return;
    };
    let t = Tmp::new("icarus_walker");
    let lats = model_mem_latencies();
    let mut sets = Vec::new();
    for (name, scene, count) in [("car", None, COUNT), ("traffic", Some(&traffic), "4000")] {
        let out = t.p(name);
        let mut args = vec![
            "vectors", "--out", &out, "--count", count, "--seed", SEED, "--width", "96",
            "--height", "64",
        ];
        let scene_path = scene.map(|s| s.display().to_string());
        match &scene_path {
            Some(p) => args.extend(["--scene", p.as_str()]),
            None => args.extend(["--depth", "5"]),
        }
        let r = run_sim(&args, None, Duration::from_secs(300));
        assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
        sets.push((name, t.dir.join(name)));
    }
    let car_rows = manifest(&sets[0].1, "walker")["depth"]
        .as_u64()
        .expect("depth");
    let traffic_rows = manifest(&sets[1].1, "walker")["depth"]
        .as_u64()
        .expect("depth");
    assert!(car_rows >= 10_000, "{car_rows} car rows");
    std::thread::scope(|s| {
        let car = &sets[0].1;
        let traffic = &sets[1].1;
        let lats = &lats;
        let a = s.spawn(move || {
            let (r, text) = walker_runs("icarus", car, "0 1", "");
            assert_walker(&r, car_rows, &lats[..2], "car", &text);
        });
        let b = s.spawn(move || {
            let (r, text) = walker_runs("icarus", car, "2", "+first=0 +count=2000");
            assert_walker(&r, 2000, &lats[2..], "car rows 0..1999", &text);
            let (r, text) = walker_runs("icarus", traffic, "0", "");
            assert_walker(&r, traffic_rows, &lats[..1], "traffic", &text);
            let (r, text) = walker_runs("icarus", traffic, "2", "+first=245 +count=1000");
            assert_walker(&r, 1000, &lats[2..], "traffic rows 245..1244", &text);
        });
        a.join().expect("car runs");
        b.join().expect("traffic runs");
    });
    println!("walker large sets: {car_rows} car rows, {traffic_rows} traffic rows");
}

#[test]
fn one_corrupted_walker_value_is_exactly_one_failure() {
    if !icarus() {
        return;
    }
    let golden = repo().join("vectors");
    let t = Tmp::new("corrupt_walker");
    for name in [
        "walker.hex",
        "walker.json",
        "walker_pkg.sv",
        "walker_visits.hex",
        "walker_visits.json",
        "walker_visits_pkg.sv",
        "walker_nodes.hex",
        "walker_attrs.hex",
    ] {
        std::fs::copy(golden.join(name), t.dir.join(name)).expect("copy a golden file");
    }
    let (row, depth) = corrupt_field(&t.dir, "walker", "steps", 100, |w| w / 4);
    let (runs, text) = walker_runs("icarus", &t.dir, "0", "");
    println!("walker: one bit of steps in row {row} flipped: {runs:?}");
    assert_eq!(runs.len(), 1, "{text}");
    assert_eq!((runs[0].1, runs[0].2), (depth - 1, 1), "{text}");
    assert!(
        text.contains(&format!("row {row}: steps")),
        "the failure does not name row {row} and steps:\n{text}"
    );
}
