//! The study's scenes: a crowd of `n` instances of two SDF shapes on a 40 m × 40 m plaza seen
//! from above at 1280×768, each instance scaled by 16/√n so the crowd's screen coverage stays
//! about the same at every count (n·s² constant), moving at a speed proportional to its size
//! and turning; a still or a moving camera.
//!
//! Pipeline position: input of `super::measure`; the same `crowds` block a scene file uses
//! (`world::scene::crowd`), expanded by the loader.

use crate::world::scene::Scene;
use std::path::Path;

/// Image size of the study (the paper's resolution).
pub const SIZE: (u32, u32) = (1280, 768);

/// One study scene.
#[derive(Clone, Copy, Debug)]
pub struct CrowdCase {
    /// Instances.
    pub n: u32,
    /// Camera moves between the two frames.
    pub moving_camera: bool,
    /// Fraction of the instances that move.
    pub moving: f64,
    /// Image size.
    pub size: (u32, u32),
    /// Asset depth.
    pub depth: u8,
}

impl CrowdCase {
    /// The scene's RON text.
    pub fn ron(&self) -> String {
        let s = 16.0 / f64::from(self.n.max(1)).sqrt();
        let cam2 = if self.moving_camera {
            ", (frame: 1, position: (0.6, 30, 38), look_at: (0, 0, 0), vfov_deg: 50)"
        } else {
            ""
        };
        let (w, h) = self.size;
        format!(
            r#"(
    resolution: ({w}, {h}),
    frames: 2,
    camera: [(frame: 0, position: (0, 30, 38), look_at: (0, 0, 0), vfov_deg: 50){cam2}],
    assets: [
        (name: "ball", depth: {d}, source: Sdf(shape: Sphere(radius: 0.45))),
        (name: "box", depth: {d}, source: Sdf(shape: Box(half: (0.3, 0.45, 0.2)))),
    ],
    crowds: [(count: {n}, seed: 18, area: (40, 40), centre: (0, {y}, 0), models: ["ball", "box"],
              speed: ({v0}, {v1}), moving: {m}, turn_deg: 4, scale: {s})],
)"#,
            d = self.depth,
            n = self.n,
            y = 0.45 * s,
            v0 = 0.02 * s,
            v1 = 0.06 * s,
            m = self.moving,
        )
    }

    /// The validated scene.
    pub fn scene(&self) -> Result<Scene, String> {
        Scene::from_ron(&self.ron(), "instances study", Path::new(".")).map_err(|e| e.to_string())
    }
}
