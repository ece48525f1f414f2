//! Asset building: from a scene's asset specs to SVO memory images.
//!
//! Pipeline position: offline, before any frame. Procedural assets are voxelised from their
//! SDF ([`voxelize`]), `.vox` files are loaded ([`vox`]); both give Morton-ordered leaves that
//! [`rtl_model::svo::SvoImage::build`] packs into the memory image the walker reads.

pub mod vox;
pub mod voxelize;

use crate::error::AssetError;
use crate::scene::{AssetSource, Scene};
use crate::sdf::Sdf;
use rtl_model::svo::{LeafSet, SvoImage, MAX_DEPTH};
use std::time::Instant;

/// Largest node + attribute memory the builder will allocate for one asset, in bytes.
pub const MAX_IMAGE_BYTES: u64 = 8 << 30;

/// A built asset.
#[derive(Clone, Debug)]
pub struct Asset {
    /// Name from the scene.
    pub name: String,
    /// The memory image.
    pub image: SvoImage,
    /// Half the side of the octree's cube in metres (before instance scale).
    pub half_size: f64,
    /// Build time in seconds.
    pub build_s: f64,
    /// "sdf" or "vox".
    pub kind: &'static str,
}

/// Depth of each asset after a `--depth` override: the deepest asset gets `depth`, the others
/// keep their offset to it (so parts keep similar voxel sizes), clamped to 1..=MAX_DEPTH.
pub fn effective_depths(scene: &Scene, depth: Option<u8>) -> Result<Vec<u8>, AssetError> {
    let own: Vec<u8> = scene.file.assets.iter().map(|a| a.depth).collect();
    let Some(d) = depth else { return Ok(own) };
    if d == 0 || d > MAX_DEPTH {
        return Err(AssetError::Depth {
            asset: "--depth".into(),
            message: format!("depth {d} is out of range (1 to {MAX_DEPTH})"),
        });
    }
    let deepest = own.iter().copied().max().unwrap_or(d);
    Ok(own
        .iter()
        .map(|&a| {
            (i32::from(a) + i32::from(d) - i32::from(deepest)).clamp(1, i32::from(MAX_DEPTH)) as u8
        })
        .collect())
}

/// Builds every asset of the scene at the given depths (see [`effective_depths`]).
pub fn build_assets(scene: &Scene, depths: &[u8]) -> Result<Vec<Asset>, AssetError> {
    scene
        .file
        .assets
        .iter()
        .zip(depths)
        .map(|(spec, &depth)| {
            let start = Instant::now();
            let name = spec.name.clone();
            let (set, half_size, kind) = match &spec.source {
                AssetSource::Sdf { shape, half_extent } => {
                    let sdf =
                        Sdf::new(shape, &format!("assets({name}).shape")).map_err(|message| {
                            AssetError::Depth {
                                asset: name.clone(),
                                message,
                            }
                        })?;
                    let half = half_extent.unwrap_or_else(|| {
                        let (lo, hi) = sdf.bounds();
                        lo.abs().max(hi.abs()).max_element() * 1.02
                    });
                    check_budget(&sdf, half, depth, &name)?;
                    let leaves = voxelize::voxelize(&sdf, half, depth);
                    let set = LeafSet::from_sorted_codes(depth, leaves).map_err(|source| {
                        AssetError::Leaves {
                            asset: name.clone(),
                            source,
                        }
                    })?;
                    (set, half, "sdf")
                }
                AssetSource::Vox { path, voxel_size } => {
                    let full = scene.base_dir.join(path);
                    let v =
                        vox::load_vox(&full, Some(depth)).map_err(|source| AssetError::Vox {
                            asset: name.clone(),
                            source,
                        })?;
                    let max_dim = v.grid_dims.iter().copied().max().unwrap_or(1).max(2);
                    let needed = 32 - (max_dim - 1).leading_zeros();
                    let half = voxel_size * f64::from(1u32 << needed) * 0.5;
                    (v.leaves, half, "vox")
                }
            };
            let image = SvoImage::build(&set).map_err(|source| AssetError::Image {
                asset: name.clone(),
                source,
            })?;
            Ok(Asset {
                name,
                image,
                half_size,
                build_s: start.elapsed().as_secs_f64(),
                kind,
            })
        })
        .collect()
}

/// Refuses depths whose memory image would not fit [`MAX_IMAGE_BYTES`]: a surface's leaf
/// count grows 4× per level, so the count at a shallower probe depth predicts it.
fn check_budget(sdf: &Sdf, half: f64, depth: u8, name: &str) -> Result<(), AssetError> {
    const PROBE: u8 = 8;
    if depth <= PROBE + 2 {
        return Ok(());
    }
    let probe = voxelize::voxelize(sdf, half, PROBE).len() as f64;
    let leaves = probe * 4f64.powi(i32::from(depth - PROBE));
    // 4 bytes of leaf slot + 8 of attributes per leaf, plus about 1/3 word of descriptors.
    let bytes = leaves * (12.0 + 4.0 / 3.0);
    if bytes > MAX_IMAGE_BYTES as f64 {
        return Err(AssetError::Depth {
            asset: name.to_string(),
            message: format!(
                "depth {depth} would need about {:.2e} leaves and {:.1} GiB of SVO memory, more than the {} GiB limit; use a smaller --depth",
                leaves,
                bytes / f64::from(1u32 << 30),
                MAX_IMAGE_BYTES >> 30
            ),
        });
    }
    Ok(())
}
