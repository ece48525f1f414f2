//! What a run refuses or warns about before or after it: a scene beyond the datapath's
//! formats is refused before the run with the value, the range and the remedy; a run that
//! saturates warns on stderr and fails unless `--allow-saturation` accepts it.
//!
//! Pipeline position: the CLI's checks of the scene and the datapath formats
//! (`sim --datapath`, `--allow-saturation`).

use super::common::process::run_sim;
use super::{Tmp, TIMEOUT};
use std::path::Path;

/// A one-frame 32x20 run of `model` with `extra` options.
fn one_small_frame(model: &str, extra: &[&str]) -> Vec<String> {
    [
        "--model", model, "--frames", "1", "--width", "32", "--height", "20",
    ]
    .iter()
    .chain(extra)
    .map(|s| s.to_string())
    .collect()
}

/// A scene beyond the datapath's position range (the camera 150 m out; sQ8.32 holds ±128 m)
/// is refused before the run: an error naming the value, the format's range and the remedy,
/// and nothing written.
#[test]
fn scene_beyond_the_formats_is_refused_before_the_run() {
    let t = Tmp::new("scene_beyond_the_formats");
    let car = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/car.ron"))
        .expect("read scenes/car.ron");
    let far = car.replace("position: (4.6, 2.2, -4.4)", "position: (150.0, 2.2, -4.4)");
    assert_ne!(far, car, "the car's camera line moved: update this test");
    let scene = t.p("far.ron");
    std::fs::write(&scene, far).expect("write the scene");
    let out = t.p("out");
    let report = t.p("r.json");
    for model in ["fixed", "cycle"] {
        let r = run_sim(
            &one_small_frame(
                model,
                &["--scene", &scene, "--out", &out, "--report-json", &report],
            ),
            None,
            TIMEOUT,
        );
        assert!(!r.status.success(), "{model}: {}", r.stderr);
        for needle in [
            "camera position = 150.000 m",
            "raygen.pos",
            "sQ8.32",
            "--datapath",
        ] {
            assert!(
                r.stderr.contains(needle),
                "{model}: no {needle:?} in {}",
                r.stderr
            );
        }
        assert!(!Path::new(&out).exists() && !Path::new(&report).exists());
    }
    // The reference has no formats: the same scene renders.
    let r = run_sim(
        &one_small_frame("reference", &["--scene", &scene, "--no-png"]),
        None,
        TIMEOUT,
    );
    assert!(r.status.success(), "{}", r.stderr);
}

/// A run that saturates anyway (here a hit-record t format narrowed to uQ2.10, 4 m, with the
/// car 6 m away) warns on stderr even under `-q`, naming the signal, and exits non-zero unless
/// `--allow-saturation` accepts it; a run that fits prints no warning.
#[test]
fn saturation_is_loud_and_fails_unless_allowed() {
    let t = Tmp::new("saturation_is_loud");
    let dp = t.p("narrow.ron");
    std::fs::write(
        &dp,
        "(hit_record: (t: (signed: false, width: 12, frac: 10)))",
    )
    .expect("write the datapath");
    let narrow = ["--datapath", dp.as_str(), "--no-png", "-q"];
    let refused = run_sim(&one_small_frame("fixed", &narrow), None, TIMEOUT);
    assert!(!refused.status.success(), "{}", refused.stderr);
    assert!(refused.stderr.contains("warning: "), "{}", refused.stderr);
    assert!(
        refused.stderr.contains("(hit_record "),
        "{}",
        refused.stderr
    );
    assert!(
        refused.stderr.contains("--allow-saturation"),
        "{}",
        refused.stderr
    );
    let allowed = run_sim(
        &one_small_frame("fixed", &[&narrow[..], &["--allow-saturation"]].concat()),
        None,
        TIMEOUT,
    );
    assert!(allowed.status.success(), "{}", allowed.stderr);
    assert!(allowed.stderr.contains("saturated"), "{}", allowed.stderr);
    let fits = run_sim(
        &one_small_frame("fixed", &["--no-png", "-q"]),
        None,
        TIMEOUT,
    );
    assert!(fits.status.success(), "{}", fits.stderr);
    assert!(!fits.stderr.contains("saturated"), "{}", fits.stderr);
}
