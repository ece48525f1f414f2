//! `sim` without a subcommand: the main job. Parses the run's options into a
//! [`RunConfig`], elaborates the pipeline for the scene (cycle model), runs it and prints
//! the text of `svo_sim::output::text`.

use crate::args::{parse_window, ModelArg, SceneArgs};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use svo_sim::models::cycle::lift::{lift, lift_datapath, nothing_to_lift};
use svo_sim::models::cycle::sample::SampleConfig;
use svo_sim::models::cycle::waves::WaveWindow;
use svo_sim::models::reference::RenderOptions;
use svo_sim::output::report::CycleSummary;
use svo_sim::output::text;
use svo_sim::run::config_files::{check_pair, load_datapath, load_hardware};
use svo_sim::run::elaborate::elaborate;
use svo_sim::run::{run, Model, RunConfig, VcdRequest};

#[derive(Args, Debug)]
pub struct RunArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Folder for the PNG frames.
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
    /// Do not write PNGs.
    #[arg(long)]
    no_png: bool,
    /// Write the JSON report here (`-`: standard output; the console text then goes to
    /// stderr). A device, FIFO or symlink is written, never replaced (docs/report.md §1.6).
    #[arg(long, value_name = "FILE")]
    report_json: Option<PathBuf>,
    /// Trace every pixel of every frame (no reuse across frames).
    #[arg(long)]
    no_hit_buffer: bool,
    /// Walk every candidate instead of stopping at the first certain hit (all three models;
    /// images unchanged).
    #[arg(long)]
    no_early_termination: bool,
    /// Make every instance a candidate of every ray, whether its bounding sphere is pierced or
    /// not (all three models; images unchanged; docs/paper.md §2).
    #[arg(long)]
    no_culling: bool,
    /// Walk the candidates in instance order instead of front to back (early termination then
    /// cannot apply; all three models; images unchanged; docs/paper.md §2).
    #[arg(long)]
    no_sort: bool,
    /// Write every pixel's hit record here (binary, or CSV if the name ends in .csv;
    /// format in docs/hit-dump.md; `-`: standard output, binary).
    #[arg(long, value_name = "FILE")]
    dump_hits: Option<PathBuf>,
    /// Print only the summary.
    #[arg(long, short)]
    quiet: bool,
    /// Which model renders the output: the cycle-accurate pipeline (default: cycle report
    /// per frame), the functional fixed-point datapath, or the f64 reference. The fixed and
    /// cycle models are compared with the reference every frame (accuracy lines,
    /// diff_NNNN.png).
    #[arg(long, value_enum, default_value = "cycle")]
    model: ModelArg,
    /// Datapath formats and parameters (RON, as printed by `sim datapath`); default: the
    /// documented default of docs/number-formats.md.
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
    /// Hardware configuration of the cycle model (RON, as printed by `sim hardware`; a file
    /// names only what it changes); default: docs/cycle-model.md.
    #[arg(long, value_name = "FILE")]
    hw: Option<PathBuf>,
    /// Cycle model: re-execute every stage's arithmetic (sphere tests, sort, transform,
    /// reciprocals, walk, record) and stop with an error at the first difference from the
    /// functional model. Slower; the hit buffer is compared word for word every frame anyway.
    #[arg(long)]
    cross_check: bool,
    /// Cycle model: write waveforms (VCD, for GTKWave) of the window given by --vcd-cycles
    /// or --vcd-pixels.
    #[arg(long, value_name = "FILE")]
    vcd: Option<PathBuf>,
    /// Cycle window of --vcd, FROM:TO (cycles of the run, the first frame starts at 0).
    #[arg(
        long,
        value_name = "FROM:TO",
        default_value = "0:20000",
        conflicts_with = "vcd_pixels"
    )]
    vcd_cycles: String,
    /// Pixel window of --vcd, FROM:TO (raster indices in frame --vcd-frame): from the cycle
    /// pixel FROM is generated until pixel TO's record is written.
    #[arg(long, value_name = "FROM:TO")]
    vcd_pixels: Option<String>,
    /// Frame of --vcd-pixels.
    #[arg(long, default_value_t = 0)]
    vcd_frame: u32,
    /// Cycle model: write the stage stamps (entry and exit cycle per stage) of the first
    /// --log-count records as JSON lines, to check an RTL's latency stage by stage.
    #[arg(long, value_name = "FILE")]
    transaction_log: Option<PathBuf>,
    /// Records in --transaction-log.
    #[arg(long, default_value_t = 1000)]
    log_count: usize,
    /// Keep every unit of the pipeline: no scene-driven elaboration (by default the cycle
    /// model leaves out what the scene cannot use, e.g. the sorter for one instance or the
    /// hit buffer when the camera moves every frame; images are identical either way;
    /// docs/elaboration.md).
    #[arg(long)]
    no_prune: bool,
    /// Fixed and cycle models: accept a run in which datapath values saturated (did not fit
    /// their formats). Without it such a run still writes its outputs and prints the warning,
    /// then exits non-zero, so a script cannot take saturated results for good ones.
    #[arg(long)]
    allow_saturation: bool,
    /// Cycle model: sampled timing. Time one band of rows in 1/RATE (RATE in (0, 1], 1 times
    /// every band: the full model's cycles with each band's increment in the report;
    /// documented default 0.125) cycle by cycle, keep the caches and the hit buffer warm
    /// functionally in between, and report each frame's cycles and fps as an estimate with a
    /// 95 % confidence interval (docs/cycle-model.md §3.5). Off by default: every cycle is
    /// simulated.
    #[arg(long, value_name = "RATE", conflicts_with_all = ["vcd", "transaction_log"])]
    sample: Option<f64>,
    /// Rows per band of --sample.
    #[arg(long, value_name = "ROWS", default_value_t = svo_sim::models::cycle::sample::DEFAULT_BAND_ROWS, requires = "sample")]
    sample_band: u32,
    /// Rows run in detail before and after each timed band of --sample (default: sized
    /// per band from the trace until the stretch holds twice what the pipeline holds in rays
    /// that walk, docs/cycle-model.md §3.5).
    #[arg(long, value_name = "ROWS", requires = "sample")]
    sample_warm: Option<u32>,
    /// Seed of the sample's random start (--sample).
    #[arg(long, value_name = "N", default_value_t = 0, requires = "sample")]
    sample_seed: u64,
    /// Cycle model: after the run, run again with LIMIT made ideal (walk_issue, write_port,
    /// walkers, walker_read_port, memory_ports, mshr_full, hit_latency, dram_latency,
    /// dram_bandwidth; or `bound`: the limit the run's bound line names) and print the frame
    /// rate gained. The second run writes nothing (docs/cycle-model.md §2.2).
    #[arg(long, value_name = "LIMIT", conflicts_with_all = ["vcd", "transaction_log"])]
    lift: Option<String>,
}

impl RunArgs {
    /// The waveform request, if `--vcd` was given.
    fn vcd(&self) -> Result<Option<VcdRequest>> {
        let Some(path) = &self.vcd else {
            return Ok(None);
        };
        let window = match &self.vcd_pixels {
            Some(t) => {
                let (from, to) = parse_window("--vcd-pixels", t)?;
                WaveWindow::Pixels {
                    frame: self.vcd_frame,
                    from,
                    to,
                }
            }
            None => {
                let (from, to) = parse_window("--vcd-cycles", &self.vcd_cycles)?;
                WaveWindow::Cycles(from, to)
            }
        };
        Ok(Some(VcdRequest {
            path: path.clone(),
            window,
        }))
    }

    /// The run's configuration (before elaboration).
    fn config(&self) -> Result<RunConfig> {
        let datapath = load_datapath(self.datapath.as_deref())?;
        let hardware = load_hardware(self.hw.as_deref())?;
        if self.model == ModelArg::Cycle {
            check_pair(
                &hardware,
                self.hw.as_deref(),
                &datapath,
                self.datapath.as_deref(),
            )?;
        }
        Ok(RunConfig {
            scene: self.scene.load((None, None))?,
            depth: self.scene.depth,
            materialise: self.scene.materialise(),
            image_layout: self.scene.image_layout.into(),
            options: RenderOptions {
                use_hit_buffer: !self.no_hit_buffer,
                early_termination: !self.no_early_termination,
                culling: !self.no_culling,
                sort: !self.no_sort,
            },
            out_dir: (!self.no_png).then(|| self.out.clone()),
            report_json: self.report_json.clone(),
            dump_hits: self.dump_hits.clone(),
            model: match self.model {
                ModelArg::Reference => Model::Reference,
                ModelArg::Fixed => Model::Fixed,
                ModelArg::Cycle => Model::Cycle,
            },
            datapath,
            hardware,
            cross_check: self.cross_check,
            sample: match self.sample {
                Some(rate) => {
                    if self.model != ModelArg::Cycle {
                        anyhow::bail!("--sample times the cycle model: use it with --model cycle");
                    }
                    Some(
                        SampleConfig::from_rate(
                            rate,
                            self.sample_band,
                            self.sample_warm,
                            self.sample_seed,
                        )
                        .map_err(anyhow::Error::msg)?,
                    )
                }
                None => None,
            },
            vcd: self.vcd()?,
            transaction_log: self.transaction_log.clone().map(|p| (p, self.log_count)),
            progress_every: (!self.quiet).then(|| std::time::Duration::from_secs(2)),
            elaboration: None,
        })
    }
}

/// Prints a line of console text: on stdout, or on stderr when an output goes to stdout
/// (`--report-json -` and the like), so that output stays clean.
fn say(to_stderr: bool, text: impl std::fmt::Display) {
    if to_stderr {
        eprintln!("{text}");
    } else {
        println!("{text}");
    }
}

/// `--lift`: runs `cfg` again, writing nothing, with `limit` made ideal, and prints the frame
/// rate gained against the first run's summary `before`.
fn lift_and_rerun(cfg: &RunConfig, limit: &str, before: &CycleSummary, e_out: bool) -> Result<()> {
    let hw = lift(&cfg.hardware, limit).map_err(anyhow::Error::msg)?;
    let quiet = RunConfig {
        hardware: hw,
        datapath: lift_datapath(&cfg.datapath, limit),
        out_dir: None,
        report_json: None,
        dump_hits: None,
        vcd: None,
        transaction_log: None,
        progress_every: None,
        ..cfg.clone()
    };
    let lifted = run(&quiet, |_, _| {})?;
    if let Some(after) = lifted.report.summary.cycle.as_ref() {
        say(e_out, text::lift_line(limit, before, after));
    }
    Ok(())
}

/// Runs the main job.
pub fn run_command(a: RunArgs) -> Result<()> {
    a.scene.set_threads()?;
    let mut cfg = a.config()?;
    if a.lift.is_some() && cfg.model != Model::Cycle {
        anyhow::bail!("--lift re-runs the cycle model: use it with --model cycle");
    }
    // An unknown limit is refused before the first run, not after it.
    if let Some(l) = a.lift.as_deref().filter(|&l| l != "bound") {
        lift(&cfg.hardware, l).map_err(anyhow::Error::msg)?;
    }
    let dash = |p: Option<&std::path::Path>| p.is_some_and(|p| p.as_os_str() == "-");
    let e_out = [
        cfg.report_json.as_deref(),
        cfg.dump_hits.as_deref(),
        cfg.vcd.as_ref().map(|v| v.path.as_path()),
        cfg.transaction_log.as_ref().map(|(p, _)| p.as_path()),
    ]
    .into_iter()
    .any(dash);
    if cfg.model == Model::Cycle {
        let e = elaborate(
            &cfg.scene,
            cfg.depth,
            &cfg.hardware,
            &cfg.datapath,
            cfg.options.use_hit_buffer,
        )?;
        let e = if a.no_prune { e.not_applied() } else { e };
        if !a.quiet {
            say(e_out, &e);
        }
        cfg = cfg.elaborated(e);
    }
    say(
        e_out,
        text::run_header(&cfg.scene, &cfg.options, rayon::current_num_threads()),
    );
    let clock_mhz = cfg.hardware.clock_mhz;
    let out = run(&cfg, |f, n| {
        if !a.quiet {
            say(e_out, text::frame_lines(f, n, clock_mhz));
        }
    })?;
    if !a.quiet {
        if let Some(last) = out.report.frames.last().and_then(|f| f.cycle.as_ref()) {
            say(e_out, text::cycle_tables(last));
        }
        say(e_out, text::assets_table(&out.report.assets));
    }
    say(e_out, text::summary(&out.report.summary));
    if let (Some(limit), Some(before)) = (a.lift.as_deref(), out.report.summary.cycle.as_ref()) {
        let bound_says = (limit == "bound")
            .then(|| nothing_to_lift(&before.bound))
            .flatten();
        let limit = if limit == "bound" {
            before.bound.as_str()
        } else {
            limit
        };
        // `--lift bound` on a limit the hardware has already lifted as far as the schema goes
        // (`lift` refuses a lift that changes nothing): said, not an error, as for the clock.
        let bound_says = bound_says.or_else(|| {
            (a.lift.as_deref() == Some("bound"))
                .then(|| lift(&cfg.hardware, limit).err())
                .flatten()
                .map(|e| format!("lift bound: {e}"))
        });
        if let Some(says) = bound_says {
            // The frame already runs at the limit of the clock: no second run, not an error.
            say(e_out, says);
        } else {
            lift_and_rerun(&cfg, limit, before, e_out)?;
        }
    }
    let written = text::written(&cfg.destinations(), out.report.summary.frames);
    if !written.is_empty() {
        say(e_out, written);
    }
    // Saturation is never silent: the warning goes to stderr whatever -q says, and the exit
    // status says it unless the user accepted it.
    if let Some(warning) = text::saturation_warning(&out.report.frames) {
        eprintln!("warning: {warning}");
        if !a.allow_saturation {
            anyhow::bail!(
                "the run saturated (warning above); pass --allow-saturation to accept its results"
            );
        }
    }
    Ok(())
}
