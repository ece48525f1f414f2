//! The evaluation of `sim explore`: every point of the space on every scene through the cycle
//! model, priced by the resource and fabric estimates, checked against the part's budget, and
//! placed on the Pareto fronts of fps against each resource.
//!
//! Pipeline position: between the space ([`super::space`]) and the outputs ([`super::output`],
//! [`super::plot`]). Per scene the assets are built once; the points run on all cores
//! (`run::parallel::map_in_order`), each a fresh `CycleRun` of its hardware on the default
//! datapath elaborated for the scene as `sim` elaborates it (`run::elaborate`: units the scene
//! does not need are dropped, many instances take the two-level scheme), timed and priced as
//! elaborated, with the instance lists' memory. Rows come back in the points' order, so the
//! result does not depend on the thread count.

use super::space::{Point, SceneSpec, Space};
use crate::models::cycle::runner::{CycleRun, CycleRunError, RecordedFrame};
use crate::models::cycle::sample::{SampleConfig, DEFAULT_BAND_ROWS};
use crate::models::cycle::CycleOptions;
use crate::models::reference::FrameInput;
use crate::run::elaborate::{analyse, plan};
use crate::run::parallel::map_in_order;
use crate::studies::scene_error::StudySceneError;
use crate::world::assets::{build_assets, effective_depths, Asset, Materialise};
use crate::world::scene::Scene;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use serde::Serialize;
use thiserror::Error;

/// Share of the part's LUTs (and flip-flops, two per LUT) a fitting design may use: above
/// about 70 % a design of this size stops routing at 300 MHz.
pub const LUT_BUDGET: f64 = 0.70;
/// Share of the part's DSP48E2, BRAM36 and URAM288 a fitting design may use.
pub const BLOCK_BUDGET: f64 = 0.90;

/// The resources a row reports, in the order of the fronts and plots.
pub const RESOURCES: [&str; 5] = ["LUT", "FF", "DSP48E2", "BRAM36", "URAM288"];

/// Why an exploration cannot run.
#[derive(Debug, Error)]
pub enum ExploreError {
    /// A scene cannot be loaded, set to the study's resolution and frames, built, or a
    /// frame's state computed.
    #[error(transparent)]
    Scene(#[from] StudySceneError),
    /// The estimate refused a point's hardware.
    #[error("point {point}: {message}")]
    Estimate {
        /// The point.
        point: usize,
        /// What is wrong.
        message: String,
    },
    /// The cycle model refused or failed a point.
    #[error("point {point} ({fields}) on scene {scene}: {source}")]
    Cycle {
        /// The point.
        point: usize,
        /// Its field values.
        fields: String,
        /// The scene.
        scene: String,
        /// What failed.
        #[source]
        source: CycleRunError,
    },
    /// SIGINT or SIGTERM stopped the exploration (nothing is written).
    #[error("{0}")]
    Interrupted(#[from] crate::output::interrupt::Interrupted),
}

/// What a point's hardware uses, and whether it fits.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Usage {
    /// LUT, FF, DSP48E2, BRAM36, URAM288 used (the order of [`RESOURCES`]).
    pub used: [u64; 5],
    /// The same the part has (FF: two per LUT).
    pub available: [u64; 5],
    /// Within the budget: LUT and FF ≤ 70 %, the hard blocks ≤ 90 %.
    pub fits: bool,
    /// Why not, one clause per resource over budget ("" when it fits).
    pub why: String,
}

/// The usage of `hw` on datapath `dp`: the resource estimate's hard blocks and the fabric
/// estimate's LUTs and flip-flops.
pub fn usage(hw: &HwConfig, dp: &DatapathConfig) -> Result<Usage, String> {
    usage_with_lists(hw, dp, None)
}

/// [`usage`], with the two-level instance scheme's list memory when elaboration chose it
/// (`units::tile_list::resource_item`, as the run's resource table adds it).
pub fn usage_with_lists(
    hw: &HwConfig,
    dp: &DatapathConfig,
    lists: Option<&rtl_model::units::tile_list::TileListConfig>,
) -> Result<Usage, String> {
    let mut r = hw.resources(dp)?;
    if let Some(tl) = lists {
        let f = &hw.frame;
        r.push(rtl_model::units::tile_list::resource_item(
            tl,
            hw.sphere_units,
            f.width,
            f.height,
        ));
    }
    let fabric = rtl_model::cost::FabricTotals::of(&hw.fabric(dp)?, u64::from(hw.part.luts));
    let (lut, ff) = (fabric.lut, fabric.ff);
    let luts = u64::from(hw.part.luts);
    let used = [lut, ff, r.used.dsp48e2, r.used.bram36, r.used.uram288];
    let available = [
        luts,
        luts.saturating_mul(2),
        r.available.dsp48e2,
        r.available.bram36,
        r.available.uram288,
    ];
    let mut why = Vec::new();
    for k in 0..5 {
        let share = if k < 2 { LUT_BUDGET } else { BLOCK_BUDGET };
        let limit = share * available[k] as f64;
        if used[k] as f64 > limit {
            why.push(format!(
                "{} {} > {:.0} % of {}",
                RESOURCES[k],
                used[k],
                100.0 * share,
                available[k]
            ));
        }
    }
    Ok(Usage {
        used,
        available,
        fits: why.is_empty(),
        why: why.join("; "),
    })
}

/// One (point, scene).
#[derive(Clone, Debug, Serialize)]
pub struct ExploreRow {
    /// The point's id (0: the base hardware added to the space).
    pub point: usize,
    /// The scene's name.
    pub scene: String,
    /// The point's field values, in the space's field order.
    pub values: Vec<String>,
    /// Whether the point is the base hardware.
    pub default: bool,
    /// Cycles per frame, the mean over the frames (an estimate under sampled timing).
    pub cycles_per_frame: f64,
    /// Frames per second at the point's clock and the scene's resolution.
    pub fps: f64,
    /// Pixels per clock.
    pub rays_per_clock: f64,
    /// Resources and fit.
    pub usage: Usage,
    /// On the Pareto front of fps against each resource (the order of [`RESOURCES`]).
    pub front: [bool; 5],
    /// The fitting point of highest fps on this scene.
    pub best: bool,
}

/// A scene as the outputs describe it.
#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    /// Name (`car`, or the file's stem).
    pub name: String,
    /// The space's entry.
    pub spec: SceneSpec,
    /// Instances.
    pub instances: usize,
}

/// The whole exploration.
#[derive(Clone, Debug, Serialize)]
pub struct ExploreResult {
    /// The explored field paths, in order.
    pub fields: Vec<String>,
    /// The scenes.
    pub scenes: Vec<SceneInfo>,
    /// Sampled timing, if any.
    pub sample: Option<super::space::SampleSpec>,
    /// One row per (scene, point), scene-major.
    pub rows: Vec<ExploreRow>,
}

/// A scene ready to run: the scene at the space's resolution and frames, and its assets.
struct Prepared {
    scene: Scene,
    assets: Vec<Asset>,
    facts: crate::models::cycle::elaboration::SceneFacts,
}

fn scene_name(spec: &SceneSpec, taken: &[SceneInfo]) -> String {
    let base = if spec.path == "car" {
        "car".to_string()
    } else {
        std::path::Path::new(&spec.path)
            .file_stem()
            .map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned())
    };
    let mut name = base.clone();
    let mut k = 2;
    while taken.iter().any(|t| t.name == name) {
        name = format!("{base}_{k}");
        k += 1;
    }
    name
}

fn prepare(spec: &SceneSpec, name: &str, max_vox_bytes: u64) -> Result<Prepared, ExploreError> {
    let scene_err = |source| StudySceneError::Scene {
        scene: name.into(),
        source,
    };
    let mut scene = if spec.path == "car" {
        Scene::default_car().map_err(scene_err)?
    } else {
        let mut s = Scene::load(std::path::Path::new(&spec.path)).map_err(scene_err)?;
        s.max_vox_bytes = max_vox_bytes;
        s
    };
    scene
        .set_resolution(spec.width, spec.height)
        .map_err(scene_err)?;
    scene.set_frames(spec.frames).map_err(scene_err)?;
    let asset_err = |source| StudySceneError::Asset {
        scene: name.into(),
        source,
    };
    let depths = effective_depths(&scene, spec.depth).map_err(asset_err)?;
    let assets = build_assets(&scene, &depths, Materialise::Auto).map_err(asset_err)?;
    let facts =
        analyse::analyse(&scene, spec.depth, &DatapathConfig::default()).map_err(asset_err)?;
    Ok(Prepared {
        scene,
        assets,
        facts,
    })
}

/// What a point's functional trace depends on besides the scene: points that share it are
/// timed on one recorded trace ([`CycleRun::frame_replayed`]).
#[derive(PartialEq)]
struct TraceIdentity {
    datapath: DatapathConfig,
    use_hit_buffer: bool,
    two_level: Option<rtl_model::units::tile_list::TileListConfig>,
    sphere_units: u32,
}

impl TraceIdentity {
    fn of(e: &plan::Plan) -> Self {
        Self {
            datapath: e.datapath.clone(),
            use_hit_buffer: e.use_hit_buffer,
            two_level: e.two_level,
            sphere_units: e.hardware.sphere_units,
        }
    }
}

/// How a point's frames get their functional trace.
enum Trace<'a> {
    /// Rendered by the functional model as the cycle model runs, and kept, one per frame.
    Record(&'a mut Vec<RecordedFrame>),
    /// Recorded by another point of the same [`TraceIdentity`].
    Replay(&'a [RecordedFrame]),
}

/// Mean cycles per frame of the elaborated hardware `e` over the prepared scene.
fn cycles_per_frame(
    p: &Prepared,
    e: &plan::Plan,
    sample: Option<SampleConfig>,
    fail: &dyn Fn(CycleRunError) -> ExploreError,
    name: &str,
    mut trace: Trace<'_>,
) -> Result<f64, ExploreError> {
    let (w, h) = p.scene.file.resolution;
    let opts = CycleOptions {
        sample,
        ..CycleOptions::default()
    };
    let (hw, dp) = (&e.hardware, &e.datapath);
    let mut run =
        CycleRun::new(hw, dp, &p.assets, &p.scene.instance_asset, (w, h), opts).map_err(fail)?;
    run.set_two_level(e.two_level);
    let half: Vec<f64> = p.assets.iter().map(|a| a.half_size).collect();
    let mut cycles = 0u64;
    let frames = p.scene.file.frames;
    for f in 0..frames {
        let state = p
            .scene
            .frame_state(f, &half)
            .map_err(|message| StudySceneError::Frame {
                scene: name.into(),
                frame: f,
                message,
            })?;
        let input = FrameInput {
            scene: &p.scene,
            assets: &p.assets,
            state: &state,
        };
        cycles += match &mut trace {
            Trace::Record(kept) => {
                let (result, recorded) = run
                    .frame_recorded(&input, dp, e.use_hit_buffer)
                    .map_err(fail)?;
                kept.push(recorded);
                result.cycles.cycles
            }
            Trace::Replay(recorded) => {
                let recorded = recorded.get(f as usize).ok_or_else(|| {
                    fail(CycleRunError::Config(format!("frame {f} was not recorded")))
                })?;
                run.frame_replayed(&input, dp, e.use_hit_buffer, recorded)
                    .map_err(fail)?
                    .cycles
            }
        };
    }
    Ok(cycles as f64 / f64::from(frames.max(1)))
}

/// Marks each scene's fronts and best fitting point.
fn place(rows: &mut [ExploreRow]) {
    for k in 0..RESOURCES.len() {
        let on: Vec<bool> = rows
            .iter()
            .map(|r| {
                !rows.iter().any(|o| {
                    o.fps >= r.fps
                        && o.usage.used[k] <= r.usage.used[k]
                        && (o.fps > r.fps || o.usage.used[k] < r.usage.used[k])
                })
            })
            .collect();
        for (r, f) in rows.iter_mut().zip(on) {
            r.front[k] = f;
        }
    }
    // Highest fps; among equals the fewest LUTs, then the first point.
    let best = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| r.usage.fits)
        .min_by(|(a, x), (b, y)| {
            y.fps
                .total_cmp(&x.fps)
                .then(x.usage.used[0].cmp(&y.usage.used[0]))
                .then(a.cmp(b))
        })
        .map(|(k, _)| k);
    if let Some(k) = best {
        rows[k].best = true;
    }
}

/// Runs every point on every scene with datapath `dp`; `progress` sees each row (before the
/// fronts are placed) in order, with its position and the total.
pub fn run_explore(
    space: &Space,
    points: &[Point],
    dp: &DatapathConfig,
    max_vox_bytes: u64,
    mut progress: impl FnMut(&ExploreRow, usize, usize),
) -> Result<ExploreResult, ExploreError> {
    let sample = space.sample.map(|s| SampleConfig {
        period: (1.0 / s.rate).round() as u32,
        band_rows: s.band_rows.unwrap_or(DEFAULT_BAND_ROWS),
        warm_rows: None,
        seed: s.seed,
    });
    let total = points.len() * space.scenes.len();
    let mut done = 0usize;
    let mut rows = Vec::with_capacity(total);
    let mut infos: Vec<SceneInfo> = Vec::new();
    for spec in &space.scenes {
        let name = scene_name(spec, &infos);
        let prepared = prepare(spec, &name, max_vox_bytes)?;
        infos.push(SceneInfo {
            name: name.clone(),
            spec: spec.clone(),
            instances: prepared.scene.file.instances.len(),
        });
        let pixels = f64::from(spec.width) * f64::from(spec.height);
        // The hardware `sim` would run for this scene: scene-driven elaboration
        // (docs/elaboration.md) of each point's hardware, timed and priced as built.
        let plans: Vec<plan::Plan> = points
            .iter()
            .map(|p| plan::plan(&prepared.facts, &p.hw, dp, true))
            .collect();
        let row = |k: usize, trace: Trace<'_>| {
            let (p, e) = (&points[k], &plans[k]);
            let fail = |source| ExploreError::Cycle {
                point: p.id,
                fields: space.describe_values(&p.values),
                scene: name.clone(),
                source,
            };
            let estimate = |message| ExploreError::Estimate {
                point: p.id,
                message,
            };
            e.hardware.validate_for(&e.datapath).map_err(estimate)?;
            let u = usage_with_lists(&e.hardware, &e.datapath, e.two_level.as_ref())
                .map_err(estimate)?;
            let c = cycles_per_frame(&prepared, e, sample, &fail, &name, trace)?;
            let clock = f64::from(p.hw.clock_mhz) * 1e6;
            Ok::<_, ExploreError>(ExploreRow {
                point: p.id,
                scene: name.clone(),
                values: p.values.clone(),
                default: p.default,
                cycles_per_frame: c,
                fps: if c > 0.0 { clock / c } else { 0.0 },
                rays_per_clock: if c > 0.0 { pixels / c } else { 0.0 },
                usage: u,
                front: [false; 5],
                best: false,
            })
        };
        // The functional trace does not depend on most hardware fields: the first point of
        // each trace identity renders and records it, the others of that identity are timed
        // on it, on all cores; the recording is dropped before the next identity's.
        let identities: Vec<TraceIdentity> = plans.iter().map(TraceIdentity::of).collect();
        let mut slots: Vec<Option<ExploreRow>> = (0..points.len()).map(|_| None).collect();
        for first in 0..points.len() {
            if identities[..first].contains(&identities[first]) {
                continue;
            }
            crate::output::interrupt::check(
                || format!("point {} of {}", first + 1, points.len()),
                String::new,
            )?;
            let mut recorded = Vec::new();
            let r = row(first, Trace::Record(&mut recorded))?;
            done += 1;
            progress(&r, done, total);
            slots[first] = Some(r);
            let others: Vec<usize> = (first + 1..points.len())
                .filter(|&k| identities[k] == identities[first])
                .collect();
            let replayed = map_in_order(
                "point",
                &others,
                |&k| row(k, Trace::Replay(&recorded)),
                |r| {
                    done += 1;
                    progress(r, done, total);
                },
            )?;
            for (k, r) in others.into_iter().zip(replayed) {
                slots[k] = Some(r);
            }
        }
        let mut mine: Vec<ExploreRow> = slots.into_iter().flatten().collect();
        place(&mut mine);
        rows.extend(mine);
    }
    Ok(ExploreResult {
        fields: space.fields.iter().map(|f| f.path.clone()).collect(),
        scenes: infos,
        sample: space.sample,
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(fps: f64, lut: u64, fits: bool) -> ExploreRow {
        ExploreRow {
            point: 1,
            scene: "s".into(),
            values: vec![],
            default: false,
            cycles_per_frame: 1.0,
            fps,
            rays_per_clock: 0.0,
            usage: Usage {
                used: [lut; 5],
                available: [100; 5],
                fits,
                why: String::new(),
            },
            front: [false; 5],
            best: false,
        }
    }

    #[test]
    fn the_front_keeps_the_undominated_and_the_best_fits() {
        let mut rows = vec![
            row(10.0, 5, true),
            row(20.0, 5, true),
            row(30.0, 9, false),
            row(20.0, 7, true),
        ];
        place(&mut rows);
        let on: Vec<bool> = rows.iter().map(|r| r.front[0]).collect();
        assert_eq!(on, [false, true, true, false]);
        let best: Vec<bool> = rows.iter().map(|r| r.best).collect();
        assert_eq!(best, [false, true, false, false]);
    }
}
