//! The one place a cycle's effects land: after every stage kernel has been evaluated on the
//! registered state, [`Effects::apply`] drives the FIFOs (the pops each stage asked, the items
//! each offered), the ray slots (the record stage's writes and releases, the walker stage's
//! cross-check results, the transform's takes), the hit-buffer BRAM (writes, then reads), the
//! transaction log and the frame's counts; the clock edge that follows commits the FIFOs and
//! the BRAM (`rtl_model::cycle::clocked`).
//!
//! Pipeline position: called by `pipeline::Pipeline::step` once per stepped cycle, between the
//! stages and the edge (docs/cycle-model.md §2.1, the stage interface). Because no kernel
//! writes anything another kernel reads in the same cycle — except the record stage's two
//! same-cycle signals, which travel in these buffers — the order the kernels ran in cannot
//! change what is applied here.

use super::error::CycleError;
use super::fifos::Fifos;
use super::stages::io::{BramFx, FifoFx, FrameFx, SlotFx};
use super::stages::{internal, FrameCounts, FrameInputs, Ray, RaySlots, Rec, Walk};
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::StageStamp;
use rtl_model::cycle::fifo::Fifo;

/// Every effect of one cycle, per part, reused from cycle to cycle (cleared by
/// [`Effects::apply`], their buffers kept).
#[derive(Default)]
pub struct Effects {
    /// `raygen_to_sphere`.
    pub rg_sp: FifoFx<Ray>,
    /// `sphere_to_sorter`.
    pub sp_so: FifoFx<Ray>,
    /// `sorter_to_check`.
    pub so_ck: FifoFx<Ray>,
    /// `check_to_transform`.
    pub ck_tr: FifoFx<Ray>,
    /// `loop_back`.
    pub loop_back: FifoFx<Walk>,
    /// `transform_to_reciprocal`.
    pub tr_rc: FifoFx<Walk>,
    /// `reciprocal_to_root`.
    pub rc_rt: FifoFx<Walk>,
    /// `root_to_dispatch`.
    pub rt_dp: FifoFx<Walk>,
    /// `walker_to_record`.
    pub wk_rc: FifoFx<Walk>,
    /// `record_to_write` (the record stage's offers first, then the check stage's).
    pub rc_wr: FifoFx<Rec>,
    /// `check_to_write`.
    pub ck_wr: FifoFx<Rec>,
    /// The ray slots.
    pub slots: SlotFx,
    /// The hit buffer.
    pub bram: BramFx,
    /// Counts and the trace row ray generation needs.
    pub frame: FrameFx,
}

/// What the effects land on.
pub struct Targets<'a, 'f> {
    /// The FIFOs.
    pub fifos: &'a mut Fifos,
    /// The ray slots.
    pub slots: &'a mut RaySlots,
    /// The hit buffer.
    pub bram: &'a mut Bram<u128>,
    /// The frame's counts.
    pub counts: &'a mut FrameCounts,
    /// The frame's inputs (rows are received here).
    pub frame: &'a mut FrameInputs<'f>,
    /// The transaction log and how many records it keeps per run.
    pub log: &'a mut Vec<(u32, Vec<StageStamp>)>,
    /// Records whose stamps the log keeps.
    pub log_limit: usize,
}

/// A FIFO's pops and pushes of the cycle, as the stage would have driven it directly, and
/// the back-pressure a producer reported (a full cycle, `FifoStats::full_cycles`).
/// Most FIFOs are untouched in most cycles: the test for that is inlined into the caller and
/// only a FIFO with effects pays for the call (inlining all of `drive` made the loop slower,
/// docs/cycle-model.md §3).
#[inline(always)]
fn drive<T>(f: &mut Fifo<T>, fx: &mut FifoFx<T>) -> Result<(), CycleError> {
    if fx.pops == 0 && fx.pushes.is_empty() && !fx.full {
        return Ok(());
    }
    drive_moves(f, fx)
}

/// [`drive`] of a FIFO with effects.
#[inline(never)]
fn drive_moves<T>(f: &mut Fifo<T>, fx: &mut FifoFx<T>) -> Result<(), CycleError> {
    // The stage already holds a copy of each item it popped: the FIFO drops its own in place.
    // The usual cycle, every pop and push firing, goes as one batch; otherwise one by one,
    // so that what does not fire is counted or refused as it would be when driven directly.
    let pops = std::mem::take(&mut fx.pops);
    if !f.drive_batch(pops, &mut fx.pushes) {
        for _ in 0..pops {
            f.pop_driven().map_err(internal)?;
        }
        for item in fx.pushes.drain(..) {
            f.push_driven(item).map_err(internal)?;
        }
    }
    // After the pushes: the held item found no room even with this cycle's offers inside.
    if std::mem::take(&mut fx.full) {
        f.note_full().map_err(internal)?;
    }
    Ok(())
}

impl Effects {
    /// Applies and clears the cycle's effects.
    pub fn apply(&mut self, t: Targets<'_, '_>) -> Result<(), CycleError> {
        let f = t.fifos;
        drive(&mut f.rg_sp, &mut self.rg_sp)?;
        drive(&mut f.sp_so, &mut self.sp_so)?;
        drive(&mut f.so_ck, &mut self.so_ck)?;
        drive(&mut f.ck_tr, &mut self.ck_tr)?;
        drive(&mut f.loop_back, &mut self.loop_back)?;
        drive(&mut f.tr_rc, &mut self.tr_rc)?;
        drive(&mut f.rc_rt, &mut self.rc_rt)?;
        drive(&mut f.rt_dp, &mut self.rt_dp)?;
        drive(&mut f.wk_rc, &mut self.wk_rc)?;
        drive(&mut f.rc_wr, &mut self.rc_wr)?;
        drive(&mut f.ck_wr, &mut self.ck_wr)?;
        if !self.slots.is_empty() {
            Self::apply_slots(&mut self.slots, t.slots, t.frame)?;
        }
        // The write port before the read: the order the stages used the ports in when they
        // drove the memory themselves (write stage first), so a port conflict reads the same.
        for r in self.bram.writes.drain(..) {
            t.bram
                .write(r.payload.pixel as usize, r.payload.word)
                .map_err(internal)?;
            if t.log.len() < t.log_limit {
                t.log.push((r.payload.pixel, r.stamps().to_vec()));
            }
            t.counts.written += 1;
        }
        for addr in self.bram.reads.drain(..) {
            t.bram.read(addr).map_err(internal)?;
        }
        let fx = std::mem::take(&mut self.frame);
        let c = t.counts;
        for (p, d) in c.passed.iter_mut().zip(fx.passed) {
            *p += d;
        }
        c.walks_entered += fx.walks_entered;
        c.early += fx.early;
        c.reused += fx.reused;
        if let Some(row) = fx.need_row {
            t.frame.need_row(row)?;
        }
        Ok(())
    }

    /// The slot table's effects: the record stage's writes and releases, the walker stage's
    /// cross-check results, then the transform's takes (which may reuse a slot released in
    /// the same cycle, as the kernel expected).
    fn apply_slots(
        fx: &mut SlotFx,
        slots: &mut RaySlots,
        frame: &FrameInputs<'_>,
    ) -> Result<(), CycleError> {
        for w in fx.writes.drain(..) {
            let s = slots.get_mut(w.slot)?;
            s.best = w.best;
            s.walks = w.walks;
        }
        for slot in fx.releases.drain(..) {
            slots.get_mut(slot)?.stamps = None;
            slots.release(slot);
        }
        for (slot, best) in fx.best_full.drain(..) {
            slots.get_mut(slot)?.best_full = Some(best);
        }
        for take in fx.takes.drain(..) {
            let (tr, pw, _) = frame.trace_at(take.pixel)?;
            let slot = slots.take(take.pixel, tr.candidates_of(pw), take.stamps)?;
            if slot != take.slot {
                return Err(CycleError::Internal(format!(
                    "the transform expected ray slot {}, the free list gave {slot}",
                    take.slot
                )));
            }
        }
        Ok(())
    }
}
