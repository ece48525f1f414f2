//! `sim drift`: parses the options and runs `svo_sim::studies::drift::command`.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use svo_sim::studies::drift;
use svo_sim::studies::drift::command::DriftCommand;

/// Options of `sim drift`.
#[derive(Args, Debug, Clone)]
pub struct DriftArgs {
    /// Frames of the animation (at least 2).
    #[arg(long, default_value_t = 10_000)]
    frames: u32,
    /// Image width in pixels.
    #[arg(long, default_value_t = 32)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 24)]
    height: u32,
    /// Octree depth of the spinning part (1-12).
    #[arg(long, default_value_t = 7)]
    depth: u8,
    /// Folder for drift.csv, drift.json and drift.png (created if missing).
    #[arg(long, default_value = "drift_out")]
    out: PathBuf,
}

/// Runs `sim drift`.
pub fn drift_command(a: DriftArgs) -> Result<()> {
    drift::command::run_command(&DriftCommand {
        frames: a.frames,
        width: a.width,
        height: a.height,
        depth: a.depth,
        out: a.out,
    })
}
