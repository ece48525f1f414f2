//! Is a voxel mismatch between the fixed-point model and the reference within the walker's
//! error bound of a boundary? The test: the exact (f64) ray, carried into the instance's
//! frame, must pass through the fixed model's voxel grown by the spatial error bound on every
//! side. A mismatch that fails it is a defect, and the report counts it separately. The
//! geometry — [`local_ray`], [`voxel_box`], [`crosses`] — serves `explain` too.

use crate::models::reference::ray::primary_ray;
use crate::world::scene::{Camera, Pose};
use glam::DVec3;
use rtl_model::cost::direction_error_bound;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::transform::origin_error_bound;
use rtl_model::units::walker::spatial_error_bound;

/// The spatial bound (metres) for a ray whose local origin is `o_local` in an octree of
/// half extent `half` and `depth` levels.
pub fn spatial_bound(cfg: &DatapathConfig, o_local: DVec3, half: DVec3, depth: u8) -> f64 {
    let rel = o_local.abs().max_element();
    let reach = rel + 2.0 * half.max_element();
    let origin_err = origin_error_bound(&cfg.transform, rel);
    // The transform's direction error, the reciprocal's relative error and its zero threshold
    // all tilt the ray (`rtl_model::cost::bounds`).
    spatial_error_bound(
        &cfg.walker,
        origin_err,
        direction_error_bound(cfg),
        reach,
        depth,
    )
}

/// Whether the exact ray of pixel (i, j) passes within the bound of leaf `voxel` (at `depth`)
/// of the instance with pose `pose`.
#[allow(clippy::too_many_arguments)]
pub fn mismatch_explained(
    cfg: &DatapathConfig,
    cam: &Camera,
    (w, h): (u32, u32),
    (i, j): (u32, u32),
    pose: &Pose,
    voxel: [u32; 3],
    depth: u8,
) -> bool {
    let (o, d) = local_ray(cam, (w, h), (i, j), pose);
    let eps = spatial_bound(cfg, o, pose.half_extent, depth);
    let (lo, hi) = voxel_box(pose, voxel, depth, eps);
    crosses(o, d, lo, hi)
}

/// The exact (f64) ray of pixel (i, j), carried into the instance's frame: (origin, dir).
pub fn local_ray(
    cam: &Camera,
    (w, h): (u32, u32),
    (i, j): (u32, u32),
    pose: &Pose,
) -> (DVec3, DVec3) {
    let ray = primary_ray(cam, w, h, i, j);
    let r = pose.world_from_local;
    let rel = ray.origin - pose.centre;
    let o = DVec3::new(r.x_axis.dot(rel), r.y_axis.dot(rel), r.z_axis.dot(rel));
    let d = DVec3::new(
        r.x_axis.dot(ray.dir),
        r.y_axis.dot(ray.dir),
        r.z_axis.dot(ray.dir),
    );
    (o, d)
}

/// The box of leaf `voxel` at `depth` in the instance's frame, grown by `eps` on every side
/// (shrunk if `eps` is negative).
pub fn voxel_box(pose: &Pose, voxel: [u32; 3], depth: u8, eps: f64) -> (DVec3, DVec3) {
    let size = 2.0 * pose.half_extent / f64::from(1u32 << depth);
    let lo = -pose.half_extent + DVec3::from_array(voxel.map(f64::from)) * size;
    (lo - eps, lo + size + eps)
}

/// Whether the ray o + t·d, t ≥ 0, meets the closed box [lo, hi] (an empty box never).
pub fn crosses(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
    let (mut t_in, mut t_out) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if lo[k] > hi[k] {
            return false;
        }
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return false;
            }
        } else {
            let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
            t_in = t_in.max(a.min(b));
            t_out = t_out.min(a.max(b));
        }
    }
    t_in <= t_out
}
