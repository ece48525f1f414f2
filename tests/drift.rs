//! The drift experiment at a small size (1 500 frames, 16×12): the claims of `docs/drift.md`
//! checked with numbers, frame by frame —
//! - (a) matrices rebuilt from keyframes in fixed point stay within their constant bounds;
//! - (b) incremental updates with re-orthonormalisation keep the orthonormality error within
//!   its steady-state bound and the matrix error within its (linear) bound;
//! - (b) without re-orthonormalisation leaves that bound far behind, and keeps growing;
//! - no mismatch or t error beyond the bound, no saturation;
//! - in the image, (a)'s t errors stay flat against their per-pixel bound while the
//!   uncorrected path's grow past it.
//!
//! And `sim drift` writes its three files deterministically and refuses bad input cleanly.

mod common;
use common::process::run_sim;
use std::time::Duration;
use svo_sim::studies::drift::run::FrameDrift;
use svo_sim::studies::drift::{run_drift, DriftOptions, Mode};

#[test]
fn bounded_with_keyframes_and_with_the_correction_drifting_without() {
    let frames = 1500;
    let r = run_drift(&DriftOptions::new(frames, 16, 12, 6), |_| {}).unwrap();
    let b = &r.bounds;
    let rows = |m: Mode| r.rows.iter().filter(move |x| x.mode == m);
    for x in rows(Mode::Keyframe) {
        assert!(x.orthonormality <= b.keyframe_orthonormality, "{x:?}");
        assert!(x.matrix_error <= b.keyframe_matrix, "{x:?}");
    }
    for x in rows(Mode::Incremental) {
        assert!(x.orthonormality <= b.incremental_orthonormality, "{x:?}");
        assert!(x.matrix_error <= x.matrix_bound, "{x:?}");
    }
    for m in Mode::ALL {
        for x in rows(m) {
            assert_eq!((x.beyond_bound, x.saturations), (0, 0), "{x:?}");
            assert!(x.t_err_over_bound <= 1.0, "{x:?}");
        }
    }
    // Without the correction: mean orthonormality error of the last tenth against the first.
    let mean =
        |it: Vec<&FrameDrift>| it.iter().map(|x| x.orthonormality).sum::<f64>() / it.len() as f64;
    let tenth = frames / 10;
    let raw: Vec<&FrameDrift> = rows(Mode::IncrementalNoReorth).collect();
    let (early, late) = (
        mean(raw[1..tenth as usize].to_vec()),
        mean(raw[(frames - tenth) as usize..].to_vec()),
    );
    let last = raw.last().unwrap().orthonormality;
    println!(
        "bound {:.3e}; without correction: first tenth {early:.3e}, last tenth {late:.3e}, last {last:.3e}",
        b.incremental_orthonormality
    );
    assert!(last > 10.0 * b.incremental_orthonormality);
    assert!(
        late > 2.0 * early,
        "the uncorrected error must keep growing"
    );
    // With it, the last tenth is no worse than the bound, and (a) has no trend either.
    let corrected: Vec<&FrameDrift> = rows(Mode::Incremental).collect();
    assert!(mean(corrected[(frames - tenth) as usize..].to_vec()) <= b.incremental_orthonormality);
    assert!(r.claims.keyframe_bounded && r.claims.incremental_bounded && r.claims.no_reorth_drifts);
    // In the image: each path's largest t error over the per-pixel bound that a pose rebuilt
    // from the keys guarantees, first tenth against last tenth. (a) stays flat; without the
    // correction it more than doubles and leaves that bound.
    let ratio = |m: Mode, late: bool| {
        let v: Vec<&FrameDrift> = rows(m).collect();
        let part = if late {
            &v[(frames - tenth) as usize..]
        } else {
            &v[..tenth as usize]
        };
        part.iter()
            .map(|x| x.t_err_over_keyframe_bound)
            .fold(0.0, f64::max)
    };
    let (a0, a1) = (ratio(Mode::Keyframe, false), ratio(Mode::Keyframe, true));
    let (n0, n1) = (
        ratio(Mode::IncrementalNoReorth, false),
        ratio(Mode::IncrementalNoReorth, true),
    );
    println!("t error / (a)'s bound: (a) {a0:.3} -> {a1:.3}; no correction {n0:.3} -> {n1:.3}");
    assert!(a1 <= 1.5 * a0 && a1 < 1.0);
    assert!(n1 > 2.0 * n0 && n1 > 1.0);
    assert!(rows(Mode::Keyframe).all(|x| x.beyond_keyframe_bound == 0));
}

#[test]
fn cli_writes_three_files_deterministically_and_refuses_bad_input() {
    let dir = std::env::temp_dir().join(format!("svo_drift_cli_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let args = |out: &std::path::Path, frames: &str| {
        vec![
            "drift".to_string(),
            "--frames".into(),
            frames.into(),
            "--width".into(),
            "12".into(),
            "--height".into(),
            "8".into(),
            "--depth".into(),
            "5".into(),
            "--out".into(),
            out.display().to_string(),
        ]
    };
    let (a, b) = (dir.join("a"), dir.join("b"));
    for out in [&a, &b] {
        let run = run_sim(&args(out, "120"), None, Duration::from_secs(120));
        assert!(run.status.success(), "{}", run.stderr);
        assert!(run.stdout.contains("claims:"), "{}", run.stdout);
    }
    for name in ["drift.csv", "drift.json", "drift.png"] {
        let (x, y) = (
            std::fs::read(a.join(name)).unwrap(),
            std::fs::read(b.join(name)).unwrap(),
        );
        assert!(x == y, "{name} differs between two runs");
    }
    let png = image::open(a.join("drift.png")).unwrap();
    assert_eq!(
        (png.width(), png.height()),
        svo_sim::studies::drift::plot::SIZE
    );
    let csv = std::fs::read_to_string(a.join("drift.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3 * 120);
    // Bad input: a clear message, a non-zero exit, nothing written.
    let c = dir.join("c");
    let run = run_sim(&args(&c, "1"), None, Duration::from_secs(60));
    assert!(!run.status.success());
    assert!(run.stderr.contains("at least 2 frames"), "{}", run.stderr);
    assert!(!c.exists(), "nothing may be written on bad input");
    let file = dir.join("a/drift.csv");
    let run = run_sim(&args(&file, "10"), None, Duration::from_secs(60));
    assert!(!run.status.success());
    assert!(run.stderr.contains("not a folder"), "{}", run.stderr);
    std::fs::remove_dir_all(&dir).unwrap();
}
