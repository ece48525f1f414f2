//! `sim fuzz`: parses the options and runs `svo_sim::studies::fuzz::command`.

use anyhow::{bail, Result};
use clap::Args;
use std::path::PathBuf;
use std::time::Duration;
use svo_sim::studies::fuzz::{self, FuzzCommand, Target};

/// Options of `sim fuzz`.
#[derive(Args, Debug, Clone)]
pub struct FuzzArgs {
    /// Parser to fuzz (repeatable): vox, scene, hardware, datapath; default: all four.
    #[arg(long = "target", value_name = "NAME")]
    targets: Vec<String>,
    /// Mutated inputs per target (each target's seeds run once more, unmutated, first).
    #[arg(long, default_value_t = 10_000, value_name = "N")]
    inputs: u64,
    /// Seed of the mutations; the same seed gives the same inputs.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// An input taking longer than this counts as a hang (and ends the run).
    #[arg(long, default_value_t = 10_000, value_name = "MS")]
    time_limit_ms: u64,
    /// Folder of .vox seed models.
    #[arg(long, default_value = "../shared/data/vox", value_name = "DIR")]
    vox_dir: PathBuf,
    /// Leave out .vox seeds larger than this (every mutated copy of a large model is slow).
    #[arg(long, default_value_t = 200_000, value_name = "BYTES")]
    max_vox_bytes: u64,
    /// Save each panicking or hanging input (and its message) into this folder.
    #[arg(long, value_name = "DIR")]
    save: Option<PathBuf>,
    /// Run one saved input through the single --target instead of fuzzing.
    #[arg(long, value_name = "FILE")]
    replay: Option<PathBuf>,
    /// No progress line on stderr.
    #[arg(short, long)]
    quiet: bool,
}

/// Runs `sim fuzz`.
pub fn fuzz_command(a: FuzzArgs) -> Result<()> {
    let mut targets = Vec::new();
    for name in &a.targets {
        match Target::from_name(name) {
            Some(t) => targets.push(t),
            None => {
                bail!("--target {name}: no such parser (known: vox, scene, hardware, datapath)")
            }
        }
    }
    fuzz::run_command(&FuzzCommand {
        targets,
        inputs: a.inputs,
        seed: a.seed,
        time_limit: Duration::from_millis(a.time_limit_ms),
        vox_dir: a.vox_dir,
        max_vox_bytes: a.max_vox_bytes,
        save: a.save,
        replay: a.replay,
        quiet: a.quiet,
    })
}
