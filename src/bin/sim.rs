//! `sim`: the command line of the animated-SVO ray-tracing pipeline model.
//!
//! `sim` runs the f64 reference of the paper's method on a scene (the embedded animated car
//! by default), prints per-frame counters and a summary, and writes PNGs, a JSON report and
//! per-pixel hit dumps. `sim bench` measures the reference's speed.

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::path::PathBuf;
use std::process::ExitCode;
use svo_sim::world::assets::Materialise;
use svo_sim::models::cycle::waves::WaveWindow;
use svo_sim::models::cycle::CycleFrame;
use svo_sim::models::fixed::{render_frame_fixed, FixedBuffer};
use svo_sim::models::reference::{render_frame, FrameInput, FrameStats, HitBuffer, RenderOptions};
use svo_sim::run::{build, run, Model, RunConfig, VcdRequest};
use svo_sim::world::scene::Scene;

#[derive(Parser, Debug)]
#[command(
    name = "sim",
    version,
    about = "Model of an FPGA ray-tracing pipeline for animated sparse voxel octrees (Espe et al. 2019)",
    long_about = "Renders a scene of animated SVOs with the f64 reference of the paper's method \
(bounding spheres, front-to-back sort with early termination, inverse ray transforms, Revelles \
octree walk, hit buffer). Without --scene it runs the embedded animated car.\n\n\
Prints one line per frame and a summary; writes frame_NNNN.png into --out, and optionally a \
JSON report (--report-json) and every pixel's hit record (--dump-hits). See docs/ for formats."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Measure the reference's speed (rays/s) with and without the hit buffer; asset build
    /// time is reported separately and excluded.
    Bench(BenchArgs),
    /// Print a datapath configuration (RON, the input format of --datapath; the default
    /// unless --datapath is given), each unit's DSP48E2 count and every named error bound.
    Datapath(DatapathArgs),
    /// Print a hardware configuration of the cycle model (RON, the input format of --hw; the
    /// default unless --hw is given) and its resource estimate against the part.
    Hardware(HardwareArgs),
    /// Error over animation run time: fixed-point pose paths over a long animation
    /// (docs/drift.md); writes drift.csv, drift.json and drift.png.
    Drift(svo_sim::studies::drift::cli::DriftArgs),
    /// Write HDL test vectors of every stage ($readmemh hex, JSON manifests, SystemVerilog
    /// packages) from adversarial cases, a real frame and seeded random stimulus
    /// (docs/vectors.md).
    Vectors(svo_sim::studies::vectors::cli::VectorsArgs),
    /// Stiff and extreme cases against the f64 reference, with a verdict each
    /// (docs/stability.md).
    Stress(svo_sim::studies::stress::cli::StressArgs),
    /// Accuracy against cost over datapath configurations on one or more scenes, with the
    /// Pareto fronts (docs/accuracy.md); writes sweep.csv, sweep.json and two PNG plots.
    Sweep(svo_sim::studies::sweep::cli::SweepArgs),
}

#[derive(Args, Debug)]
struct DatapathArgs {
    /// Configuration to print (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
}

#[derive(Args, Debug, Clone)]
struct SceneArgs {
    /// Scene file (RON, see docs/scene-format.md); default: the embedded animated car.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Image width in pixels (default: the scene's).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long)]
    height: Option<u32>,
    /// Number of frames (default: the scene's).
    #[arg(long)]
    frames: Option<u32>,
    /// Octree depth of the deepest asset (1-20); the others keep their offset to it
    /// (default: the scene's depths; the car's body is 10).
    #[arg(long)]
    depth: Option<u8>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Walk procedural (SDF) assets on demand instead of building memory images (same
    /// voxels; automatic when an image would exceed 64 M leaves, e.g. the car at depth 13+).
    #[arg(long)]
    implicit: bool,
}

#[derive(Args, Debug)]
struct RunArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Folder for the PNG frames.
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
    /// Do not write PNGs.
    #[arg(long)]
    no_png: bool,
    /// Write the JSON report here.
    #[arg(long, value_name = "FILE")]
    report_json: Option<PathBuf>,
    /// Trace every pixel of every frame (no reuse across frames).
    #[arg(long)]
    no_hit_buffer: bool,
    /// Walk every candidate instead of stopping at the first certain hit.
    #[arg(long)]
    no_early_termination: bool,
    /// Write every pixel's hit record here (binary, or CSV if the name ends in .csv;
    /// format in docs/hit-dump.md).
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
}

/// Parses `FROM:TO` with FROM ≤ TO.
fn parse_window(flag: &str, text: &str) -> Result<(u64, u64)> {
    let (a, b) = text
        .split_once(':')
        .ok_or_else(|| anyhow::anyhow!("{flag} {text:?}: expected FROM:TO"))?;
    let a: u64 = a
        .trim()
        .parse()
        .with_context(|| format!("{flag} {text:?}: FROM is not a number"))?;
    let b: u64 = b
        .trim()
        .parse()
        .with_context(|| format!("{flag} {text:?}: TO is not a number"))?;
    if a > b {
        anyhow::bail!("{flag} {text:?}: FROM is after TO");
    }
    Ok((a, b))
}

/// Reads a hardware configuration file (RON).
fn load_hw(path: Option<&PathBuf>) -> Result<HwConfig> {
    let Some(p) = path else {
        return Ok(HwConfig::default());
    };
    let text = std::fs::read_to_string(p)
        .with_context(|| format!("cannot read hardware file {}", p.display()))?;
    let cfg: HwConfig = ron::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "{}:{}:{}: malformed hardware configuration: {}",
            p.display(),
            e.position.line,
            e.position.col,
            e.code
        )
    })?;
    cfg.validate()
        .map_err(|m| anyhow::anyhow!("{}: invalid hardware configuration: {m}", p.display()))?;
    Ok(cfg)
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum ModelArg {
    /// The cycle-accurate pipeline (bit-exact with `fixed`, timed clock by clock).
    Cycle,
    /// The functional fixed-point datapath.
    Fixed,
    /// The f64 reference.
    Reference,
}

/// Reads a datapath configuration file (RON).
fn load_datapath(path: Option<&PathBuf>) -> Result<DatapathConfig> {
    let Some(p) = path else {
        return Ok(DatapathConfig::default());
    };
    let text = std::fs::read_to_string(p)
        .with_context(|| format!("cannot read datapath file {}", p.display()))?;
    let cfg: DatapathConfig = ron::from_str(&text).map_err(|e| {
        anyhow::anyhow!(
            "{}:{}:{}: malformed datapath configuration: {}",
            p.display(),
            e.position.line,
            e.position.col,
            e.code
        )
    })?;
    cfg.validate()
        .map_err(|m| anyhow::anyhow!("{}: invalid datapath configuration: {m}", p.display()))?;
    Ok(cfg)
}

#[derive(Args, Debug)]
struct BenchArgs {
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

/// `sim bench --model cycle`.
fn bench_cycle(a: &BenchArgs, scene: &Scene, assets: &[svo_sim::world::assets::Asset]) -> Result<()> {
    use svo_sim::models::cycle::bench;
    let dp = load_datapath(a.datapath.as_ref())?;
    let hw = load_hw(a.hw.as_ref())?;
    if let Some(dir) = &a.scaling {
        if !dir.is_dir() {
            anyhow::bail!("--scaling {}: not a folder", dir.display());
        }
    }
    for (label, hb) in [
        ("still camera (hit buffer on)", true),
        (
            "camera moving every frame (no reuse: every pixel traced)",
            false,
        ),
    ] {
        let frames = bench::speed(scene, assets, &dp, &hw, hb)?;
        println!("{label}:");
        println!(
            "  {:>5} {:>10} {:>10} {:>9} {:>7} {:>10} {:>9} {:>9} {:>10} {:>8}",
            "frame",
            "ref ms",
            "cycle ms",
            "func ms",
            "ratio",
            "cycles",
            "fps",
            "rays/cyc",
            "M rays/s",
            "bound"
        );
        let px = f64::from(scene.file.resolution.0) * f64::from(scene.file.resolution.1);
        for f in &frames {
            println!(
                "  {:>5} {:>10.1} {:>10.1} {:>9.1} {:>7.2} {:>10} {:>9.1} {:>9.3} {:>10.3} {:>8}",
                f.frame,
                f.reference_s * 1e3,
                f.cycle_s * 1e3,
                f.functional_s * 1e3,
                f.cycle_s / f.reference_s.max(1e-9),
                f.cycles,
                f.fps,
                f.rays_per_cycle,
                px / f.cycle_s.max(1e-9) / 1e6,
                f.bound
            );
        }
        let rs: f64 = frames.iter().map(|f| f.reference_s).sum();
        let cs: f64 = frames.iter().map(|f| f.cycle_s).sum();
        let cy: u64 = frames.iter().map(|f| f.cycles).sum();
        let n = frames.len() as f64;
        println!(
            "  total: cycle model / reference wall time {:.2}; simulated {:.3} M rays/s, {:.3} M cycles/s; modelled {:.1} fps at {} MHz (slowest frame {:.1})",
            cs / rs.max(1e-9),
            n * px / cs.max(1e-9) / 1e6,
            cy as f64 / cs.max(1e-9) / 1e6,
            n * f64::from(hw.clock_mhz) * 1e6 / cy.max(1) as f64,
            hw.clock_mhz,
            frames.iter().map(|f| f.fps).fold(f64::INFINITY, f64::min)
        );
    }
    if let Some(dir) = &a.scaling {
        println!("scaling (frame 0, every pixel traced):");
        println!(
            "  {:<13} {:>6} {:>10} {:>9}  bound",
            "sweep", "value", "cycles", "fps"
        );
        let pts = bench::scaling(scene, assets, &dp, &hw, |p| {
            println!(
                "  {:<13} {:>6} {:>10} {:>9.1}  {} — {}",
                p.sweep, p.value, p.cycles, p.fps, p.bound, p.reason
            );
        })?;
        let csv = dir.join("scaling.csv");
        svo_sim::output::atomic::write_atomic(&csv, bench::scaling_csv(&pts).as_bytes())
            .with_context(|| format!("cannot write {}", csv.display()))?;
        let (w, h) = scene.file.resolution;
        let img = bench::scaling_plot(
            &pts,
            &format!("cycles per frame, {w}×{h}, every pixel traced"),
        )
        .map_err(anyhow::Error::msg)?;
        let png = dir.join("scaling.png");
        svo_sim::output::atomic::write_atomic(&png, &svo_sim::output::png::encode_png(&img)?)
            .with_context(|| format!("cannot write {}", png.display()))?;
        println!("wrote {} and {}", csv.display(), png.display());
    }
    Ok(())
}

fn load_scene(a: &SceneArgs, defaults: (Option<(u32, u32)>, Option<u32>)) -> Result<Scene> {
    let mut scene = match &a.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::default_car()?,
    };
    let (w0, h0) = defaults.0.unwrap_or(scene.file.resolution);
    let (w, h) = (a.width.unwrap_or(w0), a.height.unwrap_or(h0));
    if (w, h) != scene.file.resolution {
        scene.set_resolution(w, h)?;
    }
    if let Some(f) = a.frames.or(defaults.1) {
        scene.set_frames(f)?;
    }
    Ok(scene)
}

fn set_threads(n: Option<usize>) -> Result<()> {
    if let Some(n) = n {
        if n == 0 || n > 1024 {
            anyhow::bail!("--threads {n} is out of range (1 to 1024)");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .context("cannot start the worker threads")?;
    }
    Ok(())
}

fn frame_line(st: &FrameStats, frames: u32) -> String {
    let cand = st.candidates as f64 / (st.rays - st.hit_buffer_reused).max(1) as f64;
    format!(
        "frame {:>4}/{frames}  rays {:>8}  sphere tests {:>9}  culled {:>9}  cand/ray {:>5.2}  walks {:>8}  steps {:>10}  early-term {:>7}  reused {:>8} ({:>5.1}%)  {:>8.1} ms  {:>7.2} M rays/s",
        st.frame,
        st.rays,
        st.sphere_tests,
        st.spheres_culled,
        cand,
        st.walks,
        st.walker_steps,
        st.early_terminations,
        st.hit_buffer_reused,
        100.0 * st.hit_buffer_reused as f64 / st.rays.max(1) as f64,
        st.wall_s * 1e3,
        st.rays_per_s / 1e6
    )
}

fn walker_cycles(c: &CycleFrame) -> f64 {
    let w = &c.walkers;
    (w.issuing + w.memory_wait + w.latency_wait + w.backpressured + w.empty).max(1) as f64
}

/// The last frame's stage, FIFO and memory tables.
fn print_cycle_tables(c: &CycleFrame) {
    let cyc = c.cycles.max(1) as f64;
    println!("last frame, per stage (% of {} cycles):", c.cycles);
    println!(
        "  {:<11} {:>7} {:>8} {:>14} {:>6} {:>12}",
        "stage", "busy", "starved", "backpressured", "idle", "transactions"
    );
    for st in &c.stages {
        println!(
            "  {:<11} {:>6.1}% {:>7.1}% {:>13.1}% {:>5.1}% {:>12}",
            st.name,
            100.0 * st.busy as f64 / cyc,
            100.0 * st.starved as f64 / cyc,
            100.0 * st.backpressured as f64 / cyc,
            100.0 * st.idle as f64 / cyc,
            st.transactions
        );
    }
    let w = &c.walkers;
    let wc = walker_cycles(c);
    println!(
        "  walkers: {} walks, {} issue slots; walker-cycles {:.1}% issuing, {:.1}% waiting on memory, {:.1}% on the step pipeline, {:.1}% back-pressured, {:.1}% empty; contexts {:.1}% occupied; {} dispatch stalls",
        w.walks,
        w.slots,
        100.0 * w.issuing as f64 / wc,
        100.0 * w.memory_wait as f64 / wc,
        100.0 * w.latency_wait as f64 / wc,
        100.0 * w.backpressured as f64 / wc,
        100.0 * w.empty as f64 / wc,
        100.0 * c.context_occupancy,
        w.dispatch_stalls
    );
    println!("  FIFOs (depth, mean / max occupancy, full cycles):");
    for f in &c.fifos {
        println!(
            "    {:<24} {:>4}  {:>6.2} / {:<4} {:>8}",
            f.name, f.depth, f.mean_occupancy, f.max_occupancy, f.full_cycles
        );
    }
    let m = &c.memory;
    println!(
        "  node memory: {} node + {} far + {} attr reads, {} bytes; {} on chip; cache hit rate {:.1}%; DRAM {} bytes = {:.1}% of peak; mean latency {:.1} cycles",
        m.node_fetches,
        m.far_fetches,
        m.attr_fetches,
        m.bytes,
        m.onchip_reads,
        100.0 * m.cache_hit_rate,
        m.dram_bytes,
        m.dram_bandwidth_pct,
        m.mean_latency
    );
    let o = &c.ops_per_pixel;
    println!(
        "  per pixel: {:.1} multiplies, {:.1} adds, {:.2} square roots, {:.2} reciprocals",
        o.multiplies, o.adds, o.square_roots, o.reciprocals
    );
    println!("  bound: {} — {}", c.bound.limit, c.bound.reason);
}

fn cmd_run(a: RunArgs) -> Result<()> {
    set_threads(a.scene.threads)?;
    let scene = load_scene(&a.scene, (None, None))?;
    let mut cfg = RunConfig {
        scene,
        depth: a.scene.depth,
        materialise: if a.scene.implicit {
            Materialise::Never
        } else {
            Materialise::Auto
        },
        options: RenderOptions {
            use_hit_buffer: !a.no_hit_buffer,
            early_termination: !a.no_early_termination,
        },
        out_dir: (!a.no_png).then(|| a.out.clone()),
        report_json: a.report_json.clone(),
        dump_hits: a.dump_hits.clone(),
        model: match a.model {
            ModelArg::Reference => Model::Reference,
            ModelArg::Fixed => Model::Fixed,
            ModelArg::Cycle => Model::Cycle,
        },
        datapath: load_datapath(a.datapath.as_ref())?,
        hardware: load_hw(a.hw.as_ref())?,
        cross_check: a.cross_check,
        vcd: match &a.vcd {
            None => None,
            Some(p) => Some(VcdRequest {
                path: p.clone(),
                window: match &a.vcd_pixels {
                    Some(t) => {
                        let (from, to) = parse_window("--vcd-pixels", t)?;
                        WaveWindow::Pixels {
                            frame: a.vcd_frame,
                            from,
                            to,
                        }
                    }
                    None => {
                        let (from, to) = parse_window("--vcd-cycles", &a.vcd_cycles)?;
                        WaveWindow::Cycles(from, to)
                    }
                },
            }),
        },
        transaction_log: a.transaction_log.clone().map(|p| (p, a.log_count)),
        progress_every: (!a.quiet).then(|| std::time::Duration::from_secs(2)),
        elaboration: None,
    };
    if cfg.model == Model::Cycle {
        let e = svo_sim::run::elaborate::elaborate(
            &cfg.scene,
            cfg.depth,
            &cfg.hardware,
            &cfg.datapath,
            cfg.options.use_hit_buffer,
        )?;
        let e = if a.no_prune { e.not_applied() } else { e };
        if !a.quiet {
            println!("{e}");
        }
        e.apply_to(&mut cfg);
    }
    let (w, h) = cfg.scene.file.resolution;
    println!(
        "sim: {} — {}x{}, {} frames, {} instances, {} threads, hit buffer {}, early termination {}",
        cfg.scene.origin,
        w,
        h,
        cfg.scene.file.frames,
        cfg.scene.file.instances.len(),
        rayon::current_num_threads(),
        if cfg.options.use_hit_buffer {
            "on"
        } else {
            "off"
        },
        if cfg.options.early_termination {
            "on"
        } else {
            "off"
        },
    );
    let quiet = a.quiet;
    let hw_mhz = cfg.hardware.clock_mhz;
    let out = run(&cfg, |st, n| {
        if !quiet {
            println!("{}", frame_line(&st.stats, n));
            if let Some(acc) = &st.accuracy {
                println!(
                    "           accuracy: {} px  hit/miss {}  instance {}  voxel {} ({} beyond bound)  t err max {:.3e} m rms {:.3e} m  saturations {}  step limits {}  zero flushes {}  reference {:.1} ms",
                    acc.pixels,
                    acc.hit_mismatches,
                    acc.instance_mismatches,
                    acc.voxel_mismatches,
                    acc.voxel_mismatches_beyond_bound,
                    acc.t_err_max,
                    acc.t_err_rms,
                    acc.saturations,
                    acc.step_limit_hits,
                    acc.zero_flushes,
                    st.reference_wall_s.unwrap_or(0.0) * 1e3
                );
            }
            if let Some(c) = &st.cycle {
                println!(
                    "           cycles {:>9}  {:>8.1} fps @ {} MHz  {:.3} rays/cycle (ideal 1)  walkers {:>3.0}% issuing {:>3.0}% on memory  cache hit {:>5.1}%  DRAM {:>4.1}% of peak  bound: {}",
                    c.cycles,
                    c.fps_at_clock,
                    hw_mhz,
                    c.rays_per_cycle,
                    100.0 * c.walkers.issuing as f64 / walker_cycles(c),
                    100.0 * c.walkers.memory_wait as f64 / walker_cycles(c),
                    100.0 * c.memory.cache_hit_rate,
                    c.memory.dram_bandwidth_pct,
                    c.bound.limit
                );
            }
        }
    })?;
    if let Some(last) = out.report.frames.last().and_then(|f| f.cycle.as_ref()) {
        if !quiet {
            print_cycle_tables(last);
        }
    }
    if !quiet {
        println!("assets:");
        for r in &out.report.assets {
            println!(
                "  {:<16} {:<3} depth {:>2}  nodes {:>9}  leaves {:>9}  far {:>5}  {:>8.2} MiB  built in {:.2} s",
                r.name,
                r.kind,
                r.depth,
                r.nodes,
                r.leaves,
                r.far_words,
                (r.node_bytes + r.attr_bytes) as f64 / (1 << 20) as f64,
                r.build_s
            );
        }
    }
    let s = &out.report.summary;
    println!(
        "summary: {} frames, {} rays in {:.3} s = {:.2} M rays/s; hit buffer reused {} pixels ({:.1}%); {} walker steps; assets built in {:.2} s",
        s.frames,
        s.rays,
        s.wall_s,
        s.rays_per_s / 1e6,
        s.hit_buffer_reused,
        100.0 * s.reuse_fraction,
        s.walker_steps,
        s.build_s
    );
    if let Some(c) = &s.cycle {
        println!(
            "cycle model: {} cycles = {:.1} fps at {} MHz (slowest frame {:.1} fps), {:.3} rays/cycle; bound: {}; simulated {:.2} M rays/s, {:.2} M cycles/s",
            c.cycles,
            c.fps_at_clock,
            c.clock_mhz,
            c.fps_at_clock_min,
            c.rays_per_cycle,
            c.bound,
            c.sim_rays_per_s / 1e6,
            c.sim_cycles_per_s / 1e6
        );
        println!("{}", c.resources);
    }
    if let Some(dir) = &cfg.out_dir {
        println!("wrote {} PNGs to {}", s.frames, dir.display());
    }
    if let Some(v) = &cfg.vcd {
        println!("wrote waveforms {}", v.path.display());
    }
    if let Some((p, _)) = &cfg.transaction_log {
        println!("wrote transaction log {}", p.display());
    }
    if let Some(p) = &cfg.report_json {
        println!("wrote report {}", p.display());
    }
    if let Some(p) = &cfg.dump_hits {
        println!("wrote hit records {}", p.display());
    }
    Ok(())
}

fn cmd_bench(a: BenchArgs) -> Result<()> {
    set_threads(a.scene.threads)?;
    let mut sa = a.scene.clone();
    sa.depth = sa.depth.or(Some(11));
    let scene = load_scene(&sa, (Some((1280, 768)), Some(8)))?;
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
    let mode = if sa.implicit {
        Materialise::Never
    } else {
        Materialise::Auto
    };
    let assets = build(&scene, sa.depth, mode)?;
    println!(
        "assets built in {:.2} s (excluded)",
        t.elapsed().as_secs_f64()
    );
    if a.model == ModelArg::Cycle {
        return bench_cycle(&a, &scene, &assets);
    }
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let mut results = Vec::new();
    for (label, hb) in [
        ("full trace (no hit buffer)", false),
        ("with hit buffer", true),
    ] {
        let mut buffer = HitBuffer::new(w, h);
        let opts = RenderOptions {
            use_hit_buffer: hb,
            early_termination: true,
        };
        let (mut rays, mut secs, mut first) = (0u64, 0f64, 0f64);
        for f in 0..scene.file.frames {
            let state = scene.frame_state(f, &half).map_err(anyhow::Error::msg)?;
            let st = render_frame(
                &FrameInput {
                    scene: &scene,
                    assets: &assets,
                    state: &state,
                },
                &mut buffer,
                opts,
            );
            if f == 0 {
                first = st.rays_per_s;
            }
            rays += st.rays;
            secs += st.wall_s;
        }
        println!(
            "  {label:<28} {:>6.2} M rays/s over {} frames (frame 0: {:.2} M rays/s)",
            rays as f64 / secs / 1e6,
            scene.file.frames,
            first / 1e6
        );
        results.push(rays as f64 / secs);
    }
    println!(
        "  hit-buffer speed-up: {:.2}x (same run)",
        results[1] / results[0]
    );
    if a.model == ModelArg::Fixed {
        let dp = load_datapath(a.datapath.as_ref())?;
        let repeat = a.repeat.max(1);
        let full = RenderOptions {
            use_hit_buffer: false,
            early_termination: true,
        };
        let (mut t_ref, mut t_fix) = (0f64, 0f64);
        println!(
            "  fixed-point model against the reference, full trace, best of {repeat} per frame:"
        );
        for f in 0..scene.file.frames {
            let state = scene.frame_state(f, &half).map_err(anyhow::Error::msg)?;
            let input = FrameInput {
                scene: &scene,
                assets: &assets,
                state: &state,
            };
            let (mut best_r, mut best_f) = (f64::INFINITY, f64::INFINITY);
            for _ in 0..repeat {
                let mut rb = HitBuffer::new(w, h);
                best_r = best_r.min(render_frame(&input, &mut rb, full).wall_s);
                let mut fb = FixedBuffer::new(w, h);
                best_f = best_f.min(render_frame_fixed(&input, &mut fb, &dp, false)?.wall_s);
            }
            println!(
                "    frame {f:>3}: reference {:>7.1} ms  fixed {:>7.1} ms  ratio {:.3}",
                best_r * 1e3,
                best_f * 1e3,
                best_r / best_f
            );
            t_ref += best_r;
            t_fix += best_f;
        }
        let rays = f64::from(w) * f64::from(h) * f64::from(scene.file.frames);
        println!(
            "  fixed {:.2} M rays/s, reference {:.2} M rays/s: ratio {:.3} (fixed rays/s ÷ reference rays/s; target ≥ 0.5)",
            rays / t_fix / 1e6,
            rays / t_ref / 1e6,
            t_ref / t_fix
        );
    }
    Ok(())
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

#[derive(Args, Debug)]
struct HardwareArgs {
    /// Configuration to print (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    hw: Option<PathBuf>,
    /// Datapath the hardware is checked against (RON); default: the documented default.
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
}

fn cmd_hardware(a: HardwareArgs) -> Result<()> {
    let hw = load_hw(a.hw.as_ref())?;
    let dp = load_datapath(a.datapath.as_ref())?;
    let pretty = ron::ser::PrettyConfig::new().struct_names(false);
    println!("// Hardware configuration of the cycle model (docs/cycle-model.md). Edit and pass with --hw.");
    println!("{}", ron::ser::to_string_pretty(&hw, pretty)?);
    hw.validate_for(&dp)
        .map_err(|m| anyhow::anyhow!("hardware configuration: {m}"))?;
    let r = hw
        .resources(&dp)
        .map_err(|m| anyhow::anyhow!("hardware configuration: {m}"))?;
    for line in r.to_string().lines() {
        println!("// {line}");
    }
    Ok(())
}

fn cmd_datapath(a: DatapathArgs) -> Result<()> {
    use rtl_model::fixed::{dsp48e2_per_product, Format};
    use rtl_model::units::{hit_record, reciprocal, sqrt, transform, walker};
    let cfg = load_datapath(a.datapath.as_ref())?;
    let pretty = ron::ser::PrettyConfig::new().struct_names(false);
    println!("// Datapath configuration (docs/number-formats.md). Edit and pass with --datapath.");
    println!("{}", ron::ser::to_string_pretty(&cfg, pretty)?);
    let wider = |f: Format| Format {
        width: f.width + 1,
        ..f
    };
    let sph = &cfg.sphere;
    let sphere_dsp = 3 * dsp48e2_per_product(wider(sph.pos), sph.dir)
        + 3 * dsp48e2_per_product(wider(sph.pos), wider(sph.pos))
        + dsp48e2_per_product(sph.tca, sph.tca);
    let walker_dsp = 6 * dsp48e2_per_product(wider(cfg.walker.pos), cfg.walker.inv);
    println!("// DSP48E2 slices per unit (27x18 products, sub-word decomposition):");
    println!("//   sphere test  {sphere_dsp:>4}  (l.d: 3, l.l: 3, t_ca^2: 1 products)");
    println!(
        "//   transform    {:>4}  (9 origin + 9 direction products)",
        transform::dsp48e2_count(&cfg.transform)
    );
    println!(
        "//   reciprocal   {:>4}  per axis (Newton-Raphson), x3 per walk",
        reciprocal::dsp48e2_count(&cfg.reciprocal)
    );
    println!("//   walker root  {walker_dsp:>4}  (6 slab products per walk; midpoints are adders)");
    println!(
        "//   square root     0  (digit recurrence: subtractors only); sorter 0; hit record 0"
    );
    let reach = cfg.sphere.reach;
    let rb = reciprocal::error_bound(&cfg.reciprocal);
    println!("// Error bounds (metres unless noted), derivations in docs/number-formats.md:");
    println!(
        "//   transform origin, |o - c| <= {reach} m : {:.3e}",
        transform::origin_error_bound(&cfg.transform, reach)
    );
    println!(
        "//   transform origin, |o - c| <= 20 m    : {:.3e}",
        transform::origin_error_bound(&cfg.transform, 20.0)
    );
    println!(
        "//   transform direction (per component) : {:.3e}",
        transform::dir_error_bound(&cfg.transform)
    );
    println!(
        "//   sphere p^2 widening W (m^2)         : {:.3e}",
        sph.widening()
    );
    println!(
        "//   sphere entry (earlier by at most)   : {:.3e}",
        sph.t_enter_error_bound(1.0)
    );
    println!(
        "//   reciprocal: relative {:.3e}, absolute {:.3e}, zero below |d| = {:.3e}",
        rb.rel,
        rb.abs,
        reciprocal::zero_threshold(&cfg.reciprocal)
    );
    let sq = sqrt::SqrtConfig::default();
    println!(
        "//   square root (default unit config)   : {:.3e}",
        sqrt::error_bound(&sq)
    );
    let dir_err = transform::dir_error_bound(&cfg.transform)
        + rb.rel
        + reciprocal::zero_threshold(&cfg.reciprocal);
    let spatial = walker::spatial_error_bound(
        &cfg.walker,
        transform::origin_error_bound(&cfg.transform, 20.0),
        dir_err,
        25.0,
        11,
    );
    println!("//   walker spatial, 20 m away, depth 11  : {spatial:.3e}");
    println!(
        "//   hit record t                        : {:.3e}",
        hit_record::t_error_bound(&cfg.hit_record)
    );
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.command {
        Some(Command::Bench(b)) => cmd_bench(b),
        Some(Command::Datapath(d)) => cmd_datapath(d),
        Some(Command::Hardware(h)) => cmd_hardware(h),
        Some(Command::Drift(d)) => svo_sim::studies::drift::cli::run_cli(&d),
        Some(Command::Vectors(v)) => svo_sim::studies::vectors::cli::run(v),
        Some(Command::Stress(s)) => svo_sim::studies::stress::cli::run_cli(&s),
        Some(Command::Sweep(s)) => svo_sim::studies::sweep::cli::run_cli(&s),
        None => cmd_run(cli.run),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_text(&e));
            ExitCode::FAILURE
        }
    }
}
