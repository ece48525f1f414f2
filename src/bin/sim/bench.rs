//! `sim bench`: parses the bench's options and prints the library's speed measurements
//! (`svo_sim::run::bench`, `svo_sim::run::cycle_bench`).

use crate::args::{ModelArg, SceneArgs};
use anyhow::Result;
use clap::{Args, Subcommand};
use std::path::PathBuf;
use svo_sim::models::cycle::sample::SampleConfig;
use svo_sim::run::bench::{
    cycle_speed_table, fixed_speed, fixed_speed_total, reference_speed, reference_speed_text,
    scaling_line, write_scaling,
};
use svo_sim::run::build;
use svo_sim::run::config_files::{load_datapath, load_hardware};
use svo_sim::run::cycle_bench;
use svo_sim::world::assets::Asset;
use svo_sim::world::scene::Scene;

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct BenchArgs {
    /// `peer`: the reference against the OpenVDB peer on the 20 benchmark cameras.
    #[command(subcommand)]
    sub: Option<BenchSub>,
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
    /// With `--model cycle`: validate sampled timing (docs/cycle-model.md §3.5) at RATE
    /// against the full model on the matrix of cases (the scene given; moving camera; 1, 8,
    /// 64 walkers; a 16 KiB cache; an external hit buffer; DRAM latency 240;
    /// scenes/vox_traffic.ron when the shared models are present; scenes/moving_camera.ron):
    /// per frame the full fps, the estimate, its 95 % interval, the error and the wall-time
    /// ratio.
    #[arg(long, value_name = "RATE", conflicts_with = "sample")]
    sample_validate: Option<f64>,
    /// With `--model cycle`: time the cycle model in sampled mode at RATE (`sim --sample`,
    /// docs/cycle-model.md §3.5) instead of the full model, against the reference on the same
    /// frames; the tables add each estimate's 95 % interval and the share of cycles timed.
    #[arg(long, value_name = "RATE")]
    sample: Option<f64>,
    /// Rows per band of --sample or --sample-validate.
    #[arg(long, value_name = "ROWS", default_value_t = svo_sim::models::cycle::sample::DEFAULT_BAND_ROWS)]
    sample_band: u32,
    /// Rows of detailed warming of --sample or --sample-validate, fixed (default: sized per
    /// band in rays that walk, docs/cycle-model.md §3.5).
    #[arg(long, value_name = "ROWS")]
    sample_warm: Option<u32>,
}

#[derive(Subcommand, Debug)]
enum BenchSub {
    /// The f64 reference (`sim render`) against the OpenVDB peer of tests/openvdb_peer/peer.cpp
    /// on the 20 benchmark cameras (five shared models × four cameras, docs/render.md §7): same
    /// rays, same threads, rounds alternating which program runs first; prints each camera's
    /// best and median Mrays/s, the ratios reference / peer and the smallest ratio. Builds the
    /// peer with g++ and OpenVDB 10 (libopenvdb-dev) unless --peer is given.
    Peer(PeerArgs),
}

#[derive(Args, Debug)]
struct PeerArgs {
    /// The folder of the shared .vox models (veh_bus, scene_store8, chr_mayor,
    /// alien_saucer2a, scene_park).
    #[arg(long, value_name = "DIR", default_value = "../shared/data/vox")]
    vox_dir: PathBuf,
    /// A built peer binary (default: build tests/openvdb_peer/peer.cpp, embedded in this
    /// binary, into --peer-cache, or reuse the build of the same source there).
    #[arg(long, value_name = "PATH")]
    peer: Option<PathBuf>,
    /// Where the peer is built and its scratch hit records go (default: the system's temporary
    /// folder, svo_sim_openvdb_peer).
    #[arg(long, value_name = "DIR")]
    peer_cache: Option<PathBuf>,
    /// Runs of each program per camera, alternating which runs first; best and median of them.
    #[arg(long, default_value_t = 4)]
    rounds: u32,
    /// Traces per run (each program reports its fastest; the peer after one untimed warm-up).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
    /// Worker threads of both programs.
    #[arg(long, default_value_t = 2)]
    threads: u32,
    /// Image sides: the test's (160×120, 161×121, 64–128²) times this.
    #[arg(long, default_value_t = 8)]
    scale: u32,
    /// Only the cameras whose `model/camera` contains this text (e.g. `scene_park/ortho`).
    #[arg(long, value_name = "TEXT")]
    only: Option<String>,
}

/// `sim bench peer`.
fn bench_peer(a: &PeerArgs) -> Result<()> {
    use svo_sim::run::peer_bench::{
        build_peer, header_text, row_text, run_peer_bench, summary_text, PeerBenchOptions,
    };
    let cache = a
        .peer_cache
        .clone()
        .unwrap_or_else(|| std::env::temp_dir().join("svo_sim_openvdb_peer"));
    let peer = match &a.peer {
        Some(p) if !p.is_file() => anyhow::bail!("--peer {}: no such file", p.display()),
        Some(p) => p.clone(),
        None => build_peer(&cache)?,
    };
    let o = PeerBenchOptions {
        vox_dir: a.vox_dir.clone(),
        sim: std::env::current_exe()?,
        peer,
        rounds: a.rounds,
        repeat: a.repeat,
        threads: a.threads,
        scale: a.scale,
        only: a.only.clone(),
        scratch: cache,
    };
    println!(
        "reference (sim render) against the OpenVDB peer {}: {} threads, {} rounds of {} traces \
         each, alternating; Mrays/s, ratio = reference / peer",
        o.peer.display(),
        o.threads,
        o.rounds,
        o.repeat
    );
    println!("{}", header_text());
    let rows = run_peer_bench(&o, &mut |r| println!("{}", row_text(r)))?;
    print!("{}", summary_text(&rows));
    Ok(())
}

/// The sample of `--sample RATE` or `--sample-validate RATE`, with `--sample-band` and
/// `--sample-warm`.
fn sample_of(a: &BenchArgs, rate: f64) -> Result<SampleConfig> {
    SampleConfig::from_rate(rate, a.sample_band, a.sample_warm, 0).map_err(anyhow::Error::msg)
}

/// `sim bench --model cycle --sample-validate RATE`: the validation matrix.
fn sample_validate(a: &BenchArgs, scene: &Scene, assets: &[Asset], rate: f64) -> Result<()> {
    use svo_sim::models::cycle::validate::compare;
    let dp = load_datapath(a.datapath.as_deref())?;
    let base = load_hardware(a.hw.as_deref())?;
    let cfg = sample_of(a, rate)?;
    let with = |f: &dyn Fn(&mut rtl_model::cycle::hw_config::HwConfig)| {
        let mut h = base.clone();
        f(&mut h);
        h
    };
    let mut cases: Vec<(String, rtl_model::cycle::hw_config::HwConfig, bool)> = vec![
        ("still camera, 32 walkers".into(), base.clone(), true),
        ("moving camera (no reuse)".into(), base.clone(), false),
    ];
    for n in [1u32, 8, 64] {
        cases.push((
            format!("{n} walker{}", if n == 1 { "" } else { "s" }),
            with(&|h| h.walker_pool.walkers = n),
            true,
        ));
    }
    cases.push((
        "16 KiB 2-way cache".into(),
        with(&|h| {
            h.node_memory.cache.size_bytes = 16384;
            h.node_memory.cache.ways = 2;
        }),
        true,
    ));
    cases.push((
        "external hit buffer".into(),
        with(&|h| h.hit_buffer.placement = rtl_model::cycle::hw_config::Placement::External),
        true,
    ));
    cases.push((
        "DRAM latency 240".into(),
        with(&|h| h.node_memory.dram.latency = 240),
        true,
    ));
    println!(
        "sampled timing at rate {rate} (1 band in {}, bands of {} rows) against the full model:",
        cfg.period, cfg.band_rows
    );
    println!(
        "  {:<34} {:>5} {:>9} {:>9} {:>19} {:>8} {:>7}",
        "case", "frame", "full fps", "est fps", "95% CI fps", "error", "wall"
    );
    let clock = |hw: &rtl_model::cycle::hw_config::HwConfig| f64::from(hw.clock_mhz) * 1e6;
    let (mut worst, mut missed) = (0.0f64, 0u32);
    let mut print = |name: &str,
                     hw: &rtl_model::cycle::hw_config::HwConfig,
                     rows: &[svo_sim::models::cycle::validate::SampleCheck]| {
        for r in rows {
            let c = clock(hw);
            worst = worst.max(r.error().abs());
            missed += u32::from(!r.covered());
            println!(
                "  {:<34} {:>5} {:>9.2} {:>9.2} {:>8.2}–{:<10.2} {:>+7.2}% {:>6.2}×{}",
                name,
                r.frame,
                c / r.full_cycles.max(1) as f64,
                c / r.estimate.max(1.0),
                c / r.high.max(1.0),
                c / r.low.max(1.0),
                100.0 * r.error(),
                r.sampled_s / r.full_s.max(1e-9),
                if r.covered() { "" } else { "  OUTSIDE" }
            );
        }
    };
    for (name, hw, reuse) in &cases {
        let rows = compare(scene, assets, &dp, hw, *reuse, cfg)?;
        print(name, hw, &rows);
    }
    for (name, file) in [
        ("vox_traffic", "scenes/vox_traffic.ron"),
        ("moving_camera", "scenes/moving_camera.ron"),
    ] {
        // A scene of the shared models is skipped with the reason when they are missing
        // (`../shared/data` is not part of the repository).
        let loaded = Scene::load(std::path::Path::new(file)).and_then(|mut v| {
            let (w, h) = scene.file.resolution;
            v.max_vox_bytes = scene.max_vox_bytes;
            v.set_resolution(w, h)?;
            v.set_frames(scene.file.frames)?;
            Ok(v)
        });
        let built = loaded.map_err(anyhow::Error::from).and_then(|v| {
            let va = build(
                &v,
                None,
                svo_sim::world::assets::Materialise::Auto,
                a.scene.image_layout.into(),
            )?;
            Ok((v, va))
        });
        match built {
            Ok((v, va)) => {
                let rows = compare(&v, &va, &dp, &base, true, cfg)?;
                print(name, &base, &rows);
            }
            Err(e) => println!("  {name} skipped: {e:#}"),
        }
    }
    println!(
        "  worst error {:.2}%; full figure outside the interval in {missed} frame(s)",
        100.0 * worst
    );
    Ok(())
}

/// `sim bench --model cycle`: both cameras, then the optional scaling sweep.
fn bench_cycle(a: &BenchArgs, scene: &Scene, assets: &[Asset]) -> Result<()> {
    let dp = load_datapath(a.datapath.as_deref())?;
    let hw = load_hardware(a.hw.as_deref())?;
    if let Some(rate) = a.sample_validate {
        return sample_validate(a, scene, assets, rate);
    }
    if let Some(dir) = &a.scaling {
        if !dir.is_dir() {
            anyhow::bail!("--scaling {}: not a folder", dir.display());
        }
    }
    let sample = a.sample.map(|r| sample_of(a, r)).transpose()?;
    if let Some(s) = &sample {
        println!(
            "sampled timing at rate {} (1 band in {}, bands of {} rows): cycles are estimates",
            1.0 / f64::from(s.period),
            s.period,
            s.band_rows
        );
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
        let frames = cycle_bench::speed(scene, assets, &dp, &hw, hb, sample)?;
        println!("{}", cycle_speed_table(label, &frames, pixels, &hw));
    }
    if let Some(dir) = &a.scaling {
        println!("scaling (frame 0, every pixel traced):");
        println!(
            "  {:<13} {:>6} {:>10} {:>9}  bound",
            "sweep", "value", "cycles", "fps"
        );
        let pts =
            cycle_bench::scaling(scene, assets, &dp, &hw, |p| println!("{}", scaling_line(p)))?;
        let [csv, png] = write_scaling(dir, &pts, scene)?;
        println!("wrote {} and {}", csv.display(), png.display());
    }
    Ok(())
}

/// Runs `sim bench`.
pub fn run_command(a: BenchArgs) -> Result<()> {
    if let Some(BenchSub::Peer(p)) = &a.sub {
        return bench_peer(p);
    }
    if a.model != ModelArg::Cycle {
        for (given, flag) in [
            (a.sample.is_some(), "--sample"),
            (a.sample_validate.is_some(), "--sample-validate"),
            (a.scaling.is_some(), "--scaling"),
            (a.hw.is_some(), "--hw"),
        ] {
            if given {
                anyhow::bail!("{flag} applies to the cycle model: add --model cycle");
            }
        }
    }
    // The sample's options are checked before the assets are built.
    match a.sample.or(a.sample_validate) {
        Some(rate) => {
            sample_of(&a, rate)?;
        }
        None if a.sample_warm.is_some() => {
            anyhow::bail!("--sample-warm needs --sample or --sample-validate")
        }
        None => {}
    }
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
    let assets = build(&scene, sa.depth, sa.materialise(), sa.image_layout.into())?;
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
