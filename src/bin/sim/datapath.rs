//! `sim datapath`: prints a datapath configuration (the RON a user edits and passes back
//! with `--datapath`) with each unit's DSP48E2 count and every named error bound; the text is
//! `svo_sim::output::config_text`.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use svo_sim::output::config_text::datapath_text;
use svo_sim::run::config_files::load_datapath;

#[derive(Args, Debug)]
pub struct DatapathArgs {
    /// Configuration to print (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
}

/// Runs `sim datapath`.
pub fn datapath_command(a: DatapathArgs) -> Result<()> {
    print!("{}", datapath_text(&load_datapath(a.datapath.as_deref())?)?);
    Ok(())
}
