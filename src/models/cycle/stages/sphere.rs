//! The sphere lanes: every instance's bounding-sphere test of a ray, `sphere_units` lanes each
//! with its square root, so a ray takes ⌈instances / lanes⌉ passes, one a cycle, and leaves
//! when its last pass does (the sphere's latency after it).
//!
//! Pipeline position: `raygen_to_sphere` → `sphere_to_sorter` (docs/cycle-model.md §2.1). The
//! candidates themselves come from the functional model's trace; under cross-check the sorter
//! stage re-runs the tests and the sort from the direction (§2.4).

use super::io::FrameFx;
use super::{hand_on, id, Cx, Ray, UnitIo};
use crate::models::cycle::error::CycleError;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_pipe::UnitPipe;

/// The sphere stage.
pub struct Sphere {
    /// In the last cycle evaluated, a ray waited at the input while the unit's initiation
    /// window kept it closed: its `ii`, or a ray's further passes over the instances (more
    /// instances, or a tile's list, than lanes). The bound line's `sphere` cause
    /// (docs/cycle-model.md §2.2).
    pub held: bool,
    pipe: UnitPipe<Stamped<Ray>>,
    /// Initiation intervals a ray occupies the lanes for.
    passes: u64,
    /// The two-level scheme's per-tile passes, replacing `passes` when present.
    tiles: Option<super::tile_list::TilePasses>,
}

impl Sphere {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pipe.next_change(now)
    }

    /// The stage of `hw` for a frame of `instances` instances.
    pub fn new(hw: &HwConfig, instances: usize) -> Self {
        let u = &hw.units;
        let passes = (instances as u64)
            .div_ceil(u64::from(hw.sphere_units.max(1)))
            .max(1);
        Self {
            held: false,
            pipe: UnitPipe::new(
                u.sphere.latency_cycles + u.sqrt.latency_cycles,
                u.sphere.ii.max(u.sqrt.ii),
            ),
            passes,
            tiles: None,
        }
    }

    /// The stage reading per-tile instance lists (`tile_list.rs`) when `tiles` is given.
    pub fn with_tiles(mut self, tiles: Option<super::tile_list::TilePasses>) -> Self {
        self.tiles = tiles;
        self
    }

    /// One cycle: the ready ray leaves into `io.out`, the next one enters from `io.input`.
    /// `upstream_more`: ray generation had rays still to pass as the cycle started (starved,
    /// not idle, while it waits).
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut UnitIo<'_, Ray, Ray>,
        cx: &Cx<'_, '_>,
        fx: &mut FrameFx,
        upstream_more: bool,
    ) -> Result<StageState, CycleError> {
        let now = cx.now;
        let pushed = hand_on(&mut self.pipe, id::SPHERE, &mut io.out, now)?;
        fx.passed[1] += u64::from(pushed);
        let input = &mut io.input;
        self.held = input.valid() && self.pipe.in_interval(now);
        if input.valid() && self.pipe.can_accept(now) {
            if let Some(mut ray) = input.pop(now)? {
                ray.enter(id::SPHERE, now);
                let (passes, extra) = match &self.tiles {
                    Some(t) => (t.passes(ray.payload.pixel), t.latency),
                    None => (self.passes, 0),
                };
                // The ray's last pass enters the lanes `passes − 1` cycles after its first
                // and its candidates are complete only when that pass leaves the square
                // roots: the RTL (svo_front.v) cannot have them sooner (issue 29).
                self.pipe
                    .accept(now, ray, passes, extra + passes.saturating_sub(1));
            }
        }
        Ok(self.pipe.state(now, !pushed, upstream_more))
    }
}
