//! The cycle model of a run: the parts that keep their state from frame to frame (node memory,
//! walker pool, hit-buffer BRAM, the clock) and [`CycleModel::run_frame`], which builds a
//! frame's [`Pipeline`], clocks it until every pixel is written, checks the hit buffer against
//! the functional model and reports.
//!
//! Pipeline position: what `runner::CycleRun` calls per frame, beside the functional model on
//! its second thread (docs/cycle-model.md §2, §2.4).

use super::layout::SceneLayout;
use super::pipeline::{EvalOrder, Pipeline};
use super::sample::{SampleConfig, Sampler};
use super::stages::{FrameInputs, FrameSetup};
use super::stats::CycleFrame;
use super::waves::PipelineWaves;
use crate::models::fixed::plan::FramePlan;
use crate::models::fixed::row_feed::RowFeed;
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::{Clock, StageStamp};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::memory::NodeMemory;
use rtl_model::cycle::walker_pool::WalkerPoolModel;
use std::time::Instant;

// Re-exported where the public API has always had them (`cycle::model::CycleError`).
pub use super::error::CycleError;
pub use super::machine::Machine;

/// Options of a cycle-model run.
#[derive(Default)]
pub struct CycleOptions {
    /// Re-execute every stage's arithmetic and compare with the functional model.
    pub cross_check: bool,
    /// Record waveforms.
    pub waves: Option<PipelineWaves>,
    /// Keep the stage stamps of this many records (in write order) per run.
    pub log_limit: usize,
    /// Step every cycle, also those in which nothing can move (off: idle cycles are taken at
    /// once, with the same report; docs/cycle-model.md §3.3). For the comparison test.
    pub step_every_cycle: bool,
    /// Sampled timing (`--sample`): time a systematic sample of row bands and estimate each
    /// frame's cycles with a confidence interval (docs/cycle-model.md §3.5). `None`: every
    /// cycle of every frame is simulated.
    pub sample: Option<SampleConfig>,
    /// The stages' evaluation order within a clock: a test hook (docs/architecture.md §4);
    /// every order it offers gives the same cycles and reports.
    pub eval_order: EvalOrder,
}

/// Per-run state of the cycle model: the memories and the pool keep their contents across
/// frames (cache lines, hit-buffer words), the pipeline drains between frames.
pub struct CycleModel {
    hw: HwConfig,
    layout: SceneLayout,
    width: u32,
    height: u32,
    cross_check: bool,
    frame: u32,
    machine: Machine,
    /// Stamps of the first transactions, for transaction logs (pixel, stamps).
    pub log: Vec<(u32, Vec<StageStamp>)>,
    log_limit: usize,
    step_every_cycle: bool,
    sample: Option<SampleConfig>,
    eval_order: EvalOrder,
    /// Cycles run so far, and of those the ones idle-cycle skipping took at once.
    cycles_run: u64,
    cycles_skipped: u64,
}

impl CycleModel {
    /// A model for frames of `width`×`height` over the placed images.
    pub fn new(
        hw: &HwConfig,
        layout: SceneLayout,
        width: u32,
        height: u32,
        opts: CycleOptions,
    ) -> Result<Self, CycleError> {
        hw.validate()
            .map_err(|e| CycleError::Config(e.to_string()))?;
        let pixels = width as usize * height as usize;
        let mem =
            NodeMemory::with_clock(hw.node_memory.clone(), layout.layout.clone(), hw.clock_mhz)
                .map_err(|e| CycleError::Config(e.to_string()))?;
        let pool = WalkerPoolModel::new(&hw.walker_pool)?;
        let ports = hw.hit_buffer.read_ports + hw.hit_buffer.write_ports;
        let bram = Bram::new(pixels.max(1), ports, 0u128)
            .map_err(|e| CycleError::Config(e.to_string()))?;
        Ok(Self {
            hw: hw.clone(),
            layout,
            width,
            height,
            cross_check: opts.cross_check,
            frame: 0,
            machine: Machine {
                mem,
                pool,
                bram,
                clock: Clock::new(),
                waves: opts.waves,
            },
            log: Vec::new(),
            log_limit: opts.log_limit,
            step_every_cycle: opts.step_every_cycle,
            sample: opts.sample,
            eval_order: opts.eval_order,
            cycles_run: 0,
            cycles_skipped: 0,
        })
    }

    /// Cycles simulated so far over all frames, and of those the ones taken at once by
    /// idle-cycle skipping (not stepped one by one).
    pub fn skipped_cycles(&self) -> (u64, u64) {
        (self.cycles_skipped, self.cycles_run)
    }

    /// The hardware configuration.
    pub fn config(&self) -> &HwConfig {
        &self.hw
    }

    /// The hit-buffer word of pixel `p` (after the last frame).
    pub fn word(&self, p: usize) -> Option<u128> {
        self.machine.bram.peek(p).copied()
    }

    /// Takes the waveform recorder (to write it).
    pub fn take_waves(&mut self) -> Option<PipelineWaves> {
        self.machine.waves.take()
    }

    /// Runs one frame. `plan` is the frame's prepared datapath, `feed` the functional
    /// model's work per row (rows may still be arriving: ray generation waits for each row
    /// before its first pixel), `dir` the frame's direction table.
    pub fn run_frame(
        &mut self,
        plan: &FramePlan<'_>,
        feed: &RowFeed,
        dir: &[[i64; 3]],
        instance_asset: &[usize],
    ) -> Result<CycleFrame, CycleError> {
        let wall = Instant::now();
        let setup = FrameSetup {
            frame: self.frame,
            width: self.width,
            height: self.height,
            cross_check: self.cross_check,
        };
        let inputs = FrameInputs::new(setup, plan, feed, dir, instance_asset, &self.layout)?;
        let mut pipeline = Pipeline::new(
            &self.hw,
            inputs,
            &mut self.machine,
            &mut self.log,
            self.log_limit,
            !self.step_every_cycle,
        )?
        .with_order(self.eval_order);
        if let Some(cfg) = self.sample {
            let s = Sampler::plan(cfg, &self.hw, self.frame, self.width, self.height);
            pipeline = pipeline.with_sampler(s)?;
        }
        while !pipeline.done() {
            pipeline.step()?;
        }
        // Bit-exact: the hit buffer equals the functional model's, word for word.
        pipeline.check_hit_buffer()?;
        self.frame += 1;
        self.cycles_skipped += pipeline.skipped();
        let sampler = pipeline.take_sampler();
        let work = match (&sampler, self.sample) {
            (Some(_), Some(cfg)) => super::sample::band_work(pipeline.rows(), cfg.band_rows),
            _ => Vec::new(),
        };
        let start = pipeline.start();
        let mut report = pipeline.report(wall.elapsed().as_secs_f64());
        self.cycles_run += report.cycles;
        if let Some(s) = sampler {
            let pixels = u64::from(self.width) * u64::from(self.height);
            let est = s.finish(
                start,
                start + report.cycles,
                self.hw.clock_mhz,
                pixels,
                &work,
            )?;
            report.set_sampled(&self.hw, pixels, est);
        }
        Ok(report)
    }
}
