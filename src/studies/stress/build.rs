//! Building blocks of the stress cases: assets from explicit voxels or procedural shapes,
//! cameras with exactly chosen bases, poses, and the scene shell the renderers read.
//!
//! Pipeline position: input side of `sim stress`. The cases bypass keyframe interpolation on
//! purpose: a camera basis or a pose is written down exactly (down to the sign of a zero) and
//! handed to both models as the frame state, so each extreme is hit exactly rather than
//! approximately.

use crate::world::assets::voxelize::voxelize;
use crate::world::assets::{Asset, AssetTree};
use crate::world::scene::{
    AssetSource, AssetSpec, Camera, CameraKey, FrameState, InstanceKey, InstanceSpec, Light, Pose,
    Scene, SceneFile,
};
use crate::world::sdf::{Sdf, Shape};
use glam::{DMat3, DVec3};
use rtl_model::svo::{LeafAttr, LeafSet, SvoImage};
use std::path::Path;

/// A frame to stress both models with.
pub struct CaseInput {
    /// The scene shell (resolution, instance → asset).
    pub scene: Scene,
    /// Built assets.
    pub assets: Vec<Asset>,
    /// The exact camera and poses.
    pub state: FrameState,
}

/// A leaf colour from its coordinates, so neighbouring leaves differ in the pictures.
fn attr(c: [u32; 3]) -> LeafAttr {
    LeafAttr::new(
        [
            60 + (c[0] * 37 % 180) as u8,
            60 + (c[1] * 53 % 180) as u8,
            60 + (c[2] * 71 % 180) as u8,
            255,
        ],
        [0.0, 1.0, 0.0],
    )
}

/// An asset from explicit leaf coordinates at `depth`, in a cube of half-size `half` metres.
pub fn voxel_asset(
    name: &str,
    depth: u8,
    half: f64,
    coords: impl IntoIterator<Item = [u32; 3]>,
) -> Result<Asset, String> {
    let set = LeafSet::from_coords(depth, coords.into_iter().map(|c| (c, attr(c))))
        .map_err(|e| format!("{name}: {e}"))?;
    image_asset(name, &set, half)
}

/// An asset from a procedural shape voxelised at `depth` in a cube of half-size `half`.
pub fn shape_asset(name: &str, shape: &Shape, half: f64, depth: u8) -> Result<Asset, String> {
    let sdf = Sdf::new(shape, name)?;
    let set = LeafSet::from_sorted_codes(depth, voxelize(&sdf, half, depth))
        .map_err(|e| format!("{name}: {e}"))?;
    image_asset(name, &set, half)
}

fn image_asset(name: &str, set: &LeafSet, half: f64) -> Result<Asset, String> {
    let img = SvoImage::build(set).map_err(|e| format!("{name}: {e}"))?;
    let stats = img.stats().clone();
    Ok(Asset {
        name: name.into(),
        tree: AssetTree::Image(img),
        stats,
        half_size: half,
        build_s: 0.0,
        kind: "sdf",
    })
}

/// A pinhole camera at `position` looking at `target` (up hint +y unless parallel), with
/// the vertical field of view `vfov_deg`.
pub fn look_at(position: DVec3, target: DVec3, up: DVec3, vfov_deg: f64) -> Camera {
    let forward = (target - position).normalize();
    let right = forward.cross(up).normalize();
    Camera {
        position,
        forward,
        right,
        up: right.cross(forward),
        tan_half_vfov: (vfov_deg.to_radians() * 0.5).tan(),
    }
}

/// An instance pose: rotation R = Rz·Ry·Rx of the angles (degrees), octree centre, half
/// extents per axis.
pub fn pose(rotation_deg: [f64; 3], centre: DVec3, half_extent: DVec3) -> Pose {
    Pose {
        world_from_local: crate::world::sdf::rotation_xyz_deg(rotation_deg),
        centre,
        half_extent,
    }
}

/// The identity pose at `centre` with half extents `half`.
pub fn upright(centre: DVec3, half: DVec3) -> Pose {
    Pose {
        world_from_local: DMat3::IDENTITY,
        centre,
        half_extent: half,
    }
}

/// The case input: a scene shell of `size` whose instance k shows asset `instance_asset[k]`,
/// with the given camera and poses (one per instance).
pub fn case(
    size: (u32, u32),
    assets: Vec<Asset>,
    instance_asset: &[usize],
    camera: Camera,
    poses: Vec<Pose>,
) -> Result<CaseInput, String> {
    if poses.len() != instance_asset.len() {
        return Err("one pose per instance".into());
    }
    let file = SceneFile {
        resolution: size,
        frames: 1,
        background: [40, 44, 52],
        light: Light::default(),
        // Only the renderers' frame state is used; the file's camera must merely be valid.
        camera: vec![CameraKey {
            frame: 0.0,
            position: [0.0, 0.0, 5.0],
            look_at: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            vfov_deg: 40.0,
        }],
        assets: assets
            .iter()
            .map(|a| AssetSpec {
                name: a.name.clone(),
                depth: a.depth(),
                source: AssetSource::Sdf {
                    shape: Shape::Sphere { radius: 1.0 },
                    half_extent: Some(a.half_size),
                },
            })
            .collect(),
        instances: instance_asset
            .iter()
            .enumerate()
            .map(|(k, &a)| InstanceSpec {
                name: format!("i{k}"),
                asset: assets[a].name.clone(),
                pivot: [0.0; 3],
                keys: vec![InstanceKey {
                    frame: 0.0,
                    translation: [0.0; 3],
                    rotation_deg: [0.0; 3],
                    scale: [1.0; 3],
                }],
            })
            .collect(),
        crowds: Vec::new(),
    };
    let scene =
        Scene::from_file(file, "<stress case>", Path::new(".")).map_err(|e| e.to_string())?;
    Ok(CaseInput {
        scene,
        assets,
        state: FrameState {
            frame: 0,
            camera,
            poses,
        },
    })
}
