//! Arguments shared by several commands: the scene and its overrides, the model, and the
//! helpers that turn them into a validated scene and a worker pool.

use anyhow::{Context, Result};
use clap::Args;
use rtl_model::svo::ImageLayout;
use std::path::PathBuf;
use svo_sim::world::assets::Materialise;
use svo_sim::world::scene::Scene;

/// The scene and how to render it: file, resolution, frames, depth, threads.
#[derive(Args, Debug, Clone)]
pub struct SceneArgs {
    /// Scene file (RON, see docs/scene-format.md); default: the embedded animated car.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Image width in pixels (default: the scene's).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long)]
    pub height: Option<u32>,
    /// Number of frames (default: the scene's).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Octree depth of the deepest asset (1-20); the others keep their offset to it
    /// (default: the scene's depths; the car's body is 10).
    #[arg(long)]
    pub depth: Option<u8>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Walk procedural (SDF) assets on demand instead of building memory images (same
    /// voxels; automatic when an image would exceed 64 M leaves, e.g. the car at depth 13+).
    #[arg(long)]
    pub implicit: bool,
    /// Largest `.vox` asset file read, MiB (1 to 65536); a larger one is refused without
    /// reading past the limit.
    #[arg(long, value_name = "MIB", default_value_t = DEFAULT_VOX_MIB)]
    pub max_vox_mib: u64,
    /// How each memory image orders its words: the top 8 levels first, level by level, so the
    /// on-chip levels are one prefix (the default), or depth first throughout (the layout
    /// before issue 29, for figures measured on it). Pixels are the same; node addresses,
    /// hence the cycle model's memory traffic, are not (docs/svo-format.md §4).
    #[arg(long, value_enum, default_value_t = LayoutArg::TopLevelsFirst)]
    pub image_layout: LayoutArg,
}

/// `--image-layout`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum LayoutArg {
    /// The top 8 levels first, level by level, then each subtree depth first.
    TopLevelsFirst,
    /// Every subtree depth first after its parent's group (before issue 29).
    DepthFirst,
}

impl From<LayoutArg> for ImageLayout {
    fn from(a: LayoutArg) -> Self {
        match a {
            LayoutArg::TopLevelsFirst => ImageLayout::TopLevelsFirst,
            LayoutArg::DepthFirst => ImageLayout::DepthFirst,
        }
    }
}

/// Default of `--max-vox-mib`.
pub const DEFAULT_VOX_MIB: u64 = svo_sim::input::DEFAULT_VOX_CAP_BYTES >> 20;

/// `--max-vox-mib` in bytes, or why it is out of range.
pub fn vox_cap_bytes(mib: u64) -> Result<u64> {
    if !(1..=65536).contains(&mib) {
        anyhow::bail!("--max-vox-mib {mib} is out of range (1 to 65536)");
    }
    Ok(mib << 20)
}

impl SceneArgs {
    /// The scene, with `defaults` (resolution, frames) applied where no option is given.
    pub fn load(&self, defaults: (Option<(u32, u32)>, Option<u32>)) -> Result<Scene> {
        let mut scene = match &self.scene {
            Some(p) => Scene::load(p)?,
            None => Scene::default_car()?,
        };
        scene.max_vox_bytes = vox_cap_bytes(self.max_vox_mib)?;
        let (w0, h0) = defaults.0.unwrap_or(scene.file.resolution);
        let (w, h) = (self.width.unwrap_or(w0), self.height.unwrap_or(h0));
        if (w, h) != scene.file.resolution {
            scene.set_resolution(w, h)?;
        }
        if let Some(f) = self.frames.or(defaults.1) {
            scene.set_frames(f)?;
        }
        Ok(scene)
    }

    /// How SDF assets are stored.
    pub fn materialise(&self) -> Materialise {
        if self.implicit {
            Materialise::Never
        } else {
            Materialise::Auto
        }
    }

    /// Starts the worker pool with `--threads` workers (all cores without it).
    pub fn set_threads(&self) -> Result<()> {
        if let Some(n) = self.threads {
            if n == 0 || n > 1024 {
                anyhow::bail!("--threads {n} is out of range (1 to 1024)");
            }
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build_global()
                .context("cannot start the worker threads")?;
        }
        Ok(())
    }
}

/// Which model renders.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelArg {
    /// The cycle-accurate pipeline (bit-exact with `fixed`, timed clock by clock).
    Cycle,
    /// The functional fixed-point datapath.
    Fixed,
    /// The f64 reference.
    Reference,
}

/// Parses `FROM:TO` with FROM ≤ TO.
pub fn parse_window(flag: &str, text: &str) -> Result<(u64, u64)> {
    let (a, b) = text
        .split_once(':')
        .ok_or_else(|| anyhow::anyhow!("{flag} {text:?}: expected FROM:TO"))?;
    let a: u64 = a
        .trim()
        .parse()
        .with_context(|| format!("{flag} {text:?}: FROM is not a number"))?;
    let b: u64 = b
        .trim()
        .parse()
        .with_context(|| format!("{flag} {text:?}: TO is not a number"))?;
    if a > b {
        anyhow::bail!("{flag} {text:?}: FROM is after TO");
    }
    Ok((a, b))
}
