//! Ray generation: the pixel counter and the direction-table read, one ray per initiation
//! interval in the configured ray order (`HwConfig::ray_order`: scanline, tiles or Morton;
//! `rtl_model::cycle::ray_order`).
//!
//! Pipeline position: the first stage (evaluated last in a cycle), pixel counter →
//! `raygen_to_sphere` (docs/cycle-model.md §2.1). Before a pixel it makes sure the
//! functional model has handed that pixel's row over; if not, it waits in wall time only, so
//! no simulated cycle depends on the other thread (§2.4). The counter counts rays generated;
//! in an order other than scanline, the pixel of the `s`-th ray is looked up in the order's
//! table, built once per frame size. Sampled timing (§3.5) times bands of rows, so it refuses
//! any order but scanline.

use super::io::{FrameFx, PushPort};
use super::{hand_on, id, internal, Cx, Ray};
use crate::models::cycle::error::CycleError;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::hw_config::{HwConfig, RayOrder};
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_pipe::UnitPipe;

/// The ray-generation stage.
pub struct Raygen {
    pipe: UnitPipe<Stamped<Ray>>,
    /// The ray counter: rays generated so far this frame (in scanline order also the next
    /// pixel).
    next_pixel: u64,
    /// The pixel order.
    order: RayOrder,
    /// The order's pixels (raster indices) for the frame size `table_size`; empty for
    /// scanline.
    table: Vec<u32>,
    table_size: (u32, u32),
    /// Sampled timing moved the counter (`jump`).
    jumped: bool,
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
            order: hw.ray_order,
            table: Vec::new(),
            table_size: (0, 0),
            jumped: false,
            track,
            limit: u64::MAX,
        }
    }

    /// Sampled timing (docs/cycle-model.md §3.5): the next pixel to generate is `next`, and
    /// generation stops before `limit` until moved on again.
    pub fn jump(&mut self, next: u64, limit: u64) {
        self.next_pixel = next;
        self.limit = limit;
        self.jumped = true;
    }

    /// Rays generated so far this frame.
    #[inline]
    pub fn next_pixel(&self) -> u64 {
        self.next_pixel
    }

    /// One cycle: the ready ray leaves into `out`, the next pixel enters (its trace row is
    /// asked for in `fx`, received at the commit).
    #[inline]
    pub fn eval(
        &mut self,
        out: &mut PushPort<'_, Ray>,
        cx: &Cx<'_, '_>,
        fx: &mut FrameFx,
    ) -> Result<StageState, CycleError> {
        let now = cx.now;
        let pushed = hand_on(&mut self.pipe, id::RAYGEN, out, now)?;
        fx.passed[0] += u64::from(pushed);
        let pixels = cx.counts.pixels;
        if self.next_pixel < pixels.min(self.limit) && self.pipe.can_accept(now) {
            let width = cx.frame.setup.width;
            let pixel = self.pixel_of(self.next_pixel, width, cx.frame.setup.height)?;
            fx.need_row = Some((pixel / width) as usize);
            let mut ray = Stamped::with_history(Ray { pixel }, self.track);
            ray.enter(id::RAYGEN, now);
            self.pipe.accept(now, ray, 1, 0);
            self.next_pixel += 1;
        }
        Ok(self.pipe.state(now, !pushed, self.next_pixel < pixels))
    }

    /// The pixel (raster index) of the `s`-th ray of the frame.
    #[inline]
    fn pixel_of(&mut self, s: u64, width: u32, height: u32) -> Result<u32, CycleError> {
        if self.order.is_scanline() {
            return u32::try_from(s).map_err(internal);
        }
        if self.jumped {
            return Err(CycleError::Config(format!(
                "ray_order = {:?} cannot be timed with --sample: sampled timing times bands of \
                 rows, which only the scanline order generates together",
                self.order
            )));
        }
        let size = (width, height);
        if self.table_size != size {
            self.table = self.order.sequence(size.0, size.1);
            self.table_size = size;
        }
        let at = usize::try_from(s).map_err(internal)?;
        self.table
            .get(at)
            .copied()
            .ok_or_else(|| internal(format!("ray {s} is beyond the frame's pixels")))
    }
}
