//! The record's fixed-point normal (rtl_model::units::normal, the record stage's normal unit)
//! against the host's f64 path it replaced, over every hit of the shipped scenes: per hit
//! pixel of the fixed model, the record's (u, v) against
//! `encode_normal(normalize(R·diag(1/scale)·attr.normal()))`, the f64 path of
//! `FramePlan::finish` before the unit (f64 matrix from the pose, not the unit's quantised one).
//! Every hit within one code per component, at most 1 % of a scene's hits differing at all,
//! except the lower hemisphere's seam (x or y exactly
//! 0 in one path, where u = ±(1 − |v|) are one direction): there the decoded directions agree
//! within 0.6°. Prints the counts quoted in docs/units/normal.md. Scenes of shared .vox models
//! are skipped without them (SKIPPED line).

mod common;

use glam::{DMat3, DVec3};
use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::{Overflows, SignalId};
use rtl_model::units::hit_record::{decode_normal, encode_normal, unpack};
use std::path::Path;
use svo_sim::models::fixed::{render_frame_fixed, FixedBuffer};
use svo_sim::models::reference::FrameInput;
use svo_sim::world::assets::{build_assets, effective_depths, AssetTree, Materialise};
use svo_sim::world::scene::Scene;

fn angle_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

#[test]
fn every_hit_of_the_shipped_scenes_within_one_code_of_the_f64_path() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cfg = DatapathConfig::default();
    let bits = cfg.hit_record.normal_bits;
    let with_vox = common::skip::shared_vox_dir_for("the scenes of shared .vox models").is_some();
    let (mut all_hits, mut all_differ) = (0u64, 0u64);
    for (name, w, h, frames) in [
        ("car", 320, 192, 3),
        ("car_static", 320, 192, 1),
        ("moving_camera", 160, 96, 3),
        ("static_single", 160, 96, 1),
        ("vox_traffic", 320, 192, 3),
        ("crowd_100", 160, 96, 2),
    ] {
        let path = repo.join(format!("scenes/{name}.ron"));
        let text = std::fs::read_to_string(&path).expect("read a scene");
        if text.contains(".vox") && !with_vox {
            continue;
        }
        let mut scene = Scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        scene.set_resolution(w, h).unwrap();
        scene.set_frames(frames).unwrap();
        let depths = effective_depths(&scene, None).unwrap();
        let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap();
        let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
        let mut buf = FixedBuffer::new(w, h);
        let (mut hits, mut differ, mut seam, mut worst) = (0u64, 0u64, 0u64, 0.0f64);
        for f in 0..frames {
            let state = scene.frame_state(f, &half).unwrap();
            let input = FrameInput {
                scene: &scene,
                assets: &assets,
                state: &state,
            };
            render_frame_fixed(&input, &mut buf, &cfg, false).unwrap();
            for (k, rec) in buf.records.iter().enumerate() {
                if !rec.hit {
                    continue;
                }
                let fields = unpack(rec.word, &cfg.hit_record);
                let inst = usize::from(fields.instance.expect("a hit has an instance"));
                let asset = &assets[scene.instance_asset[inst]];
                let AssetTree::Image(image) = &asset.tree else {
                    panic!("{name}: implicit asset");
                };
                let attr = image
                    .leaf_at(rec.voxel)
                    .unwrap_or_else(|| panic!("{name} pixel {k}: no leaf at {:?}", rec.voxel));
                let pose = &state.poses[inst];
                let scale = pose.half_extent / asset.half_size;
                let n = (pose.world_from_local * DMat3::from_diagonal(scale.recip()))
                    * DVec3::from_array(attr.normal());
                let mut ov = Overflows::new(&["n"]);
                let want =
                    encode_normal(n.normalize_or_zero().to_array(), bits, &mut ov, SignalId(0));
                let got = fields.normal;
                hits += 1;
                let d = (got[0] - want[0]).abs().max((got[1] - want[1]).abs());
                if d > 0 {
                    differ += 1;
                }
                let deg = angle_deg(decode_normal(got, bits), decode_normal(want, bits));
                if d > 1 {
                    seam += 1;
                    assert!(
                        deg < 0.6,
                        "{name} frame {f} pixel {k}: {got:?} against the f64 path's {want:?} ({deg}°)"
                    );
                } else {
                    worst = worst.max(deg);
                }
            }
        }
        println!(
            "{name} {w}x{h}, {frames} frames: {hits} hits, {differ} normals differ from the f64 path ({:.3} %), {seam} of them on the seam (> 1 code, same direction), worst one-code angle {worst:.3}°",
            100.0 * differ as f64 / hits.max(1) as f64
        );
        // The random property test (units::normal) differs in 0.11 % of cases; a scene far
        // above that has a systematic error (a rounding or format change), not bad luck.
        assert!(
            differ * 100 <= hits,
            "{name}: {differ} of {hits} hit normals differ from the f64 path (more than 1 %)"
        );
        all_hits += hits;
        all_differ += differ;
    }
    println!("all: {all_hits} hits, {all_differ} differ");
    assert!(all_hits > 0);
}
