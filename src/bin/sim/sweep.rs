//! `sim sweep`: parses the options and runs `svo_sim::studies::sweep::command`.

use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use svo_sim::studies::sweep;
use svo_sim::studies::sweep::command::SweepCommand;

/// Options of `sim sweep`.
#[derive(Args, Debug, Clone)]
pub struct SweepArgs {
    /// Configurations to sweep: a RON list of named datapath configurations,
    /// `[(name: "a", datapath: (...)), ...]`, each datapath naming only what it changes from
    /// the default (format of `sim datapath`). Default: the built-in list of docs/accuracy.md.
    #[arg(long, value_name = "FILE")]
    configs: Option<PathBuf>,
    /// Run only these configurations of the list (comma-separated names).
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    only: Vec<String>,
    /// A scene to sweep over (RON file, or `car` for the embedded car); repeatable.
    /// Default: `car` and `scenes/vox_traffic.ron` (run from the repository root).
    #[arg(long, value_name = "FILE")]
    scene: Vec<String>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 160)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 96)]
    height: u32,
    /// Frames per scene (the first traces every pixel, later ones reuse the hit buffer).
    #[arg(long, default_value_t = 4)]
    frames: u32,
    /// Octree depth of each scene's deepest asset (1-20; the others keep their offset to it,
    /// as `sim --depth`). Default: the scenes' own depths (the car's body is 10). The
    /// fixed-point model needs memory images, so the car stops at 12.
    #[arg(long)]
    depth: Option<u8>,
    /// Folder for sweep.csv, sweep.json, sweep_cycles.png and sweep_dsp.png (created if
    /// missing).
    #[arg(long, value_name = "DIR", default_value = "sweep_out")]
    out: PathBuf,
    /// Worker threads: configurations run on this many cores at once (default: all cores).
    /// The output is the same for every count.
    #[arg(long)]
    threads: Option<usize>,
    /// Largest `.vox` asset file read, MiB (1 to 65536); a larger one is refused without
    /// reading past the limit.
    #[arg(long, value_name = "MIB", default_value_t = crate::args::DEFAULT_VOX_MIB)]
    max_vox_mib: u64,
}

/// Runs `sim sweep`.
pub fn sweep_command(a: SweepArgs) -> Result<()> {
    if let Some(n) = a.threads {
        if n == 0 || n > 1024 {
            anyhow::bail!("--threads {n} is out of range (1 to 1024)");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("cannot start the worker threads")?;
    }
    sweep::command::run_command(&SweepCommand {
        configs: a.configs,
        only: a.only,
        scene: a.scene,
        width: a.width,
        height: a.height,
        frames: a.frames,
        depth: a.depth,
        out: a.out,
        max_vox_bytes: crate::args::vox_cap_bytes(a.max_vox_mib)?,
    })
}
