//! The transform: a walk's ray into its instance's frame, and the entry to the walk section.
//!
//! Pipeline position: `loop_back` (first) or `check_to_transform` → `transform_to_reciprocal`
//! (docs/cycle-model.md §2.1). A ray's candidates are walked one after the other; the record
//! stage sends the next walk of a ray back through `loop_back`, which has priority over new
//! rays so that rays in the walk section finish first. A new ray takes one of the ray slots as
//! its first walk enters here and keeps it until its record leaves; `loop_back` has one entry
//! per slot, so it can always take a returning walk and the loop cannot deadlock.

use super::io::{PopPort, PushPort, SlotTake, SlotView};
use super::{hand_on_lanes, id, Cx, Ray, Walk};
use crate::models::cycle::error::CycleError;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_lanes::UnitLanes;

/// The transform stage.
pub struct Transform {
    pipe: UnitLanes<Stamped<Walk>>,
    /// This cycle a walk waited at the input with every unit busy and room after them: the
    /// walk-issue limit (the frame's `stalls.walk_issue`).
    pub issue_stall: bool,
    /// This cycle a unit was free and no walk was at either input though rays were still to
    /// come: the walk section waited for ray generation (`stalls.ray_generation`).
    pub input_starved: bool,
}

/// The transform's ports: the loop-back and new-ray inputs, its output, the ray slots as it
/// may take them this cycle, and where its takes go.
pub struct TransformIo<'a> {
    /// `loop_back` (first).
    pub loop_back: PopPort<'a, Walk>,
    /// `check_to_transform`.
    pub new_rays: PopPort<'a, Ray>,
    /// `transform_to_reciprocal`.
    pub out: PushPort<'a, Walk>,
    /// The slots free for a take (the record stage's releases of this cycle included).
    pub slots: SlotView<'a>,
    /// The slots taken this cycle.
    pub takes: &'a mut Vec<SlotTake>,
}

impl Transform {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pipe.next_change(now)
    }

    /// The stage of `hw`: `transform_units` units side by side, each taking a walk per
    /// initiation interval.
    pub fn new(hw: &HwConfig) -> Self {
        let u = &hw.units.transform;
        Self {
            pipe: UnitLanes::new(hw.transform_units, u.latency_cycles, u.ii),
            issue_stall: false,
            input_starved: false,
        }
    }

    /// One cycle: the ready walks leave into `out`; then, while a unit is free, a returning
    /// walk from `loop_back` enters, or else the first walk of a new ray from `new_rays` if a
    /// slot is free (taken at the commit). `frame_more_rays`: rays of the frame are still to
    /// leave the check stage (what `input_starved` needs).
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut TransformIo<'_>,
        cx: &Cx<'_, '_>,
        more_walks: bool,
        frame_more_rays: bool,
    ) -> Result<StageState, CycleError> {
        let now = cx.now;
        let pushed = hand_on_lanes(&mut self.pipe, id::TRANSFORM, &mut io.out, now)?;
        while self.pipe.can_accept(now) {
            if io.loop_back.can_pop() {
                if let Some(mut w) = io.loop_back.pop(now)? {
                    w.enter(id::TRANSFORM, now);
                    self.pipe.accept(now, w, 1, 0);
                }
            } else if io.new_rays.can_pop() && io.slots.has_free() {
                if let Some(ray) = io.new_rays.pop(now)? {
                    let pixel = ray.payload.pixel;
                    let slot = io.slots.take()?;
                    io.takes.push(SlotTake {
                        slot,
                        pixel,
                        stamps: ray,
                    });
                    let mut w = Stamped::untracked(Walk { slot, cand: 0 });
                    w.enter(id::TRANSFORM, now);
                    self.pipe.accept(now, w, 1, 0);
                }
            } else {
                break;
            }
        }
        let waiting = io.loop_back.can_pop() || (io.new_rays.can_pop() && io.slots.has_free());
        self.issue_stall = waiting && !self.pipe.can_accept(now) && io.out.ready();
        self.input_starved = !io.loop_back.valid()
            && !io.new_rays.valid()
            && self.pipe.can_accept(now)
            && frame_more_rays;
        Ok(self.pipe.state(now, !pushed, more_walks))
    }
}
