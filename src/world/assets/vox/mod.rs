//! MagicaVoxel `.vox` loading: a file's voxel models become one [`LeafSet`] of surface leaves.
//!
//! Pipeline position: asset loading, offline. A `.vox` file is read once when a scene's assets
//! are prepared, before the SVO memory image is built from the leaf set
//! ([`rtl_model::svo::SvoImage::build`]); nothing here runs per frame or in the modelled
//! hardware.
//!
//! What [`load_vox`] does, in order:
//!
//! 1. **Read and parse.** The bytes are read with `std::fs::read` and parsed by
//!    [`dot_vox::load_bytes`]. Before that, the chunk tree is checked to be at most
//!    [`MAX_CHUNK_NESTING`] levels deep, because `dot_vox` parses nested chunks recursively and
//!    a crafted file of ~100 k nested chunks overflows the stack (an abort, which no error
//!    handling can catch). The parse also runs under `catch_unwind`, so a panic inside
//!    `dot_vox` becomes [`VoxError::Panicked`]; the default panic hook still prints its message
//!    (silencing it would mean replacing the process-wide hook, which races with other threads).
//!
//!    Then the models (each `XYZI` chunk with the `SIZE` chunk before it, children of `MAIN`,
//!    in file order: the index a shape node's model id and the model index refer to) are read
//!    again from the raw bytes, because `dot_vox` loses what the checks need (see `models.rs`).
//!    Each of these is a [`VoxError::Model`] naming the model's index, the chunk's byte offset
//!    and the figures: a chunk running past the end of `MAIN` (truncated), an `XYZI` count
//!    larger than its chunk's bytes can hold, an `XYZI` without a `SIZE` before it, a `SIZE`
//!    axis above [`MAX_SIZE`] (`2^MAX_DEPTH`, the side of the deepest octree), and a voxel
//!    outside its model's `SIZE` (the first one, with its number in the chunk). Voxels of
//!    colour index 0 are left out: MagicaVoxel's index 0 is empty (its palette has 255
//!    colours, 1 to 255).
//! 2. **Choose and compose.** With a model index (`model: Some(i)` of a scene's `Vox` source,
//!    `sim render --model-index i`), model `i` alone is placed untransformed (scene graph
//!    ignored); an index not below the file's model count is [`VoxError::NoSuchModel`]. Without
//!    one, a file with no scene graph and several models is a file of **animation frames**
//!    (MagicaVoxel 0.98 and earlier saved an animation as consecutive `SIZE` / `XYZI` pairs and
//!    shows one frame at a time; 0.99 added the scene graph for models placed together): its
//!    model 0 is loaded alone and [`VoxAsset::notice`] says so in one line, which the caller
//!    prints to stderr as a warning (merging the frames draws every pose at once, a horse with
//!    extra legs). Otherwise every visible shape instance of the scene graph (`nTRN` / `nGRP` /
//!    `nSHP`, walked from node 0; node ids are the chunks' order, as MagicaVoxel writes them) is
//!    placed with the product of the transforms above it (first keyframe: `frames[0]` of a
//!    transform, `models[0]` of a shape). Transforms with `_hidden = 1`, or on a hidden layer,
//!    are skipped with their subtree. A file without a scene graph (and so with one model)
//!    places it at the origin (like an instance with an identity transform). Where instances
//!    overlap, the first one in scene order keeps the voxel. At most [`MAX_PLACED_VOXELS`]
//!    voxels are placed.
//!
//!    Placement follows MagicaVoxel: `_t` is the integer translation "x y z"; `_r` is the packed
//!    rotation byte (bits 0-1: column of the non-zero entry of row 0, bits 2-3: of row 1,
//!    bits 4/5/6: sign of rows 0/1/2, set = negative). A model of size `s` rotates about the
//!    grid point `floor(s/2)`, which lands on the translation `t`. Voxel `v` (occupying the unit
//!    cell `[v, v+1)`) therefore goes to `t + floor(R·(v + ½ − floor(s/2)))`. Without rotation
//!    this is `t + v − floor(s/2)`; with a mirrored axis it differs from the naive
//!    `t + R·(v − floor(s/2))` by one voxel on that axis. (This is the placement of the
//!    vengi and voxel-io importers, which were checked against MagicaVoxel's own display of
//!    rotated and mirrored instances.)
//! 3. **Change axes.** MagicaVoxel is right-handed z-up, ours is right-handed y-up: vox
//!    `(x, y, z)` maps to ours `(x, z, −y)` (a proper rotation, determinant +1), cell for cell.
//!    The bounding box of the solid voxels (not of the models' `SIZE` boxes, which may have
//!    empty margins) is shifted to start at 0 ([`VoxAsset::grid_dims`] is its extent in our
//!    axes) and centred in the `2^depth` cube: offset `floor((2^depth − extent·k) / 2)` leaves
//!    per axis, where k = 2^(depth − needed depth) is the upscaling factor of step 6.
//! 4. **Colour.** `dot_vox` stores `Voxel::i` as the file's 1-based colour index minus one, and
//!    its `palette[i]` is the file's `RGBA` entry `i`, which the format defines as the colour of
//!    index `i + 1`; so `palette[voxel.i]` is the voxel's colour. (`dot_vox` computes `i` with
//!    a saturating subtraction, so file index 0 and 1 both become 0: which is why step 1 reads
//!    the raw index and drops index 0 before this.) Files without an `RGBA` chunk get
//!    MagicaVoxel's default palette from `dot_vox`. Alpha is forced to 255 (leaves are
//!    opaque).
//! 5. **Surface only.** A voxel with all six face neighbours solid can never be hit by a ray,
//!    so only voxels with at least one empty face neighbour become leaves. Their normal is the
//!    normalised sum of the unit directions towards the empty neighbours, in our axes; where
//!    those cancel (a one-voxel-thick wall, a lone voxel) the first open direction of
//!    +y, −y, +x, −x, +z, −z is used instead.
//! 6. **Depth.** The needed depth is the smallest `d ≥ 1` with `2^d ≥` the largest extent.
//!    `None` uses it. `Some(d)` must lie in `1..=MAX_DEPTH` and be at least the needed depth;
//!    a larger `d` scales the model up by `k = 2^(d − needed)`: each voxel becomes a `k³`
//!    block of which only the leaves on faces towards an empty neighbour are kept (so memory
//!    stays proportional to the surface), with the voxel's colour and normal. At most
//!    [`MAX_UPSCALED_LEAVES`] leaves are produced.
//!
//! Where each step lives (private sub-modules of this folder): `parse.rs` (step 1: the nesting
//! guard and the guarded `dot_vox` parse), `models.rs` (step 1: the models read and checked
//! from the raw chunks), `graph.rs` (step 2: the scene-graph walk and voxel placement),
//! `transform.rs` (the `_t` / `_r` decoding and the integer affine maps it makes),
//! `surface.rs` (steps 3 to 6: axes, colours, surface leaves, normals and upscaling) on top of
//! `occupancy.rs` (the solid-cell set), and `error.rs` ([`VoxError`]). `model_frame.rs` (public)
//! maps the loaded leaves back to the file's own voxel indices for `sim render`. This file holds the
//! public API and the limits.

mod error;
mod graph;
pub mod model_frame;
mod models;
mod occupancy;
mod parse;
mod surface;
mod transform;

use std::path::Path;

use rtl_model::svo::{LeafSet, MAX_DEPTH};

pub use error::VoxError;

/// Deepest chain of nested chunks accepted. MagicaVoxel writes `MAIN` with one level of
/// children; the limit only exists to keep `dot_vox`'s recursive chunk parser off the end of
/// the stack.
pub const MAX_CHUNK_NESTING: usize = 16;

/// Most leaves an upscaled load may produce (16 bytes each in the leaf set, twice that while
/// it is sorted), so a large `depth` on a large model fails cleanly instead of exhausting
/// memory.
pub const MAX_UPSCALED_LEAVES: u64 = 1 << 26;

/// Most voxels the composed scene may place (instances counted separately; 32 bytes each
/// while composing). A small file can instance a large model many times; this keeps such a
/// file from exhausting memory. The largest sample (`scene_store8.vox`) places 441 118.
pub const MAX_PLACED_VOXELS: u64 = 1 << 26;

/// Widest `SIZE` axis accepted, in voxels: the side of the deepest octree the SVO builder
/// takes (`2^MAX_DEPTH`). MagicaVoxel itself writes at most 256 (a voxel index is one byte).
pub const MAX_SIZE: u64 = 1 << MAX_DEPTH;

/// What was loaded from a `.vox` file.
#[derive(Clone, Debug)]
pub struct VoxAsset {
    /// Solid surface leaves in our axes, centred in the `2^depth` cube.
    pub leaves: LeafSet,
    /// Octree depth of `leaves`.
    pub depth: u8,
    /// Extent of the composed model in (file) voxels, in our axes (x, y up, z).
    pub grid_dims: [u32; 3],
    /// Model instances (shape nodes, or the one chosen model) composed.
    pub models: usize,
    /// Models (`SIZE` / `XYZI` pairs) in the file.
    pub file_models: usize,
    /// One line for stderr when the loader chose for the user: a file without scene graph
    /// holding several models (animation frames) loads its model 0 and says so here.
    pub notice: Option<String>,
    /// Distinct solid voxels of the composed model, before the interior was dropped.
    pub voxels: usize,
    /// Smallest corner of the solid bounding box in our axes, in composed file voxels before
    /// the shift to 0 (step 3); [`model_frame`] turns it back into MagicaVoxel indices.
    pub solid_min: [i64; 3],
    /// Leaves between the octree's corner and the shifted bounding box, per axis in our axes
    /// (the centring offset of step 3).
    pub offset: [u64; 3],
    /// Leaves per file voxel along each axis, `k = 2^(depth − needed depth)` (step 6).
    pub upscale: u64,
}

/// Loads a `.vox` file as surface leaves; `depth: None` picks the smallest depth that holds
/// the model; a file larger than `max_bytes` is refused (read up to there only). See the
/// module documentation for the conventions.
pub fn load_vox(path: &Path, depth: Option<u8>, max_bytes: u64) -> Result<VoxAsset, VoxError> {
    load_vox_model(path, depth, None, max_bytes)
}

/// Like [`load_vox`], with a choice of model: `Some(i)` loads the file's model `i` alone
/// (0-based, in file order), untransformed; `None` is the default of step 2.
pub fn load_vox_model(
    path: &Path,
    depth: Option<u8>,
    model: Option<usize>,
    max_bytes: u64,
) -> Result<VoxAsset, VoxError> {
    check_requested_depth(path, depth)?;
    let bytes = crate::input::read_bytes(path, crate::input::Cap::vox(max_bytes))?;
    load_vox_bytes_model(&bytes, path, depth, model)
}

/// Like [`load_vox`] for bytes already in memory; `path` only names them in errors.
pub fn load_vox_bytes(bytes: &[u8], path: &Path, depth: Option<u8>) -> Result<VoxAsset, VoxError> {
    load_vox_bytes_model(bytes, path, depth, None)
}

/// Like [`load_vox_model`] for bytes already in memory; `path` only names them in errors.
pub fn load_vox_bytes_model(
    bytes: &[u8],
    path: &Path,
    depth: Option<u8>,
    model: Option<usize>,
) -> Result<VoxAsset, VoxError> {
    check_requested_depth(path, depth)?;
    let mut data = parse::parse(bytes, path)?;
    let models = models::read_models(bytes, path)?;
    if models.len() != data.models.len() {
        // Both read the same chunks; a difference would shift every shape's model id.
        return Err(VoxError::Model {
            path: path.to_path_buf(),
            message: format!(
                "the file's chunks give {} models, the .vox parser read {}",
                models.len(),
                data.models.len()
            ),
        });
    }
    data.models = models;
    let file_models = data.models.len();
    let (placements, frame_0) = match model {
        Some(index) if index >= file_models => {
            return Err(VoxError::NoSuchModel {
                path: path.to_path_buf(),
                index,
                models: file_models,
            })
        }
        Some(index) => (vec![graph::Placement::alone(index)], false),
        // Without a scene graph several models are the frames of an animation (MagicaVoxel
        // 0.98 and earlier), shown one at a time: merging them draws every pose at once.
        None if data.scenes.is_empty() && file_models > 1 => {
            (vec![graph::Placement::alone(0)], true)
        }
        None => (
            graph::placements(&data).map_err(|message| VoxError::Scene {
                path: path.to_path_buf(),
                message,
            })?,
            false,
        ),
    };
    let total: u64 = placements
        .iter()
        .filter_map(|p| data.models.get(p.model))
        .map(|m| m.voxels.len() as u64)
        .sum();
    if total > MAX_PLACED_VOXELS {
        return Err(VoxError::TooManyVoxels {
            path: path.to_path_buf(),
            voxels: total,
        });
    }
    let placed = graph::place_voxels(&data, &placements);
    let mut asset = surface::build(path, &data, placements.len(), placed, depth)?;
    asset.file_models = file_models;
    if frame_0 {
        asset.notice = Some(format!(
            "{}: {file_models} models and no scene graph (animation frames): loaded model 0 \
             alone ({} voxels), not all {file_models} merged; choose one with `model: Some(N)` \
             in a scene or `sim render --model-index N` (N from 0 to {})",
            path.display(),
            asset.voxels,
            file_models - 1
        ));
    }
    Ok(asset)
}

fn check_requested_depth(path: &Path, depth: Option<u8>) -> Result<(), VoxError> {
    match depth {
        Some(d) if d == 0 || d > MAX_DEPTH => Err(VoxError::DepthOutOfRange {
            path: path.to_path_buf(),
            given: d,
        }),
        _ => Ok(()),
    }
}
