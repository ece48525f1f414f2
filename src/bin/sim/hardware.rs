//! `sim hardware`: prints a hardware configuration of the cycle model (the RON a user edits
//! and passes back with `--hw`) with its resource estimate against the part; the text is
//! `svo_sim::output::config_text`. With `--synth` it also synthesises the RTL units with Yosys
//! (`svo_sim::studies::synthesis`) and prints them beside the estimate, with the logic levels
//! and the clock verdict; a line per unit as it starts and finishes goes to stderr. With
//! `--sv-package FILE` it writes the configuration as a SystemVerilog package instead
//! (`rtl_model::cycle::hw_package`), the RTL's copy of the same numbers.

use anyhow::{bail, Context, Result};
use clap::Args;
use rtl_model::cost::timing;
use rtl_model::cycle::hw_package::hardware_package;
use std::path::{Path, PathBuf};
use svo_sim::output::config_text::hardware_text;
use svo_sim::output::writer::write_whole;
use svo_sim::run::config_files::{load_datapath, load_hardware};
use svo_sim::studies::synthesis::{self, text, SynthOptions};

#[derive(Args, Debug)]
pub struct HardwareArgs {
    /// Configuration to print (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    hw: Option<PathBuf>,
    /// Datapath the hardware is checked against (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
    /// Also synthesise the RTL units (testbench/synth/units.tsv) with Yosys and print them
    /// beside the estimate; fails when yosys is missing or a unit's DSP48E2 count differs
    /// from the estimate without a recorded reason.
    #[arg(long)]
    synth: bool,
    /// With --synth: only these units (comma-separated).
    #[arg(long, value_name = "UNITS", value_delimiter = ',', requires = "synth")]
    units: Vec<String>,
    /// With --synth: the repository holding testbench/ and vectors/.
    #[arg(long, value_name = "DIR", default_value = ".", requires = "synth")]
    repo: PathBuf,
    /// With --synth: cache of synthesis results (default: REPO/target/synth-cache); a unit
    /// whose files, script and Yosys version are unchanged is not synthesised again.
    #[arg(long, value_name = "DIR", requires = "synth")]
    synth_cache: Option<PathBuf>,
    /// With --synth: units synthesised at a time.
    #[arg(long, value_name = "N", default_value_t = 2, requires = "synth")]
    jobs: usize,
    /// Write the configuration as a SystemVerilog package to FILE (`-`: standard output)
    /// instead of printing it: every field a constant named by its path (e.g.
    /// WALKER_POOL_WALKERS), then the derived WALK_LANES, RAY_SLOTS, CHECK_LATENCY
    /// (testbench/README.md, "The hardware package").
    #[arg(long, value_name = "FILE", conflicts_with = "synth")]
    sv_package: Option<PathBuf>,
    /// Print the logic levels of a mapped Yosys JSON netlist (from `synth_xilinx` or
    /// `synth_ecp5`) by the clock rule instead: the slowest stages with the clock each
    /// allows (testbench/synth/pnr_ecp5.sh sets it beside nextpnr's figure).
    #[arg(long, value_name = "JSON", conflicts_with_all = ["synth", "sv_package"])]
    levels: Option<PathBuf>,
    /// With --levels: the netlist's top module.
    #[arg(long, value_name = "MODULE", requires = "levels")]
    top: Option<String>,
    /// With --levels: the clock rule, `xcup-2` (UltraScale+ −2, the model's) or `ecp5-6`
    /// (Lattice ECP5, speed grade 6).
    #[arg(
        long,
        value_name = "NAME",
        default_value = "xcup-2",
        requires = "levels"
    )]
    rule: String,
    /// With --levels: stages shown.
    #[arg(long, value_name = "N", default_value_t = 8, requires = "levels")]
    stages: usize,
    /// With --levels: also print each shown stage's slowest path, from the register it
    /// starts at, as the named nets it passes and the cells between them.
    #[arg(long, requires = "levels")]
    path: bool,
    /// With --sv-package: the package's name.
    #[arg(
        long,
        value_name = "NAME",
        default_value = "svo_hw_pkg",
        requires = "sv_package"
    )]
    package_name: String,
}

/// Runs `sim hardware`.
pub fn hardware_command(a: HardwareArgs) -> Result<()> {
    if let Some(json) = &a.levels {
        return levels_command(json, a.top.as_deref(), &a.rule, a.stages, a.path);
    }
    let hw = load_hardware(a.hw.as_deref())?;
    let dp = load_datapath(a.datapath.as_deref())?;
    if let Some(out) = &a.sv_package {
        let source = a.hw.as_ref().map_or_else(
            || "the default hardware".to_string(),
            |p| {
                p.file_name()
                    .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
            },
        );
        // The datapath must agree with the hardware (the sorter's lanes), as for a run.
        if let Err(m) = hw.validate_for(&dp) {
            bail!("the hardware does not fit the datapath: {m}");
        }
        let text = hardware_package(&hw, &a.package_name, &source)?;
        if out.as_os_str() == "-" {
            print!("{text}");
        } else {
            write_whole(out, text.as_bytes())
                .with_context(|| format!("writing {}", out.display()))?;
        }
        return Ok(());
    }
    let (config, estimate) = hardware_text(&hw, &dp);
    print!("{config}");
    print!("{}", estimate?);
    if !a.synth {
        return Ok(());
    }
    let list = a.repo.join("testbench/synth/units.tsv");
    if !list.is_file() {
        bail!(
            "{} not found: run from the repository root or pass --repo",
            list.display()
        );
    }
    let mut o = SynthOptions::new(
        &a.repo,
        &a.synth_cache
            .unwrap_or_else(|| a.repo.join("target/synth-cache")),
    );
    o.units = a.units;
    o.jobs = a.jobs;
    // A line per unit as it starts and finishes, on stderr: the whole run takes minutes.
    let units =
        synthesis::synthesise_with_progress(&o, &|p| eprintln!("{}", text::progress_line(p)))
            .context("sim hardware --synth")?;
    print!(
        "{}",
        text::synthesis_text(&hw, &dp, &units, &o.rule, hw.clock_mhz)
    );
    let bad = text::dsp_mismatches(&hw, &dp, &units);
    if !bad.is_empty() {
        bail!(
            "{} unit(s) differ from the DSP48E2 estimate without a recorded reason: {}",
            bad.len(),
            bad.join("; ")
        );
    }
    Ok(())
}

/// `sim hardware --levels JSON --top MODULE --rule NAME`: the netlist's slowest stages.
fn levels_command(
    json: &Path,
    top: Option<&str>,
    rule: &str,
    shown: usize,
    path: bool,
) -> Result<()> {
    let Some(top) = top else {
        bail!("--levels needs --top MODULE (the netlist's top module)");
    };
    let Some(r) = timing::rule_named(rule) else {
        let names: Vec<&str> = timing::RULES.iter().map(|r| r.name).collect();
        bail!(
            "--rule {rule}: no such clock rule (known: {})",
            names.join(", ")
        );
    };
    let text = std::fs::read_to_string(json)
        .with_context(|| format!("reading the netlist {}", json.display()))?;
    let stages = synthesis::netlist::stage_paths(&text, top, r)
        .map_err(|m| anyhow::anyhow!("{}: {m}", json.display()))?;
    print!(
        "{}",
        text::levels_text(&json.display().to_string(), top, &stages, &r, shown)
    );
    if path {
        print!("{}", text::paths_text(&stages, shown));
    }
    Ok(())
}
