//! The RON scene file, exactly as written on disk (see `docs/scene-format.md`).
//!
//! These types only describe; [`super::Scene::from_file`] checks them and turns them into
//! the validated [`super::Scene`] the renderers use.

use crate::world::sdf::Shape;
use serde::{Deserialize, Serialize};

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Image width and height in pixels.
    pub resolution: (u32, u32),
    /// Number of frames to render (frame numbers 0 .. frames-1).
    pub frames: u32,
    /// Background colour (sRGB) of pixels whose ray hits nothing.
    #[serde(default = "default_background")]
    pub background: [u8; 3],
    /// The light used for the PNG shading.
    #[serde(default)]
    pub light: Light,
    /// Camera keyframes (at least one).
    pub camera: Vec<CameraKey>,
    /// Named assets: each becomes one SVO.
    pub assets: Vec<AssetSpec>,
    /// Placed, animated copies of assets.
    #[serde(default)]
    pub instances: Vec<InstanceSpec>,
    /// Procedural crowds the loader expands into more instances (`super::crowd`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub crowds: Vec<super::crowd::CrowdSpec>,
}

fn default_background() -> [u8; 3] {
    [40, 44, 52]
}

/// A directional light plus ambient term, for the PNG only (not part of the hit record).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    /// Direction the light travels (from the light toward the scene); need not be unit.
    pub direction: [f64; 3],
    /// Ambient fraction in 0..=1.
    #[serde(default = "default_ambient")]
    pub ambient: f64,
}

fn default_ambient() -> f64 {
    0.3
}

impl Default for Light {
    fn default() -> Self {
        Self {
            direction: [-0.4, -1.0, 0.3],
            ambient: default_ambient(),
        }
    }
}

/// One camera keyframe.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    /// Frame number of this key (may be fractional).
    pub frame: f64,
    /// Eye position (world, metres).
    pub position: [f64; 3],
    /// Point the camera looks at.
    pub look_at: [f64; 3],
    /// Up hint; must not be parallel to the view direction.
    #[serde(default = "default_up")]
    pub up: [f64; 3],
    /// Vertical field of view in degrees, in (0, 180).
    pub vfov_deg: f64,
}

fn default_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}

/// A named asset: one SVO.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssetSpec {
    /// Name that instances refer to.
    pub name: String,
    /// Octree depth (levels below the root, 1..=20). `sim --depth` shifts all assets so the
    /// deepest one gets that depth.
    pub depth: u8,
    /// Where the voxels come from.
    pub source: AssetSource,
}

/// The source of an asset's voxels.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum AssetSource {
    /// A procedural shape, voxelised on its surface.
    Sdf {
        /// The shape, in asset coordinates (metres, centred on the octree).
        shape: Shape,
        /// Half the side of the octree's cube; by default the shape's bounds plus 2 %.
        #[serde(default)]
        half_extent: Option<f64>,
    },
    /// A MagicaVoxel file: all its models composed through its scene graph, or one model.
    Vox {
        /// Path, relative to the scene file's folder.
        path: String,
        /// Edge length of one of the file's voxels in metres.
        voxel_size: f64,
        /// `Some(i)`: only the file's model `i` (0-based, in file order), untransformed.
        /// `None`: the scene graph's composition, or model 0 of a file of animation frames
        /// (several models, no scene graph), with a warning (`docs/scene-format.md` §5).
        #[serde(default)]
        model: Option<usize>,
    },
}

/// A placed, animated copy of an asset.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceSpec {
    /// Name for reports.
    pub name: String,
    /// Name of the asset.
    pub asset: String,
    /// The point of the (scaled) asset that sits at the keyframed translation and about which
    /// it rotates; by default the octree's centre.
    #[serde(default)]
    pub pivot: [f64; 3],
    /// Keyframes (at least one).
    pub keys: Vec<InstanceKey>,
}

/// One keyframe of an instance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceKey {
    /// Frame number of this key (may be fractional).
    pub frame: f64,
    /// World position of the pivot.
    #[serde(default)]
    pub translation: [f64; 3],
    /// Rotation in degrees about x, then y, then z (R = Rz·Ry·Rx), interpolated per angle
    /// linearly, so a wheel may turn several times between two keys.
    #[serde(default)]
    pub rotation_deg: [f64; 3],
    /// Scale per asset axis, applied before the rotation; each positive.
    #[serde(default = "unit_scale")]
    pub scale: [f64; 3],
}

fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}
