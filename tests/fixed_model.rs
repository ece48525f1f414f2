//! The functional fixed-point model end to end.
//!
//! - Its hit buffer is sound: every frame rendered with reuse equals, bit for bit (packed
//!   record, walker t, voxel), the same frame re-traced in full without it.
//! - Against the f64 reference on the animated default scene: no hit/miss or instance
//!   mismatch, every voxel mismatch within the walker's bound, no saturation.
//! - `sim --model fixed` reports `frames[].accuracy` with the documented fields.

use rtl_model::datapath::DatapathConfig;
use std::path::Path;
use svo_sim::models::fixed::bound::mismatch_explained;
use svo_sim::models::fixed::{compare, render_frame_fixed, to_hit_records, FixedBuffer};
use svo_sim::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use svo_sim::world::assets::{build_assets, effective_depths, Materialise};
use svo_sim::world::scene::Scene;

#[test]
fn fixed_hit_buffer_never_changes_a_pixel_and_accuracy_holds() {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(96, 64).unwrap();
    scene.set_frames(10).unwrap();
    let depths = effective_depths(&scene, Some(7)).unwrap();
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let cfg = DatapathConfig::default();
    let (w, h) = scene.file.resolution;
    let mut reused_buf = FixedBuffer::new(w, h);
    let mut reference = HitBuffer::new(w, h);
    let mut reused = 0;
    for f in 0..scene.file.frames {
        let state = scene.frame_state(f, &half).unwrap();
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &state,
        };
        let st = render_frame_fixed(&input, &mut reused_buf, &cfg, true).unwrap();
        reused += st.hit_buffer_reused;
        let mut fresh = FixedBuffer::new(w, h);
        render_frame_fixed(&input, &mut fresh, &cfg, false).unwrap();
        assert_eq!(
            reused_buf.records, fresh.records,
            "frame {f}: hit-buffer reuse changed a record"
        );
        assert_eq!(
            st.overflows.as_ref().map(|o| o.total()),
            Some(0),
            "frame {f}: saturations"
        );
        render_frame(&input, &mut reference, RenderOptions::default());
        let fixed = to_hit_records(&reused_buf, &cfg);
        let acc = compare(&reference.records, &fixed, |k| {
            let inst = usize::from(fixed[k].instance);
            let depth = assets[scene.instance_asset[inst]].depth();
            mismatch_explained(
                &cfg,
                &state.camera,
                (w, h),
                (k as u32 % w, k as u32 / w),
                &state.poses[inst],
                fixed[k].voxel,
                depth,
            )
        });
        assert_eq!(
            (acc.hit_mismatches, acc.instance_mismatches),
            (0, 0),
            "frame {f}: {acc:?}"
        );
        assert_eq!(acc.voxel_mismatches_beyond_bound, 0, "frame {f}: {acc:?}");
        assert!(acc.t_err_max < 1e-6, "frame {f}: {acc:?}");
    }
    assert!(
        reused > 0,
        "the still camera and static body must reuse pixels"
    );
}

#[test]
fn implicit_assets_are_refused_clearly() {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(8, 8).unwrap();
    let depths = effective_depths(&scene, Some(5)).unwrap();
    let assets = build_assets(&scene, &depths, Materialise::Never).unwrap();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let state = scene.frame_state(0, &half).unwrap();
    let input = FrameInput {
        scene: &scene,
        assets: &assets,
        state: &state,
    };
    let err = render_frame_fixed(
        &input,
        &mut FixedBuffer::new(8, 8),
        &DatapathConfig::default(),
        true,
    )
    .unwrap_err();
    assert!(err.to_string().contains("memory image"), "{err}");
}

#[test]
fn cli_reports_accuracy() {
    let dir = std::env::temp_dir().join(format!("svo_fixed_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let report = dir.join("r.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sim"))
        .args([
            "--model", "fixed", "--width", "48", "--height", "32", "--frames", "2", "--depth", "6",
        ])
        .arg("--out")
        .arg(&dir)
        .arg("--report-json")
        .arg(&report)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("accuracy:"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["options"]["model"], "fixed");
    for f in json["frames"].as_array().unwrap() {
        for field in [
            "pixels",
            "hit_mismatches",
            "instance_mismatches",
            "voxel_mismatches",
            "t_err_max",
            "t_err_rms",
            "saturations",
        ] {
            assert!(
                f["accuracy"][field].is_number(),
                "frames[].accuracy.{field} missing: {f}"
            );
        }
        assert_eq!(f["accuracy"]["pixels"], 48 * 32);
    }
    assert!(
        json["datapath"]["walker"]["t"].is_object(),
        "the report carries the datapath"
    );
    assert!(Path::new(&dir).join("diff_0001.png").is_file());
    std::fs::remove_dir_all(&dir).unwrap();
}
