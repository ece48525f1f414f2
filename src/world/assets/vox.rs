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
//! 2. **Compose the scene.** Every visible shape instance of the scene graph (`nTRN` / `nGRP` /
//!    `nSHP`, walked from node 0; node ids are the chunks' order, as MagicaVoxel writes them) is
//!    placed with the product of the transforms above it (first keyframe: `frames[0]` of a
//!    transform, `models[0]` of a shape). Transforms with `_hidden = 1`, or on a hidden layer,
//!    are skipped with their subtree. A file without a scene graph places each model at the
//!    origin (like an instance with an identity transform). Where instances overlap, the first
//!    one in scene order keeps the voxel. At most [`MAX_PLACED_VOXELS`] voxels are placed.
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
//!    index `i + 1`; so `palette[voxel.i]` is the voxel's colour. Files without an `RGBA` chunk
//!    get MagicaVoxel's default palette from `dot_vox`. Alpha is forced to 255 (leaves are
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

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use rtl_model::svo::{LeafAttr, LeafSet, LeafSetError, MAX_DEPTH};
use thiserror::Error;

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

/// Composed grids with at most this many cells use a dense occupancy bitset (32 MiB at most);
/// larger, sparse ones use a hash set.
const DENSE_OCCUPANCY_CELLS: u64 = 1 << 28;

/// Why a `.vox` file could not be loaded. Every message names the file.
#[derive(Debug, Error)]
pub enum VoxError {
    /// The file could not be read.
    #[error("cannot read MagicaVoxel file {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
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

/// What was loaded from a `.vox` file.
#[derive(Clone, Debug)]
pub struct VoxAsset {
    /// Solid surface leaves in our axes, centred in the `2^depth` cube.
    pub leaves: LeafSet,
    /// Octree depth of `leaves`.
    pub depth: u8,
    /// Extent of the composed model in (file) voxels, in our axes (x, y up, z).
    pub grid_dims: [u32; 3],
    /// Model instances (shape nodes, or models of a file without scene graph) composed.
    pub models: usize,
    /// Distinct solid voxels of the composed model, before the interior was dropped.
    pub voxels: usize,
}

/// Loads a `.vox` file as surface leaves; `depth: None` picks the smallest depth that holds
/// the model. See the module documentation for the conventions.
pub fn load_vox(path: &Path, depth: Option<u8>) -> Result<VoxAsset, VoxError> {
    check_requested_depth(path, depth)?;
    let bytes = std::fs::read(path).map_err(|source| VoxError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    load_vox_bytes(&bytes, path, depth)
}

/// Like [`load_vox`] for bytes already in memory; `path` only names them in errors.
pub fn load_vox_bytes(bytes: &[u8], path: &Path, depth: Option<u8>) -> Result<VoxAsset, VoxError> {
    check_requested_depth(path, depth)?;
    let data = parse(bytes, path)?;
    let scene_error = |message: String| VoxError::Scene {
        path: path.to_path_buf(),
        message,
    };
    let placements = placements(&data).map_err(scene_error)?;
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
    let placed = place_voxels(&data, &placements);
    build(path, &data, placements.len(), placed, depth)
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

// ---------------------------------------------------------------------------------------------
// Parsing

fn parse(bytes: &[u8], path: &Path) -> Result<dot_vox::DotVoxData, VoxError> {
    if let Some(depth) = chunk_nesting_exceeds(bytes, MAX_CHUNK_NESTING) {
        return Err(VoxError::Parse {
            path: path.to_path_buf(),
            message: format!("chunks nested at least {depth} deep (at most {MAX_CHUNK_NESTING})"),
        });
    }
    match std::panic::catch_unwind(|| dot_vox::load_bytes(bytes)) {
        Ok(Ok(data)) => Ok(data),
        Ok(Err(message)) => Err(VoxError::Parse {
            path: path.to_path_buf(),
            message: message.to_string(),
        }),
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "non-text panic payload".to_string());
            Err(VoxError::Panicked {
                path: path.to_path_buf(),
                message,
            })
        }
    }
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Walks the RIFF-style chunk tree the way `dot_vox` does (header: id, content size, children
/// size; children parsed as a chunk list when their size is non-zero) and returns the nesting
/// depth reached if it exceeds `limit`. It follows every chunk `dot_vox` could descend into
/// (and possibly more), so `dot_vox`'s recursion is never deeper than what passed here.
/// Iterative, so the check itself cannot overflow the stack.
fn chunk_nesting_exceeds(bytes: &[u8], limit: usize) -> Option<usize> {
    const HEADER: usize = 12;
    // (start, end, depth) of chunk lists still to scan; the file's chunks start after
    // "VOX " and the version.
    let mut lists = vec![(8usize.min(bytes.len()), bytes.len(), 1usize)];
    while let Some((mut pos, end, depth)) = lists.pop() {
        while end.saturating_sub(pos) >= HEADER {
            let (Some(content), Some(children)) =
                (read_u32(bytes, pos + 4), read_u32(bytes, pos + 8))
            else {
                break;
            };
            let children_start = (pos + HEADER).checked_add(content as usize);
            let next = children_start.and_then(|s| s.checked_add(children as usize));
            let (Some(children_start), Some(next)) = (children_start, next) else {
                break;
            };
            if next > end {
                break; // dot_vox fails on the short read and stops this list here too
            }
            if children > 0 {
                if depth + 1 > limit {
                    return Some(depth + 1);
                }
                lists.push((children_start, next, depth + 1));
            }
            pos = next;
        }
    }
    None
}

// ---------------------------------------------------------------------------------------------
// Scene graph

/// Integer affine map `x ↦ r·x + t` with `r` a signed permutation matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Affine {
    r: [[i64; 3]; 3],
    t: [i64; 3],
}

impl Affine {
    const IDENTITY: Self = Self {
        r: [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        t: [0, 0, 0],
    };

    /// `self ∘ inner`: apply `inner` first.
    fn then_inner(&self, inner: &Self) -> Self {
        let mut r = [[0i64; 3]; 3];
        let mut t = self.t;
        for (row, out) in r.iter_mut().enumerate() {
            for (col, v) in out.iter_mut().enumerate() {
                *v = (0..3).map(|k| self.r[row][k] * inner.r[k][col]).sum();
            }
            t[row] += (0..3).map(|k| self.r[row][k] * inner.t[k]).sum::<i64>();
        }
        Self { r, t }
    }
}

/// One model instance to compose.
#[derive(Clone, Copy, Debug)]
struct Placement {
    model: usize,
    transform: Affine,
}

/// Decodes MagicaVoxel's packed rotation byte (row-major signed permutation).
fn decode_rotation(byte: u8) -> Option<[[i64; 3]; 3]> {
    let c0 = usize::from(byte & 3);
    let c1 = usize::from((byte >> 2) & 3);
    if c0 > 2 || c1 > 2 || c0 == c1 {
        return None;
    }
    let c2 = 3 - c0 - c1;
    let sign = |bit: u8| if byte & (1 << bit) != 0 { -1 } else { 1 };
    let mut r = [[0i64; 3]; 3];
    r[0][c0] = sign(4);
    r[1][c1] = sign(5);
    r[2][c2] = sign(6);
    Some(r)
}

/// The local transform of a transform node's first frame.
fn frame_transform(frame: &dot_vox::Frame, node: usize) -> Result<Affine, String> {
    let mut a = Affine::IDENTITY;
    if let Some(text) = frame.attributes.get("_r") {
        let r = text
            .trim()
            .parse::<u8>()
            .ok()
            .and_then(decode_rotation)
            .ok_or_else(|| format!("node {node}: invalid rotation _r = {text:?}"))?;
        a.r = r;
    }
    if let Some(text) = frame.attributes.get("_t") {
        let parts: Vec<Option<i64>> = text
            .split_whitespace()
            .map(|p| p.parse::<i32>().ok().map(i64::from))
            .collect();
        match parts.as_slice() {
            [Some(x), Some(y), Some(z)] => a.t = [*x, *y, *z],
            _ => return Err(format!("node {node}: invalid translation _t = {text:?}")),
        }
    }
    Ok(a)
}

fn is_hidden(attributes: &dot_vox::Dict) -> bool {
    attributes.get("_hidden").is_some_and(|v| v.trim() == "1")
}

/// Every visible model instance with its model-to-world transform (vox axes), in scene order.
fn placements(data: &dot_vox::DotVoxData) -> Result<Vec<Placement>, String> {
    if data.scenes.is_empty() {
        // Pre-scene-graph files (or files saved without one): each model untransformed.
        return Ok((0..data.models.len())
            .map(|model| Placement {
                model,
                transform: Affine::IDENTITY,
            })
            .collect());
    }
    let n = data.scenes.len();
    let mut seen = vec![false; n];
    let mut out = Vec::new();
    // Depth-first with an explicit stack, children pushed in reverse so they are visited in
    // file order (which decides who keeps a voxel where instances overlap).
    let mut stack = vec![(0usize, Affine::IDENTITY)];
    while let Some((node, parent)) = stack.pop() {
        let Some(scene_node) = data.scenes.get(node) else {
            return Err(format!(
                "reference to node {node}, but the file has {n} nodes"
            ));
        };
        // A tree visits each node once; a repeat means a cycle or a shared subtree, which
        // MagicaVoxel never writes and which could make the walk endless or exponential.
        if std::mem::replace(&mut seen[node], true) {
            return Err(format!("node {node} is referenced more than once"));
        }
        match scene_node {
            dot_vox::SceneNode::Transform {
                attributes,
                frames,
                child,
                layer_id,
            } => {
                let layer_hidden = data
                    .layers
                    .get(*layer_id as usize)
                    .is_some_and(|layer| layer.hidden());
                if is_hidden(attributes) || layer_hidden {
                    continue;
                }
                let local = match frames.first() {
                    Some(frame) => frame_transform(frame, node)?,
                    None => Affine::IDENTITY,
                };
                stack.push((*child as usize, parent.then_inner(&local)));
            }
            dot_vox::SceneNode::Group {
                attributes,
                children,
            } => {
                if is_hidden(attributes) {
                    continue;
                }
                stack.extend(children.iter().rev().map(|&c| (c as usize, parent)));
            }
            dot_vox::SceneNode::Shape { attributes, models } => {
                if is_hidden(attributes) {
                    continue;
                }
                if let Some(shape_model) = models.first() {
                    let model = shape_model.model_id as usize;
                    if model >= data.models.len() {
                        return Err(format!(
                            "shape node {node} uses model {model}, but the file has {} models",
                            data.models.len()
                        ));
                    }
                    out.push(Placement {
                        model,
                        transform: parent,
                    });
                }
            }
        }
    }
    Ok(out)
}

/// Every voxel of every placement in our axes (y up), with its palette index, in scene order.
fn place_voxels(data: &dot_vox::DotVoxData, placements: &[Placement]) -> Vec<([i64; 3], u8)> {
    let total: usize = placements
        .iter()
        .filter_map(|p| data.models.get(p.model))
        .map(|m| m.voxels.len())
        .sum();
    let mut out = Vec::with_capacity(total);
    for p in placements {
        let Some(model) = data.models.get(p.model) else {
            continue;
        };
        let size = [model.size.x, model.size.y, model.size.z];
        // Doubled coordinates keep the half-voxel offset exact: 2·(v + ½ − floor(s/2)).
        let pivot2 = size.map(|s| 2 * i64::from(s / 2));
        let Affine { r, t } = p.transform;
        for v in &model.voxels {
            let d = [
                2 * i64::from(v.x) + 1 - pivot2[0],
                2 * i64::from(v.y) + 1 - pivot2[1],
                2 * i64::from(v.z) + 1 - pivot2[2],
            ];
            // Each component of r·d is odd, so div_euclid(2) is the floor of a half-integer.
            let w: [i64; 3] = std::array::from_fn(|row| {
                (r[row][0] * d[0] + r[row][1] * d[1] + r[row][2] * d[2]).div_euclid(2) + t[row]
            });
            // z-up to y-up, cell for cell: the cell [y, y+1) becomes [−y−1, −y).
            out.push(([w[0], w[2], -w[1] - 1], v.i));
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Grid, surface and leaves

/// Directions to the six face neighbours, in our axes; bit `i` of a face mask is set when the
/// neighbour in direction `i` is empty.
const DIRS: [[i64; 3]; 6] = [
    [-1, 0, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [0, 0, -1],
    [0, 0, 1],
];

/// Fallback order for normals whose open directions cancel: +y, −y, +x, −x, +z, −z.
const FALLBACK_DIRS: [usize; 6] = [3, 2, 1, 0, 5, 4];

fn normal_for_mask(mask: u8) -> [f64; 3] {
    let mut sum = [0i64; 3];
    for (i, d) in DIRS.iter().enumerate() {
        if mask & (1 << i) != 0 {
            for k in 0..3 {
                sum[k] += d[k];
            }
        }
    }
    if sum == [0, 0, 0] {
        // LeafAttr would store a zero normal as +z, a side direction in a y-up world; an open
        // face direction is a better guess.
        if let Some(&i) = FALLBACK_DIRS.iter().find(|&&i| mask & (1 << i) != 0) {
            sum = DIRS[i];
        }
    }
    let len = ((sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) as f64).sqrt();
    if len == 0.0 {
        return [0.0, 1.0, 0.0];
    }
    sum.map(|c| c as f64 / len)
}

/// Solid cells of the composed grid, dense or hashed.
enum Occupancy {
    Dense { dims: [u64; 3], bits: Vec<u64> },
    Sparse(HashSet<u64>),
}

impl Occupancy {
    fn new(dims: [u64; 3]) -> Self {
        let cells = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
        if cells <= DENSE_OCCUPANCY_CELLS {
            Self::Dense {
                dims,
                bits: vec![0; cells.div_ceil(64) as usize],
            }
        } else {
            Self::Sparse(HashSet::new())
        }
    }

    /// Key of an in-grid cell: linear index (dense) or packed 20-bit fields (sparse: every
    /// extent is at most 2^MAX_DEPTH).
    fn key(&self, c: [i64; 3]) -> Option<u64> {
        match self {
            Self::Dense { dims, .. } => {
                let [x, y, z] = c.map(|v| u64::try_from(v).ok());
                let (x, y, z) = (x?, y?, z?);
                (x < dims[0] && y < dims[1] && z < dims[2]).then(|| x + dims[0] * (y + dims[1] * z))
            }
            Self::Sparse(_) => {
                let [x, y, z] = c.map(|v| u64::try_from(v).ok().filter(|&v| v < 1 << 20));
                Some(x? | (y? << 20) | (z? << 40))
            }
        }
    }

    /// Marks a cell solid; false if it already was (or lies outside the grid).
    fn insert(&mut self, c: [i64; 3]) -> bool {
        let Some(key) = self.key(c) else {
            return false;
        };
        match self {
            Self::Dense { bits, .. } => {
                let (word, bit) = ((key / 64) as usize, key % 64);
                let was = bits[word] & (1 << bit) != 0;
                bits[word] |= 1 << bit;
                !was
            }
            Self::Sparse(set) => set.insert(key),
        }
    }

    fn contains(&self, c: [i64; 3]) -> bool {
        let Some(key) = self.key(c) else {
            return false;
        };
        match self {
            Self::Dense { bits, .. } => bits[(key / 64) as usize] & (1 << (key % 64)) != 0,
            Self::Sparse(set) => set.contains(&key),
        }
    }
}

/// Smallest `d ≥ 1` with `2^d ≥ extent`.
fn needed_depth(extent: u64) -> u32 {
    extent.max(2).next_power_of_two().trailing_zeros()
}

/// Fine leaves of a `k³` block on the faces towards empty neighbours:
/// `k³ − Π(k − open faces on that axis)`.
fn block_surface_cells(k: u64, mask: u8) -> u64 {
    let inner: u64 = (0..3)
        .map(|axis| {
            let open =
                u64::from((mask >> (2 * axis)) & 1) + u64::from((mask >> (2 * axis + 1)) & 1);
            k.saturating_sub(open)
        })
        .product();
    k * k * k - inner
}

fn build(
    path: &Path,
    data: &dot_vox::DotVoxData,
    models: usize,
    placed: Vec<([i64; 3], u8)>,
    depth: Option<u8>,
) -> Result<VoxAsset, VoxError> {
    let empty = || VoxError::Empty {
        path: path.to_path_buf(),
    };
    let first = placed.first().ok_or_else(empty)?.0;
    let (mut lo, mut hi) = (first, first);
    for (c, _) in &placed {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let dims: [u64; 3] = std::array::from_fn(|k| (hi[k] - lo[k]) as u64 + 1);
    let extent = dims[0].max(dims[1]).max(dims[2]);
    let needed = needed_depth(extent);
    if needed > u32::from(MAX_DEPTH) {
        return Err(VoxError::DepthTooLarge {
            path: path.to_path_buf(),
            needed,
            extent,
        });
    }
    let needed = needed as u8; // at most MAX_DEPTH
    let depth = match depth {
        None => needed,
        Some(d) if d < needed => {
            return Err(VoxError::DepthTooSmall {
                path: path.to_path_buf(),
                needed,
                given: d,
                extent,
            })
        }
        Some(d) => d, // range checked on entry
    };

    // Occupancy in grid coordinates (bounding box at 0); a repeated cell keeps the first voxel.
    let mut occupancy = Occupancy::new(dims);
    let mut solid: Vec<([i64; 3], u8)> = Vec::with_capacity(placed.len());
    for (c, colour) in placed {
        let g = [c[0] - lo[0], c[1] - lo[1], c[2] - lo[2]];
        if occupancy.insert(g) {
            solid.push((g, colour));
        }
    }
    let voxels = solid.len();
    if voxels == 0 {
        return Err(empty());
    }

    let surface: Vec<([i64; 3], u8, u8)> = solid
        .iter()
        .filter_map(|&(c, colour)| {
            let mask = DIRS.iter().enumerate().fold(0u8, |m, (i, d)| {
                let n = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                if occupancy.contains(n) {
                    m
                } else {
                    m | (1 << i)
                }
            });
            (mask != 0).then_some((c, colour, mask))
        })
        .collect();
    drop(solid);
    drop(occupancy);

    let colours: [[u8; 4]; 256] = std::array::from_fn(|i| {
        let c = data
            .palette
            .get(i)
            .or_else(|| dot_vox::DEFAULT_PALETTE.get(i))
            .copied()
            .unwrap_or(dot_vox::Color {
                r: 255,
                g: 0,
                b: 255,
                a: 255,
            });
        [c.r, c.g, c.b, 255]
    });
    let normals: [[f64; 3]; 64] = std::array::from_fn(|m| normal_for_mask(m as u8));
    let attr = |colour: u8, mask: u8| {
        LeafAttr::new(colours[usize::from(colour)], normals[usize::from(mask)])
    };

    let k = 1u64 << (depth - needed);
    let side = 1u64 << depth;
    let offset: [u64; 3] = std::array::from_fn(|a| (side - dims[a] * k) / 2);
    let leaves_error = |source| VoxError::Leaves {
        path: path.to_path_buf(),
        source,
    };

    let leaves = if k == 1 {
        let leaves = surface.iter().map(|&(c, colour, mask)| {
            let p: [u32; 3] = std::array::from_fn(|a| (offset[a] + c[a] as u64) as u32);
            (p, attr(colour, mask))
        });
        LeafSet::from_coords(depth, leaves).map_err(leaves_error)?
    } else {
        let count: u64 = surface
            .iter()
            .map(|&(_, _, mask)| block_surface_cells(k, mask))
            .fold(0u64, u64::saturating_add);
        if count > MAX_UPSCALED_LEAVES {
            return Err(VoxError::TooManyLeaves {
                path: path.to_path_buf(),
                depth,
                leaves: count,
            });
        }
        let leaves = surface.iter().flat_map(|&(c, colour, mask)| {
            let base: [u64; 3] = std::array::from_fn(|a| offset[a] + c[a] as u64 * k);
            let a = attr(colour, mask);
            block_surface(k, mask)
                .into_iter()
                .map(move |f| (std::array::from_fn(|i| (base[i] + f[i]) as u32), a))
        });
        LeafSet::from_coords(depth, leaves).map_err(leaves_error)?
    };

    Ok(VoxAsset {
        leaves,
        depth,
        grid_dims: dims.map(|d| d as u32),
        models,
        voxels,
    })
}

/// Offsets inside a `k³` block of the cells on its open faces (mask bit `2a` = low face of
/// axis `a`, `2a + 1` = high face), each cell once.
fn block_surface(k: u64, mask: u8) -> Vec<[u64; 3]> {
    let plane = |face: usize| if face % 2 == 1 { k - 1 } else { 0 };
    let mut out = Vec::new();
    for face in (0..6).filter(|&f| mask & (1 << f) != 0) {
        let axis = face / 2;
        let (u_axis, v_axis) = ((axis + 1) % 3, (axis + 2) % 3);
        for u in 0..k {
            for v in 0..k {
                let mut cell = [0u64; 3];
                cell[axis] = plane(face);
                cell[u_axis] = u;
                cell[v_axis] = v;
                // Edges and corners lie on several open faces; the first one emits them.
                let on_earlier = (0..face).any(|g| mask & (1 << g) != 0 && cell[g / 2] == plane(g));
                if !on_earlier {
                    out.push(cell);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_byte_decodes_spec_example() {
        // The format description's example: R = [[0,1,0],[0,0,-1],[-1,0,0]],
        // _r = (1 << 0) | (2 << 2) | (0 << 4) | (1 << 5) | (1 << 6).
        let byte = 1 | (2 << 2) | (1 << 5) | (1 << 6);
        assert_eq!(
            decode_rotation(byte),
            Some([[0, 1, 0], [0, 0, -1], [-1, 0, 0]])
        );
        assert_eq!(decode_rotation(4), Some(Affine::IDENTITY.r));
        assert_eq!(decode_rotation(0), None); // both rows point at column 0
        assert_eq!(decode_rotation(3), None); // column 3 does not exist
    }

    #[test]
    fn affine_composition_applies_inner_first() {
        let rot_z90 = Affine {
            r: [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
            t: [10, 0, 0],
        };
        let shift = Affine {
            r: Affine::IDENTITY.r,
            t: [1, 2, 3],
        };
        let m = rot_z90.then_inner(&shift);
        // rot_z90(shift(0)) = rot_z90((1,2,3)) = (-2 + 10, 1, 3)
        assert_eq!(m.t, [8, 1, 3]);
        assert_eq!(m.r, rot_z90.r);
    }

    #[test]
    fn needed_depth_is_smallest_power_of_two_cover() {
        assert_eq!(needed_depth(1), 1);
        assert_eq!(needed_depth(2), 1);
        assert_eq!(needed_depth(3), 2);
        assert_eq!(needed_depth(124), 7);
        assert_eq!(needed_depth(128), 7);
        assert_eq!(needed_depth(129), 8);
    }

    #[test]
    fn block_surface_matches_count_and_is_unique() {
        for k in [1u64, 2, 3, 4] {
            for mask in 0u8..64 {
                let cells = block_surface(k, mask);
                let unique: HashSet<[u64; 3]> = cells.iter().copied().collect();
                assert_eq!(unique.len(), cells.len(), "k {k} mask {mask:#08b}");
                assert_eq!(
                    cells.len() as u64,
                    block_surface_cells(k, mask),
                    "k {k} mask {mask:#08b}"
                );
            }
        }
    }

    #[test]
    fn normals_point_to_open_faces() {
        assert_eq!(normal_for_mask(0b00_1000), [0.0, 1.0, 0.0]);
        assert_eq!(normal_for_mask(0b00_0001), [-1.0, 0.0, 0.0]);
        // +x and +y open: diagonal
        let n = normal_for_mask(0b00_1010);
        assert!((n[0] - n[1]).abs() < 1e-12 && (n[0] - 0.5f64.sqrt()).abs() < 1e-12);
        // ±x open cancels: fall back to +x (the first open in the fallback order)
        assert_eq!(normal_for_mask(0b00_0011), [1.0, 0.0, 0.0]);
        // everything open: +y
        assert_eq!(normal_for_mask(0b11_1111), [0.0, 1.0, 0.0]);
    }

    #[test]
    fn deep_chunk_nesting_is_rejected_before_parsing() {
        let levels = 100_000usize;
        let mut b = b"VOX ".to_vec();
        b.extend(150u32.to_le_bytes());
        for l in 0..levels {
            b.extend(b"MAIN");
            b.extend(0u32.to_le_bytes());
            b.extend((((levels - l - 1) * 12) as u32).to_le_bytes());
        }
        assert_eq!(
            chunk_nesting_exceeds(&b, MAX_CHUNK_NESTING),
            Some(MAX_CHUNK_NESTING + 1)
        );
        let err = load_vox_bytes(&b, Path::new("nested.vox"), None).unwrap_err();
        assert!(matches!(err, VoxError::Parse { .. }), "{err}");
        assert!(err.to_string().contains("nested.vox"), "{err}");
    }
}
