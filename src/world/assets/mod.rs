//! Asset building: from a scene's asset specs to SVO memory images.
//!
//! Pipeline position: offline, before any frame. Procedural assets are voxelised from their
//! SDF ([`voxelize`]), `.vox` files are loaded ([`vox`]); both give Morton-ordered leaves that
//! [`rtl_model::svo::SvoImage::build`] packs into the memory image the walker reads.

pub mod vox;
pub mod voxelize;

use crate::error::AssetError;
use crate::world::scene::{AssetSource, Scene};
use crate::world::sdf::Sdf;
use rtl_model::svo::{ImageLayout, LeafSet, SvoImage, SvoStats, MAX_DEPTH};
use std::time::Instant;
use voxelize::SdfOctree;

/// SDF assets whose estimated leaf count exceeds this are not materialised but walked
/// implicitly (64 M leaves ≈ 0.9 GB of image and a build of tens of seconds on 2 cores).
pub const MAX_MATERIALISED_LEAVES: f64 = 64e6;

/// An asset's octree: a memory image, or an SDF walked on demand when the image would be
/// too large to build (the same voxels either way, see [`crate::models::reference::octree`]).
#[derive(Clone, Debug)]
pub enum AssetTree {
    /// The packed memory image the hardware reads.
    Image(SvoImage),
    /// An SDF octree evaluated during the walk.
    Implicit(SdfOctree),
}

/// How SDF assets are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Materialise {
    /// A memory image unless it would exceed [`MAX_MATERIALISED_LEAVES`].
    #[default]
    Auto,
    /// Always walk SDF assets implicitly (`sim --implicit`).
    Never,
}

/// A built asset.
#[derive(Clone, Debug)]
pub struct Asset {
    /// Name from the scene.
    pub name: String,
    /// The octree.
    pub tree: AssetTree,
    /// Statistics: of the image, or for an implicit tree the estimated leaf count only.
    pub stats: SvoStats,
    /// Half the side of the octree's cube in metres (before instance scale).
    pub half_size: f64,
    /// Build time in seconds.
    pub build_s: f64,
    /// "sdf", "sdf-implicit" or "vox".
    pub kind: &'static str,
}

impl Asset {
    /// The memory image, if the asset has one.
    pub fn image(&self) -> Option<&SvoImage> {
        match &self.tree {
            AssetTree::Image(i) => Some(i),
            AssetTree::Implicit(_) => None,
        }
    }

    /// Octree depth.
    pub fn depth(&self) -> u8 {
        self.stats.depth
    }
}

/// Depth of each asset after a `--depth` override: the deepest asset gets `depth`, the others
/// keep their offset to it (so parts keep similar voxel sizes), clamped to 1..=MAX_DEPTH.
pub fn effective_depths(scene: &Scene, depth: Option<u8>) -> Result<Vec<u8>, AssetError> {
    let own: Vec<u8> = scene.file.assets.iter().map(|a| a.depth).collect();
    let Some(d) = depth else { return Ok(own) };
    if d == 0 || d > MAX_DEPTH {
        return Err(AssetError::DepthOption(d));
    }
    let deepest = own.iter().copied().max().unwrap_or(d);
    Ok(own
        .iter()
        .map(|&a| {
            (i32::from(a) + i32::from(d) - i32::from(deepest)).clamp(1, i32::from(MAX_DEPTH)) as u8
        })
        .collect())
}

/// Builds every asset of the scene at the given depths (see [`effective_depths`]), images in
/// the default layout.
pub fn build_assets(
    scene: &Scene,
    depths: &[u8],
    mode: Materialise,
) -> Result<Vec<Asset>, AssetError> {
    build_assets_in(scene, depths, mode, ImageLayout::default())
}

/// Builds every asset of the scene at the given depths, images in `layout` (`sim
/// --image-layout`: the layout moves node addresses, so the cycle model's memory traffic, not
/// the pixels).
pub fn build_assets_in(
    scene: &Scene,
    depths: &[u8],
    mode: Materialise,
    layout: ImageLayout,
) -> Result<Vec<Asset>, AssetError> {
    scene
        .file
        .assets
        .iter()
        .zip(depths)
        .enumerate()
        .map(|(index, (spec, &depth))| {
            let start = Instant::now();
            let name = spec.name.clone();
            let image = |set: &LeafSet| {
                SvoImage::build_with(set, layout).map_err(|source| AssetError::Image {
                    asset: name.clone(),
                    source,
                })
            };
            let (tree, half_size, kind) = match &spec.source {
                AssetSource::Sdf { shape, half_extent } => {
                    let sdf = Sdf::new(shape, &format!("assets[{index}]({name}).shape")).map_err(
                        |message| AssetError::Depth {
                            asset: name.clone(),
                            message,
                        },
                    )?;
                    let half = half_extent.unwrap_or_else(|| {
                        let (lo, hi) = sdf.bounds();
                        lo.abs().max(hi.abs()).max_element() * 1.02
                    });
                    let octree = SdfOctree::new(sdf, half, depth);
                    // Shallow trees always fit: count only when it decides something or the
                    // implicit tree's report needs it.
                    let small = depth <= ESTIMATE_PROBE + 1;
                    let estimate = if small && mode == Materialise::Auto {
                        0.0
                    } else {
                        estimate_leaves(&octree)
                    };
                    if mode == Materialise::Never || estimate > MAX_MATERIALISED_LEAVES {
                        let stats = SvoStats {
                            depth,
                            leaves: estimate as u64,
                            ..SvoStats::default()
                        };
                        let a = Asset {
                            name: name.clone(),
                            tree: AssetTree::Implicit(octree),
                            stats,
                            half_size: half,
                            build_s: start.elapsed().as_secs_f64(),
                            kind: "sdf-implicit",
                        };
                        return Ok(a);
                    }
                    let set =
                        LeafSet::from_sorted_codes(depth, octree.leaves()).map_err(|source| {
                            AssetError::Leaves {
                                asset: name.clone(),
                                source,
                            }
                        })?;
                    (image(&set)?, half, "sdf")
                }
                AssetSource::Vox {
                    path,
                    voxel_size,
                    model,
                } => {
                    let full = scene.base_dir.join(path);
                    let v = vox::load_vox_model(&full, Some(depth), *model, scene.max_vox_bytes)
                        .map_err(|source| AssetError::Vox {
                            asset: name.clone(),
                            source,
                        })?;
                    if let Some(notice) = &v.notice {
                        // One line whatever the caller: a choice made for the user is never
                        // silent, and no caller of build_assets may forget to print it.
                        eprintln!("warning: asset \"{name}\": {notice}");
                    }
                    let max_dim = v.grid_dims.iter().copied().max().unwrap_or(1).max(2);
                    let needed = 32 - (max_dim - 1).leading_zeros();
                    let half = voxel_size * f64::from(1u32 << needed) * 0.5;
                    (image(&v.leaves)?, half, "vox")
                }
            };
            let stats = tree.stats().clone();
            Ok(Asset {
                name,
                tree: AssetTree::Image(tree),
                stats,
                half_size,
                build_s: start.elapsed().as_secs_f64(),
                kind,
            })
        })
        .collect()
}

/// Depth of the probe build behind [`estimate_leaves`].
pub const ESTIMATE_PROBE: u8 = 9;

/// Leaf count of an SDF octree: exact (a full count) up to depth `ESTIMATE_PROBE + 1`, else
/// predicted from a build at `ESTIMATE_PROBE`, since a surface's leaf count grows about 4× per
/// level.
pub fn estimate_leaves(octree: &SdfOctree) -> f64 {
    let depth = octree.depth();
    if depth <= ESTIMATE_PROBE + 1 {
        return octree.leaves().len() as f64;
    }
    let probe = SdfOctree::new(octree.sdf().clone(), octree.half(), ESTIMATE_PROBE)
        .leaves()
        .len() as f64;
    probe * 4f64.powi(i32::from(depth - ESTIMATE_PROBE))
}
