//! The hit-buffer check: the pixel's previous word read at entry, the reuse rule applied at
//! exit.
//!
//! Pipeline position: `sorter_to_check` → `check_to_transform` (rays to walk) or
//! `record_to_write` (reused pixels and rays without candidates) (docs/cycle-model.md §2.1).
//! The read goes to this model's own hit-buffer BRAM (READ_FIRST, written by its own write
//! stage in the previous frame); the decision is this model's own and is checked against the
//! functional model's (§2.4). With one hit-buffer write path the record stage has priority on
//! the write FIFO (it is evaluated first and takes its ports); with two
//! (`hit_buffer.write_ports: 2`) this stage has its own write FIFO.

use super::io::{FrameFx, PopPort, PushPort};
use super::{id, internal, Cx, Ray, Rec};
use crate::models::cycle::error::CycleError;
use crate::models::fixed::plan::PixelCounters;
use crate::models::reference::SphereCount;
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_pipe::UnitPipe;

/// The check stage: rays with the word their read returned.
pub struct Check {
    pipe: UnitPipe<(Stamped<Ray>, u128)>,
    /// The record word of a ray with no candidate: the same for every such ray of the frame
    /// (the plan's background record), computed once.
    miss_word: Option<u128>,
    /// This cycle a decided word waited for the write path (the frame's
    /// `stalls.write_port`).
    pub write_blocked: bool,
    /// Counters the plan's reuse rule and record packing update (not reported).
    counters: PixelCounters,
}

/// The check stage's ports: its input, the walk queue, the write path, and the hit-buffer
/// memory it reads (registered contents; the read takes a port at the commit).
pub struct CheckIo<'a> {
    /// `sorter_to_check`.
    pub input: PopPort<'a, Ray>,
    /// `check_to_transform`.
    pub to_walk: PushPort<'a, Ray>,
    /// `record_to_write` (after the record stage's offers) or `check_to_write`.
    pub to_write: PushPort<'a, Rec>,
    /// The hit buffer.
    pub bram: &'a Bram<u128>,
    /// The addresses read this cycle.
    pub reads: &'a mut Vec<usize>,
}

impl Check {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pipe.next_change(now)
    }

    /// The stage of `hw`: the hit buffer's read latency (0 without one) and the unpacking, at
    /// the unpacking unit's initiation interval (before: always 1, the field was ignored).
    pub fn new(hw: &HwConfig) -> Self {
        let u = &hw.units.hit_unpack;
        let latency = hw.hit_buffer_read_cycles() + u.latency_cycles;
        Self {
            pipe: UnitPipe::new(latency, u.ii),
            miss_word: None,
            write_blocked: false,
            counters: PixelCounters::default(),
        }
    }

    /// One cycle: the ready ray is decided and leaves into `to_walk` or `to_write` (if the
    /// write FIFO has a port and room left after the record stage); the next ray enters from
    /// `input` and reads the hit buffer. `upstream_more`: the sorter had rays still to pass as
    /// the cycle started.
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut CheckIo<'_>,
        cx: &Cx<'_, '_>,
        fx: &mut FrameFx,
        upstream_more: bool,
    ) -> Result<StageState, CycleError> {
        let (now, frame) = (cx.now, cx.frame);
        let mut blocked = false;
        self.write_blocked = false;
        if let Some(&(ref ray, prev)) = self.pipe.ready(now) {
            let pixel = ray.payload.pixel;
            let (tr, pw, _) = frame.trace_at(pixel)?;
            let cands = tr.candidates_of(pw);
            let plan = frame.plan;
            let counters = &mut self.counters;
            let reuse = plan.reuse(prev, cands, counters);
            if reuse.is_some() != pw.reused {
                return Err(frame.mismatch(
                    pixel,
                    format!(
                        "hit-buffer reuse {} here, {} in the functional model",
                        reuse.is_some(),
                        pw.reused
                    ),
                ));
            }
            let miss_word = &mut self.miss_word;
            let direct = reuse.or_else(|| {
                cands.is_empty().then(|| {
                    *miss_word
                        .get_or_insert_with(|| plan.finish(None, SphereCount::None, counters).word)
                })
            });
            if let Some(word) = direct {
                // Reused word, or a ray with no candidate: straight to the write port.
                if io.to_write.can_push() {
                    if let Some((mut ray, _)) = self.pipe.pop(now) {
                        let _ = ray.leave(id::CHECK, now);
                        fx.reused += u64::from(reuse.is_some());
                        io.to_write.push(ray.map(|r| Rec {
                            pixel: r.pixel,
                            word,
                        }))?;
                        fx.passed[3] += 1;
                    }
                } else {
                    blocked = true;
                    self.write_blocked = true;
                    io.to_write.note_full();
                }
            } else if io.to_walk.ready() {
                if let Some((mut ray, _)) = self.pipe.pop(now) {
                    let _ = ray.leave(id::CHECK, now);
                    io.to_walk.push(ray)?;
                    fx.walks_entered += 1;
                    fx.passed[3] += 1;
                }
            } else {
                blocked = true;
                io.to_walk.note_full();
            }
        }
        if io.input.valid() && self.pipe.can_accept(now) {
            if let Some(mut ray) = io.input.pop(now)? {
                ray.enter(id::CHECK, now);
                let addr = ray.payload.pixel as usize;
                // READ_FIRST: the word at the start of the cycle, whatever is written in it.
                let word = io.bram.peek(addr).copied().ok_or_else(|| {
                    internal(format!(
                        "hit-buffer read of pixel {addr} beyond its {} words",
                        io.bram.depth()
                    ))
                })?;
                io.reads.push(addr);
                self.pipe.accept(now, (ray, word), 1, 0);
            }
        }
        Ok(self.pipe.state(now, blocked, upstream_more))
    }
}
