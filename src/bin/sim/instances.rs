//! `sim instances`: parses the options and runs `svo_sim::studies::instances::command`.

use anyhow::{bail, Result};
use clap::Args;
use std::path::PathBuf;
use svo_sim::studies::instances::command::{run_command, InstancesCommand};

/// Options of `sim instances`.
#[derive(Args, Debug, Clone)]
pub struct InstancesArgs {
    /// Instance counts of the frame-rate table (comma-separated).
    #[arg(long, value_delimiter = ',', default_values_t = [1u32, 10, 100, 1000, 10000])]
    counts: Vec<u32>,
    /// Largest count the flat scheme is simulated at; beyond it the table gives its
    /// sphere-lane bound.
    #[arg(long, default_value_t = 100)]
    flat_limit: u32,
    /// Image width and height of the frame-rate table.
    #[arg(long, default_value_t = 1280)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 768)]
    height: u32,
    /// Only the frame-rate table (no speed or reuse measurements).
    #[arg(long)]
    fps_only: bool,
    /// Folder for instances.md, instances.json and instances.png (created if missing).
    #[arg(long, value_name = "DIR", default_value = "instances")]
    out: PathBuf,
}

/// Runs `sim instances`.
pub fn instances_command(a: InstancesArgs) -> Result<()> {
    if a.counts.is_empty() || a.counts.iter().any(|&n| n == 0 || n > 65_535) {
        bail!("--counts: every count must be within 1 and 65535");
    }
    if !(1..=1280).contains(&a.width) || !(1..=768).contains(&a.height) {
        bail!("--width/--height: at most 1280×768 (the hardware frame)");
    }
    let md = run_command(&InstancesCommand {
        counts: a.counts,
        flat_limit: a.flat_limit,
        size: (a.width, a.height),
        depth: 6,
        fps_only: a.fps_only,
        out: a.out,
    })
    .map_err(anyhow::Error::msg)?;
    print!("{md}");
    Ok(())
}
