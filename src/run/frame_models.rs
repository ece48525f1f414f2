//! One frame of `sim`'s run through the chosen model: the f64 reference alone, or the
//! fixed-point datapath (functional, or timed by the cycle model) compared with the reference.
//!
//! Pipeline position: inside the frame loop of [`super::frames::run`], which renders the
//! reference first (every model is compared with it), then calls [`FrameModel::frame`].
//! [`FrameModel::new`] holds each model's per-run state: nothing for the reference, a fixed
//! hit buffer for the functional model, the pipeline for the cycle model.

use super::frames::{Model, RunConfig};
use crate::models::cycle::runner::CycleRun;
use crate::models::cycle::waves::PipelineWaves;
use crate::models::cycle::{CycleFrame, CycleOptions};
use crate::models::fixed::bound::mismatch_explained;
use crate::models::fixed::render_frame_fixed_with;
use crate::models::fixed::{compare, to_hit_records, FixedBuffer, FixedStats};
use crate::models::reference::{FrameInput, FrameStats, HitRecord};
use crate::output::report::FrameReport;
use crate::world::assets::Asset;
use anyhow::Result;
use rtl_model::datapath::{overflow_table, signals};

/// The model behind the output, with its state across frames.
pub enum FrameModel {
    /// The f64 reference: its records are the output.
    Reference,
    /// The functional fixed-point datapath and its hit buffer (boxed, as the pipeline: the
    /// enum stays small).
    Fixed(Box<FixedBuffer>),
    /// The cycle model.
    Cycle(Box<CycleRun>),
}

/// What one frame of the chosen model produced.
pub struct FrameResult {
    /// Counters in the reference's shape.
    pub stats: FrameStats,
    /// The frame's report (accuracy and cycles for the fixed-point models).
    pub report: FrameReport,
    /// The fixed-point records, in the reference's shape (`None`: the reference is the output).
    pub records: Option<Vec<HitRecord>>,
    /// The frame's cycles (cycle model).
    pub cycles: Option<CycleFrame>,
    /// Wall time of the cycle model's simulation in this frame.
    pub sim_wall_s: f64,
}

impl FrameModel {
    /// The chosen model's state for a run of `cfg` over `assets`.
    pub fn new(cfg: &RunConfig, assets: &[Asset]) -> Result<Self> {
        let (w, h) = cfg.scene.file.resolution;
        Ok(match cfg.model {
            Model::Reference => Self::Reference,
            Model::Fixed => Self::Fixed(Box::new(FixedBuffer::new(w, h))),
            Model::Cycle => Self::Cycle(Box::new(cycle_run(cfg, assets)?)),
        })
    }

    /// The cycle model's run, if this is the cycle model.
    pub fn cycle_run(&mut self) -> Option<&mut CycleRun> {
        match self {
            Self::Cycle(cr) => Some(cr),
            _ => None,
        }
    }

    /// Frame `f` through the model; `reference` is the reference's counters for this frame
    /// and `reference_records` its records.
    pub fn frame(
        &mut self,
        cfg: &RunConfig,
        input: &FrameInput<'_>,
        f: u32,
        reference: &FrameStats,
        reference_records: &[HitRecord],
    ) -> Result<FrameResult> {
        let (fx, cycles, sim_wall_s, fbuf) = match self {
            Self::Reference => {
                return Ok(FrameResult {
                    stats: reference.clone(),
                    report: FrameReport::of(reference.clone()),
                    records: None,
                    cycles: None,
                    sim_wall_s: 0.0,
                })
            }
            Self::Fixed(buffer) => {
                let fx = render_frame_fixed_with(input, buffer, &cfg.datapath, cfg.options)?;
                (fx, None, 0.0, &**buffer)
            }
            Self::Cycle(cr) => {
                // A pipeline without a hit buffer (`hit_buffer.present: false`) traces every
                // pixel, whatever the reuse switch says.
                let reuse = cfg.options.use_hit_buffer && cfg.hardware.hit_buffer.present;
                let r = cr.frame(input, &cfg.datapath, reuse)?;
                (r.fixed, Some(r.cycles), r.wall_s, cr.buffer())
            }
        };
        let records = to_hit_records(fbuf, &cfg.datapath);
        let mut report = checked_report(cfg, input, f, &fx, reference, reference_records, &records);
        report.cycle = cycles.clone();
        Ok(FrameResult {
            stats: fixed_frame_stats(f, &fx, reference),
            report,
            records: Some(records),
            cycles,
            sim_wall_s,
        })
    }
}

/// The cycle model's run: the pipeline of `cfg.hardware`, with waveforms if asked for and the
/// two-level instance scheme when elaboration keeps it (docs/instances.md §7).
fn cycle_run(cfg: &RunConfig, assets: &[Asset]) -> Result<CycleRun> {
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
        assets,
        &cfg.scene.instance_asset,
        cfg.scene.file.resolution,
        CycleOptions {
            cross_check: cfg.cross_check,
            sample: cfg.sample,
            waves,
            log_limit: cfg.transaction_log.as_ref().map_or(0, |(_, n)| *n),
            ..CycleOptions::default()
        },
    )?;
    run.set_two_level(cfg.elaboration.as_ref().and_then(|e| e.two_level));
    run.set_switches(cfg.options.ray_switches());
    Ok(run)
}

/// The report of a fixed-point frame: its counters, overflows and accuracy against the
/// reference, each difference explained by a named bound or counted as unexplained.
fn checked_report(
    cfg: &RunConfig,
    input: &FrameInput<'_>,
    f: u32,
    fx: &FixedStats,
    reference: &FrameStats,
    reference_records: &[HitRecord],
    records: &[HitRecord],
) -> FrameReport {
    let (w, h) = cfg.scene.file.resolution;
    let depths: Vec<u8> = input.assets.iter().map(Asset::depth).collect();
    let mut acc = compare(reference_records, records, |k| {
        let (i, j) = (k as u32 % w, k as u32 / w);
        let inst = usize::from(records[k].instance);
        let pose = &input.state.poses[inst];
        let depth = depths[input.scene.instance_asset[inst]];
        mismatch_explained(
            &cfg.datapath,
            &input.state.camera,
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
    let mut report = FrameReport::of(fixed_frame_stats(f, fx, reference));
    report.overflows = Some(ov.nonzero().map(|(n, c)| (n.to_string(), c)).collect());
    report.reference_wall_s = Some(reference.wall_s);
    report.accuracy = Some(acc);
    report
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
