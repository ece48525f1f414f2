//! Running one stress case through both models and judging the result.
//!
//! Pipeline position: `sim stress`, after a case is built. The f64 reference and the
//! fixed-point model render the same frame state (no hit buffer); every pixel is compared
//! and every mismatch and t error checked against the datapath's bound
//! (`models::fixed::explain`). The verdict follows from the numbers alone:
//!
//! - **pass**: nothing saturated, no walk hit the step limit, and every mismatch and t error
//!   is within its bound;
//! - **flagged**: the default formats cannot represent the case and the model says so —
//!   saturations or step-limit stops were counted (the report names the signals), so any
//!   wrong pixel in it is reported, not silent;
//! - **FAIL**: a mismatch or t error beyond the bound with nothing counted: a silently wrong
//!   pixel, which would be a defect of the model.

use super::build::CaseInput;
use crate::models::fixed::explain::{bound_with_matrix_error, judge, DirectionError, JudgeCtx};
use crate::models::fixed::{render_frame_fixed, to_hit_records, FixedBuffer};
use crate::models::reference::ray::primary_ray;
use crate::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use glam::DVec3;
use rtl_model::datapath::{signals, DatapathConfig};
use serde::Serialize;

/// The outcome of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Within every bound, nothing saturated.
    Pass,
    /// Not representable by the formats, and reported as such.
    Flagged,
    /// A silently wrong pixel.
    Fail,
}

impl Verdict {
    /// The word in the table.
    pub fn word(self) -> &'static str {
        match self {
            Verdict::Pass => "pass",
            Verdict::Flagged => "flagged",
            Verdict::Fail => "FAIL",
        }
    }
}

/// What the rays of a case exercise, counted on the exact rays (world direction d).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RayCensus {
    /// Direction components that are exactly +0.
    pub zero_components: u64,
    /// Direction components that are exactly −0.
    pub negative_zero_components: u64,
    /// Direction components with 0 < |d| < 2^−20.
    pub tiny_components: u64,
    /// (ray, instance) pairs within 10^−6 (relative) of tangent to the bounding sphere.
    pub grazing: u64,
    /// Instances whose bounding sphere holds the camera.
    pub camera_in_spheres: u64,
    /// Instances whose box holds the camera.
    pub camera_in_boxes: u64,
    /// Most candidates (spheres pierced) of one ray.
    pub candidates_max: u64,
}

/// The measured figures of a case.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CaseResult {
    /// Case name.
    pub name: String,
    /// What it stresses.
    pub what: String,
    /// The bound it is judged against.
    pub bound: String,
    /// The verdict the documentation expects.
    pub expected: Verdict,
    /// The verdict from the numbers.
    pub verdict: Verdict,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Deepest octree of the case.
    pub depth_max: u8,
    /// The spatial bound ε (metres) for rays from the camera into the first instance (the
    /// datapath's bound, `number-formats.md` §3.5, at this distance and depth), for a ray
    /// with a component that may be flushed to zero.
    pub eps: f64,
    /// The same for a ray without one (no zero-threshold term).
    pub eps_unflushed: f64,
    /// What the rays exercise.
    pub census: RayCensus,
    /// Pixels the reference hit.
    pub reference_hits: u64,
    /// Pixels the fixed-point model hit.
    pub fixed_hits: u64,
    /// Hit/miss mismatches.
    pub hit_mismatches: u64,
    /// Instance mismatches.
    pub instance_mismatches: u64,
    /// Voxel mismatches.
    pub voxel_mismatches: u64,
    /// Mismatches and t errors beyond the bound.
    pub beyond_bound: u64,
    /// Largest t error over same-leaf pixels (metres).
    pub t_err_max: f64,
    /// Largest t error over its per-pixel bound.
    pub t_err_over_bound: f64,
    /// Saturations (all datapath signals but the step limit).
    pub saturations: u64,
    /// Signals that saturated, with counts.
    pub saturated_signals: Vec<(String, u64)>,
    /// Walks stopped by the step limit.
    pub step_limit_hits: u64,
    /// Direction components flushed to zero by the reciprocal unit (within the bound).
    pub zero_flushes: u64,
    /// Sorter chunks beyond the first (more candidates than the network's N).
    pub sorter_overflow_batches: u64,
    /// Deepest walker stack.
    pub max_stack: u32,
}

/// Counts what the exact rays of a case exercise.
fn census(input: &CaseInput) -> RayCensus {
    let (w, h) = input.scene.file.resolution;
    let cam = &input.state.camera;
    let mut c = RayCensus::default();
    for p in &input.state.poses {
        let r = p.sphere_radius();
        c.camera_in_spheres += u64::from((cam.position - p.centre).length() <= r);
        let rel = p.world_from_local.transpose() * (cam.position - p.centre);
        c.camera_in_boxes += u64::from((0..3).all(|k| rel[k].abs() <= p.half_extent[k]));
    }
    for j in 0..h {
        for i in 0..w {
            let ray = primary_ray(cam, w, h, i, j);
            for v in ray.dir.to_array() {
                if v == 0.0 {
                    if v.is_sign_negative() {
                        c.negative_zero_components += 1;
                    } else {
                        c.zero_components += 1;
                    }
                } else if v.abs() < 2f64.powi(-20) {
                    c.tiny_components += 1;
                }
            }
            let mut pierced = 0;
            for p in &input.state.poses {
                let l = p.centre - ray.origin;
                let tca = l.dot(ray.dir);
                let p2 = l.dot(l) - tca * tca;
                let r2 = p.sphere_radius().powi(2);
                c.grazing += u64::from((p2 - r2).abs() <= 1e-6 * r2);
                pierced += u64::from(p2 <= r2);
            }
            c.candidates_max = c.candidates_max.max(pierced);
        }
    }
    c
}

/// Renders a case with both models and judges it.
pub fn measure(
    name: &str,
    what: &str,
    bound: &str,
    expected: Verdict,
    input: &CaseInput,
    cfg: &DatapathConfig,
) -> Result<CaseResult, String> {
    let (w, h) = input.scene.file.resolution;
    let frame = FrameInput {
        scene: &input.scene,
        assets: &input.assets,
        state: &input.state,
    };
    let opts = RenderOptions {
        use_hit_buffer: false,
        ..RenderOptions::default()
    };
    let mut reference = HitBuffer::new(w, h);
    render_frame(&frame, &mut reference, opts);
    let mut buffer = FixedBuffer::new(w, h);
    let fx = render_frame_fixed(&frame, &mut buffer, cfg, false).map_err(|e| e.to_string())?;
    let fixed = to_hit_records(&buffer, cfg);
    let depths: Vec<u8> = input
        .scene
        .instance_asset
        .iter()
        .map(|&a| input.assets[a].depth())
        .collect();
    let ctx = JudgeCtx {
        cfg,
        camera: &input.state.camera,
        size: (w, h),
        poses: &input.state.poses,
        depths: &depths,
        mat_err: 0.0,
    };
    let j = judge(&ctx, &reference.records, &fixed);
    let dir = DirectionError::of(cfg);
    let (eps, eps_unflushed) = input.state.poses.first().map_or((0.0, 0.0), |p| {
        let rel = p.world_from_local.transpose() * (input.state.camera.position - p.centre);
        let at = |d: f64| bound_with_matrix_error(cfg, d, rel, p.half_extent, depths[0], 0.0);
        (at(dir.any_ray()), at(dir.for_ray(DVec3::ONE, 0.0)))
    });
    let ov = fx
        .overflows
        .clone()
        .unwrap_or_else(rtl_model::datapath::overflow_table);
    let saturated_signals: Vec<(String, u64)> = ov
        .nonzero()
        .filter(|(n, _)| *n != "walker/step_limit")
        .map(|(n, c)| (n.to_string(), c))
        .collect();
    let saturations = ov.total() - ov.count(signals::WALKER_STEP_LIMIT);
    let step_limit_hits = fx.walker.step_limit_hits;
    let beyond = j.all_beyond_bound();
    let verdict = if saturations > 0 || step_limit_hits > 0 {
        Verdict::Flagged
    } else if beyond > 0 {
        Verdict::Fail
    } else {
        Verdict::Pass
    };
    let a = &j.accuracy;
    Ok(CaseResult {
        name: name.into(),
        what: what.into(),
        bound: bound.into(),
        expected,
        verdict,
        width: w,
        height: h,
        depth_max: depths.iter().copied().max().unwrap_or(0),
        eps,
        eps_unflushed,
        census: census(input),
        reference_hits: reference.records.iter().filter(|r| r.hit).count() as u64,
        fixed_hits: fixed.iter().filter(|r| r.hit).count() as u64,
        hit_mismatches: a.hit_mismatches,
        instance_mismatches: a.instance_mismatches,
        voxel_mismatches: a.voxel_mismatches,
        beyond_bound: beyond,
        t_err_max: a.t_err_max,
        t_err_over_bound: j.t_err_over_bound_max,
        saturations,
        saturated_signals,
        step_limit_hits,
        zero_flushes: fx.zero_flushes,
        sorter_overflow_batches: fx.sorter.overflow_batches,
        max_stack: fx.walker.max_stack,
    })
}
