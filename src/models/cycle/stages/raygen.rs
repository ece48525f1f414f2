//! Ray generation: the pixel counter and the direction-table read, one ray per initiation
//! interval in raster order.
//!
//! Pipeline position: the first stage (evaluated last in a cycle), pixel counter →
//! `raygen_to_sphere` (docs/cycle-model.md §2.1). Before a row's first pixel it makes sure the
//! functional model has handed that row over; if not, it waits in wall time only, so no
//! simulated cycle depends on the other thread (§2.4).

use super::{hand_on, id, internal, FrameCounts, FrameInputs, Ray};
use crate::models::cycle::model::CycleError;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::fifo::Fifo;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_pipe::UnitPipe;

/// The ray-generation stage.
pub struct Raygen {
    pipe: UnitPipe<Stamped<Ray>>,
    /// The pixel counter: the next pixel to generate.
    next_pixel: u64,
    /// Whether rays keep their whole stamp history (only a transaction log reads it).
    track: bool,
    /// Pixels from here on wait (sampled timing: the end of the timed segment).
    limit: u64,
}

impl Raygen {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pipe.next_change(now)
    }

    /// The stage of `hw`, at pixel 0; `track`: rays keep their whole stamp history.
    pub fn new(hw: &HwConfig, track: bool) -> Self {
        let u = &hw.units.raygen;
        Self {
            pipe: UnitPipe::new(u.latency_cycles, u.ii),
            next_pixel: 0,
            track,
            limit: u64::MAX,
        }
    }

    /// Sampled timing (docs/cycle-model.md §3.5): the next pixel to generate is `next`, and
    /// generation stops before `limit` until moved on again.
    pub fn jump(&mut self, next: u64, limit: u64) {
        self.next_pixel = next;
        self.limit = limit;
    }

    /// Pixels generated so far.
    #[inline]
    pub fn next_pixel(&self) -> u64 {
        self.next_pixel
    }

    /// One cycle: the ready ray leaves into `out`, the next pixel enters.
    #[inline]
    pub fn eval(
        &mut self,
        out: &mut Fifo<Ray>,
        frame: &mut FrameInputs<'_>,
        counts: &mut FrameCounts,
        now: u64,
    ) -> Result<StageState, CycleError> {
        let pushed = hand_on(&mut self.pipe, id::RAYGEN, out, now)?;
        counts.passed[0] += u64::from(pushed);
        let pixels = counts.pixels;
        if self.next_pixel < pixels.min(self.limit) && self.pipe.can_accept(now) {
            let width = u64::from(frame.setup.width);
            frame.need_row((self.next_pixel / width) as usize)?;
            let pixel = u32::try_from(self.next_pixel).map_err(internal)?;
            let mut ray = Stamped::with_history(Ray { pixel }, self.track);
            ray.enter(id::RAYGEN, now);
            self.pipe.accept(now, ray, 1, 0);
            self.next_pixel += 1;
        }
        Ok(self.pipe.state(now, !pushed, self.next_pixel < pixels))
    }
}
