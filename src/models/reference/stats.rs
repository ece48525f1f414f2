//! Per-frame counters of the reference renderer (`stage/metric` style names in reports).

use serde::Serialize;

/// Counters of one frame. Sums over pixels; deterministic (integers only, except times).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FrameStats {
    /// Frame number.
    pub frame: u32,
    /// Primary rays (pixels).
    pub rays: u64,
    /// Ray–sphere tests performed.
    pub sphere_tests: u64,
    /// Sphere tests that culled the instance.
    pub spheres_culled: u64,
    /// Candidates (pierced spheres) over all rays that were traced (not reused).
    pub candidates: u64,
    /// Largest candidate count of one ray.
    pub candidates_max: u32,
    /// Octree walks started.
    pub walks: u64,
    /// Walker loop iterations (children examined).
    pub walker_steps: u64,
    /// Descriptor fetches.
    pub node_fetches: u64,
    /// Deepest walker stack (frames).
    pub max_stack: u32,
    /// Rays that stopped with candidates left unwalked.
    pub early_terminations: u64,
    /// Candidates skipped by early termination.
    pub walks_skipped: u64,
    /// Pixels taken from the hit buffer without walking.
    pub hit_buffer_reused: u64,
    /// Pixels whose ray hit a voxel.
    pub hits: u64,
    /// Whether the camera changed since the previous frame.
    pub camera_dirty: bool,
    /// Instances whose pose changed since the previous frame.
    pub instances_dirty: u32,
    /// Wall time of the frame's tracing, seconds.
    pub wall_s: f64,
    /// Rays per second of wall time.
    pub rays_per_s: f64,
}

impl FrameStats {
    /// Adds the counters of `o` (a part of the same frame).
    pub fn merge(&mut self, o: &Self) {
        self.rays += o.rays;
        self.sphere_tests += o.sphere_tests;
        self.spheres_culled += o.spheres_culled;
        self.candidates += o.candidates;
        self.candidates_max = self.candidates_max.max(o.candidates_max);
        self.walks += o.walks;
        self.walker_steps += o.walker_steps;
        self.node_fetches += o.node_fetches;
        self.max_stack = self.max_stack.max(o.max_stack);
        self.early_terminations += o.early_terminations;
        self.walks_skipped += o.walks_skipped;
        self.hit_buffer_reused += o.hit_buffer_reused;
        self.hits += o.hits;
    }
}
