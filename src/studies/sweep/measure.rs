//! Error of a fixed-point run against the f64 reference, pixel by pixel over all frames of a
//! scene, and the single error score the Pareto fronts of `sim sweep` order by.
//!
//! Pipeline position: after both models rendered a frame (the hit records of the reference and
//! of the fixed-point datapath, `models::fixed::to_hit_records`); one [`ErrorTally`] per
//! (configuration, scene) collects every frame, [`ErrorTally::summary`] closes it.

use crate::models::reference::HitRecord;
use serde::Serialize;

/// Entry faces further apart than this (degrees) count as a normal mismatch: faces of a cube
/// are 90° apart, and the fixed model's face (axes × 127, rounded) is within 0.6° of exact.
pub const FACE_MISMATCH_DEG: f64 = 45.0;

/// Running counts over the frames of one (configuration, scene).
#[derive(Clone, Debug, Default)]
pub struct ErrorTally {
    pixels: u64,
    hit: u64,
    instance: u64,
    voxel: u64,
    t_max: f64,
    t_sum2: f64,
    t_n: u64,
    normal_mismatches: u64,
    normal_max_deg: f64,
    saturations: u64,
}

/// The error of one (configuration, scene).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ErrorSummary {
    /// Pixels compared (width × height × frames).
    pub pixels: u64,
    /// One model hit, the other missed.
    pub hit_mismatches: u64,
    /// Both hit, different instances.
    pub instance_mismatches: u64,
    /// Both hit the same instance, different leaves.
    pub voxel_mismatches: u64,
    /// Largest |t_fixed − t_ref| over pixels that hit the same leaf (metres).
    pub t_err_max: f64,
    /// Root mean square of the same (metres).
    pub t_err_rms: f64,
    /// Same-leaf pixels whose entry faces differ by more than [`FACE_MISMATCH_DEG`].
    pub normal_mismatches: u64,
    /// Largest angle between the shading normals of same-leaf pixels (degrees; the record's
    /// octahedral normal against the reference's f32 normal).
    pub normal_err_max_deg: f64,
    /// Saturations and wraps counted in the datapath (step-limit stops excluded).
    pub saturations: u64,
    /// Edge of the scene's smallest leaf (metres), the unit of t in the score.
    pub leaf_edge: f64,
    /// The score: (hit + instance + voxel mismatches) / pixels + t_err_rms / leaf_edge.
    pub error_score: f64,
}

fn angle_deg(a: [f32; 3], b: [f32; 3]) -> f64 {
    let (a, b) = (a.map(f64::from), b.map(f64::from));
    let dot: f64 = (0..3).map(|k| a[k] * b[k]).sum();
    let na = (0..3).map(|k| a[k] * a[k]).sum::<f64>().sqrt();
    let nb = (0..3).map(|k| b[k] * b[k]).sum::<f64>().sqrt();
    if na == 0.0 || nb == 0.0 {
        return if na == nb { 0.0 } else { 180.0 };
    }
    (dot / (na * nb)).clamp(-1.0, 1.0).acos().to_degrees()
}

impl ErrorTally {
    /// Adds one frame: the reference's and the fixed model's records (same length, raster
    /// order) and the saturations the datapath counted in it.
    pub fn add_frame(&mut self, reference: &[HitRecord], fixed: &[HitRecord], saturations: u64) {
        self.pixels += reference.len() as u64;
        self.saturations += saturations;
        for (r, f) in reference.iter().zip(fixed) {
            if r.hit != f.hit {
                self.hit += 1;
            } else if !r.hit {
                continue;
            } else if r.instance != f.instance {
                self.instance += 1;
            } else if r.voxel != f.voxel {
                self.voxel += 1;
            } else {
                let e = (f.t - r.t).abs();
                self.t_max = self.t_max.max(e);
                self.t_sum2 += e * e;
                self.t_n += 1;
                if angle_deg(r.face_normal, f.face_normal) > FACE_MISMATCH_DEG {
                    self.normal_mismatches += 1;
                }
                self.normal_max_deg = self
                    .normal_max_deg
                    .max(angle_deg(r.shade_normal, f.shade_normal));
            }
        }
    }

    /// The summary, with t measured in edges of the scene's smallest leaf (`leaf_edge` > 0).
    pub fn summary(&self, leaf_edge: f64) -> ErrorSummary {
        let t_err_rms = if self.t_n > 0 {
            (self.t_sum2 / self.t_n as f64).sqrt()
        } else {
            0.0
        };
        let wrong = self.hit + self.instance + self.voxel;
        let error_score = wrong as f64 / self.pixels.max(1) as f64 + t_err_rms / leaf_edge;
        ErrorSummary {
            pixels: self.pixels,
            hit_mismatches: self.hit,
            instance_mismatches: self.instance,
            voxel_mismatches: self.voxel,
            t_err_max: self.t_max,
            t_err_rms,
            normal_mismatches: self.normal_mismatches,
            normal_err_max_deg: self.normal_max_deg,
            saturations: self.saturations,
            leaf_edge,
            error_score,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hit(instance: u16, voxel: [u32; 3], t: f64, face: [f32; 3]) -> HitRecord {
        HitRecord {
            hit: true,
            instance,
            voxel,
            t,
            face_normal: face,
            shade_normal: [0.0, 1.0, 0.0],
            ..HitRecord::MISS
        }
    }

    #[test]
    fn each_pixel_counts_once_and_the_score_adds_both_parts() {
        let up = [0.0, 1.0, 0.0];
        let side = [1.0, 0.0, 0.0];
        let r = vec![
            hit(0, [1, 1, 1], 2.0, up),
            hit(0, [1, 1, 1], 2.0, up),
            hit(1, [0, 0, 0], 1.0, up),
            HitRecord::MISS,
            hit(2, [3, 3, 3], 5.0, up),
            hit(2, [3, 3, 3], 5.0, up),
        ];
        let f = vec![
            hit(0, [1, 1, 1], 2.003, up),
            HitRecord::MISS,
            hit(0, [0, 0, 0], 1.0, up),
            HitRecord::MISS,
            hit(2, [3, 3, 4], 5.0, up),
            hit(2, [3, 3, 3], 4.996, side),
        ];
        let mut t = ErrorTally::default();
        t.add_frame(&r, &f, 2);
        t.add_frame(&r[..1], &f[..1], 1);
        let s = t.summary(0.01);
        assert_eq!(
            (
                s.pixels,
                s.hit_mismatches,
                s.instance_mismatches,
                s.voxel_mismatches,
                s.normal_mismatches,
                s.saturations
            ),
            (7, 1, 1, 1, 1, 3)
        );
        // Same-leaf errors 0.003, 0.004, 0.003: max 0.004, rms √(34e-6 / 3).
        assert!((s.t_err_max - 0.004).abs() < 1e-12);
        let rms = (34e-6f64 / 3.0).sqrt();
        assert!((s.t_err_rms - rms).abs() < 1e-12);
        assert!((s.error_score - (3.0 / 7.0 + rms / 0.01)).abs() < 1e-12);
        assert_eq!(s.normal_err_max_deg, 0.0);
    }

    #[test]
    fn identical_frames_have_zero_error() {
        let r = vec![hit(0, [1, 2, 3], 2.0, [0.0, 0.0, 1.0]), HitRecord::MISS];
        let mut t = ErrorTally::default();
        t.add_frame(&r, &r, 0);
        assert_eq!(t.summary(1.0).error_score, 0.0);
    }
}
