//! `sim bench`: parses the bench's options and prints the library's speed measurements
//! (`svo_sim::run::bench`, `svo_sim::models::cycle::bench`).

use crate::args::{ModelArg, SceneArgs};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;
use svo_sim::models::cycle::bench;
use svo_sim::run::bench::{
    cycle_speed_table, fixed_speed, fixed_speed_total, reference_speed, reference_speed_text,
    scaling_line, write_scaling,
};
use svo_sim::run::build;
use svo_sim::run::config_files::{load_datapath, load_hardware};
use svo_sim::world::assets::Asset;
use svo_sim::world::scene::Scene;

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scene, resolution, frames, depth and threads (bench defaults: 1280x768, 8 frames,
    /// depth 11).
    #[command(flatten)]
    scene: SceneArgs,
    /// `fixed`: also time the fixed-point model against the reference on the same frames
    /// (full trace, interleaved, best of `--repeat`) and print the speed ratio. `cycle`: time
    /// the cycle model against the reference frame by frame (still and moving camera), with
    /// the modelled frame rate, and with --scaling the walker and DRAM-latency sweep.
    #[arg(long, value_enum, default_value = "reference")]
    model: ModelArg,
    /// Repetitions per frame for the fixed/reference ratio (the fastest run of each counts,
    /// which damps noise from other work on a shared machine).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
    /// Datapath configuration for the fixed-point model (RON).
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
    /// Hardware configuration for `--model cycle` (RON).
    #[arg(long, value_name = "FILE")]
    hw: Option<PathBuf>,
    /// With `--model cycle`: also sweep walkers (1–64) and DRAM latency (15–480 cycles) on one
    /// full-trace frame and write scaling.csv and scaling.png into DIR.
    #[arg(long, value_name = "DIR")]
    scaling: Option<PathBuf>,
}

/// `sim bench --model cycle`: both cameras, then the optional scaling sweep.
fn bench_cycle(a: &BenchArgs, scene: &Scene, assets: &[Asset]) -> Result<()> {
    let dp = load_datapath(a.datapath.as_deref())?;
    let hw = load_hardware(a.hw.as_deref())?;
    if let Some(dir) = &a.scaling {
        if !dir.is_dir() {
            anyhow::bail!("--scaling {}: not a folder", dir.display());
        }
    }
    let (w, h) = scene.file.resolution;
    let pixels = f64::from(w) * f64::from(h);
    for (label, hb) in [
        ("still camera (hit buffer on)", true),
        (
            "camera moving every frame (no reuse: every pixel traced)",
            false,
        ),
    ] {
        let frames = bench::speed(scene, assets, &dp, &hw, hb)?;
        println!("{}", cycle_speed_table(label, &frames, pixels, &hw));
    }
    if let Some(dir) = &a.scaling {
        println!("scaling (frame 0, every pixel traced):");
        println!(
            "  {:<13} {:>6} {:>10} {:>9}  bound",
            "sweep", "value", "cycles", "fps"
        );
        let pts = bench::scaling(scene, assets, &dp, &hw, |p| println!("{}", scaling_line(p)))?;
        let [csv, png] = write_scaling(dir, &pts, scene)?;
        println!("wrote {} and {}", csv.display(), png.display());
    }
    Ok(())
}

/// Runs `sim bench`.
pub fn run_command(a: BenchArgs) -> Result<()> {
    a.scene.set_threads()?;
    let mut sa = a.scene.clone();
    sa.depth = sa.depth.or(Some(11));
    let scene = sa.load((Some((1280, 768)), Some(8)))?;
    let (w, h) = scene.file.resolution;
    println!(
        "bench: {} at {}x{}, {} frames, depth {}, {} threads",
        scene.origin,
        w,
        h,
        scene.file.frames,
        sa.depth.unwrap_or(0),
        rayon::current_num_threads()
    );
    let t = std::time::Instant::now();
    let assets = build(&scene, sa.depth, sa.materialise())?;
    println!(
        "assets built in {:.2} s (excluded)",
        t.elapsed().as_secs_f64()
    );
    if a.model == ModelArg::Cycle {
        return bench_cycle(&a, &scene, &assets);
    }
    println!(
        "{}",
        reference_speed_text(&reference_speed(&scene, &assets)?)
    );
    if a.model == ModelArg::Fixed {
        let dp = load_datapath(a.datapath.as_deref())?;
        println!(
            "  fixed-point model against the reference, full trace, best of {} per frame:",
            a.repeat.max(1)
        );
        let frames = fixed_speed(&scene, &assets, &dp, a.repeat, |f| println!("{}", f.line()))?;
        println!(
            "{}",
            fixed_speed_total(&frames, f64::from(w) * f64::from(h))
        );
    }
    Ok(())
}
