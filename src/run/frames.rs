//! A whole `sim` run: build the assets, render every frame with the chosen model (reference,
//! fixed or cycle), compare with the reference, write the outputs.
//!
//! Everything that can be checked is checked before the first file is written: the scene
//! (when loaded), depths, asset builds, output paths. The loop is shared by the three models:
//! each frame renders the reference, then the chosen model ([`super::frame_models`]), then
//! writes what the frame produced ([`super::run_files`], through the one output writer);
//! between frames it checks for SIGINT/SIGTERM.

use super::elaborate::Elaboration;
use super::frame_models::{FrameModel, FrameResult};
use super::ranges::check_scene_ranges;
use super::run_files::{write_cycle_files, write_report, RunFiles};
use crate::models::cycle::CycleFrame;
use crate::models::reference::{
    render_frame, render_frame_with_progress, FrameInput, FrameStats, HitBuffer, RenderOptions,
};
use crate::output::interrupt;
use crate::output::report::CycleSummary;
use crate::output::report::{
    AssetReport, FrameReport, OptionsReport, Report, SceneReport, Summary,
};
use crate::world::assets::{build_assets_in, effective_depths, Asset, Materialise};
use crate::world::scene::Scene;
use anyhow::Result;
use rtl_model::cost::FabricTotals;
use rtl_model::cost::ResourceReport;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::svo::ImageLayout;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// What to run and where to write.
#[derive(Clone, Debug)]
pub struct RunConfig {
    /// The validated scene (resolution and frames already overridden).
    pub scene: Scene,
    /// `--depth`: depth of the deepest asset.
    pub depth: Option<u8>,
    /// How SDF assets are stored.
    pub materialise: Materialise,
    /// How the memory images order their words (`--image-layout`).
    pub image_layout: ImageLayout,
    /// Renderer switches.
    pub options: RenderOptions,
    /// Folder for PNGs (`None`: no images).
    pub out_dir: Option<PathBuf>,
    /// JSON report path.
    pub report_json: Option<PathBuf>,
    /// Hit-record dump path (`.csv` for CSV, else binary).
    pub dump_hits: Option<PathBuf>,
    /// Print a progress line on stderr this often while a frame renders (`None`: never).
    pub progress_every: Option<Duration>,
    /// Which model renders the output.
    pub model: Model,
    /// Formats and parameters of the fixed-point datapath (used by `Model::Fixed` and
    /// `Model::Cycle`).
    pub datapath: DatapathConfig,
    /// The hardware the cycle model times (used by `Model::Cycle`).
    pub hardware: HwConfig,
    /// Re-execute every stage of the cycle model and compare with the functional model.
    pub cross_check: bool,
    /// Cycle model: sampled timing (`--sample`; docs/cycle-model.md §3.5).
    pub sample: Option<crate::models::cycle::sample::SampleConfig>,
    /// Waveforms of the cycle model.
    pub vcd: Option<VcdRequest>,
    /// Stage stamps of the first N records of the cycle model, written as JSON lines here.
    pub transaction_log: Option<(PathBuf, usize)>,
    /// The scene-driven elaboration behind `datapath`, `hardware` and the hit-buffer switch
    /// (`None`: none was made); its resource adjustments and report section come from here.
    pub elaboration: Option<Elaboration>,
}

impl RunConfig {
    /// This configuration running the pipeline of `e` (when applied; under `--no-prune` only
    /// reporting it): its hardware, datapath and hit-buffer switch, and the elaboration in the
    /// report. Elaboration decides from the scene and the configured hardware; the run only
    /// takes the result, so neither module depends on the other's types.
    pub fn elaborated(mut self, e: Elaboration) -> Self {
        if e.applied {
            self.hardware = e.hardware.clone();
            self.datapath = e.datapath.clone();
            self.options.use_hit_buffer = e.use_hit_buffer;
        }
        self.elaboration = Some(e);
        self
    }

    /// The files this configuration asks for, as the plain paths the output layer lists
    /// (`output::text::written`).
    pub fn destinations(&self) -> crate::output::text::Destinations<'_> {
        crate::output::text::Destinations {
            out_dir: self.out_dir.as_deref(),
            vcd: self.vcd.as_ref().map(|v| v.path.as_path()),
            transaction_log: self.transaction_log.as_ref().map(|(p, _)| p.as_path()),
            report_json: self.report_json.as_deref(),
            dump_hits: self.dump_hits.as_deref(),
            diff_pngs: self.model != Model::Reference,
        }
    }
}

/// The model whose records become the output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Model {
    /// The f64 reference.
    #[default]
    Reference,
    /// The functional fixed-point datapath, compared with the reference every frame.
    Fixed,
    /// The cycle-accurate pipeline: the functional fixed-point datapath timed clock by clock
    /// (bit-exact with `Fixed`), compared with the reference every frame.
    Cycle,
}

/// Waveform output of the cycle model.
#[derive(Clone, Debug)]
pub struct VcdRequest {
    /// File to write.
    pub path: PathBuf,
    /// Window.
    pub window: crate::models::cycle::waves::WaveWindow,
}

/// Renders a frame; if it runs longer than `every`, prints the share of rows done on stderr
/// at that interval, so long frames (huge resolutions, depth 16) show they are alive.
fn render_with_ticker(
    input: &FrameInput<'_>,
    buffer: &mut HitBuffer,
    opts: RenderOptions,
    frame: u32,
    frames: u32,
    every: Option<Duration>,
) -> FrameStats {
    let Some(every) = every else {
        return render_frame(input, buffer, opts);
    };
    let rows = u64::from(buffer.height);
    let done = AtomicU64::new(0);
    let finished = AtomicBool::new(false);
    std::thread::scope(|s| {
        s.spawn(|| {
            let start = Instant::now();
            let mut next = every;
            while !finished.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(50));
                if start.elapsed() >= next {
                    let d = done.load(Ordering::Relaxed);
                    eprintln!(
                        "  frame {frame}/{frames}: {:.0}% of rows after {:.0} s",
                        100.0 * d as f64 / rows as f64,
                        start.elapsed().as_secs_f64()
                    );
                    next += every;
                }
            }
        });
        let st = render_frame_with_progress(input, buffer, opts, &done);
        finished.store(true, Ordering::Relaxed);
        st
    })
}

/// Result of a run.
pub struct RunOutput {
    /// Built assets.
    pub assets: Vec<Asset>,
    /// Per-frame counters.
    pub frames: Vec<FrameStats>,
    /// The report (also written to `report_json` if set).
    pub report: Report,
    /// Final hit buffer (last frame's records).
    pub buffer: HitBuffer,
}

/// Builds the assets of a scene at the configured depths, images in `layout`.
pub fn build(
    scene: &Scene,
    depth: Option<u8>,
    mode: Materialise,
    layout: ImageLayout,
) -> Result<Vec<Asset>> {
    let depths = effective_depths(scene, depth)?;
    Ok(build_assets_in(scene, &depths, mode, layout)?)
}

/// Runs the chosen model over all frames and writes the outputs. `progress` is called after
/// each frame. Stops with `Interrupted` between frames once SIGINT or SIGTERM was received
/// (`crate::output::interrupt`); the frames finished so far keep their PNGs.
pub fn run(cfg: &RunConfig, mut progress: impl FnMut(&FrameReport, u32)) -> Result<RunOutput> {
    let resources = check(cfg)?;
    RunFiles::check(cfg)?;
    let (w, h) = cfg.scene.file.resolution;
    // Before the assets (a run that cannot fit is refused at once) and after them (their
    // memory is then no longer available); both before any output exists.
    super::memory::check(cfg.model, w, h)?;
    let build_start = Instant::now();
    let assets = build(&cfg.scene, cfg.depth, cfg.materialise, cfg.image_layout)?;
    let build_s = build_start.elapsed().as_secs_f64();
    super::memory::check(cfg.model, w, h)?;
    let scene = &cfg.scene;
    let frames = scene.file.frames;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    if cfg.model != Model::Reference {
        // Before any file: a scene the formats cannot carry is an input error, not a run.
        check_scene_ranges(scene, &half, &cfg.datapath)?;
    }
    let mut model = FrameModel::new(cfg, &assets)?;
    let mut files = RunFiles::open(cfg)?;
    let mut buffer = HitBuffer::new(w, h);
    let mut totals = Totals::default();
    for f in 0..frames {
        interrupt::check(|| format!("frame {f} of {frames}"), || files.kept())?;
        let state = scene
            .frame_state(f, &half)
            .map_err(|m| anyhow::anyhow!("frame {f}: {m}"))?;
        let input = FrameInput {
            scene,
            assets: &assets,
            state: &state,
        };
        let reference = render_with_ticker(
            &input,
            &mut buffer,
            cfg.options,
            f,
            frames,
            cfg.progress_every,
        );
        let done = model.frame(cfg, &input, f, &reference, &buffer.records)?;
        files.frame(cfg, f, &buffer.records, done.records.as_deref())?;
        progress(&done.report, frames);
        totals.add(done);
    }
    interrupt::check(
        || format!("the end of frame {frames} of {frames}, before the run's last files"),
        || files.kept(),
    )?;
    files.finish_dump()?;
    if let Some(cr) = model.cycle_run() {
        write_cycle_files(cfg, cr)?;
    }
    let stats = totals.stats.clone();
    let report = run_report(cfg, &assets, totals, resources, build_s);
    if let Some(p) = &cfg.report_json {
        write_report(p, &report)?;
    }
    Ok(RunOutput {
        assets,
        frames: stats,
        report,
        buffer,
    })
}

/// What the frames of a run add up to, for the report.
#[derive(Default)]
struct Totals {
    stats: Vec<FrameStats>,
    reports: Vec<FrameReport>,
    cycle_frames: Vec<CycleFrame>,
    sim_wall_s: f64,
}

impl Totals {
    fn add(&mut self, done: FrameResult) {
        self.sim_wall_s += done.sim_wall_s;
        self.cycle_frames.extend(done.cycles);
        self.stats.push(done.stats);
        self.reports.push(done.report);
    }
}

/// The run's report: scene, options, assets, the frames and their summary.
fn run_report(
    cfg: &RunConfig,
    assets: &[Asset],
    t: Totals,
    resources: Option<ResourceReport>,
    build_s: f64,
) -> Report {
    let scene = &cfg.scene;
    let (width, height) = scene.file.resolution;
    Report {
        tool: format!("svo_sim {}", env!("CARGO_PKG_VERSION")),
        scene: SceneReport {
            origin: scene.origin.clone(),
            width,
            height,
            frames: scene.file.frames,
            instances: scene.file.instances.len(),
        },
        options: OptionsReport {
            model: match cfg.model {
                Model::Reference => "reference".into(),
                Model::Fixed => "fixed".into(),
                Model::Cycle => "cycle".into(),
            },
            hit_buffer: cfg.options.use_hit_buffer,
            early_termination: cfg.options.early_termination,
            culling: cfg.options.culling,
            sort: cfg.options.sort,
            threads: rayon::current_num_threads(),
            image_layout: cfg.image_layout.name().into(),
        },
        assets: assets.iter().map(AssetReport::from).collect(),
        summary: Summary {
            cycle: resources.map(|r| {
                let fabric = cfg
                    .hardware
                    .fabric(&cfg.datapath)
                    .ok()
                    .map(|items| FabricTotals::of(&items, u64::from(cfg.hardware.part.luts)));
                CycleSummary::of(&t.cycle_frames, &cfg.hardware, r, fabric, t.sim_wall_s)
            }),
            ..Summary::of(&t.stats, build_s)
        },
        frames: t.reports,
        datapath: (cfg.model != Model::Reference).then(|| cfg.datapath.clone()),
        hardware: (cfg.model == Model::Cycle).then(|| cfg.hardware.clone()),
        elaboration: cfg.elaboration.clone(),
    }
}

/// Checks the options against the model and validates the configurations the model uses;
/// returns the cycle model's resource estimate.
fn check(cfg: &RunConfig) -> Result<Option<ResourceReport>> {
    if cfg.model != Model::Reference {
        cfg.datapath
            .validate()
            .map_err(|m| anyhow::anyhow!("datapath configuration: {m}"))?;
    }
    if cfg.model != Model::Cycle {
        return Ok(None);
    }
    cfg.hardware
        .validate_for(&cfg.datapath)
        .map_err(|m| anyhow::anyhow!("hardware configuration: {m}"))?;
    let mut r = cfg
        .hardware
        .resources(&cfg.datapath)
        .map_err(|m| anyhow::anyhow!("hardware configuration: {m}"))?;
    if let Some(tl) = cfg.elaboration.as_ref().and_then(|e| e.two_level) {
        let (hw, f) = (&cfg.hardware, &cfg.hardware.frame);
        r.push(rtl_model::units::tile_list::resource_item(
            &tl,
            hw.sphere_units,
            f.width,
            f.height,
        ));
    }
    Ok(Some(r))
}
