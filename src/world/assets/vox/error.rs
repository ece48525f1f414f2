//! Errors of the `.vox` loader: every way a file can fail to become leaves, each naming the
//! file. Pipeline position: asset loading, offline (see the [parent module](super)).

use std::path::PathBuf;

use rtl_model::svo::{LeafSetError, MAX_DEPTH};
use thiserror::Error;

use super::{MAX_PLACED_VOXELS, MAX_UPSCALED_LEAVES};

/// Why a `.vox` file could not be loaded. Every message names the file.
#[derive(Debug, Error)]
pub enum VoxError {
    /// The file could not be read, or is larger than its cap (boxed: the asset and sweep
    /// errors that carry a `VoxError` stay small).
    #[error(transparent)]
    Input(Box<crate::input::InputError>),
    /// The bytes are not a (well-formed) `.vox` file.
    #[error("{} is not a valid MagicaVoxel file: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// The `.vox` parser panicked on the file's bytes.
    #[error("the .vox parser panicked on {}: {message}", path.display())]
    Panicked {
        /// The file.
        path: PathBuf,
        /// The panic message.
        message: String,
    },
    /// A model's chunks are inconsistent: a truncated chunk, an `XYZI` count beyond its
    /// chunk's bytes, an `XYZI` without `SIZE`, a `SIZE` above
    /// [`MAX_SIZE`](super::MAX_SIZE), a voxel outside its model's `SIZE`.
    #[error("{}: invalid MagicaVoxel model: {message}", path.display())]
    Model {
        /// The file.
        path: PathBuf,
        /// What is wrong: the model's index, the chunk's byte offset and the figures.
        message: String,
    },
    /// The requested model index is not in the file.
    #[error(
        "{}: model index {index} is out of range: the file has {models} model(s){}",
        path.display(),
        if *models > 0 { format!(" (0 to {})", models - 1) } else { String::new() }
    )]
    NoSuchModel {
        /// The file.
        path: PathBuf,
        /// The requested index.
        index: usize,
        /// Models in the file.
        models: usize,
    },
    /// The scene graph is unusable (dangling or repeated node reference, bad transform).
    #[error("{}: invalid MagicaVoxel scene graph: {message}", path.display())]
    Scene {
        /// The file.
        path: PathBuf,
        /// What is wrong and where.
        message: String,
    },
    /// No visible voxel.
    #[error("{} contains no visible voxels", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The requested depth is outside `1..=MAX_DEPTH`.
    #[error("{}: requested octree depth {given} is out of range (1 to {MAX_DEPTH})", path.display())]
    DepthOutOfRange {
        /// The file.
        path: PathBuf,
        /// The requested depth.
        given: u8,
    },
    /// The requested depth cannot hold the model.
    #[error(
        "{}: octree depth {given} is too small, the model spans {extent} voxels and needs depth {needed}",
        path.display()
    )]
    DepthTooSmall {
        /// The file.
        path: PathBuf,
        /// Smallest depth that holds the model.
        needed: u8,
        /// The requested depth.
        given: u8,
        /// Largest extent of the composed model, in voxels.
        extent: u64,
    },
    /// The composed model is wider than the deepest octree.
    #[error(
        "{}: the composed model spans {extent} voxels, which needs octree depth {needed} (at most {MAX_DEPTH})",
        path.display()
    )]
    DepthTooLarge {
        /// The file.
        path: PathBuf,
        /// Smallest depth that would hold the model.
        needed: u32,
        /// Largest extent of the composed model, in voxels.
        extent: u64,
    },
    /// The scene places more voxels than [`MAX_PLACED_VOXELS`].
    #[error(
        "{}: the scene places {voxels} voxels (at most {MAX_PLACED_VOXELS})",
        path.display()
    )]
    TooManyVoxels {
        /// The file.
        path: PathBuf,
        /// Voxels over all instances.
        voxels: u64,
    },
    /// Upscaling to the requested depth would make too many leaves.
    #[error(
        "{}: depth {depth} would make {leaves} surface leaves (at most {MAX_UPSCALED_LEAVES})",
        path.display()
    )]
    TooManyLeaves {
        /// The file.
        path: PathBuf,
        /// The requested depth.
        depth: u8,
        /// Leaves the upscaled surface would have.
        leaves: u64,
    },
    /// The leaf set rejected the leaves (an internal error: coordinates are made to fit).
    #[error("{}: internal error collecting leaves: {source}", path.display())]
    Leaves {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: LeafSetError,
    },
}

impl From<crate::input::InputError> for VoxError {
    fn from(e: crate::input::InputError) -> Self {
        Self::Input(Box::new(e))
    }
}
