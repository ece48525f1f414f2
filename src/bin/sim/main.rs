//! `sim`: the command line of the model of an FPGA ray-tracing pipeline for animated sparse
//! voxel octrees.
//!
//! One file per command, each parsing its options (clap) and calling the library; the
//! library holds no clap type. Without a subcommand, `sim` runs the main job ([`run`]): the
//! embedded animated car (or `--scene`) through the cycle model of the pipeline elaborated for
//! the scene. Errors from every command reach [`main`], which prints the chain once and exits
//! non-zero.

mod args;
mod bench;
mod datapath;
mod drift;
mod explore;
mod fuzz;
mod hardware;
mod instances;
mod paper;
mod render;
mod run;
mod stress;
mod sweep;
mod vectors;

use clap::{Parser, Subcommand};
use std::process::ExitCode;
use svo_sim::output::interrupt::{self, Interrupted};

#[derive(Parser, Debug)]
#[command(
    name = "sim",
    version,
    about = "Model of an FPGA ray-tracing pipeline for animated sparse voxel octrees (Espe et al. 2019)",
    long_about = "Runs a scene of animated SVOs through the cycle-accurate model of the \
pipeline (the default; --model fixed for the bit-exact fixed-point datapath alone, --model \
reference for the f64 reference of the paper's method: bounding spheres, front-to-back sort \
with early termination, inverse ray transforms, Revelles octree walk, hit buffer). The fixed \
and cycle models are compared with the reference every frame. Without --scene it runs the \
embedded animated car.\n\n\
Prints one line per frame and a summary; writes frame_NNNN.png into --out (and, for the fixed \
and cycle models, diff_NNNN.png: where the model differs from the reference), and optionally a \
JSON report (--report-json) and every pixel's hit record (--dump-hits). See docs/ for formats."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    run: run::RunArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Measure simulator speed: the reference's rays/s with and without the hit buffer (asset
    /// build time excluded); with --model fixed or cycle, that model against the reference,
    /// with --scaling, --sample and --sample-validate for the cycle model.
    Bench(bench::BenchArgs),
    /// Print a datapath configuration (RON, the input format of --datapath; the default
    /// unless --datapath is given), each unit's DSP48E2 count and every named error bound.
    Datapath(datapath::DatapathArgs),
    /// Print a hardware configuration of the cycle model (RON, the input format of --hw; the
    /// default unless --hw is given) and its resource estimate against the part; with
    /// --synth, also synthesise the RTL units with Yosys and print them beside the estimate.
    Hardware(hardware::HardwareArgs),
    /// Error over animation run time: fixed-point pose paths over a long animation
    /// (docs/drift.md); writes drift.csv, drift.json and drift.png.
    Drift(drift::DriftArgs),
    /// The hardware design space: every point of a space of hardware fields (lists or ranges,
    /// by their path in the hardware file) on its scenes through the cycle model, priced by
    /// the resource and fabric estimates (docs/explore.md); writes explore.csv, explore.json
    /// and the Pareto fronts of fps against LUT, FF, DSP48E2, BRAM36 and URAM288 as PNG.
    Explore(explore::ExploreArgs),
    /// Seeded mutation fuzzing of the input parsers (.vox, scene, hardware and datapath RON):
    /// every input must end in a result or a clear error; panics and hangs are saved and
    /// fail the run (docs/fuzz.md).
    Fuzz(fuzz::FuzzArgs),
    /// Frame rate against instance count for the flat and the two-level instance scheme
    /// (1 … 10,000 instances, still and moving camera), the functional models' speed and the
    /// hit buffer's reuse (docs/instances.md); writes instances.md, .json and .png.
    Instances(instances::InstancesArgs),
    /// The paper's experiment (Espe et al. 2019, Fig. 7): the static car as one SVO against
    /// the animated car without and with §4's optimisations, timed by the reference (best of
    /// N) and the cycle model, at 640x384 and 1280x768 (docs/paper.md); writes paper.md, .csv,
    /// .json and .png.
    Paper(paper::PaperArgs),
    /// Write HDL test vectors of every stage ($readmemh hex, JSON manifests, SystemVerilog
    /// packages) from adversarial cases, a real frame and seeded random stimulus
    /// (docs/vectors.md).
    Vectors(vectors::VectorsArgs),
    /// Render a bare MagicaVoxel model with the reference walk and a camera in the model's own
    /// voxel coordinates (z up); print where it sits in the octree (docs/render.md).
    Render(render::RenderArgs),
    /// Stiff and extreme cases against the f64 reference, with a verdict each
    /// (docs/stability.md).
    Stress(stress::StressArgs),
    /// Accuracy against cost over datapath configurations on one or more scenes, with the
    /// Pareto fronts (docs/accuracy.md); writes sweep.csv, sweep.json and two PNG plots.
    Sweep(sweep::SweepArgs),
}

/// The error and its causes, each cause only if the text so far does not already say it
/// (library errors include their source's message in their own).
fn error_text(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !text.contains(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

/// Ends the process quietly when stdout is a closed pipe (`sim hardware | head`): Rust's
/// `println!` panics there, and a backtrace would bury the output the user asked for. The exit
/// status is 141, what a shell reports for a process ended by SIGPIPE, as other tools do.
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let text = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if text.contains("failed printing to stdout") && text.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

/// Whether `e` comes from writing to a pipe whose reader has gone (any cause in its chain is
/// an I/O error of kind `BrokenPipe`).
fn closed_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// The exit of a process that received SIGINT or SIGTERM: removes every unfinished
/// temporary, prints one line saying where the work stopped and what was kept, and returns
/// 128 + the signal (130, 143). `r` is the command's result: an [`Interrupted`] error says
/// where it stopped; any other end (an error caused by the interruption, or work that
/// finished before it looked at the flag) is reported as such.
fn interrupted_exit(signal: i32, r: &anyhow::Result<()>) -> ExitCode {
    let name = interrupt::signal_name(signal);
    let line = match r {
        Err(e) => match e.chain().find_map(|c| c.downcast_ref::<Interrupted>()) {
            Some(i) => interrupt::finish_line(&i.to_string(), &i.kept),
            None => {
                // A study whose errors are text carries the interruption's words in it.
                let text = error_text(e);
                let head = if text.contains("interrupted by") {
                    text
                } else {
                    format!("interrupted by {name}; the work ended with: {text}")
                };
                interrupt::finish_line(&head, "the outputs that were complete")
            }
        },
        Ok(()) => interrupt::finish_line(
            &format!("interrupted by {name} after the work finished"),
            "every output",
        ),
    };
    eprintln!("{line}");
    ExitCode::from(interrupt::exit_status(signal))
}

fn main() -> ExitCode {
    quiet_on_broken_pipe();
    let cli = Cli::parse();
    // SIGINT/SIGTERM only set a flag the long loops check; the exit below cleans up.
    if let Err(e) = interrupt::install() {
        eprintln!("error: cannot install the SIGINT/SIGTERM handling: {e}");
        return ExitCode::FAILURE;
    }
    let r = match cli.command {
        Some(Command::Bench(a)) => bench::run_command(a),
        Some(Command::Datapath(a)) => datapath::datapath_command(a),
        Some(Command::Hardware(a)) => hardware::hardware_command(a),
        Some(Command::Drift(a)) => drift::drift_command(a),
        Some(Command::Explore(a)) => explore::explore_command(a),
        Some(Command::Fuzz(a)) => fuzz::fuzz_command(a),
        Some(Command::Instances(a)) => instances::instances_command(a),
        Some(Command::Paper(a)) => paper::paper_command(a),
        Some(Command::Vectors(a)) => vectors::vectors_command(a),
        Some(Command::Render(a)) => render::render_command(a),
        Some(Command::Stress(a)) => stress::stress_command(a),
        Some(Command::Sweep(a)) => sweep::sweep_command(a),
        None => run::run_command(cli.run),
    };
    if let Some(signal) = interrupt::received() {
        return interrupted_exit(signal, &r);
    }
    match r {
        Ok(()) => ExitCode::SUCCESS,
        // An output given as `-` whose reader closed the pipe (`--report-json - | head`): the
        // same quiet 141 as the console text's closed pipe, not an error report.
        Err(e) if closed_pipe(&e) => ExitCode::from(141),
        Err(e) => {
            eprintln!("error: {}", error_text(&e));
            ExitCode::FAILURE
        }
    }
}
