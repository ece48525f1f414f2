//! One stage's evaluation within a clock: the order the stages are evaluated in
//! ([`EvalOrder`]), the same-cycle signals they share ([`Wires`]), and
//! `Pipeline::eval_stage`, which runs one stage kernel on read-only ports of the registered
//! state and gathers its effects.
//!
//! Pipeline position: inside [`super::Pipeline::step`], before the commit; each stage's kernel
//! is in `super::super::stages`, one file each.

use super::super::error::CycleError;
use super::super::stages::check::CheckIo;
use super::super::stages::io::{PopPort, PushPort, SlotView};
use super::super::stages::record::RecordIo;
use super::super::stages::transform::TransformIo;
use super::super::stages::walkers::{WalkerIo, WalkerRegs};
use super::super::stages::write::WriteIo;
use super::super::stages::{Cx, UnitIo};
use super::{
    Pipeline, S_CHECK, S_RAYGEN, S_RECIP, S_RECORD, S_ROOT, S_SORTER, S_SPHERE, S_TRANSFORM,
    S_WALK, S_WRITE,
};
use rtl_model::cycle::stage_stats::StageState;

/// The order the stages are evaluated in within a clock (docs/architecture.md §4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EvalOrder {
    /// Write port first, ray generation last: what every run uses.
    #[default]
    ConsumersFirst,
    /// The reverse: ray generation first, write port last, except that the record stage
    /// moves up to just before the check stage, the first stage that reads its same-cycle
    /// signals (its offers to the write FIFO, the slots it frees). A test hook: the cycles,
    /// stall counters, stage states, images and reports must be the same as
    /// [`EvalOrder::ConsumersFirst`]'s.
    ProducersFirst,
}

/// [`EvalOrder::ProducersFirst`]: `ConsumersFirst` reversed, the record stage moved up to
/// just before the check stage.
pub(super) const PRODUCERS_FIRST: [usize; 10] = [
    S_RAYGEN,
    S_SPHERE,
    S_SORTER,
    S_RECORD,
    S_CHECK,
    S_TRANSFORM,
    S_RECIP,
    S_ROOT,
    S_WALK,
    S_WRITE,
];

/// What one cycle's stages read besides the registered FIFOs: the frame's counters as the
/// cycle started (for the starved/idle accounting) and the record stage's same-cycle signals.
pub(super) struct Wires {
    /// Rays still to leave raygen, sphere and sorter (what the next stage may still get).
    pub(super) upstream_more: [bool; 3],
    /// A ray has entered the walk section this frame.
    pub(super) walked: bool,
    /// Walks are in the walk section or may still come.
    pub(super) more_walks: bool,
    /// Rays of the frame are still to leave the check stage.
    pub(super) more_rays: bool,
    /// The record stage has been evaluated (and has freed the slots of its records).
    pub(super) record_done: bool,
}

impl Pipeline<'_> {
    /// Evaluates stage `stage` (an `S_*` row) for cycle `now`: its kernel, on read-only
    /// ports of the registered FIFOs, slots and memory, its effects into `self.fx`. `wires`
    /// carries the two same-cycle signals of the record stage (docs/architecture.md §4), which
    /// reach the check stage and the transform through the effects it has already returned:
    /// its offers to the write FIFO (the check stage may not take those ports) and the slots
    /// it frees (the transform may take them in the same cycle); a stage that reads one before
    /// the record stage has been evaluated is an error, not a silent different result.
    #[inline(always)]
    pub(super) fn eval_stage(
        &mut self,
        stage: usize,
        now: u64,
        wires: &mut Wires,
    ) -> Result<StageState, CycleError> {
        let (f, fx) = (&self.fifos, &mut self.fx);
        let cx = Cx {
            now,
            frame: &self.frame,
            counts: &self.counts,
        };
        let record_first = |what: &str| {
            if wires.record_done {
                Ok(())
            } else {
                Err(CycleError::Internal(format!(
                    "{what} evaluated before the record stage in a cycle"
                )))
            }
        };
        Ok(match stage {
            S_WRITE => {
                let mut io = WriteIo {
                    input: PopPort::new(&f.rc_wr),
                    second: f.two_write_paths.then(|| PopPort::new(&f.ck_wr)),
                    writes: &mut fx.bram.writes,
                };
                let state = self.write.eval(&mut io, &cx)?;
                fx.rc_wr.pops += io.input.asked();
                fx.ck_wr.pops += io.second.map_or(0, |p| p.asked());
                state
            }
            S_RECORD => {
                let mut io = RecordIo {
                    input: PopPort::new(&f.wk_rc),
                    loop_back: PushPort::new(&f.loop_back, &mut fx.loop_back),
                    out: PushPort::new(&f.rc_wr, &mut fx.rc_wr),
                    slots: &self.slots,
                    slot_fx: &mut fx.slots,
                };
                let state = self
                    .record
                    .eval(&mut io, &cx, &mut fx.frame, wires.walked)?;
                fx.wk_rc.pops += io.input.asked();
                wires.record_done = true;
                state
            }
            S_WALK => {
                let m = &mut *self.machine;
                let mut io = WalkerIo {
                    input: PopPort::new(&f.rt_dp),
                    out: PushPort::new(&f.wk_rc, &mut fx.wk_rc),
                    slots: &self.slots,
                    best_full: &mut fx.slots.best_full,
                };
                let mut regs = WalkerRegs {
                    pool: &mut m.pool,
                    mem: &mut m.mem,
                };
                let state = self
                    .walkers
                    .eval(&mut io, &mut regs, &cx, wires.more_walks)?;
                fx.rt_dp.pops += io.input.asked();
                state
            }
            S_ROOT => {
                let mut io = UnitIo {
                    input: PopPort::new(&f.rc_rt),
                    out: PushPort::new(&f.rt_dp, &mut fx.rt_dp),
                };
                let state = self.root.eval(&mut io, wires.more_walks, now)?;
                fx.rc_rt.pops += io.input.asked();
                state
            }
            S_RECIP => {
                let mut io = UnitIo {
                    input: PopPort::new(&f.tr_rc),
                    out: PushPort::new(&f.rc_rt, &mut fx.rc_rt),
                };
                let state = self.recip.eval(&mut io, wires.more_walks, now)?;
                fx.tr_rc.pops += io.input.asked();
                state
            }
            S_TRANSFORM => {
                record_first("the transform")?;
                if self.hold.is_some() {
                    StageState::Starved
                } else {
                    let slot_fx = &mut fx.slots;
                    let mut io = TransformIo {
                        loop_back: PopPort::new(&f.loop_back),
                        new_rays: PopPort::new(&f.ck_tr),
                        out: PushPort::new(&f.tr_rc, &mut fx.tr_rc),
                        slots: SlotView::new(&self.slots, &slot_fx.releases),
                        takes: &mut slot_fx.takes,
                    };
                    let state =
                        self.transform
                            .eval(&mut io, &cx, wires.more_walks, wires.more_rays)?;
                    fx.loop_back.pops += io.loop_back.asked();
                    fx.ck_tr.pops += io.new_rays.asked();
                    state
                }
            }
            S_CHECK => {
                record_first("the check stage")?;
                let (to_write, write_fx) = if f.two_write_paths {
                    (&f.ck_wr, &mut fx.ck_wr)
                } else {
                    (&f.rc_wr, &mut fx.rc_wr)
                };
                let mut io = CheckIo {
                    input: PopPort::new(&f.so_ck),
                    to_walk: PushPort::new(&f.ck_tr, &mut fx.ck_tr),
                    to_write: PushPort::new(to_write, write_fx),
                    bram: &self.machine.bram,
                    reads: &mut fx.bram.reads,
                };
                let state = self
                    .check
                    .eval(&mut io, &cx, &mut fx.frame, wires.upstream_more[2])?;
                fx.so_ck.pops += io.input.asked();
                state
            }
            S_SORTER => {
                let mut io = UnitIo {
                    input: PopPort::new(&f.sp_so),
                    out: PushPort::new(&f.so_ck, &mut fx.so_ck),
                };
                let state =
                    self.sorter
                        .eval(&mut io, &cx, &mut fx.frame, wires.upstream_more[1])?;
                fx.sp_so.pops += io.input.asked();
                state
            }
            S_SPHERE => {
                let mut io = UnitIo {
                    input: PopPort::new(&f.rg_sp),
                    out: PushPort::new(&f.sp_so, &mut fx.sp_so),
                };
                let state =
                    self.sphere
                        .eval(&mut io, &cx, &mut fx.frame, wires.upstream_more[0])?;
                fx.rg_sp.pops += io.input.asked();
                state
            }
            _ => {
                let mut out = PushPort::new(&f.rg_sp, &mut fx.rg_sp);
                self.raygen.eval(&mut out, &cx, &mut fx.frame)?
            }
        })
    }
}
