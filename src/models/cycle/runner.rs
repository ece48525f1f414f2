//! Runs frames through the functional model (recording their work) and then the cycle model,
//! keeping both models' state across frames.
//!
//! Pipeline position: what `sim` calls per frame for the cycle model; tests use it directly.

use super::layout::{LayoutBuildError, SceneLayout};
use super::model::{CycleError, CycleModel, CycleOptions};
use super::stats::{CycleFrame, OpCounts};
use crate::models::fixed::plan::FramePlan;
use crate::models::fixed::row_feed::RowFeed;
use crate::models::fixed::trace::RowTrace;
use crate::models::fixed::{render_streamed, FixedBuffer, FixedError, FixedStats};
use crate::models::reference::{FrameInput, RaySwitches};
use crate::world::assets::Asset;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::{overflow_table, DatapathConfig};
use std::time::Instant;
use thiserror::Error;

/// Why a cycle-model frame failed.
#[derive(Debug, Error)]
pub enum CycleRunError {
    /// The functional model refused the frame.
    #[error(transparent)]
    Fixed(#[from] FixedError),
    /// The images cannot be placed in the node memory.
    #[error(transparent)]
    Layout(#[from] LayoutBuildError),
    /// The cycle model failed or disagreed with the functional model.
    #[error(transparent)]
    Cycle(#[from] CycleError),
    /// The hardware does not match the datapath or the frame.
    #[error("hardware configuration: {0}")]
    Config(String),
}

/// Both models' state across the frames of a run.
pub struct CycleRun {
    model: CycleModel,
    buffer: FixedBuffer,
    instance_asset: Vec<usize>,
    /// The two-level instance scheme's list memory, when used (`set_two_level`).
    two_level: Option<rtl_model::units::tile_list::TileListConfig>,
    /// Culling, sorting and early termination (`set_switches`; all on by default).
    switches: RaySwitches,
}

/// One frame's results.
/// One frame's functional trace and the hit buffer after it, recorded by
/// [`CycleRun::frame_recorded`] for [`CycleRun::frame_replayed`].
pub struct RecordedFrame {
    /// Every row's trace, published and closed.
    feed: RowFeed,
    /// The functional model's hit buffer after the frame.
    buffer_after: FixedBuffer,
    /// What the trace depends on besides the scene and the frame.
    key: TraceKey,
}

/// The inputs of a frame's functional trace that a run (not the scene) sets.
#[derive(Clone, Debug, PartialEq)]
struct TraceKey {
    datapath: DatapathConfig,
    use_hit_buffer: bool,
    switches: RaySwitches,
    two_level: Option<(rtl_model::units::tile_list::TileListConfig, u32)>,
    size: (u32, u32),
}

pub struct CycleFrameResult {
    /// The functional model's counters (its wall time included).
    pub fixed: FixedStats,
    /// The cycle report.
    pub cycles: CycleFrame,
    /// Wall time of the whole frame (functional and cycle model), seconds.
    pub wall_s: f64,
}

impl CycleRun {
    /// A run over `assets` at `width`×`height`.
    pub fn new(
        hw: &HwConfig,
        dp: &DatapathConfig,
        assets: &[Asset],
        instance_asset: &[usize],
        (width, height): (u32, u32),
        opts: CycleOptions,
    ) -> Result<Self, CycleRunError> {
        hw.validate_for(dp).map_err(CycleRunError::Config)?;
        if u64::from(width) * u64::from(height) > hw.frame.pixels()
            || width > hw.frame.width
            || height > hw.frame.height
        {
            return Err(CycleRunError::Config(format!(
                "frame {width}×{height} is larger than the {}×{} the hit buffer and direction table are built for (hardware frame)",
                hw.frame.width, hw.frame.height
            )));
        }
        let layout = SceneLayout::new(assets, &hw.node_memory.onchip)?;
        Ok(Self {
            model: CycleModel::new(hw, layout, width, height, opts)?,
            buffer: FixedBuffer::new(width, height),
            instance_asset: instance_asset.to_vec(),
            two_level: None,
            switches: RaySwitches::default(),
        })
    }

    /// Uses the two-level instance scheme with list memory `tl` from the next frame on
    /// (`None`: the flat scheme). The records do not change; the sphere stage's passes do.
    pub fn set_two_level(&mut self, tl: Option<rtl_model::units::tile_list::TileListConfig>) {
        self.two_level = tl;
    }

    /// Culling, sorting and early termination from the next frame on (docs/paper.md §2): the
    /// functional model's walk lists follow them and the pipeline times what they leave.
    pub fn set_switches(&mut self, s: RaySwitches) {
        self.switches = s;
    }

    /// The functional model's buffer after the last frame (equal to the cycle model's).
    pub fn buffer(&self) -> &FixedBuffer {
        &self.buffer
    }

    /// The cycle model.
    pub fn model(&mut self) -> &mut CycleModel {
        &mut self.model
    }

    /// Runs one frame through both models at the same time: the functional model renders
    /// rows on a second thread and hands each to the cycle model as it completes
    /// (`models::fixed::row_feed`), so a frame takes about as long as the slower of the two.
    pub fn frame(
        &mut self,
        input: &FrameInput<'_>,
        dp: &DatapathConfig,
        use_hit_buffer: bool,
    ) -> Result<CycleFrameResult, CycleRunError> {
        self.frame_fed(input, dp, use_hit_buffer).map(|(r, _)| r)
    }

    /// [`CycleRun::frame`], keeping the functional model's trace and the hit buffer it left,
    /// so that other hardware can be timed on the same frame by [`CycleRun::frame_replayed`]
    /// without rendering it again (`sim explore`, docs/explore.md §2).
    pub fn frame_recorded(
        &mut self,
        input: &FrameInput<'_>,
        dp: &DatapathConfig,
        use_hit_buffer: bool,
    ) -> Result<(CycleFrameResult, RecordedFrame), CycleRunError> {
        let (result, feed) = self.frame_fed(input, dp, use_hit_buffer)?;
        let recorded = RecordedFrame {
            feed,
            buffer_after: self.buffer.clone(),
            key: self.trace_key(dp, use_hit_buffer),
        };
        Ok((result, recorded))
    }

    /// Times one frame on the functional trace `recorded` holds, which another run recorded
    /// for the same frame (and every frame before it) with [`CycleRun::frame_recorded`]: the
    /// cycle model runs as in [`CycleRun::frame`] and checks its work against that trace word
    /// for word, but the functional model does not render the frame again. The trace does
    /// not depend on the hardware except through the datapath, the hit-buffer switch, the ray
    /// switches and the sphere lanes the instance lists are cut for; a run whose any of them
    /// differs from the recording's is refused (it would be checked against another trace).
    pub fn frame_replayed(
        &mut self,
        input: &FrameInput<'_>,
        dp: &DatapathConfig,
        use_hit_buffer: bool,
        recorded: &RecordedFrame,
    ) -> Result<CycleFrame, CycleRunError> {
        if recorded.key != self.trace_key(dp, use_hit_buffer) {
            return Err(CycleRunError::Config(
                "the recorded trace is of another datapath, hit-buffer switch, ray switches or \
                 sphere-lane count than this run's: render the frame instead"
                    .into(),
            ));
        }
        let mut host_ov = overflow_table();
        let plan = self.plan(input, dp, use_hit_buffer, &mut host_ov)?;
        let dir: &[[i64; 3]] = &self.buffer.dir_table;
        let cycles = self
            .model
            .run_frame(&plan, &recorded.feed, dir, &self.instance_asset)?;
        // The hit buffer as the functional model left it after this frame, as after `frame`:
        // the plan above already moved the buffer's previous frame and direction table on, and
        // the records are what a later rendered frame (`frame`) would start from.
        self.buffer.clone_from(&recorded.buffer_after);
        Ok(cycles)
    }

    /// The frame's plan, as every way of running a frame makes it: the hit buffer moved on to
    /// this frame, the run's ray switches, and the instance lists cut for the sphere lanes when
    /// the two-level scheme is on.
    fn plan<'a>(
        &mut self,
        input: &FrameInput<'a>,
        dp: &'a DatapathConfig,
        use_hit_buffer: bool,
        host_ov: &mut rtl_model::fixed::Overflows,
    ) -> Result<FramePlan<'a>, CycleRunError> {
        let mut plan = FramePlan::new(input, &mut self.buffer, dp, use_hit_buffer, host_ov)?
            .with_switches(self.switches);
        if let Some(tl) = &self.two_level {
            let lanes = self.model.config().sphere_units;
            crate::models::fixed::cull::install_lists(&mut plan, input, tl, lanes);
        }
        Ok(plan)
    }

    /// What the functional trace of a frame depends on besides the scene and the frame.
    fn trace_key(&self, dp: &DatapathConfig, use_hit_buffer: bool) -> TraceKey {
        TraceKey {
            datapath: dp.clone(),
            use_hit_buffer,
            switches: self.switches,
            two_level: self
                .two_level
                .map(|tl| (tl, self.model.config().sphere_units)),
            size: (self.buffer.width, self.buffer.height),
        }
    }

    /// [`CycleRun::frame`], returning the feed the functional model filled.
    fn frame_fed(
        &mut self,
        input: &FrameInput<'_>,
        dp: &DatapathConfig,
        use_hit_buffer: bool,
    ) -> Result<(CycleFrameResult, RowFeed), CycleRunError> {
        let start = Instant::now();
        let mut host_ov = overflow_table();
        let plan = self.plan(input, dp, use_hit_buffer, &mut host_ov)?;
        let (w, h) = (self.buffer.width, self.buffer.height);
        let feed = RowFeed::new(h as usize);
        let FixedBuffer {
            records, dir_table, ..
        } = &mut self.buffer;
        let dir: &[[i64; 3]] = dir_table;
        let model = &mut self.model;
        let instance_asset = &self.instance_asset;
        let (mut fixed, cycles) = std::thread::scope(|s| {
            let producer = s.spawn(|| render_streamed(&plan, dir, records, (w, h), &feed));
            let cycles = model.run_frame(&plan, &feed, dir, instance_asset);
            if cycles.is_err() {
                feed.cancel();
            }
            match producer.join() {
                Ok(fixed) => (fixed, cycles),
                // A panic in the functional model is a bug there: let it surface as one.
                Err(panic) => std::panic::resume_unwind(panic),
            }
        });
        if let Some(ov) = fixed.overflows.as_mut() {
            ov.merge(&host_ov);
        }
        let mut cycles = cycles?;
        let descents = fixed.walker.fetches.saturating_sub(fixed.walks);
        cycles.ops_per_pixel = OpCounts::per_pixel(
            fixed.rays,
            fixed.sphere_tests,
            fixed.walks,
            fixed.walker.steps,
            descents,
        );
        Ok((
            CycleFrameResult {
                fixed,
                cycles,
                wall_s: start.elapsed().as_secs_f64(),
            },
            feed,
        ))
    }

    /// A test hook (tests/cycle_checks.rs): runs one frame as [`CycleRun::frame`] does, but the
    /// functional model renders the whole frame first and `corrupt` may change each row of its
    /// trace (row index, row) before the cycle model reads it — so the tests can show that the
    /// cycle model's checks against the trace fail, and with which message.
    #[doc(hidden)]
    pub fn frame_with_corrupt_trace(
        &mut self,
        input: &FrameInput<'_>,
        dp: &DatapathConfig,
        use_hit_buffer: bool,
        corrupt: &mut dyn FnMut(usize, &mut RowTrace),
    ) -> Result<CycleFrame, CycleRunError> {
        let mut host_ov = overflow_table();
        let plan = self.plan(input, dp, use_hit_buffer, &mut host_ov)?;
        let (w, h) = (self.buffer.width, self.buffer.height);
        let rendered = RowFeed::new(h as usize);
        let FixedBuffer {
            records, dir_table, ..
        } = &mut self.buffer;
        let dir: &[[i64; 3]] = dir_table;
        render_streamed(&plan, dir, records, (w, h), &rendered);
        let feed = RowFeed::new(h as usize);
        for j in 0..h as usize {
            let mut row = rendered.get(j).cloned().ok_or_else(|| {
                CycleError::Internal(format!("row {j} of the functional model is missing"))
            })?;
            corrupt(j, &mut row);
            feed.publish(j, row)
                .map_err(|e| CycleError::Internal(e.to_string()))?;
        }
        feed.close();
        Ok(self
            .model
            .run_frame(&plan, &feed, dir, &self.instance_asset)?)
    }
}
