//! Judging a difference between the fixed-point model and the reference with an extra matrix
//! error: the leaf's nearness to the exact ray and the entry-distance bound, on the geometry of
//! [`super::bound`] (the exact ray in an instance's frame, a leaf's box grown or shrunk by an
//! error bound, and whether the ray crosses it).
//!
//! Pipeline position: after both models have rendered a frame (`sim drift`, `sim stress`).
//! [`super::bound::mismatch_explained`] answers "is this voxel mismatch within the datapath's
//! bound?" for the formats alone; the functions here also take an extra matrix error (a
//! matrix that did not come straight from the exact pose, as in the drift experiment) and
//! answer the hit/miss question both ways: a pixel that one model hits and the other misses is
//! explained only if the exact ray passes within the bound of the hit leaf's surface.

#[cfg(doc)]
use super::bound::spatial_bound;
use super::bound::{crosses, local_ray, voxel_box};
use crate::world::scene::{Camera, Pose};
use glam::DVec3;
use rtl_model::cost::DirectionErrorBound;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::transform::origin_error_bound;
use rtl_model::units::walker::spatial_error_bound;

/// The direction part of the datapath's spatial bound, per ray: the transform's direction
/// error and the reciprocal's relative error always, and the reciprocal's zero threshold
/// (a component at or below it is walked as parallel) only for a ray with a component that
/// can be flushed. [`spatial_bound`] adds the threshold for every ray; judging each ray by
/// its own term is a hundred times tighter for the rays that have none. Built once per
/// judgement: computing the reciprocal's bound scans its seed ROM.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionError {
    /// Transform direction bound + reciprocal relative bound.
    base: f64,
    /// The transform's direction bound alone (how far a component can move before the
    /// reciprocal sees it).
    transform: f64,
    /// The reciprocal's zero threshold.
    threshold: f64,
}

impl DirectionError {
    /// The terms of a datapath.
    pub fn of(cfg: &DatapathConfig) -> Self {
        let b = DirectionErrorBound::of(cfg);
        Self {
            base: b.without_zero_threshold(),
            transform: b.transform,
            threshold: b.zero_threshold,
        }
    }

    /// For every ray (as [`spatial_bound`]).
    pub fn any_ray(&self) -> f64 {
        self.base + self.threshold
    }

    /// For a ray whose exact local direction is `d`, through a matrix whose entries may be off
    /// by `mat_err`: the threshold term only if some |d_k| ≤ threshold + transform error +
    /// 3·mat_err, i.e. if the component the reciprocal sees could be at or below it.
    pub fn for_ray(&self, d: DVec3, mat_err: f64) -> f64 {
        let limit = self.threshold + self.transform + 3.0 * mat_err;
        if d.abs().min_element() <= limit {
            self.any_ray()
        } else {
            self.base
        }
    }
}

/// The spatial bound (metres) of the datapath plus a matrix whose entries may differ from the
/// exact rotation's by `mat_err`: that moves the local origin by at most 3·mat_err·|o − c| and
/// tilts the direction by at most 3·mat_err per component, stretched over the path.
/// `dir_err` is [`DirectionError::for_ray`] (or [`DirectionError::any_ray`], with which and
/// `mat_err` = 0 this is [`spatial_bound`]).
pub fn bound_with_matrix_error(
    cfg: &DatapathConfig,
    dir_err: f64,
    o_local: DVec3,
    half: DVec3,
    depth: u8,
    mat_err: f64,
) -> f64 {
    let rel = o_local.abs().max_element();
    let reach = rel + 2.0 * half.max_element();
    let origin_err = origin_error_bound(&cfg.transform, rel);
    spatial_error_bound(&cfg.walker, origin_err, dir_err, reach, depth)
        + 3.0 * mat_err * (rel + reach)
}

/// Bound on the error of the entry distance into the box [lo, hi] (the leaf, unshrunk) along
/// o + t·d when the ray may be displaced by `eps` per axis: each slab's entry t0_k moves by at
/// most e_k = eps/|d_k|, so their maximum moves by at most max(e_k*, max_k(t0_k + e_k) − t0)
/// with k* the entry axis. Zero components have no slab (t0 = −∞).
pub fn entry_t_bound(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3, eps: f64) -> f64 {
    let mut t0 = [f64::NEG_INFINITY; 3];
    let mut e = [0.0f64; 3];
    for k in 0..3 {
        if d[k] != 0.0 {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            t0[k] = a.min(b);
            e[k] = eps / d[k].abs();
        }
    }
    let k_star = (0..3).fold(0, |m, k| if t0[k] > t0[m] { k } else { m });
    let enter = t0[k_star];
    if enter == f64::NEG_INFINITY {
        return 0.0;
    }
    let up = (0..3)
        .filter(|&k| t0[k] > f64::NEG_INFINITY)
        .map(|k| t0[k] + e[k] - enter)
        .fold(0.0, f64::max);
    up.max(e[k_star])
}

/// How a leaf lies relative to the exact ray, with the bound ε (metres) of the pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Nearness {
    /// The ray misses the leaf grown by ε: a model reporting it is beyond its bound.
    Far,
    /// The ray passes within ε of the leaf's surface (it crosses the grown box but not the
    /// box shrunk by ε): either answer is within the bound.
    Boundary,
    /// The ray crosses the leaf shrunk by ε: a model missing it is beyond its bound.
    Through,
}

/// Where leaf `voxel` of the instance with pose `pose` lies relative to pixel (i, j)'s exact
/// ray, for the datapath's bound plus a matrix error `mat_err`.
#[allow(clippy::too_many_arguments)]
pub fn nearness(
    cfg: &DatapathConfig,
    dir: &DirectionError,
    cam: &Camera,
    wh: (u32, u32),
    ij: (u32, u32),
    pose: &Pose,
    voxel: [u32; 3],
    depth: u8,
    mat_err: f64,
) -> Nearness {
    let (o, d) = local_ray(cam, wh, ij, pose);
    let dir_err = dir.for_ray(d, mat_err);
    let eps = bound_with_matrix_error(cfg, dir_err, o, pose.half_extent, depth, mat_err);
    let (lo, hi) = voxel_box(pose, voxel, depth, eps);
    if !crosses(o, d, lo, hi) {
        return Nearness::Far;
    }
    let (lo, hi) = voxel_box(pose, voxel, depth, -eps);
    if crosses(o, d, lo, hi) {
        Nearness::Through
    } else {
        Nearness::Boundary
    }
}

/// What a frame's judgement needs besides the records: the datapath, the exact camera and
/// poses, each instance's octree depth, and an extra matrix error allowed on top of the
/// datapath's (0 when the matrices come straight from the exact poses).
#[derive(Clone, Copy)]
pub struct JudgeCtx<'a> {
    /// The datapath whose bounds apply.
    pub cfg: &'a DatapathConfig,
    /// The exact camera.
    pub camera: &'a Camera,
    /// Image size.
    pub size: (u32, u32),
    /// The exact poses, one per instance.
    pub poses: &'a [Pose],
    /// Octree depth of each instance's asset.
    pub depths: &'a [u8],
    /// Extra matrix-entry error allowed (see [`bound_with_matrix_error`]).
    pub mat_err: f64,
}

/// A frame's accuracy with every kind of mismatch checked against the bound.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Judgement {
    /// The counters of [`super::compare`]; `voxel_mismatches_beyond_bound` uses this
    /// module's bound (with the extra matrix error).
    pub accuracy: super::Accuracy,
    /// Hit/miss mismatches the bound does not explain: the fixed model hit a leaf the exact
    /// ray misses by more than ε, or missed a leaf the exact ray crosses deeper than ε.
    pub hit_mismatches_beyond_bound: u64,
    /// Instance mismatches whose fixed-model leaf is farther than ε from the exact ray.
    pub instance_mismatches_beyond_bound: u64,
    /// Largest |t_fixed − t_ref| / (its bound, [`entry_t_bound`]) over pixels both hit on the
    /// same leaf: at most 1 when the t errors are within their bound.
    pub t_err_over_bound_max: f64,
    /// Pixels whose t error exceeds its bound.
    pub t_beyond_bound: u64,
}

impl Judgement {
    /// Every mismatch beyond the bound, of any kind.
    pub fn beyond_bound(&self) -> u64 {
        self.accuracy.voxel_mismatches_beyond_bound
            + self.hit_mismatches_beyond_bound
            + self.instance_mismatches_beyond_bound
    }

    /// Every mismatch or t error beyond its bound.
    pub fn all_beyond_bound(&self) -> u64 {
        self.beyond_bound() + self.t_beyond_bound
    }
}

/// Compares a frame's records and checks every mismatch against the bound.
pub fn judge(
    ctx: &JudgeCtx<'_>,
    reference: &[crate::models::reference::HitRecord],
    fixed: &[crate::models::reference::HitRecord],
) -> Judgement {
    let (w, _) = ctx.size;
    let dir = DirectionError::of(ctx.cfg);
    let near = |k: usize, rec: &crate::models::reference::HitRecord| {
        let inst = usize::from(rec.instance);
        match (ctx.poses.get(inst), ctx.depths.get(inst)) {
            (Some(pose), Some(&depth)) => nearness(
                ctx.cfg,
                &dir,
                ctx.camera,
                ctx.size,
                (k as u32 % w, k as u32 / w),
                pose,
                rec.voxel,
                depth,
                ctx.mat_err,
            ),
            // An instance id outside the scene can only be a defect.
            _ => Nearness::Far,
        }
    };
    let accuracy = super::compare(reference, fixed, |k| near(k, &fixed[k]) != Nearness::Far);
    let mut j = Judgement {
        accuracy,
        ..Judgement::default()
    };
    for (k, (r, f)) in reference.iter().zip(fixed).enumerate() {
        if r.hit != f.hit {
            let beyond = if f.hit {
                near(k, f) == Nearness::Far
            } else {
                near(k, r) == Nearness::Through
            };
            j.hit_mismatches_beyond_bound += u64::from(beyond);
        } else if r.hit && r.instance != f.instance {
            j.instance_mismatches_beyond_bound += u64::from(near(k, f) == Nearness::Far);
        } else if r.hit && r.voxel == f.voxel {
            let inst = usize::from(r.instance);
            let (Some(pose), Some(&depth)) = (ctx.poses.get(inst), ctx.depths.get(inst)) else {
                continue;
            };
            let (o, d) = local_ray(ctx.camera, ctx.size, (k as u32 % w, k as u32 / w), pose);
            let dir_err = dir.for_ray(d, ctx.mat_err);
            let eps =
                bound_with_matrix_error(ctx.cfg, dir_err, o, pose.half_extent, depth, ctx.mat_err);
            let (lo, hi) = voxel_box(pose, r.voxel, depth, 0.0);
            // The walker's t rounds down: one more LSB of t on top of the spatial bound.
            let bound = entry_t_bound(o, d, lo, hi, eps) + ctx.cfg.walker.t.lsb();
            let ratio = (f.t - r.t).abs() / bound;
            j.t_err_over_bound_max = j.t_err_over_bound_max.max(ratio);
            j.t_beyond_bound += u64::from(ratio > 1.0);
        }
    }
    j
}
