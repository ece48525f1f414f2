//! A whole `sim` run: build the assets, render every frame with the chosen model (reference,
//! fixed or cycle), compare with the reference, write the outputs.
//!
//! Everything that can be checked is checked before the first file is written: the scene
//! (when loaded), depths, asset builds, output folders. Each output file is written
//! atomically.

use super::elaborate::Elaboration;
use super::ranges::check_scene_ranges;
use crate::models::cycle::runner::CycleRun;
use crate::models::cycle::waves::PipelineWaves;
use crate::models::cycle::CycleOptions;
use crate::models::fixed::bound::mismatch_explained;
use crate::models::fixed::{
    compare, diff_image, render_frame_fixed, to_hit_records, FixedBuffer, FixedStats,
};
use crate::models::reference::{
    render_frame, render_frame_with_progress, FrameInput, FrameStats, HitBuffer, RenderOptions,
};
use crate::output::atomic::{write_atomic, AtomicFile};
use crate::output::report::CycleSummary;
use crate::output::report::{
    AssetReport, FrameReport, OptionsReport, Report, SceneReport, Summary,
};
use crate::output::{dump, png};
use crate::world::assets::{build_assets, effective_depths, Asset, Materialise};
use crate::world::scene::Scene;
use anyhow::{bail, Context, Result};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use std::io::Write;
use std::path::{Path, PathBuf};
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

/// A fixed-point frame's counters in the reference's report shape.
fn fixed_frame_stats(frame: u32, fx: &FixedStats, reference: &FrameStats) -> FrameStats {
    FrameStats {
        frame,
        rays: fx.rays,
        sphere_tests: fx.sphere_tests,
        spheres_culled: fx.spheres_culled,
        candidates: fx.candidates,
        candidates_max: reference.candidates_max,
        walks: fx.walks,
        walker_steps: fx.walker.steps,
        node_fetches: fx.walker.fetches,
        max_stack: fx.walker.max_stack,
        early_terminations: fx.early_terminations,
        walks_skipped: 0,
        hit_buffer_reused: fx.hit_buffer_reused,
        hits: fx.hits,
        camera_dirty: reference.camera_dirty,
        instances_dirty: reference.instances_dirty,
        wall_s: fx.wall_s,
        rays_per_s: fx.rays as f64 / fx.wall_s.max(1e-9),
    }
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

fn check_parent(path: &Path, what: &str) -> Result<()> {
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !parent.is_dir() {
        bail!(
            "{what} {}: folder {} does not exist",
            path.display(),
            parent.display()
        );
    }
    if path.is_dir() {
        bail!("{what} {} is a folder", path.display());
    }
    Ok(())
}

/// Builds the assets of a scene at the configured depths.
pub fn build(scene: &Scene, depth: Option<u8>, mode: Materialise) -> Result<Vec<Asset>> {
    let depths = effective_depths(scene, depth)?;
    Ok(build_assets(scene, &depths, mode)?)
}

/// Runs the reference over all frames. `progress` is called after each frame.
pub fn run(cfg: &RunConfig, mut progress: impl FnMut(&FrameReport, u32)) -> Result<RunOutput> {
    if cfg.model != Model::Reference && !cfg.options.early_termination {
        bail!("--no-early-termination applies to --model reference only: the fixed-point and cycle models are the hardware, which always terminates early");
    }
    if cfg.model != Model::Reference {
        cfg.datapath
            .validate()
            .map_err(|m| anyhow::anyhow!("datapath configuration: {m}"))?;
    }
    let resources = if cfg.model == Model::Cycle {
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
        Some(r)
    } else {
        None
    };
    if let Some(v) = &cfg.vcd {
        check_parent(&v.path, "--vcd")?;
    }
    if let Some((p, _)) = &cfg.transaction_log {
        check_parent(p, "--transaction-log")?;
    }
    if let Some(p) = &cfg.report_json {
        check_parent(p, "--report-json")?;
    }
    if let Some(p) = &cfg.dump_hits {
        check_parent(p, "--dump-hits")?;
    }
    let (w, h) = cfg.scene.file.resolution;
    // Before the assets (a run that cannot fit is refused at once) and after them (their
    // memory is then no longer available); both before any output exists.
    super::memory::check(cfg.model, w, h)?;
    let build_start = Instant::now();
    let assets = build(&cfg.scene, cfg.depth, cfg.materialise)?;
    let build_s = build_start.elapsed().as_secs_f64();
    super::memory::check(cfg.model, w, h)?;
    let scene = &cfg.scene;
    let frames = scene.file.frames;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    if cfg.model != Model::Reference {
        // Before any file: a scene the formats cannot carry is an input error, not a run.
        check_scene_ranges(scene, &half, &cfg.datapath)?;
    }
    let csv = cfg
        .dump_hits
        .as_ref()
        .is_some_and(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")));
    let mut dump_file = match &cfg.dump_hits {
        Some(p) => {
            let mut f =
                AtomicFile::create(p).with_context(|| format!("cannot create {}", p.display()))?;
            if csv {
                writeln!(f.writer(), "{}", dump::CSV_HEADER)?;
            } else {
                dump::write_header(f.writer(), w, h, frames)?;
            }
            Some(f)
        }
        None => None,
    };
    let mut buffer = HitBuffer::new(w, h);
    let mut fixed_buffer = FixedBuffer::new(w, h);
    let mut cycle_run = if cfg.model == Model::Cycle {
        let waves = match &cfg.vcd {
            Some(v) => Some(
                PipelineWaves::new(
                    cfg.hardware.clock_mhz,
                    v.window,
                    cfg.hardware.walker_pool.walkers,
                    cfg.hardware.walker_pool.contexts_per_walker,
                )
                .map_err(|e| anyhow::anyhow!("--vcd: {e}"))?,
            ),
            None => None,
        };
        let mut run = CycleRun::new(
            &cfg.hardware,
            &cfg.datapath,
            &assets,
            &scene.instance_asset,
            (w, h),
            CycleOptions {
                cross_check: cfg.cross_check,
                sample: cfg.sample,
                waves,
                log_limit: cfg.transaction_log.as_ref().map_or(0, |(_, n)| *n),
                ..CycleOptions::default()
            },
        )?;
        // The two-level instance scheme, when elaboration keeps it (docs/instances.md §7).
        run.set_two_level(cfg.elaboration.as_ref().and_then(|e| e.two_level));
        Some(run)
    } else {
        None
    };
    let mut cycle_frames = Vec::new();
    if let Some(dir) = &cfg.out_dir {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))?;
    }
    let mut sim_wall = 0.0f64;
    let mut stats = Vec::with_capacity(frames as usize);
    let mut reports = Vec::with_capacity(frames as usize);
    for f in 0..frames {
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
        let (st, report, fixed_records) = match cfg.model {
            Model::Reference => (reference.clone(), FrameReport::of(reference), None),
            Model::Fixed | Model::Cycle => {
                let (fx, cyc, fbuf) = match cycle_run.as_mut() {
                    Some(cr) => {
                        // A pipeline without a hit buffer (`hit_buffer.present: false`)
                        // traces every pixel, whatever the reuse switch says.
                        let reuse = cfg.options.use_hit_buffer && cfg.hardware.hit_buffer.present;
                        let r = cr.frame(&input, &cfg.datapath, reuse)?;
                        sim_wall += r.wall_s;
                        (r.fixed, Some(r.cycles), cr.buffer())
                    }
                    None => (
                        render_frame_fixed(
                            &input,
                            &mut fixed_buffer,
                            &cfg.datapath,
                            cfg.options.use_hit_buffer,
                        )?,
                        None,
                        &fixed_buffer,
                    ),
                };
                let records = to_hit_records(fbuf, &cfg.datapath);
                let depths: Vec<u8> = assets.iter().map(Asset::depth).collect();
                let mut acc = compare(&buffer.records, &records, |k| {
                    let (i, j) = (k as u32 % w, k as u32 / w);
                    let inst = usize::from(records[k].instance);
                    let pose = &state.poses[inst];
                    let depth = depths[scene.instance_asset[inst]];
                    mismatch_explained(
                        &cfg.datapath,
                        &state.camera,
                        (w, h),
                        (i, j),
                        pose,
                        records[k].voxel,
                        depth,
                    )
                });
                let ov = fx.overflows.clone().unwrap_or_else(overflow_table);
                acc.saturations = ov.total() - ov.count(signals::WALKER_STEP_LIMIT);
                acc.step_limit_hits = fx.walker.step_limit_hits;
                acc.zero_flushes = fx.zero_flushes;
                let st = fixed_frame_stats(f, &fx, &reference);
                let mut report = FrameReport::of(st.clone());
                report.overflows = Some(ov.nonzero().map(|(n, c)| (n.to_string(), c)).collect());
                report.reference_wall_s = Some(reference.wall_s);
                report.accuracy = Some(acc);
                if let Some(c) = cyc {
                    cycle_frames.push(c.clone());
                    report.cycle = Some(c);
                }
                if let Some(dir) = &cfg.out_dir {
                    let img = diff_image(&buffer.records, &records, w, h, 1e-6);
                    let path = dir.join(format!("diff_{f:04}.png"));
                    write_atomic(&path, &png::encode_png(&img)?)
                        .with_context(|| format!("cannot write {}", path.display()))?;
                }
                (st, report, Some(records))
            }
        };
        let out_records = fixed_records.as_deref().unwrap_or(&buffer.records);
        if let Some(dir) = &cfg.out_dir {
            let l = &scene.file.light;
            let img = png::shade(
                out_records,
                w,
                h,
                l.direction,
                l.ambient,
                scene.file.background,
            );
            let bytes = png::encode_png(&img)?;
            let path = dir.join(format!("frame_{f:04}.png"));
            write_atomic(&path, &bytes)
                .with_context(|| format!("cannot write {}", path.display()))?;
        }
        if let Some(df) = dump_file.as_mut() {
            if csv {
                dump::write_frame_csv(df.writer(), f, w, out_records)?;
            } else {
                dump::write_frame(df.writer(), f, w, out_records)?;
            }
        }
        progress(&report, frames);
        stats.push(st);
        reports.push(report);
    }
    if let Some(df) = dump_file {
        df.commit().context("cannot finish the hit dump")?;
    }
    if let Some(cr) = cycle_run.as_mut() {
        if let Some(v) = &cfg.vcd {
            if let Some(waves) = cr.model().take_waves() {
                waves
                    .write(&v.path)
                    .with_context(|| format!("cannot write --vcd {}", v.path.display()))?;
            }
        }
        if let Some((p, _)) = &cfg.transaction_log {
            let mut text = String::new();
            for (pixel, stamps) in &cr.model().log {
                let line = serde_json::json!({
                    "pixel": pixel,
                    "x": pixel % w,
                    "y": pixel / w,
                    "stages": stamps.iter().map(|s| serde_json::json!({
                        "stage": crate::models::cycle::pipeline::STAGE_NAMES
                            .get(usize::from(s.stage.0)).copied().unwrap_or("?"),
                        "entered": s.entered,
                        "left": s.left,
                    })).collect::<Vec<_>>(),
                });
                text.push_str(&line.to_string());
                text.push('\n');
            }
            write_atomic(p, text.as_bytes())
                .with_context(|| format!("cannot write {}", p.display()))?;
        }
    }
    let report = Report {
        tool: format!("svo_sim {}", env!("CARGO_PKG_VERSION")),
        scene: SceneReport {
            origin: scene.origin.clone(),
            width: w,
            height: h,
            frames,
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
            threads: rayon::current_num_threads(),
        },
        assets: assets.iter().map(AssetReport::from).collect(),
        summary: Summary {
            cycle: resources.map(|r| CycleSummary::of(&cycle_frames, &cfg.hardware, r, sim_wall)),
            ..Summary::of(&stats, build_s)
        },
        frames: reports,
        datapath: (cfg.model != Model::Reference).then(|| cfg.datapath.clone()),
        hardware: (cfg.model == Model::Cycle).then(|| cfg.hardware.clone()),
        elaboration: cfg.elaboration.clone(),
    };
    if let Some(p) = &cfg.report_json {
        let text = serde_json::to_string_pretty(&report)?;
        write_atomic(p, text.as_bytes())
            .with_context(|| format!("cannot write {}", p.display()))?;
    }
    Ok(RunOutput {
        assets,
        frames: stats,
        report,
        buffer,
    })
}
