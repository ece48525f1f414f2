//! Sampled timing (`--sample`, docs/cycle-model.md §3.5): on small cases — the default car
//! with a still and a moving camera, and the small machine of the golden reports — the full
//! model's cycles lie in every frame's 95 % interval, and the sample plan is deterministic
//! (the same seed gives the same estimate); at the documented default rate and band, over three
//! seeds, the estimate is within 1 % of the full figure and its interval's half-width within 5 %.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use svo_sim::models::cycle::sample::{SampleConfig, DEFAULT_BAND_ROWS, DEFAULT_RATE};
use svo_sim::models::cycle::validate::compare;
use svo_sim::world::assets::{build_assets, effective_depths, Asset, Materialise};
use svo_sim::world::scene::Scene;

fn small_hw() -> HwConfig {
    let text = std::fs::read_to_string("tests/golden/small_hw.ron").unwrap();
    ron::from_str(&text).unwrap()
}

/// The default car, two frames at `w`×`h`, its deepest asset at `depth`.
fn car(w: u32, h: u32, depth: u8) -> (Scene, Vec<Asset>) {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(w, h).unwrap();
    scene.set_frames(2).unwrap();
    let depths = effective_depths(&scene, Some(depth)).unwrap();
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap();
    (scene, assets)
}

#[test]
fn full_cycles_lie_in_the_sampled_interval() {
    let (scene, assets) = car(320, 192, 8);
    let dp = DatapathConfig::default();
    let mut hw_small = small_hw();
    hw_small.frame = HwConfig::default().frame;
    // 320 wide: bands of 2 rows, one in 4, the warming sized from the trace (the documented
    // rule: at least 10 rows a band here). A fixed 2 rows under-warm the walker-bound default
    // of issue 29 (32 walkers × 8 contexts): frame 0's estimate came out +1.4 % with its
    // interval, 62,717–63,462, above the full model's 62,215 cycles; 48 × 16 had covered it.
    let cfg = SampleConfig {
        period: 4,
        band_rows: 2,
        warm_rows: None,
        seed: 3,
    };
    for (name, hw, reuse) in [
        ("default hardware, still camera", HwConfig::default(), true),
        (
            "default hardware, moving camera",
            HwConfig::default(),
            false,
        ),
        ("small machine, still camera", hw_small, true),
    ] {
        let rows = compare(&scene, &assets, &dp, &hw, reuse, cfg).unwrap();
        for r in &rows {
            println!(
                "{name}, frame {}: full {} estimate {:.0} [{:.0}, {:.0}] error {:+.2}%",
                r.frame,
                r.full_cycles,
                r.estimate,
                r.low,
                r.high,
                100.0 * r.error()
            );
            assert!(
                r.covered(),
                "{name}, frame {}: full cycles outside the interval",
                r.frame
            );
            assert!(r.high > r.low, "{name}: an interval of zero width");
        }
        let again = compare(&scene, &assets, &dp, &hw, reuse, cfg).unwrap();
        for (a, b) in rows.iter().zip(&again) {
            assert_eq!((a.estimate, a.low, a.high), (b.estimate, b.low, b.high));
        }
    }
}

/// Caps on the estimate at the documented default (docs/cycle-model.md §3.5: one band in 8,
/// bands of 2 rows, warming sized automatically), over three start seeds of the systematic
/// sample (`SampleConfig::seed`, mixed with the frame number by `Sampler::plan`): the 95 %
/// interval's half-width at most 5 % and the estimate's error at most 1 % of the full model's
/// cycles, on the default car (depth 8, default hardware) with a still camera — frame 0 traces
/// every pixel, frame 1 reuses 69 % of them.
///
/// Measured (this test, seeds 1–3, opt-level 2, about 20 s): at 640×384 the worst error is
/// 0.61 % and the worst half-width 4.03 %. At 320×192 (96 bands, 12 of them timed) the caps do
/// not hold — worst error 1.34 % (seed 1 and 2, moving camera frame 1), half-width 6.22 % —
/// so 640×384 is the smallest of the two sizes where they do, and the test runs there.
#[test]
fn default_sample_is_close_and_narrow() {
    const MAX_ERROR: f64 = 0.01;
    const MAX_HALF_WIDTH: f64 = 0.05;
    let (scene, assets) = car(640, 384, 8);
    let dp = DatapathConfig::default();
    let (mut worst_err, mut worst_half) = (0.0f64, 0.0f64);
    for seed in [1, 2, 3] {
        let cfg = SampleConfig::from_rate(DEFAULT_RATE, DEFAULT_BAND_ROWS, None, seed).unwrap();
        assert_eq!((cfg.period, cfg.band_rows, cfg.warm_rows), (8, 2, None));
        let rows = compare(&scene, &assets, &dp, &HwConfig::default(), true, cfg).unwrap();
        for r in &rows {
            let full = r.full_cycles as f64;
            let half = (r.high - r.low) / 2.0 / full;
            println!(
                "seed {seed}, frame {}: full {} estimate {:.0} [{:.0}, {:.0}] error {:+.3}% half-width {:.3}%",
                r.frame,
                r.full_cycles,
                r.estimate,
                r.low,
                r.high,
                100.0 * r.error(),
                100.0 * half
            );
            assert!(
                r.error().abs() <= MAX_ERROR,
                "seed {seed}, frame {}: error {:+.3}% above {}%",
                r.frame,
                100.0 * r.error(),
                100.0 * MAX_ERROR
            );
            assert!(
                half <= MAX_HALF_WIDTH,
                "seed {seed}, frame {}: half-width {:.3}% above {}%",
                r.frame,
                100.0 * half,
                100.0 * MAX_HALF_WIDTH
            );
            assert!(
                r.covered(),
                "seed {seed}, frame {}: outside the interval",
                r.frame
            );
            worst_err = worst_err.max(r.error().abs());
            worst_half = worst_half.max(half);
        }
    }
    println!(
        "worst error {:.3}%, worst half-width {:.3}%",
        100.0 * worst_err,
        100.0 * worst_half
    );
}

/// Rate 1 (`--sample 1`) times every band in one segment: the estimate is the full model's
/// cycles exactly, the reference against which a sample's bands are compared band by band.
#[test]
fn every_band_timed_is_the_full_run() {
    let (scene, assets) = car(160, 96, 7);
    let cfg = SampleConfig::from_rate(1.0, 2, None, 0).unwrap();
    assert_eq!(cfg.period, 1);
    let dp = DatapathConfig::default();
    for reuse in [true, false] {
        let rows = compare(&scene, &assets, &dp, &HwConfig::default(), reuse, cfg).unwrap();
        for r in &rows {
            println!(
                "frame {} (reuse {reuse}): full {} every band timed {}",
                r.frame, r.full_cycles, r.estimate
            );
            assert_eq!(r.estimate, r.full_cycles as f64, "frame {}", r.frame);
        }
    }
    assert!(SampleConfig::from_rate(1.01, 2, None, 0).is_err());
    assert!(SampleConfig::from_rate(0.0, 2, None, 0).is_err());
}

/// The figure after `= ` and before ` fps` on the line starting with `prefix`.
fn fps_on(stdout: &str, prefix: &str) -> String {
    let line = stdout
        .lines()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starting with {prefix:?} in:\n{stdout}"));
    let after = line.split_once(" = ").expect("` = ` on the line").1;
    after.split(' ').next().expect("a figure").to_string()
}

/// A sampled run states one frame rate: its SAMPLED summary line and its cycle summary line
/// print the same cycles and fps, and the report's `summary.fps_at_clock` is
/// `summary.sampled.fps` (they were two computations, one over the frames' rounded
/// cycles and one over the unrounded estimates, and printed e.g. 2346.1 and 2346.2 fps).
#[test]
fn a_sampled_run_prints_one_frame_rate() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("sampled_one_rate_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("r.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sim"))
        .args([
            "--sample",
            "0.25",
            "--width",
            "160",
            "--height",
            "96",
            "--frames",
            "3",
            "--depth",
            "7",
            "--no-png",
            "-q",
            "--report-json",
        ])
        .arg(&json)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sampled = fps_on(&stdout, "cycle model, SAMPLED timing");
    let summary = fps_on(&stdout, "cycle model: ");
    println!("SAMPLED line {sampled} fps, summary line {summary} fps");
    assert_eq!(sampled, summary, "{stdout}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let c = &r["summary"];
    let fps = c["fps_at_clock"].as_f64().expect("summary.fps_at_clock");
    let cycles = c["cycles"].as_u64().expect("summary.cycles");
    assert_eq!(Some(fps), c["sampled"]["fps"].as_f64(), "{c}");
    assert_eq!(
        Some(cycles as f64),
        c["sampled"]["cycles_estimate"].as_f64(),
        "{c}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
