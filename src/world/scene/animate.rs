//! Keyframe sampling: the camera and every instance's pose at an integer frame.
//!
//! Interpolation is piecewise linear in the frame number, per component, between the two
//! keys around the frame, and holds the first/last key outside the keyed range. Rotations
//! interpolate their three Euler angles linearly (so a key pair 0° → 720° turns twice); the
//! matrix is R = Rz·Ry·Rx of the interpolated angles.

use super::Scene;
use crate::world::sdf::rotation_xyz_deg;
use glam::{DMat3, DVec3};

/// The camera of one frame: a pinhole at `position` with an orthonormal basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub position: DVec3,
    /// Unit view direction.
    pub forward: DVec3,
    /// Unit right vector (forward × up, normalised).
    pub right: DVec3,
    /// Unit up vector of the image plane (right × forward).
    pub up: DVec3,
    /// tan(vfov / 2).
    pub tan_half_vfov: f64,
}

/// An instance's placement in one frame, as the traversal uses it (paper Eq. 3 and §3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Rotation taking local axes to world axes (orthonormal).
    pub world_from_local: DMat3,
    /// World position of the octree's centre (the local origin); also the sphere centre.
    pub centre: DVec3,
    /// Half extents of the octree's box in local (scaled, unrotated) coordinates.
    pub half_extent: DVec3,
}

impl Pose {
    /// Radius of the bounding sphere: half the diagonal of the scaled box.
    pub fn sphere_radius(&self) -> f64 {
        self.half_extent.length()
    }
}

/// Camera and poses of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameState {
    /// Frame number.
    pub frame: u32,
    /// The camera.
    pub camera: Camera,
    /// One pose per instance, in scene order.
    pub poses: Vec<Pose>,
}

/// Interpolation weight and the two key indices around `frame`.
fn bracket(frames: &[f64], frame: f64) -> (usize, usize, f64) {
    let last = frames.len() - 1;
    if frame <= frames[0] {
        return (0, 0, 0.0);
    }
    if frame >= frames[last] {
        return (last, last, 0.0);
    }
    let hi = frames.partition_point(|&f| f <= frame);
    let lo = hi - 1;
    (lo, hi, (frame - frames[lo]) / (frames[hi] - frames[lo]))
}

fn lerp3(a: [f64; 3], b: [f64; 3], w: f64) -> DVec3 {
    let (a, b) = (DVec3::from_array(a), DVec3::from_array(b));
    a + (b - a) * w
}

impl Scene {
    /// The camera at a frame, or why it is degenerate.
    pub fn camera_at(&self, frame: u32) -> Result<Camera, String> {
        let keys = &self.file.camera;
        let frames: Vec<f64> = keys.iter().map(|k| k.frame).collect();
        let (a, b, w) = bracket(&frames, f64::from(frame));
        let (ka, kb) = (&keys[a], &keys[b]);
        let position = lerp3(ka.position, kb.position, w);
        let look_at = lerp3(ka.look_at, kb.look_at, w);
        let up_hint = lerp3(ka.up, kb.up, w);
        let vfov = ka.vfov_deg + (kb.vfov_deg - ka.vfov_deg) * w;
        let view = look_at - position;
        if view.length() < 1e-9 {
            return Err(format!("camera position {position} and look_at coincide"));
        }
        let forward = view.normalize();
        let side = forward.cross(up_hint);
        if up_hint.length() < 1e-12 || side.length() < 1e-9 * up_hint.length() {
            return Err(format!(
                "camera up {up_hint} is parallel to the view direction {forward} (or zero)"
            ));
        }
        let right = side.normalize();
        let up = right.cross(forward);
        Ok(Camera {
            position,
            forward,
            right,
            up,
            tan_half_vfov: (vfov.to_radians() * 0.5).tan(),
        })
    }

    /// Every instance's pose at a frame, given each asset's octree half-size (metres).
    pub fn poses_at(&self, frame: u32, asset_half_size: &[f64]) -> Vec<Pose> {
        self.file
            .instances
            .iter()
            .zip(&self.instance_asset)
            .map(|(inst, &ai)| {
                let frames: Vec<f64> = inst.keys.iter().map(|k| k.frame).collect();
                let (a, b, w) = bracket(&frames, f64::from(frame));
                let (ka, kb) = (&inst.keys[a], &inst.keys[b]);
                let translation = lerp3(ka.translation, kb.translation, w);
                let rot = lerp3(ka.rotation_deg, kb.rotation_deg, w);
                let scale = lerp3(ka.scale, kb.scale, w);
                let world_from_local = rotation_xyz_deg(rot.to_array());
                // The pivot sits at `translation`: centre = translation − R·pivot.
                let centre = translation - world_from_local * DVec3::from_array(inst.pivot);
                Pose {
                    world_from_local,
                    centre,
                    half_extent: scale * asset_half_size[ai],
                }
            })
            .collect()
    }

    /// Camera and poses of a frame.
    pub fn frame_state(&self, frame: u32, asset_half_size: &[f64]) -> Result<FrameState, String> {
        Ok(FrameState {
            frame,
            camera: self.camera_at(frame)?,
            poses: self.poses_at(frame, asset_half_size),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bracket_holds_and_interpolates() {
        let f = [0.0, 10.0, 20.0];
        assert_eq!(bracket(&f, -5.0), (0, 0, 0.0));
        assert_eq!(bracket(&f, 25.0), (2, 2, 0.0));
        assert_eq!(bracket(&f, 10.0), (1, 2, 0.0));
        let (a, b, w) = bracket(&f, 15.0);
        assert_eq!((a, b), (1, 2));
        assert!((w - 0.5).abs() < 1e-15);
    }
}
