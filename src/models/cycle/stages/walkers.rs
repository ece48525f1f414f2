//! The walker pool as a stage: wake, retire, dispatch, issue.
//!
//! Pipeline position: `root_to_dispatch` → `walker_to_record` (docs/cycle-model.md §2.1, the
//! pool itself §2.3). Per cycle: contexts whose read completed or whose step latency ended
//! move on; the oldest finished walks leave and walks are dispatched, up to the walk lanes
//! (`HwConfig::walk_lanes`, the FIFOs' ports) each, a walk with its recorded ops, their node
//! and attribute addresses relocated to its asset's place in node memory; every walker
//! issues. Under cross-check the dispatcher re-executes the transform, reciprocals and
//! the whole walk from the ray's direction and compares every op and the hit with the trace
//! (§2.4).

use super::io::{PopPort, PushPort};
use super::{id, Cx, FrameInputs, RaySlots, Scratch, Walk};
use crate::models::cycle::error::CycleError;
use crate::models::fixed::plan::Best;
use crate::models::fixed::trace::{OpRecorder, WalkOp};
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::memory::NodeMemory;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::walker_pool::WalkerPoolModel;
use rtl_model::units::walker::WalkOutcome;

/// The walker stage. Its registers are the pool's contexts and the node memory, which live
/// across frames in the model ([`WalkerRegs`]); the stage is how the pipeline drives them.
#[derive(Default)]
pub struct Walkers {
    /// The cross-check's scratch.
    xc: Scratch,
}

/// The walker stage's own state that outlives the frame: the pool and the node memory. The
/// stage mutates them in its kernel (they are its registers); its FIFO and slot effects go
/// through the commit.
pub struct WalkerRegs<'a> {
    /// The walker pool.
    pub pool: &'a mut WalkerPoolModel,
    /// The node memory.
    pub mem: &'a mut NodeMemory,
}

/// The walker stage's ports: walks in, finished walks out, the ray slots it reads, and the
/// cross-check's best results it writes to them.
pub struct WalkerIo<'a> {
    /// `root_to_dispatch`.
    pub input: PopPort<'a, Walk>,
    /// `walker_to_record`.
    pub out: PushPort<'a, Walk>,
    /// The ray slots at the start of the cycle.
    pub slots: &'a RaySlots,
    /// Under cross-check: the walker's own best result per slot.
    pub best_full: &'a mut Vec<(u32, Best)>,
}

/// The pool's tag of walk `w`: slot in the high bits, candidate in the low 16.
#[inline]
fn tag_of(w: Walk) -> u64 {
    (u64::from(w.slot) << 16) | u64::from(w.cand)
}

/// The walk a pool tag names.
#[inline]
fn walk_of(tag: u64) -> Walk {
    Walk {
        slot: (tag >> 16) as u32,
        cand: tag as u16,
    }
}

impl Walkers {
    /// One cycle of the pool. `more_walks`: whether walks may still come (for the
    /// starved/idle accounting). The stage is busy when any walker issued.
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut WalkerIo<'_>,
        regs: &mut WalkerRegs<'_>,
        cx: &Cx<'_, '_>,
        more_walks: bool,
    ) -> Result<StageState, CycleError> {
        let now = cx.now;
        let (pool, mem) = (&mut *regs.pool, &mut *regs.mem);
        let out = &mut io.out;
        pool.wake(now, mem)?;
        // Up to the walk lanes (the FIFOs' ports) retire and dispatch per cycle.
        while pool.finished_head().is_some() && out.can_push() {
            let Some(tag) = pool.retire() else { break };
            let mut wk = Stamped::untracked(walk_of(tag));
            wk.enter(id::WALKER, now);
            let _ = wk.leave(id::WALKER, now);
            out.push(wk)?;
        }
        // A finished walker left behind is back-pressure if `walker_to_record` has no room.
        if pool.finished_head().is_some() {
            out.note_full();
        }
        while io.input.can_pop() {
            if !pool.has_free() {
                pool.note_dispatch_stall();
                break;
            }
            if let Some(wk) = io.input.pop(now)? {
                let best = self.dispatch(wk.payload, pool, io.slots, cx.frame)?;
                if let Some(b) = best {
                    io.best_full.push((wk.payload.slot, b));
                }
            }
        }
        pool.issue();
        Ok(if pool.issued_count() > 0 {
            StageState::Busy
        } else if pool.busy_contexts() > 0 {
            if out.ready() {
                StageState::Idle
            } else {
                StageState::Backpressured
            }
        } else if more_walks {
            StageState::Starved
        } else {
            StageState::Idle
        })
    }

    /// Hands walk `w` to a free context with its recorded ops, relocated to its asset.
    /// Under cross-check, returns the slot's new best result when this walk improves it.
    fn dispatch(
        &mut self,
        w: Walk,
        pool: &mut WalkerPoolModel,
        slots: &RaySlots,
        frame: &FrameInputs<'_>,
    ) -> Result<Option<Best>, CycleError> {
        let Walk { slot, cand } = w;
        let s = slots.get(slot)?;
        let mut best = None;
        let (tr, pw, _) = frame.trace_at(s.pixel)?;
        let Some(&(_, k)) = s.cands.get(usize::from(cand)) else {
            return Err(CycleError::Internal(format!(
                "walk {cand} of a ray with {} candidates",
                s.cands.len()
            )));
        };
        let Some(tw) = tr.walks_of(pw).get(usize::from(cand)) else {
            return Err(frame.mismatch(
                s.pixel,
                format!(
                    "walk {cand} wanted here, the functional model did {}",
                    pw.walk_len
                ),
            ));
        };
        let asset = frame
            .instance_asset
            .get(usize::from(k))
            .copied()
            .unwrap_or(0);
        let nb = frame.layout.node_base.get(asset).copied().unwrap_or(0);
        let ab = frame.layout.attr_base.get(asset).copied().unwrap_or(0);
        let ops = tr.ops_of(tw);
        if frame.setup.cross_check {
            // Re-execute the walk from this stage's own inputs.
            let mut mine: Vec<u64> = Vec::with_capacity(ops.len());
            let mut rec = OpRecorder::new(&mut mine);
            let d = frame.dir[s.pixel as usize];
            let (out, signs) = frame.plan.walk(d, k, &mut self.xc.counters, &mut rec);
            rec.finish();
            let hit_t = match out {
                WalkOutcome::Hit(h) => Some(h.t),
                _ => None,
            };
            if mine != ops || hit_t != tw.hit_t {
                // Name the first op that differs, so the message says what disagreed.
                let first = (0..mine.len().max(ops.len()))
                    .find(|&n| mine.get(n) != ops.get(n))
                    .map(|n| {
                        let op = |w: Option<&u64>| w.map(|&w| WalkOp::unpack(w));
                        format!(
                            "; op {n}: {:?} here, {:?} in the functional model",
                            op(mine.get(n)),
                            op(ops.get(n))
                        )
                    })
                    .unwrap_or_default();
                return Err(frame.mismatch(
                    s.pixel,
                    format!(
                        "walk {cand} (instance {k}) differs: {} ops / t {:?} here, {} ops / t {:?} in the functional model{first}",
                        mine.len(),
                        hit_t,
                        ops.len(),
                        tw.hit_t
                    ),
                ));
            }
            if let WalkOutcome::Hit(h) = out {
                if s.best_full.is_none_or(|(bt, _, _, _)| h.t < bt) {
                    best = Some((h.t, k, h, signs));
                }
            }
        }
        // Node and attribute addresses are per asset: relocate them to the asset's place in
        // the node memory as the context takes them.
        // On the packed word (`WalkOp::pack`: the kind in bits 32.., the address in the low
        // 32; `unpack` reads any kind above 2 as an attribute read): an issue run (kind 0)
        // stays, a node or far word read (1, 2) moves by `nb`, an attribute read by `ab`.
        let relocate = |&o: &u64| {
            let (kind, base) = match o >> 32 {
                0 => return o,
                k @ (1 | 2) => (k, nb),
                _ => (3, ab),
            };
            (kind << 32) | u64::from((o as u32).wrapping_add(base))
        };
        pool.dispatch_with(tag_of(w), |v| v.extend(ops.iter().map(relocate)));
        Ok(best)
    }
}
