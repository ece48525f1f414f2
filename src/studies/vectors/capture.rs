//! Captures one real frame's transactions, stage by stage, for the vectors: the frame is run
//! through the fixed-point units in the order `models::fixed::frame` runs them (frame 0 of a
//! run: every pixel traced, no hit-buffer reuse), one pixel at a time, recording each unit's
//! inputs and each pixel's end result.
//!
//! Pipeline position: the root package's side of `sim vectors`; `rtl_model::vectors` turns
//! the recorded inputs into rows with the golden model's outputs. The per-pixel words this
//! produces are checked against `render_frame_fixed` in `tests/vectors.rs`, so this replay
//! cannot drift from the functional model unnoticed.

use super::VectorsError;
use crate::models::reference::ray::primary_ray;
use crate::world::assets::{Asset, AssetTree};
use crate::world::scene::{FrameState, Scene};
use glam::{DMat3, DVec3};
use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::{from_f64, to_f64, Overflows, SignalId};
use rtl_model::svo::SvoImage;
use rtl_model::units::hit_record::{pack, quantise, HitRecordF64, SphereCount};
use rtl_model::units::raygen::direction_entry;
use rtl_model::units::reciprocal::ReciprocalUnit;
use rtl_model::units::sorter::{Sorter, SorterStats};
use rtl_model::units::sphere::{sphere_test, SphereRaw, SphereSignals};
use rtl_model::units::transform::{transform_with_signs, InstanceRaw, TransformSignals};
use rtl_model::units::walker::{walk_fixed, WalkOutcome, WalkerHit, WalkerInput, WalkerStats};
use rtl_model::vectors::frame::{FrameInstance, FramePixel};
use rtl_model::vectors::stage::raygen::RaygenTxn;
use rtl_model::vectors::stage::sphere::{SphereStage, SphereTxn};
use rtl_model::vectors::stage::transform::TransformTxn;
use rtl_model::vectors::stage::walker::WalkTxn;
use rtl_model::vectors::Captured;

/// A captured frame: every unit's inputs, and the end-to-end view.
pub struct FrameCapture {
    /// Per-stage inputs.
    pub captured: Captured,
    /// Camera position codes.
    pub origin: [i64; 3],
    /// What the host programs per instance.
    pub instances: Vec<FrameInstance>,
    /// Every pixel in raster order.
    pub pixels: Vec<FramePixel>,
}

struct Inst<'a> {
    raw: InstanceRaw,
    sphere: SphereRaw,
    half: [i64; 3],
    asset: usize,
    image: &'a SvoImage,
    normal_to_world: DMat3,
}

/// Overflows are not what the capture is for (the rows carry their own flags); one
/// throw-away table serves every call.
fn scratch() -> Overflows {
    Overflows::new(&rtl_model::datapath::SIGNAL_NAMES)
}

/// Runs `state` (a frame of `scene` at its resolution) through the units and records it.
pub fn capture_frame(
    scene: &Scene,
    assets: &[Asset],
    state: &FrameState,
    dp: &DatapathConfig,
) -> Result<FrameCapture, VectorsError> {
    dp.validate().map_err(VectorsError::Datapath)?;
    let (w, h) = scene.file.resolution;
    let mut ov = scratch();
    let sig = SignalId(0);
    let rg = dp.raygen;
    let q = |v: DVec3, f, ov: &mut Overflows| v.to_array().map(|x| from_f64(x, f, ov, sig));
    let mut insts = Vec::with_capacity(state.poses.len());
    for (pose, &ai) in state.poses.iter().zip(&scene.instance_asset) {
        let asset = &assets[ai];
        let AssetTree::Image(image) = &asset.tree else {
            return Err(VectorsError::Implicit(asset.name.clone()));
        };
        let r = pose.world_from_local;
        let centre = q(pose.centre, rg.pos, &mut ov);
        let scale = pose.half_extent / asset.half_size;
        insts.push(Inst {
            raw: InstanceRaw {
                axes: [r.x_axis, r.y_axis, r.z_axis].map(|c| q(c, rg.mat, &mut ov)),
                centre,
            },
            sphere: SphereRaw::new(centre, pose.sphere_radius(), &dp.sphere),
            half: q(pose.half_extent, dp.walker.pos, &mut ov),
            asset: ai,
            image,
            normal_to_world: r * DMat3::from_diagonal(scale.recip()),
        });
    }
    let cam = state.camera;
    let origin = q(cam.position, rg.pos, &mut ov);
    let sphere_sig = SphereSignals {
        tca: sig,
        sq: sig,
        t_enter: sig,
        reach: sig,
    };
    let tr_sig = TransformSignals {
        origin: sig,
        dir: sig,
    };
    let sphere_stage = SphereStage::new(dp);
    let sorter = Sorter::new(&dp.sorter);
    let lanes = usize::from(dp.sorter.n.max(1));
    let recip = ReciprocalUnit::new(&dp.reciprocal);
    let (key_fmt, t_fmt) = (dp.sorter.key, dp.walker.t);
    let mut cap = Captured::default();
    let mut pixels = Vec::with_capacity(w as usize * h as usize);
    for j in 0..h {
        for i in 0..w {
            let ray = primary_ray(&cam, w, h, i, j);
            cap.raygen.push(RaygenTxn {
                pixel: [i as u16, j as u16],
                dir: ray.dir.to_array(),
                origin: cam.position.to_array(),
            });
            let d = direction_entry(ray.dir.to_array(), &rg, &mut ov, sig);
            let mut cands: Vec<(i64, u16)> = Vec::with_capacity(insts.len());
            for (k, inst) in insts.iter().enumerate() {
                let txn = SphereTxn::of(origin, d, &inst.sphere);
                cap.sphere.push(txn);
                if let Some(x) = sphere_stage.radicand(&txn) {
                    cap.sqrt.push(x);
                }
                if let Some(s) =
                    sphere_test(origin, d, &inst.sphere, &dp.sphere, &mut ov, sphere_sig)
                {
                    cands.push((s.t_enter, k as u16));
                }
            }
            let spheres = SphereCount::from_count(cands.len());
            cap.sorter.extend(cands.chunks(lanes).map(<[_]>::to_vec));
            let candidates = cands.len() as u32;
            sorter.sort_in_place(&mut cands, &mut SorterStats::default());
            let mut best: Option<(i64, u16, WalkerHit)> = None;
            let mut walks = 0u32;
            for &(key, k) in &cands {
                if let Some((bt, _, _)) = best {
                    // Early termination, as the functional model decides it.
                    let f = key_fmt.frac.max(t_fmt.frac);
                    if i128::from(bt) << (f - t_fmt.frac) <= i128::from(key) << (f - key_fmt.frac) {
                        break;
                    }
                }
                let inst = &insts[usize::from(k)];
                cap.transform.push(TransformTxn {
                    o: origin,
                    d,
                    inst: inst.raw,
                });
                let (o_local, d_local, signs) =
                    transform_with_signs(origin, d, &inst.raw, &dp.transform, &mut ov, tr_sig);
                let mut inp = WalkerInput {
                    origin: o_local,
                    half: inst.half,
                    ..WalkerInput::default()
                };
                for a in 0..3 {
                    cap.reciprocal.push((d_local[a], signs[a]));
                    let r = recip.eval(d_local[a], signs[a], &mut ov, sig);
                    inp.inv[a] = r.raw.saturating_abs();
                    inp.zero[a] = r.zero;
                    inp.negative[a] = r.negative;
                }
                cap.walker.push(WalkTxn {
                    image: inst.asset,
                    input: inp,
                });
                walks += 1;
                let out = walk_fixed(
                    inst.image,
                    &inp,
                    &dp.walker,
                    &mut ov,
                    sig,
                    &mut WalkerStats::default(),
                );
                if let WalkOutcome::Hit(hit) = out {
                    if best.is_none_or(|(bt, _, _)| hit.t < bt) {
                        best = Some((hit.t, k, hit));
                    }
                }
            }
            let f64_record = match best {
                None => HitRecordF64 {
                    kind: spheres,
                    instance: None,
                    t: f64::INFINITY,
                    normal: [0.0; 3],
                    colour: [0; 3],
                    voxel: [0; 3],
                },
                Some((t, k, hit)) => {
                    let inst = &insts[usize::from(k)];
                    let attr = inst.image.attrs()[hit.attr as usize];
                    let n = (inst.normal_to_world * DVec3::from_array(attr.normal()))
                        .normalize_or_zero();
                    let [r, g, b, _] = attr.rgba();
                    HitRecordF64 {
                        kind: spheres,
                        instance: Some(k),
                        t: to_f64(t, t_fmt),
                        normal: n.to_array(),
                        colour: [r, g, b],
                        voxel: hit.voxel,
                    }
                }
            };
            let fields = quantise(&f64_record, &dp.hit_record, &mut ov, sig);
            cap.hit_record.push(fields);
            pixels.push(FramePixel {
                xy: [i as u16, j as u16],
                dir: d,
                candidates,
                walks,
                hit: best.is_some(),
                t: best.map_or(0, |b| b.0),
                voxel: best.map_or([0; 3], |b| b.2.voxel),
                word: pack(&fields, &dp.hit_record, &mut ov, sig),
            });
        }
    }
    let instances = insts
        .iter()
        .map(|i| FrameInstance {
            raw: i.raw,
            threshold: i.sphere.threshold,
            inside: i.sphere.inside,
            delta_t: i.sphere.delta_t,
            reach: i.sphere.reach,
            half: i.half,
            image: i.asset,
        })
        .collect();
    Ok(FrameCapture {
        captured: cap,
        origin,
        instances,
        pixels,
    })
}
