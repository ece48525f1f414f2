//! `sim sweep` (docs/accuracy.md) at small sizes:
//! - the Pareto front, the distance to it and the error excess against brute-force oracles on
//!   seeded random point sets with many ties and zeros;
//! - a three-configuration sweep of the car writes well-formed CSV, JSON and plots, the same
//!   bytes on a rerun apart from the wall-time figures, and the deliberately coarse
//!   configuration has more error than the default;
//! - the same on the MagicaVoxel traffic scene (skipped with a reason when the shared models
//!   are missing, a failure under CI=true);
//! - a bad `--configs` file or `--only` name: a clear message, a non-zero exit, nothing written.

mod common;
use common::process::run_sim;
use common::{test_seed, SplitMix64};
use std::path::Path;
use std::time::Duration;
use svo_sim::studies::sweep::configs::builtin;
use svo_sim::studies::sweep::pareto::{distance, error_excess, on_front, Point};
use svo_sim::studies::sweep::{run_sweep, NamedScene, SweepOptions};
use svo_sim::world::scene::Scene;

/// q dominates p: no worse on both axes, better on one.
fn dominates(q: Point, p: Point) -> bool {
    q.error <= p.error && q.cost <= p.cost && (q.error < p.error || q.cost < p.cost)
}

/// The distance by bisection on its definition: the least δ for which no point dominates
/// ((1 − δ)·p.e, (1 − δ)·p.c).
fn distance_oracle(pts: &[Point], p: Point) -> f64 {
    let escapes = |d: f64| {
        let s = Point {
            error: (1.0 - d) * p.error,
            cost: (1.0 - d) * p.cost,
        };
        !pts.iter().any(|&q| dominates(q, s))
    };
    if escapes(0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if escapes(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

#[test]
fn pareto_front_distance_and_excess_match_brute_force() {
    let seed = test_seed();
    println!("seed {seed:#x} (SVO_TEST_SEED reproduces)");
    let mut rng = SplitMix64::derive(seed, "sweep_pareto");
    let mut off_front = 0;
    for trial in 0..2000 {
        let n = 1 + rng.below(24) as usize;
        // A small grid gives ties on both axes; zeros test the edge of the ratios.
        let grid = 1 + rng.below(12);
        let pts: Vec<Point> = (0..n)
            .map(|_| Point {
                error: rng.below(grid) as f64 * 0.25,
                cost: rng.below(grid) as f64 * 10.0,
            })
            .collect();
        let front = on_front(&pts);
        let dist = distance(&pts);
        let excess = error_excess(&pts);
        for (k, &p) in pts.iter().enumerate() {
            let want = !pts.iter().any(|&q| dominates(q, p));
            assert_eq!(
                front[k], want,
                "seed {seed:#x} trial {trial} point {k}: {pts:?}"
            );
            off_front += usize::from(!want);
            let d = distance_oracle(&pts, p);
            assert!(
                (dist[k] - d).abs() < 1e-9,
                "seed {seed:#x} trial {trial} point {k}: distance {} vs oracle {d}: {pts:?}",
                dist[k]
            );
            let e_min = pts
                .iter()
                .filter(|q| q.cost <= p.cost)
                .map(|q| q.error)
                .fold(f64::INFINITY, f64::min);
            let x = if p.error > 0.0 {
                1.0 - e_min / p.error
            } else {
                0.0
            };
            assert!(
                (excess[k] - x).abs() < 1e-12,
                "seed {seed:#x} trial {trial} point {k}: excess {} vs {x}",
                excess[k]
            );
        }
    }
    assert!(off_front > 1000, "the cases must include dominated points");
}

/// Columns of a CSV line by header name.
fn column<'a>(header: &str, line: &'a str, name: &str) -> &'a str {
    let k = header
        .split(',')
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    line.split(',').nth(k).unwrap()
}

fn row<'a>(csv: &'a str, config: &str) -> &'a str {
    csv.lines()
        .find(|l| l.starts_with(&format!("{config},")))
        .unwrap_or_else(|| panic!("no row {config}"))
}

/// The CSV without its last column (wall time).
fn without_wall(csv: &str) -> String {
    csv.lines()
        .map(|l| l.rsplit_once(',').unwrap().0)
        .collect::<Vec<_>>()
        .join("\n")
}

/// The JSON without the rows' wall times.
fn json_without_wall(text: &str) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
    for r in v["rows"].as_array_mut().unwrap() {
        r.as_object_mut().unwrap().remove("wall_s").unwrap();
    }
    v
}

fn sweep_args(out: &Path) -> Vec<String> {
    [
        "sweep",
        "--only",
        "default,coarse,recip_iter1",
        "--scene",
        "car",
        "--width",
        "40",
        "--height",
        "24",
        "--frames",
        "2",
        "--out",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([out.display().to_string()])
    .collect()
}

#[test]
fn small_sweep_writes_well_formed_deterministic_files() {
    let dir = std::env::temp_dir().join(format!("svo_sweep_cli_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (a, b) = (dir.join("a"), dir.join("b"));
    for out in [&a, &b] {
        let run = run_sim(&sweep_args(out), None, Duration::from_secs(300));
        assert!(run.status.success(), "{}", run.stderr);
        assert!(run.stdout.contains("default on car:"), "{}", run.stdout);
    }
    let csv = std::fs::read_to_string(a.join("sweep.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert_eq!(header, svo_sim::studies::sweep::output::CSV_HEADER);
    let fields = header.split(',').count();
    assert_eq!(csv.lines().count(), 1 + 3);
    for l in csv.lines() {
        assert_eq!(l.split(',').count(), fields, "{l}");
    }
    let score = |c: &str| -> f64 { column(header, row(&csv, c), "error_score").parse().unwrap() };
    println!(
        "error score: default {:e}, recip_iter1 {:e}, coarse {:e}",
        score("default"),
        score("recip_iter1"),
        score("coarse")
    );
    assert!(score("coarse") > 10.0 * score("default"));
    assert!(score("recip_iter1") > score("default"));
    let dsp = |c: &str| -> u64 { column(header, row(&csv, c), "dsp48e2").parse().unwrap() };
    assert_eq!(dsp("default"), 569);
    assert!(dsp("coarse") < dsp("default"));
    let pixels: u64 = column(header, row(&csv, "default"), "pixels")
        .parse()
        .unwrap();
    assert_eq!(pixels, 40 * 24 * 2);

    let json = std::fs::read_to_string(a.join("sweep.json")).unwrap();
    let v = json_without_wall(&json);
    assert_eq!(v["rows"].as_array().unwrap().len(), 3);
    assert_eq!(v["configs"].as_array().unwrap().len(), 3);
    assert_eq!(v["default"][0]["scene"], "car");
    assert_eq!(v["options"]["width"], 40);

    // Reruns agree byte for byte apart from the wall-time figures.
    let csv_b = std::fs::read_to_string(b.join("sweep.csv")).unwrap();
    assert_eq!(without_wall(&csv), without_wall(&csv_b));
    let json_b = std::fs::read_to_string(b.join("sweep.json")).unwrap();
    assert_eq!(v, json_without_wall(&json_b));
    for name in ["sweep_cycles.png", "sweep_dsp.png"] {
        let (x, y) = (
            std::fs::read(a.join(name)).unwrap(),
            std::fs::read(b.join(name)).unwrap(),
        );
        assert!(x == y, "{name} differs between two runs");
        let png = image::load_from_memory(&x).unwrap();
        assert_eq!(
            (png.width(), png.height()),
            svo_sim::studies::sweep::plot::PANEL,
            "{name}: one panel per scene"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_configs_are_refused_and_nothing_is_written() {
    let dir = std::env::temp_dir().join(format!("svo_sweep_bad_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("out");
    let cases = [
        ("[(name: \"x\", datapath: (walker: 3))]", "malformed configuration list"),
        ("[]", "empty"),
        (
            // A t format of 63 bits: walker.t must be at most 62 bits wide.
            "[(name: \"wide_t\", datapath: (walker: (pos: (signed: true, width: 40, frac: 32, quant: RndConv), inv: (signed: true, width: 52, frac: 30, quant: RndConv), t: (signed: true, width: 63, frac: 31), max_steps: 100000)))]",
            "configuration \"wide_t\" is invalid: walker.t",
        ),
    ];
    for (k, (text, want)) in cases.iter().enumerate() {
        let file = dir.join(format!("bad{k}.ron"));
        std::fs::write(&file, text).unwrap();
        let args = [
            "sweep".to_string(),
            "--configs".into(),
            file.display().to_string(),
            "--scene".into(),
            "car".into(),
            "--out".into(),
            out.display().to_string(),
        ];
        let run = run_sim(&args, None, Duration::from_secs(60));
        assert!(!run.status.success(), "case {k} must fail");
        assert!(run.stderr.contains(want), "case {k}: {}", run.stderr);
        assert!(
            run.stderr.contains(&file.display().to_string()),
            "case {k} must name the file: {}",
            run.stderr
        );
        assert!(!out.exists(), "case {k}: nothing may be written");
    }
    let run = run_sim(
        &[
            "sweep",
            "--only",
            "default,nosuch",
            "--out",
            &out.display().to_string(),
        ],
        None,
        Duration::from_secs(60),
    );
    assert!(!run.status.success());
    assert!(
        run.stderr.contains("--only nosuch: no such configuration"),
        "{}",
        run.stderr
    );
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn coarse_datapath_has_more_error_on_the_vox_scene() {
    let Some(path) = common::skip::vox_scene_path("scenes/vox_traffic.ron") else {
        return;
    };
    let scene = Scene::load(&path).unwrap();
    let configs: Vec<_> = builtin()
        .into_iter()
        .filter(|c| c.name == "default" || c.name == "coarse")
        .collect();
    let r = run_sweep(
        &configs,
        &[NamedScene {
            name: "vox_traffic".into(),
            scene,
        }],
        SweepOptions {
            width: 64,
            height: 40,
            frames: 2,
            depth: None,
        },
        |_| {},
    )
    .unwrap();
    let (d, c) = (&r.rows[0], &r.rows[1]);
    assert_eq!(
        (d.config.as_str(), c.config.as_str()),
        ("default", "coarse")
    );
    println!(
        "vox_traffic: default score {:e} (t rms {:e} m), coarse {:e} (t rms {:e} m)",
        d.error.error_score, d.error.t_err_rms, c.error.error_score, c.error.t_err_rms
    );
    assert!(d.error.pixels == 64 * 40 * 2);
    assert!(c.error.error_score > 10.0 * d.error.error_score);
    assert!(c.error.t_err_rms > 10.0 * d.error.t_err_rms);
    // Two points: each is on both fronts (coarse is cheaper, the default more accurate) or
    // the default dominates.
    assert!(d.dsp_front.on_front && c.dsp_front.on_front);
    assert_eq!(r.default.len(), 1);
    assert!(r.default[0].within_5_percent);
}

#[test]
fn docs_match_the_built_in_list_and_the_example_file_is_valid() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/accuracy.md")).unwrap();
    let list = builtin();
    assert!(list.len() >= 12);
    for c in &list {
        // Each configuration has its row in the cost table of §2.
        let cell = format!("| `{}` |", c.name);
        assert!(doc.contains(&cell), "docs/accuracy.md lacks {cell}");
    }
    let example =
        svo_sim::studies::sweep::configs::load(&root.join("docs/sweep_configs_example.ron"))
            .unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = example.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["default", "former_default"]);
    assert_eq!(example[0].datapath, list[0].datapath);
    // The example's second entry is the default before `sim sweep` moved it onto the front: two
    // built-in variants combined, recip_frac26's reciprocal and walker and tca_frac32's sphere.
    let pick = |n: &str| list.iter().find(|c| c.name == n).unwrap().datapath.clone();
    let (r26, tca) = (pick("recip_frac26"), pick("tca_frac32"));
    let combo = &example[1].datapath;
    assert_eq!(combo.reciprocal, r26.reciprocal);
    assert_eq!(combo.walker, r26.walker);
    assert_eq!(combo.sphere, tca.sphere);
    assert_eq!(combo.transform, list[0].datapath.transform);
}
