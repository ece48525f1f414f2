//! Scenes: the RON file, its validation, and the per-frame state the renderers consume.
//!
//! Pipeline position: the input of everything. A [`Scene`] is checked once when loaded, so
//! the renderers never see a NaN, a zero scale or a degenerate camera.

mod animate;
pub mod crowd;
mod default_scene;
pub mod format;

pub use animate::{Camera, FrameState, Pose};
pub use default_scene::DEFAULT_SCENE_RON;
pub use format::{AssetSource, AssetSpec, CameraKey, InstanceKey, InstanceSpec, Light, SceneFile};

use crate::error::SceneError;
use std::path::{Path, PathBuf};

/// Largest accepted image side.
pub const MAX_SIDE: u32 = 16_384;
/// Largest accepted number of pixels per frame (8192², 64 Mi): the hit buffer keeps one
/// 56-byte record per pixel (updated in place), about 3.5 GiB, plus the RGB image for the PNG.
pub const MAX_PIXELS: u64 = 8192 * 8192;
/// Largest accepted number of frames.
pub const MAX_FRAMES: u32 = 1_000_000;
/// Largest accepted number of instances (instance ids are 16 bits in the hit record).
pub const MAX_INSTANCES: usize = 65_535;

/// A validated scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file's content.
    pub file: SceneFile,
    /// Folder that relative asset paths are resolved against.
    pub base_dir: PathBuf,
    /// For each instance, the index of its asset in `file.assets`.
    pub instance_asset: Vec<usize>,
    /// Where the scene came from, for messages.
    pub origin: String,
    /// Largest `.vox` asset file read, in bytes (`--max-vox-mib`; default
    /// [`crate::input::DEFAULT_VOX_CAP_BYTES`]).
    pub max_vox_bytes: u64,
}

impl Scene {
    /// The embedded default scene (the animated car).
    ///
    /// ```
    /// let scene = svo_sim::world::scene::Scene::default_car().unwrap();
    /// assert_eq!(scene.file.instances.len(), 8);
    /// assert_eq!(scene.file.resolution, (640, 384));
    /// ```
    pub fn default_car() -> Result<Self, SceneError> {
        Self::from_ron(
            DEFAULT_SCENE_RON,
            "<embedded default scene>",
            Path::new("."),
        )
    }

    /// Loads and validates a scene file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let text = crate::input::read_text(path, crate::input::Cap::config("scene"))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_ron(&text, &path.display().to_string(), &base)
    }

    /// Parses and validates RON text; `origin` names it in messages.
    pub fn from_ron(text: &str, origin: &str, base_dir: &Path) -> Result<Self, SceneError> {
        let file: SceneFile = ron::from_str(text).map_err(|e| SceneError::Parse {
            origin: origin.to_string(),
            line: e.position.line,
            column: e.position.col,
            message: e.code.to_string(),
        })?;
        Self::from_file(file, origin, base_dir)
    }

    /// Validates an already parsed scene.
    pub fn from_file(
        mut file: SceneFile,
        origin: &str,
        base_dir: &Path,
    ) -> Result<Self, SceneError> {
        let bad = |what: String| SceneError::Invalid {
            origin: origin.to_string(),
            message: what,
        };
        // Crowd blocks become ordinary instances, validated below like hand-written ones.
        for (i, crowd) in std::mem::take(&mut file.crowds).into_iter().enumerate() {
            crowd
                .validate(&file, file.instances.len())
                .map_err(|e| bad(format!("crowds[{i}]: {e}")))?;
            let frames = file.frames;
            let first = file.instances.len();
            file.instances.extend(crowd.expand(frames, first));
        }
        let (w, h) = file.resolution;
        check_resolution(w, h).map_err(bad)?;
        if file.frames == 0 || file.frames > MAX_FRAMES {
            return Err(bad(format!(
                "frames: {} is out of range (1 to {MAX_FRAMES})",
                file.frames
            )));
        }
        let l = &file.light;
        if !l.direction.iter().all(|v| v.is_finite()) || l.direction.iter().all(|&v| v == 0.0) {
            return Err(bad(format!(
                "light.direction {:?} must be finite and non-zero",
                l.direction
            )));
        }
        if !(0.0..=1.0).contains(&l.ambient) {
            return Err(bad(format!(
                "light.ambient {} must be within 0 and 1",
                l.ambient
            )));
        }
        if file.camera.is_empty() {
            return Err(bad("camera: at least one keyframe is needed".into()));
        }
        check_key_frames(file.camera.iter().map(|k| k.frame), "camera").map_err(bad)?;
        for (i, k) in file.camera.iter().enumerate() {
            let p = format!("camera[{i}]");
            for (name, v) in [
                ("position", k.position),
                ("look_at", k.look_at),
                ("up", k.up),
            ] {
                if !v.iter().all(|x| x.is_finite()) {
                    return Err(bad(format!("{p}.{name} {v:?} must be finite")));
                }
            }
            if !(k.vfov_deg.is_finite() && k.vfov_deg > 0.0 && k.vfov_deg < 180.0) {
                return Err(bad(format!(
                    "{p}.vfov_deg {} must be within (0, 180)",
                    k.vfov_deg
                )));
            }
        }
        if file.assets.is_empty() {
            return Err(bad("assets: at least one asset is needed".into()));
        }
        for (i, a) in file.assets.iter().enumerate() {
            let p = format!("assets[{i}]({})", a.name);
            if a.name.trim().is_empty() {
                return Err(bad(format!(
                    "assets[{i}].name: an asset needs a non-empty name"
                )));
            }
            if file.assets[..i].iter().any(|b| b.name == a.name) {
                return Err(bad(format!("{p}: the name is used twice")));
            }
            if a.depth == 0 || a.depth > rtl_model::svo::MAX_DEPTH {
                return Err(bad(format!(
                    "{p}.depth {} is out of range (1 to {})",
                    a.depth,
                    rtl_model::svo::MAX_DEPTH
                )));
            }
            match &a.source {
                AssetSource::Sdf { shape, half_extent } => {
                    crate::world::sdf::Sdf::new(shape, &format!("{p}.shape")).map_err(bad)?;
                    if let Some(e) = half_extent {
                        if !(e.is_finite() && *e > 0.0) {
                            return Err(bad(format!(
                                "{p}.half_extent {e} must be positive and finite"
                            )));
                        }
                    }
                }
                AssetSource::Vox { voxel_size, .. } => {
                    if !(voxel_size.is_finite() && *voxel_size > 0.0) {
                        return Err(bad(format!(
                            "{p}.voxel_size {voxel_size} must be positive and finite"
                        )));
                    }
                }
            }
        }
        if file.instances.is_empty() {
            return Err(bad("instances: at least one instance is needed".into()));
        }
        if file.instances.len() > MAX_INSTANCES {
            return Err(bad(format!(
                "instances: {} is more than {MAX_INSTANCES}",
                file.instances.len()
            )));
        }
        let mut instance_asset = Vec::with_capacity(file.instances.len());
        for (i, inst) in file.instances.iter().enumerate() {
            let p = format!("instances[{i}]({})", inst.name);
            let Some(ai) = file.assets.iter().position(|a| a.name == inst.asset) else {
                let known: Vec<_> = file.assets.iter().map(|a| a.name.as_str()).collect();
                return Err(bad(format!(
                    "{p}.asset: unknown asset \"{}\" (known: {})",
                    inst.asset,
                    known.join(", ")
                )));
            };
            instance_asset.push(ai);
            if !inst.pivot.iter().all(|v| v.is_finite()) {
                return Err(bad(format!("{p}.pivot {:?} must be finite", inst.pivot)));
            }
            if inst.keys.is_empty() {
                return Err(bad(format!("{p}.keys: at least one keyframe is needed")));
            }
            check_key_frames(inst.keys.iter().map(|k| k.frame), &format!("{p}.keys"))
                .map_err(bad)?;
            for (j, k) in inst.keys.iter().enumerate() {
                let kp = format!("{p}.keys[{j}]");
                for (name, v) in [
                    ("translation", k.translation),
                    ("rotation_deg", k.rotation_deg),
                ] {
                    if !v.iter().all(|x| x.is_finite()) {
                        return Err(bad(format!("{kp}.{name} {v:?} must be finite")));
                    }
                }
                if !k.scale.iter().all(|s| s.is_finite() && *s > 0.0) {
                    return Err(bad(format!(
                        "{kp}.scale {:?}: every component must be positive and finite (zero, negative, NaN and inf scales are not invertible)",
                        k.scale
                    )));
                }
            }
        }
        let scene = Self {
            file,
            base_dir: base_dir.to_path_buf(),
            instance_asset,
            origin: origin.to_string(),
            max_vox_bytes: crate::input::DEFAULT_VOX_CAP_BYTES,
        };
        // Every frame's camera must be well formed, including interpolated ones.
        for f in 0..scene.file.frames {
            scene
                .camera_at(f)
                .map_err(|m| bad(format!("frame {f}: {m}")))?;
        }
        Ok(scene)
    }

    /// Overrides the resolution (checked like the file's).
    pub fn set_resolution(&mut self, w: u32, h: u32) -> Result<(), SceneError> {
        check_resolution(w, h).map_err(|m| SceneError::Invalid {
            origin: "command line".into(),
            message: m,
        })?;
        self.file.resolution = (w, h);
        Ok(())
    }

    /// Overrides the frame count (checked like the file's); cameras of the new frames are
    /// checked too.
    pub fn set_frames(&mut self, frames: u32) -> Result<(), SceneError> {
        let bad = |m: String| SceneError::Invalid {
            origin: "command line".into(),
            message: m,
        };
        if frames == 0 || frames > MAX_FRAMES {
            return Err(bad(format!(
                "--frames {frames} is out of range (1 to {MAX_FRAMES})"
            )));
        }
        self.file.frames = frames;
        for f in 0..frames {
            self.camera_at(f)
                .map_err(|m| bad(format!("frame {f}: {m}")))?;
        }
        Ok(())
    }
}

fn check_resolution(w: u32, h: u32) -> Result<(), String> {
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || u64::from(w) * u64::from(h) > MAX_PIXELS
    {
        return Err(format!(
            "resolution {w}x{h} is out of range (each side 1 to {MAX_SIDE}, at most {MAX_PIXELS} pixels)"
        ));
    }
    Ok(())
}

fn check_key_frames(frames: impl Iterator<Item = f64>, what: &str) -> Result<(), String> {
    let mut last = f64::NEG_INFINITY;
    for (i, f) in frames.enumerate() {
        if !f.is_finite() {
            return Err(format!("{what}[{i}].frame {f} must be finite"));
        }
        if f <= last {
            return Err(format!(
                "{what}[{i}].frame {f}: keyframes must be in strictly increasing frame order"
            ));
        }
        last = f;
    }
    Ok(())
}
