//! The record stage: early termination, the best hit, and packing the hit-buffer word.
//!
//! Pipeline position: `walker_to_record` → `loop_back` (the ray's next walk) or, through the
//! packing unit, `record_to_write` (docs/cycle-model.md §2.1). After each walk it decides
//! whether the next candidate is needed (paper §4.2, `FramePlan::stops`: the best hit so far
//! is in front of the next candidate's entry); if not, the ray's record is packed and its slot
//! freed. The number of walks and, at the end of the frame, the words are checked against the
//! functional model (§2.4); under cross-check the word is packed from this model's own best
//! walk instead of taken from the trace.

use super::{hand_on_lanes, id, internal, FrameCounts, FrameInputs, Ray, RaySlots, Rec, Walk};
use crate::models::cycle::error::CycleError;
use crate::models::fixed::plan::FramePlan;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::fifo::Fifo;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_lanes::UnitLanes;

/// The record stage: the packing units and the decision in front of them, one per walk lane
/// (`HwConfig::walk_lanes`).
pub struct Record {
    pack: UnitLanes<Stamped<Rec>>,
    /// In the last cycle evaluated, a packed record could not enter `record_to_write` (full):
    /// the bound line's `record_write` cause (docs/cycle-model.md §2.2).
    pub write_blocked: bool,
}

impl Record {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pack.next_change(now)
    }

    /// The stage of `hw`.
    pub fn new(hw: &HwConfig) -> Self {
        let u = &hw.units.hit_pack;
        Self {
            pack: UnitLanes::new(hw.walk_lanes(), u.latency_cycles, u.ii),
            write_blocked: false,
        }
    }

    /// One cycle: the packed records leave into `out` (the write FIFO's ports are the record
    /// stage's first), then walk results from `input` are decided, one per lane. Returns the
    /// stage's state and whether it pushed into the write FIFO this cycle.
    /// `walked`: a ray had entered the walk section as the cycle started.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn eval(
        &mut self,
        input: &mut Fifo<Walk>,
        loop_back: &mut Fifo<Walk>,
        out: &mut Fifo<Rec>,
        slots: &mut RaySlots,
        frame: &mut FrameInputs<'_>,
        counts: &mut FrameCounts,
        walked: bool,
        now: u64,
    ) -> Result<(StageState, bool), CycleError> {
        let pushed = hand_on_lanes(&mut self.pack, id::RECORD, out, now)?;
        self.write_blocked = self.pack.ready(now).is_some() && !out.can_push();
        let mut state = self.pack.state(now, !pushed, walked);
        while input.can_pop() && self.pack.can_accept(now) {
            if let Some(wk) = input.try_pop().map_err(internal)? {
                self.decide(wk, loop_back, slots, frame, counts, now)?;
                state = StageState::Busy;
            }
        }
        Ok((state, pushed))
    }

    /// The decision on walk result `wk`: loop back for the next candidate, or pack the record
    /// and free the slot.
    fn decide(
        &mut self,
        wk: Stamped<Walk>,
        loop_back: &mut Fifo<Walk>,
        slots: &mut RaySlots,
        frame: &mut FrameInputs<'_>,
        counts: &mut FrameCounts,
        now: u64,
    ) -> Result<(), CycleError> {
        let Walk { slot, cand } = wk.payload;
        let s = slots.get_mut(slot)?;
        let (tr, pw, i) = frame.trace_at(s.pixel)?;
        let twalks = tr.walks_of(pw);
        let Some(tw) = twalks.get(usize::from(cand)) else {
            return Err(frame.mismatch(
                s.pixel,
                format!(
                    "walk {cand} done here, the functional model did {}",
                    twalks.len()
                ),
            ));
        };
        if let Some(t) = tw.hit_t {
            if s.best.is_none_or(|(bt, _)| t < bt) {
                s.best = Some((t, cand));
            }
        }
        s.walks += 1;
        let next = usize::from(cand) + 1;
        let more = next < s.cands.len()
            && !s
                .best
                .is_some_and(|(bt, _)| frame.plan.stops(bt, s.cands[next].0));
        if more {
            let mut w2 = wk.map(|_| Walk {
                slot,
                cand: next as u16,
            });
            w2.enter(id::RECORD, now);
            let _ = w2.leave(id::RECORD, now);
            loop_back
                .try_push(w2)
                .map_err(|e| CycleError::Internal(format!("loop-back: {e}")))?;
            return Ok(());
        }
        if next < s.cands.len() {
            counts.early += 1;
        }
        if s.walks != pw.walk_len {
            return Err(frame.mismatch(
                s.pixel,
                format!(
                    "{} walks here, {} in the functional model (early termination differs)",
                    s.walks, pw.walk_len
                ),
            ));
        }
        let word = if frame.setup.cross_check {
            let spheres = FramePlan::sphere_count(&s.cands);
            frame
                .plan
                .finish(s.best_full, spheres, &mut frame.xc_counters)
                .word
        } else {
            tr.words
                .get(i)
                .copied()
                .ok_or_else(|| CycleError::Internal(format!("no word for pixel {}", s.pixel)))?
        };
        let mut ray = s
            .stamps
            .take()
            .unwrap_or_else(|| Stamped::untracked(Ray { pixel: s.pixel }));
        ray.enter(id::RECORD, now);
        let rec = ray.map(|r| Rec {
            pixel: r.pixel,
            word,
        });
        self.pack.accept(now, rec, 1, 0);
        // The slot is initialised afresh when the transform takes it again.
        slots.release(slot);
        Ok(())
    }
}
