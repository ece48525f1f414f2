//! `sim explore`: parses the options and runs `svo_sim::studies::explore::command`.

use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use svo_sim::studies::explore::command::{run_command, ExploreCommand};

/// Options of `sim explore`.
#[derive(Args, Debug, Clone)]
pub struct ExploreArgs {
    /// The space: a RON file of hardware fields by their path in the hardware file, each a
    /// list or a range of values, and the scenes to run every point on (docs/explore.md;
    /// example: configs/explore_default.ron).
    #[arg(value_name = "SPACE")]
    space: PathBuf,
    /// Folder for explore.csv, explore.json and the five explore_*.png fronts (created if
    /// missing).
    #[arg(long, value_name = "DIR", default_value = "explore_out")]
    out: PathBuf,
    /// Worker threads: points run on this many cores at once (default: all cores). The
    /// files are the same for every count.
    #[arg(long)]
    threads: Option<usize>,
    /// Largest `.vox` asset file read, MiB (1 to 65536); a larger one is refused without
    /// reading past the limit.
    #[arg(long, value_name = "MIB", default_value_t = crate::args::DEFAULT_VOX_MIB)]
    max_vox_mib: u64,
}

/// Runs `sim explore`.
pub fn explore_command(a: ExploreArgs) -> Result<()> {
    if let Some(n) = a.threads {
        if n == 0 || n > 1024 {
            anyhow::bail!("--threads {n} is out of range (1 to 1024)");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("cannot start the worker threads")?;
    }
    run_command(&ExploreCommand {
        space: a.space,
        out: a.out,
        max_vox_bytes: crate::args::vox_cap_bytes(a.max_vox_mib)?,
    })
}
