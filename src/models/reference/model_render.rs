//! What a render of one bare `.vox` model produces (`sim render`): how pixels became rays,
//! and every pixel's ray and hit in the model's own voxel coordinates.
//!
//! Pipeline position: the result types of the reference's octree walk run alone on one model
//! (`crate::run::render::render_model` fills them; the hit dump `crate::output::model_dump`
//! and the PNG write them). They live in the models layer so that the output layer can take
//! them without importing the run layer (docs/architecture.md §1).

use super::walk::WalkCounters;
use crate::world::assets::vox::model_frame::ModelFrame;

/// How pixels become rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole at the eye with this vertical field of view, degrees in (0, 180).
    Pinhole {
        /// Vertical field of view in degrees.
        vfov_deg: f64,
    },
    /// Parallel rays along the view direction from the plane through the eye; the view is
    /// this wide (voxels) and width·H/W high.
    Ortho {
        /// Width of the view in voxels.
        view_width: f64,
    },
}

/// One pixel: its ray and what it hit, in model coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelHit {
    /// Ray origin.
    pub origin: [f64; 3],
    /// Unit ray direction (exact zeros are +0.0).
    pub dir: [f64; 3],
    /// A solid voxel was hit.
    pub hit: bool,
    /// Ray parameter where the ray enters the voxel (0 if the origin is inside it); −1 on a
    /// miss.
    pub t: f64,
    /// The voxel's index in the model (x, y, z as in the `.vox` file); 0 on a miss.
    pub voxel: [i32; 3],
    /// Entry face normal in model axes (−1/0/1, against the ray); 0 on a miss.
    pub face: [i8; 3],
    /// The voxel's colour; 0 on a miss.
    pub rgba: [u8; 4],
    /// The voxel's attribute normal in model axes, for shading; 0 on a miss.
    pub normal: [f32; 3],
    /// The voxel's index in the octree's attribute array; 0 on a miss.
    pub leaf: u32,
}

/// The `t` of a miss in [`ModelHit`] and in dumps: every real t is ≥ 0.
pub const MISS_T: f64 = -1.0;

impl ModelHit {
    /// The record of a ray that hits nothing.
    pub(crate) fn miss(origin: [f64; 3], dir: [f64; 3]) -> Self {
        Self {
            origin,
            dir,
            hit: false,
            t: MISS_T,
            voxel: [0; 3],
            face: [0; 3],
            rgba: [0; 4],
            normal: [0.0; 3],
            leaf: 0,
        }
    }
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct ModelRender {
    /// Where the model sits.
    pub frame: ModelFrame,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Records, row-major from the top-left pixel.
    pub hits: Vec<ModelHit>,
    /// Walk work, summed over all pixels.
    pub counters: WalkCounters,
    /// Wall time of ray generation and walks (not loading), seconds.
    pub trace_seconds: f64,
    /// The loader's one-line notice for stderr, if it chose a model for the user.
    pub notice: Option<String>,
}
