//! `sim hardware`: prints a hardware configuration of the cycle model (the RON a user edits
//! and passes back with `--hw`) with its resource estimate against the part; the text is
//! `svo_sim::output::config_text`.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use svo_sim::output::config_text::hardware_text;
use svo_sim::run::config_files::{load_datapath, load_hardware};

#[derive(Args, Debug)]
pub struct HardwareArgs {
    /// Configuration to print (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    hw: Option<PathBuf>,
    /// Datapath the hardware is checked against (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
}

/// Runs `sim hardware`.
pub fn hardware_command(a: HardwareArgs) -> Result<()> {
    let hw = load_hardware(a.hw.as_deref())?;
    let dp = load_datapath(a.datapath.as_deref())?;
    let (config, estimate) = hardware_text(&hw, &dp);
    print!("{config}");
    print!("{}", estimate?);
    Ok(())
}
