//! The fixed units between the transform and the walker pool — the three reciprocals and the
//! walker root — as plain pipes between FIFOs.
//!
//! Pipeline position: `transform_to_reciprocal` → reciprocal → `reciprocal_to_root` → root →
//! `root_to_dispatch` (docs/cycle-model.md §2.1). Their arithmetic is the functional model's
//! (under cross-check the walker stage re-executes it with the walk, §2.4); here they only
//! take time: a latency, and an initiation interval shared by their units.

use super::{hand_on_lanes, id, UnitIo, Walk};
use crate::models::cycle::error::CycleError;
use rtl_model::cycle::clocked::{StageId, Stamped};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_lanes::UnitLanes;

/// A fixed unit that passes walks through unchanged.
pub struct PassThrough {
    pipe: UnitLanes<Stamped<Walk>>,
    stage: StageId,
    /// Initiation intervals a walk occupies the unit for.
    passes: u64,
    /// This cycle a walk waited at the input with every unit busy and room after them (the
    /// walk-issue limit, the frame's `stalls.walk_issue`).
    pub issue_stall: bool,
}

impl PassThrough {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pipe.next_change(now)
    }

    /// The reciprocal stage of `hw`: three units per walk (one per axis), so
    /// `reciprocal_units / 3` walks side by side; with fewer than three units a walk takes
    /// several passes.
    pub fn reciprocal(hw: &HwConfig) -> Self {
        let u = &hw.units.reciprocal;
        let walks = hw.reciprocal_walk_lanes();
        let passes = if hw.reciprocal_units < 3 {
            u64::from(3u32.div_ceil(hw.reciprocal_units.max(1)))
        } else {
            1
        };
        Self {
            pipe: UnitLanes::new(walks, u.latency_cycles, u.ii),
            stage: id::RECIP,
            passes,
            issue_stall: false,
        }
    }

    /// The walker-root stage of `hw`: `walker_root_units` units side by side.
    pub fn root(hw: &HwConfig) -> Self {
        let u = &hw.units.walker_root;
        Self {
            pipe: UnitLanes::new(hw.walker_root_units, u.latency_cycles, u.ii),
            stage: id::ROOT,
            passes: 1,
            issue_stall: false,
        }
    }

    /// One cycle: the ready walks leave into `io.out`, the next ones enter from `io.input`
    /// while a unit is free.
    /// `more_walks`: whether walks may still come (for the starved/idle accounting).
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut UnitIo<'_, Walk, Walk>,
        more_walks: bool,
        now: u64,
    ) -> Result<StageState, CycleError> {
        let pushed = hand_on_lanes(&mut self.pipe, self.stage, &mut io.out, now)?;
        let input = &mut io.input;
        while input.can_pop() && self.pipe.can_accept(now) {
            if let Some(mut w) = input.pop(now)? {
                w.enter(self.stage, now);
                self.pipe.accept(now, w, self.passes, 0);
            }
        }
        self.issue_stall = input.can_pop() && !self.pipe.can_accept(now) && io.out.ready();
        Ok(self.pipe.state(now, !pushed, more_walks))
    }
}
