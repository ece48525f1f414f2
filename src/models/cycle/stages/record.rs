//! The record stage: early termination, the best hit, and packing the hit-buffer word.
//!
//! Pipeline position: `walker_to_record` → `loop_back` (the ray's next walk) or, through the
//! packing unit, `record_to_write` (docs/cycle-model.md §2.1). After each walk it decides
//! whether the next candidate is needed (paper §4.2, `FramePlan::stops`: the best hit so far
//! is in front of the next candidate's entry); if not, the ray's record is packed and its slot
//! freed. The number of walks and, at the end of the frame, the words are checked against the
//! functional model (§2.4); under cross-check the word is packed from this model's own best
//! walk instead of taken from the trace.

use super::io::{FrameFx, PopPort, PushPort, SlotFx, SlotWrite};
use super::{hand_on_lanes, id, Cx, Ray, RaySlots, Rec, Walk};
use crate::models::cycle::error::CycleError;
use crate::models::fixed::plan::{FramePlan, PixelCounters};
use rtl_model::cycle::clocked::Stamped;
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
    /// Counters the plan's record packing updates under cross-check (not reported).
    counters: PixelCounters,
}

/// The record stage's ports: walk results in, the loop-back and the write FIFO out, the ray
/// slots it reads (registered) and its slot effects (writes and releases, which the
/// transform sees in the same cycle).
pub struct RecordIo<'a> {
    /// `walker_to_record`.
    pub input: PopPort<'a, Walk>,
    /// `loop_back`.
    pub loop_back: PushPort<'a, Walk>,
    /// `record_to_write` (its ports are the record stage's first).
    pub out: PushPort<'a, Rec>,
    /// The ray slots at the start of the cycle.
    pub slots: &'a RaySlots,
    /// Slot writes and releases.
    pub slot_fx: &'a mut SlotFx,
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
            counters: PixelCounters::default(),
        }
    }

    /// One cycle: the packed records leave into `out` (the write FIFO's ports are the record
    /// stage's first), then walk results from `input` are decided, one per lane.
    /// `walked`: a ray had entered the walk section as the cycle started.
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut RecordIo<'_>,
        cx: &Cx<'_, '_>,
        fx: &mut FrameFx,
        walked: bool,
    ) -> Result<StageState, CycleError> {
        let now = cx.now;
        let pushed = hand_on_lanes(&mut self.pack, id::RECORD, &mut io.out, now)?;
        self.write_blocked = self.pack.has_ready(now) && !io.out.can_push();
        let mut state = self.pack.state(now, !pushed, walked);
        while io.input.can_pop() && self.pack.can_accept(now) {
            if let Some(wk) = io.input.pop(now)? {
                self.decide(wk, io, cx, fx)?;
                state = StageState::Busy;
            }
        }
        Ok(state)
    }

    /// The decision on walk result `wk`: loop back for the next candidate, or pack the record
    /// and free the slot. Reads the slot as registered (a ray has one walk in flight, so no
    /// other effect of this cycle touches it) and writes it through the effects.
    fn decide(
        &mut self,
        wk: Stamped<Walk>,
        io: &mut RecordIo<'_>,
        cx: &Cx<'_, '_>,
        fx: &mut FrameFx,
    ) -> Result<(), CycleError> {
        let (now, frame) = (cx.now, cx.frame);
        let Walk { slot, cand } = wk.payload;
        let s = io.slots.get(slot)?;
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
        let mut best = s.best;
        if let Some(t) = tw.hit_t {
            if best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, cand));
            }
        }
        let walks = s.walks + 1;
        io.slot_fx.writes.push(SlotWrite { slot, best, walks });
        let next = usize::from(cand) + 1;
        let more = next < s.cands.len()
            && !best.is_some_and(|(bt, _)| frame.plan.stops(bt, s.cands[next].0));
        if more {
            let mut w2 = wk.map(|_| Walk {
                slot,
                cand: next as u16,
            });
            w2.enter(id::RECORD, now);
            let _ = w2.leave(id::RECORD, now);
            return io
                .loop_back
                .push(w2)
                .map_err(|e| CycleError::Internal(format!("loop-back: {e}")));
        }
        if next < s.cands.len() {
            fx.early += 1;
        }
        if walks != pw.walk_len {
            return Err(frame.mismatch(
                s.pixel,
                format!(
                    "{} walks here, {} in the functional model (early termination differs)",
                    walks, pw.walk_len
                ),
            ));
        }
        let word = if frame.setup.cross_check {
            let spheres = FramePlan::sphere_count(&s.cands);
            frame
                .plan
                .finish(s.best_full, spheres, &mut self.counters)
                .word
        } else {
            tr.words
                .get(i)
                .copied()
                .ok_or_else(|| CycleError::Internal(format!("no word for pixel {}", s.pixel)))?
        };
        // The slot's stamps are dropped at the commit, as the slot is freed.
        let mut ray = s
            .stamps
            .clone()
            .unwrap_or_else(|| Stamped::untracked(Ray { pixel: s.pixel }));
        ray.enter(id::RECORD, now);
        let rec = ray.map(|r| Rec {
            pixel: r.pixel,
            word,
        });
        self.pack.accept(now, rec, 1, 0);
        // The slot is initialised afresh when the transform takes it again.
        io.slot_fx.releases.push(slot);
        Ok(())
    }
}
