//! `sim stress`: parses the options and runs `svo_sim::studies::stress::command`.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use svo_sim::studies::stress;
use svo_sim::studies::stress::command::StressCommand;

/// Options of `sim stress`.
#[derive(Args, Debug, Clone)]
pub struct StressArgs {
    /// Run only this case (repeatable); default: all. Names as in docs/stability.md.
    #[arg(long = "case", value_name = "NAME")]
    cases: Vec<String>,
    /// Folder for stress.md, stress.csv and stress.json (created if missing).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// Runs `sim stress`.
pub fn stress_command(a: StressArgs) -> Result<()> {
    stress::command::run_command(&StressCommand {
        cases: a.cases,
        out: a.out,
    })
}
