//! The sweep itself: every configuration over every scene through the cycle model, measured
//! against the f64 reference, then the Pareto fronts per scene.
//!
//! Pipeline position: the core of `sim sweep`, between the inputs ([`super::configs`], scenes)
//! and the outputs ([`super::output`], [`super::plot`]). Per scene the assets are built and the
//! reference renders every frame once (hit buffer and early termination on, as in `sim`); per
//! configuration a fresh cycle-model run (`CycleRun`, whose functional model is bit-exact with
//! the fixed-point model) renders the same frames on the hardware `HwConfig::for_datapath`
//! derives, so each unit's latency follows the configuration's formats.

use super::configs::{NamedConfig, DEFAULT_NAME};
use super::cost::{cost, Cost};
use super::measure::{ErrorSummary, ErrorTally};
use super::pareto::{distance, error_excess, on_front, Point};
use crate::models::cycle::runner::{CycleRun, CycleRunError};
use crate::models::cycle::CycleOptions;
use crate::models::fixed::to_hit_records;
use crate::models::reference::{render_frame, FrameInput, HitBuffer, HitRecord, RenderOptions};
use crate::run::parallel::map_in_order;
use crate::studies::scene_error::StudySceneError;
use crate::world::assets::{build_assets, effective_depths, Asset, Materialise};
use crate::world::scene::Scene;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use serde::Serialize;
use std::time::Instant;
use thiserror::Error;

/// Resolution and frames every scene is run at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct SweepOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Frames per scene.
    pub frames: u32,
    /// Octree depth of each scene's deepest asset (the others keep their offset to it, as
    /// `sim --depth`); `None`: the scenes' own depths.
    pub depth: Option<u8>,
}

/// A scene to sweep over, under the name the outputs use.
#[derive(Clone, Debug)]
pub struct NamedScene {
    /// Short name (`car` for the embedded scene, else the file's stem).
    pub name: String,
    /// The loaded scene (its resolution and frames are overridden by the options).
    pub scene: Scene,
}

/// Why a sweep cannot run.
#[derive(Debug, Error)]
pub enum SweepError {
    /// A scene cannot be loaded, set to the study's resolution and frames, built, or a
    /// frame's state computed.
    #[error(transparent)]
    Scene(#[from] StudySceneError),
    /// The hardware derived from a configuration is refused.
    #[error("configuration {config}: hardware: {message}")]
    Hardware {
        /// The configuration.
        config: String,
        /// What is wrong.
        message: String,
    },
    /// The cycle model refused or failed a frame.
    #[error("configuration {config} on scene {scene}: {source}")]
    Cycle {
        /// The configuration.
        config: String,
        /// The scene.
        scene: String,
        /// What failed.
        #[source]
        source: CycleRunError,
    },
    /// SIGINT or SIGTERM stopped the sweep (nothing is written).
    #[error("{0}")]
    Interrupted(#[from] crate::output::interrupt::Interrupted),
}

/// Where a row sits against one Pareto front (error against one cost) of its scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FrontPlace {
    /// On the front.
    pub on_front: bool,
    /// Relative distance to the front (a fraction, 0.05 = 5 %; `pareto::distance`).
    pub distance: f64,
    /// Share of the error a configuration of no greater cost avoids (a fraction;
    /// `pareto::error_excess`).
    pub excess: f64,
}

/// One (configuration, scene): its error, its cost and where it sits on the fronts.
#[derive(Clone, Debug, Serialize)]
pub struct SweepRow {
    /// Configuration name.
    pub config: String,
    /// Scene name.
    pub scene: String,
    /// Error against the f64 reference.
    pub error: ErrorSummary,
    /// Cycles per frame of the cycle model, the mean over the frames.
    pub cycles_per_frame: f64,
    /// Hardware cost.
    pub cost: Cost,
    /// Place against the front of error against cycles per frame.
    pub cycles_front: FrontPlace,
    /// Place against the front of error against DSP48E2.
    pub dsp_front: FrontPlace,
    /// Wall time of the simulation (functional and cycle model, all frames), seconds. The only
    /// figure that changes from run to run.
    pub wall_s: f64,
}

/// A scene as the outputs describe it.
#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    /// Name.
    pub name: String,
    /// Where it came from.
    pub origin: String,
    /// Instances.
    pub instances: usize,
    /// Edge of its smallest leaf (metres, before instance scale).
    pub leaf_edge: f64,
}

/// Where the configuration named `default` sits on one scene's fronts.
#[derive(Clone, Debug, Serialize)]
pub struct DefaultVerdict {
    /// Scene name.
    pub scene: String,
    /// Its place against the cycles front.
    pub cycles_front: FrontPlace,
    /// Its place against the DSP front.
    pub dsp_front: FrontPlace,
    /// Both distances ≤ 5 %.
    pub within_5_percent: bool,
}

/// A configuration as the outputs list it.
#[derive(Clone, Debug, Serialize)]
pub struct ConfigInfo {
    /// Name.
    pub name: String,
    /// The configuration (the `--datapath` RON format).
    pub datapath: DatapathConfig,
}

/// The whole sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepResult {
    /// Resolution and frames.
    pub options: SweepOptions,
    /// The scenes, in order.
    pub scenes: Vec<SceneInfo>,
    /// The configurations, in order.
    pub configs: Vec<ConfigInfo>,
    /// One row per (scene, configuration), scene-major.
    pub rows: Vec<SweepRow>,
    /// The default's position per scene (empty when no configuration is named `default`).
    pub default: Vec<DefaultVerdict>,
}

/// Edge of the smallest leaf of the assets (asset space).
fn leaf_edge(assets: &[Asset]) -> f64 {
    assets
        .iter()
        .map(|a| 2.0 * a.half_size / 2f64.powi(i32::from(a.depth())))
        .fold(f64::INFINITY, f64::min)
}

/// A scene prepared for the sweep: assets and the reference's records of every frame.
struct Prepared {
    scene: Scene,
    assets: Vec<Asset>,
    reference: Vec<Vec<HitRecord>>,
}

fn prepare(ns: &NamedScene, opts: SweepOptions) -> Result<Prepared, SweepError> {
    let scene_err = |source| StudySceneError::Scene {
        scene: ns.name.clone(),
        source,
    };
    let mut scene = ns.scene.clone();
    scene
        .set_resolution(opts.width, opts.height)
        .map_err(scene_err)?;
    scene.set_frames(opts.frames).map_err(scene_err)?;
    let asset_err = |source| StudySceneError::Asset {
        scene: ns.name.clone(),
        source,
    };
    let depths = effective_depths(&scene, opts.depth).map_err(asset_err)?;
    let assets = build_assets(&scene, &depths, Materialise::Auto).map_err(asset_err)?;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let mut buffer = HitBuffer::new(opts.width, opts.height);
    let mut reference = Vec::new();
    for f in 0..opts.frames {
        let state = scene
            .frame_state(f, &half)
            .map_err(|message| StudySceneError::Frame {
                scene: ns.name.clone(),
                frame: f,
                message,
            })?;
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &state,
        };
        render_frame(&input, &mut buffer, RenderOptions::default());
        reference.push(buffer.records.clone());
    }
    Ok(Prepared {
        scene,
        assets,
        reference,
    })
}

/// Runs one configuration over a prepared scene.
fn run_one(
    cfg: &NamedConfig,
    scene_name: &str,
    p: &Prepared,
    hw: &HwConfig,
    cost: &Cost,
) -> Result<SweepRow, SweepError> {
    let start = Instant::now();
    let dp = &cfg.datapath;
    let cycle_err = |source| SweepError::Cycle {
        config: cfg.name.clone(),
        scene: scene_name.into(),
        source,
    };
    let (w, h) = p.scene.file.resolution;
    let mut run = CycleRun::new(
        hw,
        dp,
        &p.assets,
        &p.scene.instance_asset,
        (w, h),
        CycleOptions::default(),
    )
    .map_err(cycle_err)?;
    let half: Vec<f64> = p.assets.iter().map(|a| a.half_size).collect();
    let mut tally = ErrorTally::default();
    let mut cycles = 0u64;
    for (f, reference) in (0..).zip(&p.reference) {
        let state = p
            .scene
            .frame_state(f, &half)
            .map_err(|message| StudySceneError::Frame {
                scene: scene_name.into(),
                frame: f,
                message,
            })?;
        let input = FrameInput {
            scene: &p.scene,
            assets: &p.assets,
            state: &state,
        };
        let r = run.frame(&input, dp, true).map_err(cycle_err)?;
        let ov = r.fixed.overflows.unwrap_or_else(overflow_table);
        let saturations = ov.total() - ov.count(signals::WALKER_STEP_LIMIT);
        tally.add_frame(reference, &to_hit_records(run.buffer(), dp), saturations);
        cycles += r.cycles.cycles;
    }
    Ok(SweepRow {
        config: cfg.name.clone(),
        scene: scene_name.into(),
        error: tally.summary(leaf_edge(&p.assets)),
        cycles_per_frame: cycles as f64 / p.reference.len().max(1) as f64,
        cost: cost.clone(),
        cycles_front: FrontPlace::default(),
        dsp_front: FrontPlace::default(),
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// Marks the fronts and distances of one scene's rows.
fn place_on_fronts(rows: &mut [SweepRow]) {
    let pts = |c: fn(&SweepRow) -> f64| -> Vec<Point> {
        rows.iter()
            .map(|r| Point {
                error: r.error.error_score,
                cost: c(r),
            })
            .collect()
    };
    let places = |p: &[Point]| -> Vec<FrontPlace> {
        let (f, d, x) = (on_front(p), distance(p), error_excess(p));
        (0..p.len())
            .map(|k| FrontPlace {
                on_front: f[k],
                distance: d[k],
                excess: x[k],
            })
            .collect()
    };
    let cyc = places(&pts(|r| r.cycles_per_frame));
    let dsp = places(&pts(|r| r.cost.dsp48e2 as f64));
    for ((r, c), d) in rows.iter_mut().zip(cyc).zip(dsp) {
        r.cycles_front = c;
        r.dsp_front = d;
    }
}

/// Runs every configuration on every scene; `progress` sees each row as it is measured
/// (before the fronts are known).
pub fn run_sweep(
    configs: &[NamedConfig],
    scenes: &[NamedScene],
    opts: SweepOptions,
    mut progress: impl FnMut(&SweepRow),
) -> Result<SweepResult, SweepError> {
    let mut hardware = Vec::with_capacity(configs.len());
    for c in configs {
        let hw = HwConfig::for_datapath(&c.datapath);
        let k = cost(&c.datapath, &hw).map_err(|message| SweepError::Hardware {
            config: c.name.clone(),
            message,
        })?;
        hardware.push((hw, k));
    }
    let mut rows = Vec::new();
    let mut infos = Vec::new();
    let mut verdicts = Vec::new();
    for ns in scenes {
        let p = prepare(ns, opts)?;
        infos.push(SceneInfo {
            name: ns.name.clone(),
            origin: ns.scene.origin.clone(),
            instances: p.scene.file.instances.len(),
            leaf_edge: leaf_edge(&p.assets),
        });
        // The configurations run on all cores; rows and progress come in the sequential
        // order (`run::parallel::map_in_order`), so the output is that of a sequential loop.
        let jobs: Vec<usize> = (0..configs.len()).collect();
        let mut mine = map_in_order(
            "configuration",
            &jobs,
            |&c| {
                let (hw, k) = &hardware[c];
                run_one(&configs[c], &ns.name, &p, hw, k)
            },
            |row| progress(row),
        )?;
        place_on_fronts(&mut mine);
        if let Some(d) = mine.iter().find(|r| r.config == DEFAULT_NAME) {
            verdicts.push(DefaultVerdict {
                scene: ns.name.clone(),
                cycles_front: d.cycles_front,
                dsp_front: d.dsp_front,
                within_5_percent: d.cycles_front.distance <= 0.05 && d.dsp_front.distance <= 0.05,
            });
        }
        rows.extend(mine);
    }
    Ok(SweepResult {
        options: opts,
        scenes: infos,
        configs: configs
            .iter()
            .map(|c| ConfigInfo {
                name: c.name.clone(),
                datapath: c.datapath.clone(),
            })
            .collect(),
        rows,
        default: verdicts,
    })
}
