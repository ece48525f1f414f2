//! Ray generation: one primary ray per pixel centre of a pinhole camera.
//!
//! For pixel (i, j) of a W×H image (i to the right, j downward, both from 0), with
//! a = W/H and τ = tan(vfov/2):
//!   u = (2(i + ½)/W − 1)·τ·a,   v = (1 − 2(j + ½)/H)·τ,
//!   d = normalise(forward + u·right + v·up),   o = camera position.
//! The same formula is in `docs/reference.md`.

use crate::world::scene::Camera;
use glam::DVec3;

/// A ray o + t·d, t ≥ 0, with unit d.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
}

/// The primary ray through the centre of pixel (i, j).
#[inline]
pub fn primary_ray(cam: &Camera, width: u32, height: u32, i: u32, j: u32) -> Ray {
    let aspect = f64::from(width) / f64::from(height);
    let u = (2.0 * (f64::from(i) + 0.5) / f64::from(width) - 1.0) * cam.tan_half_vfov * aspect;
    let v = (1.0 - 2.0 * (f64::from(j) + 0.5) / f64::from(height)) * cam.tan_half_vfov;
    let d = cam.forward + cam.right * u + cam.up * v;
    Ray {
        origin: cam.position,
        dir: d.normalize(),
    }
}
