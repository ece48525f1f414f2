//! The hit buffer across frames (paper §4.3) with per-instance and camera dirty flags.
//!
//! Reuse rule (the sound form, see `docs/reference.md`): a pixel's previous record is reused
//! without walking iff
//!   1. the camera is clean (same ray as last frame),
//!   2. this frame's sphere tests found exactly one candidate instance i,
//!   3. instance i is clean (same pose as last frame), and
//!   4. last frame's record is a hit on i, or a miss.
//!
//! Then walking i alone would repeat last frame's walk of i exactly: a hit on i last frame is
//! i's nearest voxel; a miss means every candidate, i included (its sphere test is unchanged),
//! was walked without a hit. "Exactly one sphere" must come from *this* frame's tests: another
//! instance may have moved in front of a clean one since, which last frame's record cannot know.

use super::record::HitRecord;
use crate::world::scene::{Camera, FrameState, Pose};
use glam::DVec3;

// Dirty flags compare bit patterns, not values: 0.0 == −0.0, but the walker mirrors on the
// sign bit, so a pose or camera that only flips a zero's sign can change the walk.
fn v3(v: DVec3) -> [u64; 3] {
    v.to_array().map(f64::to_bits)
}

fn camera_bits(c: &Camera) -> [[u64; 3]; 5] {
    [
        v3(c.position),
        v3(c.forward),
        v3(c.right),
        v3(c.up),
        [c.tan_half_vfov.to_bits(), 0, 0],
    ]
}

fn pose_bits(p: &Pose) -> [[u64; 3]; 5] {
    let m = p.world_from_local;
    [
        v3(m.x_axis),
        v3(m.y_axis),
        v3(m.z_axis),
        v3(p.centre),
        v3(p.half_extent),
    ]
}

/// Records of the previous frame and what has changed since.
#[derive(Clone, Debug)]
pub struct HitBuffer {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// One record per pixel, row-major.
    pub records: Vec<HitRecord>,
    prev: Option<FrameState>,
}

/// Dirty flags for one frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Dirty {
    /// Camera (or resolution) changed, or no previous frame: nothing can be reused.
    pub camera: bool,
    /// Per instance: pose changed since the previous frame.
    pub instances: Vec<bool>,
}

impl Dirty {
    /// Dirty flags of `now` against the previous frame (`None`: everything is dirty). Host
    /// control logic, shared by the reference and the fixed-point model.
    pub fn between(prev: Option<&FrameState>, now: &FrameState) -> Self {
        match prev {
            None => Dirty {
                camera: true,
                instances: vec![true; now.poses.len()],
            },
            Some(p) => Dirty {
                camera: camera_bits(&p.camera) != camera_bits(&now.camera),
                instances: now
                    .poses
                    .iter()
                    .enumerate()
                    .map(|(i, pose)| p.poses.get(i).map(pose_bits) != Some(pose_bits(pose)))
                    .collect(),
            },
        }
    }
}

impl HitBuffer {
    /// An empty buffer: the first frame traces every pixel.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            records: vec![HitRecord::MISS; width as usize * height as usize],
            prev: None,
        }
    }

    /// Compares `state` with the previous frame's (bitwise) and remembers it.
    pub fn begin_frame(&mut self, state: &FrameState) -> Dirty {
        let dirty = Dirty::between(self.prev.as_ref(), state);
        self.prev = Some(state.clone());
        dirty
    }

    /// Forgets the previous frame (the next frame is traced in full).
    pub fn invalidate(&mut self) {
        self.prev = None;
    }
}
