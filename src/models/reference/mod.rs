//! The f64 reference of the paper's method, end to end (see `docs/reference.md`).
//!
//! Per pixel: [`ray`] generation → [`sphere`] tests in world space (paper Eq. 4) → sort by
//! entry distance → [`hit_buffer`] reuse check → for each candidate in order: inverse
//! transform (Eq. 3, scale through the octree's extents, §3.2) and the Revelles walk
//! ([`walk`]) → early termination → [`record::HitRecord`]. [`frame`] runs a whole frame;
//! [`model_render`] holds what a render of one bare model (`sim render`) produces.
//! Nothing here shares code with the oracles in `tests/`.

pub mod cull;
pub mod frame;
pub mod hit_buffer;
pub mod model_render;
pub mod octree;
pub mod ray;
pub mod record;
pub mod sphere;
pub mod stats;
pub mod walk;

pub use frame::{
    render_frame, render_frame_two_level, render_frame_with_progress, FrameInput, RaySwitches,
    RenderOptions,
};
pub use hit_buffer::HitBuffer;
pub use record::{HitRecord, SphereCount};
pub use stats::FrameStats;
