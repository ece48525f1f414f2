//! The model's own voxel coordinates: where a loaded `.vox` sits, in the indices of the file
//! (MagicaVoxel axes, z up), and an octree of its leaves laid out along those axes.
//!
//! Pipeline position: asset loading, offline, for `sim render` (`src/run/render.rs`), which
//! renders a bare model with a camera given in the file's coordinates. The scene path does
//! not use it: scenes keep the loader's y-up leaves.
//!
//! The loader (steps 3 and 6 of the [parent module](super)) maps a composed file voxel
//! w = (w₀, w₁, w₂) (the cell [w, w+1)³ of the file's scene) to our y-up axes as
//! g = (w₀, w₂, −w₁ − 1), then to the leaf p = offset + (g − solid_min). For `sim render` we go
//! back: a leaf p of the loaded set is the model voxel
//!
//! ```text
//! g = p − offset + solid_min,   w = (g₀, −g₂ − 1, g₁)
//! ```
//!
//! and is placed in a second octree of the same depth whose axes are the model's own axes,
//! with no axis negated: leaf q = w − base, where base = model_min − model_offset is the model
//! coordinate of that octree's corner (model_min the solid box's smallest model index,
//! model_offset the loader's centring offset with its axes permuted to the model's). So model
//! cell [w, w+1)³ is octree cell q and the octree occupies [base, base + 2^depth]³ in model
//! coordinates: a camera given in model coordinates needs no transform at all (see
//! `docs/render.md` for why this fixes the plane rule). Normals are permuted the same way
//! (ours (x, y, z) = model (x, z, −y), so model = (x, −z, y)).

use std::path::Path;

use rtl_model::svo::{LeafAttr, LeafSet};

use super::{load_vox_model, VoxError};

/// Where a model sits, in its own voxel indices, and in the octree `sim render` walks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelFrame {
    /// Octree depth (the smallest that holds the model).
    pub depth: u8,
    /// Smallest solid voxel index per axis (model axes: MagicaVoxel x, y, z).
    pub solid_min: [i64; 3],
    /// Largest solid voxel index per axis, inclusive.
    pub solid_max: [i64; 3],
    /// Empty leaves between the octree's corner and the solid box, per model axis.
    pub offset: [u64; 3],
    /// Model coordinate of the octree's corner: the octree is [base, base + 2^depth]³.
    pub base: [i64; 3],
    /// Composed model instances.
    pub models: usize,
    /// Models in the file.
    pub file_models: usize,
    /// Distinct solid voxels.
    pub voxels: usize,
    /// Surface voxels (the leaves; the interior is dropped, as for every `.vox` asset).
    pub leaves: usize,
}

impl ModelFrame {
    /// Octree side in voxels.
    pub fn side(&self) -> u64 {
        1u64 << self.depth
    }

    /// Solid extent per model axis, in voxels.
    pub fn extent(&self) -> [u64; 3] {
        std::array::from_fn(|k| (self.solid_max[k] - self.solid_min[k]) as u64 + 1)
    }
}

/// A model loaded for `sim render`: its frame and its leaves in an octree along model axes.
#[derive(Clone, Debug)]
pub struct ModelLeaves {
    /// Where it sits.
    pub frame: ModelFrame,
    /// Leaf q is model voxel `base + q`; attribute normals are in model axes.
    pub leaves: LeafSet,
    /// The loader's one-line notice for stderr, if it chose a model for the user.
    pub notice: Option<String>,
}

/// Loads `path` (at most `max_bytes` long) at its natural depth and lays its leaves out along
/// the model's own axes; `model` chooses one of the file's models as [`load_vox_model`] does.
pub fn load_model_frame(
    path: &Path,
    model: Option<usize>,
    max_bytes: u64,
) -> Result<ModelLeaves, VoxError> {
    let asset = load_vox_model(path, None, model, max_bytes)?;
    // Natural depth: one leaf per file voxel (upscale 1), so leaf and voxel indices agree.
    debug_assert_eq!(asset.upscale, 1);
    let [d0, d1, d2] = asset.grid_dims.map(i64::from);
    let lo = asset.solid_min;
    // Our axes (x, y up, z) are model (x, z, −y − 1): the model's y range comes from ours z.
    let solid_min = [lo[0], -(lo[2] + d2 - 1) - 1, lo[1]];
    let solid_max = [lo[0] + d0 - 1, -lo[2] - 1, lo[1] + d1 - 1];
    let offset = [asset.offset[0], asset.offset[2], asset.offset[1]];
    let base: [i64; 3] = std::array::from_fn(|k| solid_min[k] - offset[k] as i64);
    let frame = ModelFrame {
        depth: asset.depth,
        solid_min,
        solid_max,
        offset,
        base,
        models: asset.models,
        file_models: asset.file_models,
        voxels: asset.voxels,
        leaves: asset.leaves.len(),
    };
    let to_model = |p: [u32; 3]| -> [i64; 3] {
        let g: [i64; 3] = std::array::from_fn(|k| i64::from(p[k]) - asset.offset[k] as i64 + lo[k]);
        [g[0], -g[2] - 1, g[1]]
    };
    let leaves = asset.leaves.coords().map(|(p, attr)| {
        let w = to_model(p);
        // In the octree by construction: w lies in the solid box, which the loader centred.
        let q: [u32; 3] = std::array::from_fn(|k| (w[k] - base[k]) as u32);
        let n = attr.normal();
        (q, LeafAttr::new(attr.rgba(), [n[0], -n[2], n[1]]))
    });
    let leaves = LeafSet::from_coords(asset.depth, leaves).map_err(|source| VoxError::Leaves {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(ModelLeaves {
        frame,
        leaves,
        notice: asset.notice,
    })
}
