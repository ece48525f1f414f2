//! Accuracy of a fixed-point frame against the f64 reference, pixel by pixel, and the diff
//! image that shows where they differ.
//!
//! Pipeline position: after both models have rendered the same frame; feeds the `accuracy`
//! section of the report (`frames[].accuracy`).

use crate::models::reference::HitRecord;
use image::RgbImage;
use serde::Serialize;

/// Per-frame accuracy counters (`frames[].accuracy` in the JSON report).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Accuracy {
    /// Pixels compared.
    pub pixels: u64,
    /// Pixels where one model hit and the other missed.
    pub hit_mismatches: u64,
    /// Pixels both hit, on different instances.
    pub instance_mismatches: u64,
    /// Pixels both hit on the same instance, at different voxels.
    pub voxel_mismatches: u64,
    /// Voxel mismatches not explained by the walker's error bound (should be 0).
    pub voxel_mismatches_beyond_bound: u64,
    /// Largest |t_fixed − t_ref| over pixels both hit on the same voxel (metres).
    pub t_err_max: f64,
    /// Root mean square of the same (metres).
    pub t_err_rms: f64,
    /// Saturations and wraps counted in the datapath during the frame.
    pub saturations: u64,
    /// Walks stopped by the step limit.
    pub step_limit_hits: u64,
    /// Direction components below the reciprocal's zero threshold, walked as parallel
    /// (Revelles §3.3; within the walker's bound, not a saturation).
    pub zero_flushes: u64,
}

/// Compares records. `explained(k)` says whether a voxel mismatch at pixel k lies within the
/// walker's error bound of a boundary.
pub fn compare(
    reference: &[HitRecord],
    fixed: &[HitRecord],
    mut explained: impl FnMut(usize) -> bool,
) -> Accuracy {
    let mut a = Accuracy {
        pixels: reference.len() as u64,
        ..Accuracy::default()
    };
    let (mut sum2, mut n) = (0.0f64, 0u64);
    for (k, (r, f)) in reference.iter().zip(fixed).enumerate() {
        if r.hit != f.hit {
            a.hit_mismatches += 1;
        } else if r.hit && r.instance != f.instance {
            a.instance_mismatches += 1;
        } else if r.hit && r.voxel != f.voxel {
            a.voxel_mismatches += 1;
            if !explained(k) {
                a.voxel_mismatches_beyond_bound += 1;
            }
        } else if r.hit {
            let e = (f.t - r.t).abs();
            a.t_err_max = a.t_err_max.max(e);
            sum2 += e * e;
            n += 1;
        }
    }
    a.t_err_rms = if n > 0 { (sum2 / n as f64).sqrt() } else { 0.0 };
    a
}

/// The diff image: mismatched pixels marked (red: hit/miss, magenta: instance, yellow:
/// voxel), matching hits as a heat map of |Δt| from black (0) to white (`t_scale` or more),
/// misses dark blue.
pub fn diff_image(
    reference: &[HitRecord],
    fixed: &[HitRecord],
    width: u32,
    height: u32,
    t_scale: f64,
) -> RgbImage {
    let mut img = RgbImage::new(width, height);
    for (p, (r, f)) in img.pixels_mut().zip(reference.iter().zip(fixed)) {
        p.0 = if r.hit != f.hit {
            [255, 0, 0]
        } else if !r.hit {
            [10, 10, 40]
        } else if r.instance != f.instance {
            [255, 0, 255]
        } else if r.voxel != f.voxel {
            [255, 255, 0]
        } else {
            let v = ((f.t - r.t).abs() / t_scale.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            let g = (v.sqrt() * 255.0).round() as u8;
            [g, g, g]
        };
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(instance: u16, voxel: [u32; 3], t: f64) -> HitRecord {
        HitRecord {
            hit: true,
            instance,
            voxel,
            t,
            ..HitRecord::MISS
        }
    }

    #[test]
    fn counts_each_kind_once() {
        let r = vec![
            hit(0, [1, 1, 1], 2.0),
            hit(0, [1, 1, 1], 2.0),
            hit(1, [0, 0, 0], 1.0),
            HitRecord::MISS,
            hit(2, [3, 3, 3], 5.0),
        ];
        let f = vec![
            hit(0, [1, 1, 1], 2.5),
            HitRecord::MISS,
            hit(0, [0, 0, 0], 1.0),
            HitRecord::MISS,
            hit(2, [3, 3, 4], 5.0),
        ];
        let a = compare(&r, &f, |_| false);
        assert_eq!(
            (
                a.pixels,
                a.hit_mismatches,
                a.instance_mismatches,
                a.voxel_mismatches
            ),
            (5, 1, 1, 1)
        );
        assert_eq!(a.voxel_mismatches_beyond_bound, 1);
        assert_eq!(a.t_err_max, 0.5);
        assert_eq!(a.t_err_rms, 0.5);
        let img = diff_image(&r, &f, 5, 1, 1.0);
        assert_eq!(img.get_pixel(1, 0).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(4, 0).0, [255, 255, 0]);
    }
}
