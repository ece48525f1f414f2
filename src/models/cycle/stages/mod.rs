//! The stages of the cycle pipeline, one file each, and what they hand each other.
//!
//! Pipeline position: the parts [`super::pipeline::Pipeline`] evaluates once per clock,
//! consumers first (docs/cycle-model.md §2.1). A stage is a struct holding its registers — a
//! fixed-latency [`UnitPipe`] for the units, the pixel counter for ray generation — with one
//! `eval` that is a kernel (issue 30, rhdl style): a function of its own state and a read-only
//! view of the registered state around it — `io::PopPort`/`io::PushPort` on its FIFOs, the ray
//! slots, the hit buffer's words, the frame's inputs and counts as the cycle started ([`Cx`]) —
//! that updates its own state and returns the cycle's effects into the pipeline's reused
//! buffers (`io`: pops, offered items, slot writes/takes/releases, BRAM reads and writes, count
//! increments) and its state for the cycle's accounting. No stage holds a `&mut` to a FIFO,
//! the slot table or a memory; `commit::Effects::apply` applies every stage's effects in one
//! place after all of them, then the clock edge commits (`rtl_model::cycle::clocked`). The
//! walker stage's own state is the walker pool and the node memory (`walkers::WalkerRegs`).
//!
//! Interface rule: a stage takes its ports grouped in one struct (`UnitIo`, `CheckIo`, …) —
//! no trait objects, no allocation per transaction beyond its stamps — so that the loop's data
//! layout can change under the stages without changing what they decide. Nothing here imports
//! the model or the pipeline (`imports.rs` checks it).
//!
//! This file holds what several stages share: the transactions, the ray slots of the walk
//! section, the frame's inputs (the functional model's trace, read as rows arrive), the
//! frame's counters and the kernels' cycle context.

pub mod check;
#[cfg(test)]
mod imports;
pub mod io;
pub mod passthrough;
pub mod raygen;
pub mod record;
pub mod sorter;
pub mod sphere;
pub mod tile_list;
pub mod transform;
pub mod walkers;
pub mod write;

use super::error::CycleError;
use super::layout::SceneLayout;
use crate::models::fixed::plan::{Best, FramePlan, PixelCounters};
use crate::models::fixed::row_feed::RowFeed;
use crate::models::fixed::trace::{PixelWork, RowTrace};
use io::{PopPort, PushPort};
use rtl_model::cycle::clocked::{StageId, Stamped};
use rtl_model::cycle::unit_lanes::UnitLanes;
use rtl_model::cycle::unit_pipe::UnitPipe;
use rtl_model::units::walker::WalkerT;

/// Stage ids for stamps and the transaction log, in pipeline order, FIFOs included.
pub mod id {
    use rtl_model::cycle::clocked::StageId;

    /// Ray generation.
    pub const RAYGEN: StageId = StageId(0);
    /// FIFO raygen → sphere.
    pub const F_RG_SP: StageId = StageId(1);
    /// Sphere lanes.
    pub const SPHERE: StageId = StageId(2);
    /// FIFO sphere → sorter.
    pub const F_SP_SO: StageId = StageId(3);
    /// Sorter.
    pub const SORTER: StageId = StageId(4);
    /// FIFO sorter → check.
    pub const F_SO_CK: StageId = StageId(5);
    /// Hit-buffer check.
    pub const CHECK: StageId = StageId(6);
    /// FIFO check → transform.
    pub const F_CK_TR: StageId = StageId(7);
    /// Loop-back FIFO record → transform.
    pub const F_LOOP: StageId = StageId(8);
    /// Transform.
    pub const TRANSFORM: StageId = StageId(9);
    /// FIFO transform → reciprocal.
    pub const F_TR_RC: StageId = StageId(10);
    /// Reciprocal units.
    pub const RECIP: StageId = StageId(11);
    /// FIFO reciprocal → root.
    pub const F_RC_RT: StageId = StageId(12);
    /// Walker-root units.
    pub const ROOT: StageId = StageId(13);
    /// FIFO root → dispatcher.
    pub const F_RT_DP: StageId = StageId(14);
    /// Walker pool.
    pub const WALKER: StageId = StageId(15);
    /// FIFO walkers → record.
    pub const F_WK_RC: StageId = StageId(16);
    /// Record.
    pub const RECORD: StageId = StageId(17);
    /// FIFO record → write.
    pub const F_RC_WR: StageId = StageId(18);
    /// Hit-buffer write port.
    pub const WRITE: StageId = StageId(19);
    /// FIFO check → write (the check stage's own write path, two write ports).
    pub const F_CK_WR: StageId = StageId(20);
}

/// Names of the stage ids (`id`), in pipeline order, for transaction logs.
pub const STAGE_NAMES: [&str; 21] = [
    "raygen",
    "raygen_to_sphere",
    "sphere",
    "sphere_to_sorter",
    "sorter",
    "sorter_to_check",
    "check",
    "check_to_transform",
    "loop_back",
    "transform",
    "transform_to_reciprocal",
    "reciprocal",
    "reciprocal_to_root",
    "root",
    "root_to_dispatch",
    "walker",
    "walker_to_record",
    "record",
    "record_to_write",
    "write",
    "check_to_write",
];

/// A ray between ray generation and the check stage.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Pixel index in raster order.
    pub pixel: u32,
}

/// One walk of a ray: its slot and candidate index.
#[derive(Clone, Copy, Debug)]
pub struct Walk {
    /// Ray slot (index into [`RaySlots`]).
    pub slot: u32,
    /// Candidate index in the ray's sorted list.
    pub cand: u16,
}

/// A record on its way to the write port.
#[derive(Clone, Copy, Debug)]
pub struct Rec {
    /// Pixel index.
    pub pixel: u32,
    /// Packed hit-buffer word.
    pub word: u128,
}

/// A misused FIFO or BRAM: a model bug, reported with the part's own message.
pub fn internal(e: impl std::fmt::Display) -> CycleError {
    CycleError::Internal(e.to_string())
}

/// The output half of a fixed unit between FIFOs: the ready head leaves into `out` when `out`
/// is ready (registered); a ready head `out` cannot take is back-pressure
/// (`PushPort::note_full`). Returns whether it left.
#[inline]
pub fn hand_on<T>(
    pipe: &mut UnitPipe<Stamped<T>>,
    stage: StageId,
    out: &mut PushPort<'_, T>,
    now: u64,
) -> Result<bool, CycleError> {
    if pipe.ready(now).is_some() {
        if !out.ready() {
            out.note_full();
        } else if let Some(mut w) = pipe.pop(now) {
            let _ = w.leave(stage, now);
            out.push(w)?;
            return Ok(true);
        }
    }
    Ok(false)
}

/// [`hand_on`] for `n` units side by side: ready results leave, oldest first, while `out`
/// takes them (up to its ports); a ready result left behind is reported to `out`, which
/// counts it as back-pressure only if it had no room (`PushPort::note_full`). Returns
/// whether any left.
#[inline]
pub fn hand_on_lanes<T>(
    lanes: &mut UnitLanes<Stamped<T>>,
    stage: StageId,
    out: &mut PushPort<'_, T>,
    now: u64,
) -> Result<bool, CycleError> {
    let mut any = false;
    // `has_ready` is one compare against the lanes' cached earliest result: the common cycle
    // with nothing ready costs no scan of the lanes.
    while lanes.has_ready(now) && out.can_push() {
        let Some(mut w) = lanes.pop(now) else { break };
        let _ = w.leave(stage, now);
        out.push(w)?;
        any = true;
    }
    if lanes.has_ready(now) {
        out.note_full();
    }
    Ok(any)
}

/// What every kernel reads of the cycle besides its ports: the cycle, the frame's inputs and
/// the frame's counts as the cycle started (registered: no stage sees another's count of this
/// cycle).
#[derive(Clone, Copy)]
pub struct Cx<'a, 'f> {
    /// The cycle.
    pub now: u64,
    /// The frame's inputs (trace rows received so far, plan, direction table, layout).
    pub frame: &'a FrameInputs<'f>,
    /// The frame's counts at the start of the cycle.
    pub counts: &'a FrameCounts,
}

/// The two ports of a unit between two FIFOs.
pub struct UnitIo<'a, I, O> {
    /// Its input FIFO's consumer side.
    pub input: PopPort<'a, I>,
    /// Its output FIFO's producer side.
    pub out: PushPort<'a, O>,
}

/// Scratch of a stage's cross-check (and of the plan's unit functions it calls): its own,
/// so that kernels read the frame's inputs through a shared reference.
#[derive(Default)]
pub struct Scratch {
    /// This model's own candidates of a ray.
    pub cands: Vec<(i64, u16)>,
    /// Counters the plan's unit functions update (not reported by the cycle model).
    pub counters: PixelCounters,
}

/// A ray in the walk section.
#[derive(Clone, Debug, Default)]
pub struct Slot {
    /// Pixel index.
    pub pixel: u32,
    /// Sorted candidates (from the trace, or this model's own sort under cross-check).
    pub cands: Vec<(i64, u16)>,
    /// Best hit so far: walker t (raw) and candidate index.
    pub best: Option<(WalkerT, u16)>,
    /// Under cross-check, the walker's own best result.
    pub best_full: Option<Best>,
    /// Walks done.
    pub walks: u16,
    /// The ray's stamps up to the check stage, taken back by its record.
    pub stamps: Option<Stamped<Ray>>,
}

/// The ray slots of the walk section: a ray takes one as its first walk enters the transform
/// and frees it when its record leaves (docs/cycle-model.md §2.1).
pub struct RaySlots {
    slots: Vec<Slot>,
    free: Vec<u32>,
}

impl RaySlots {
    /// `n` free slots; the lowest index is taken first.
    pub fn new(n: u32) -> Self {
        Self {
            slots: (0..n).map(|_| Slot::default()).collect(),
            free: (0..n).rev().collect(),
        }
    }

    /// Takes a free slot for the ray `stamps` of `pixel` with its sorted candidates `cands`,
    /// initialising it afresh.
    pub fn take(
        &mut self,
        pixel: u32,
        cands: &[(i64, u16)],
        stamps: Stamped<Ray>,
    ) -> Result<u32, CycleError> {
        let Some(slot) = self.free.pop() else {
            return Err(CycleError::Internal("no ray slot".into()));
        };
        let s = self.get_mut(slot)?;
        s.pixel = pixel;
        s.cands.clear();
        s.cands.extend_from_slice(cands);
        s.best = None;
        s.best_full = None;
        s.walks = 0;
        s.stamps = Some(stamps);
        Ok(slot)
    }

    /// Free slots.
    #[inline]
    pub fn free_count(&self) -> usize {
        self.free.len()
    }

    /// The free slot `k` places below the top of the free stack (0: the next one taken).
    #[inline]
    pub fn free_from_top(&self, k: usize) -> Option<u32> {
        self.free
            .len()
            .checked_sub(k + 1)
            .and_then(|i| self.free.get(i))
            .copied()
    }

    /// Slot `slot`, read only.
    #[inline]
    pub fn get(&self, slot: u32) -> Result<&Slot, CycleError> {
        self.slots
            .get(slot as usize)
            .ok_or_else(|| CycleError::Internal(format!("no ray slot {slot}")))
    }

    /// Slot `slot`.
    #[inline]
    pub fn get_mut(&mut self, slot: u32) -> Result<&mut Slot, CycleError> {
        self.slots
            .get_mut(slot as usize)
            .ok_or_else(|| CycleError::Internal(format!("no ray slot {slot}")))
    }

    /// Frees slot `slot` (its contents stay until it is taken again).
    #[inline]
    pub fn release(&mut self, slot: u32) {
        self.free.push(slot);
    }
}

/// Where a frame sits in the run and how it is checked.
#[derive(Clone, Copy, Debug)]
pub struct FrameSetup {
    /// Frame number in the run.
    pub frame: u32,
    /// Frame width in pixels.
    pub width: u32,
    /// Frame height in pixels.
    pub height: u32,
    /// Re-execute every stage's arithmetic and compare (docs/cycle-model.md §2.4).
    pub cross_check: bool,
}

/// The frame's inputs as the stages read them: the prepared datapath, the direction table,
/// the scene's placement in node memory, and the functional model's trace, taken row by row
/// as it arrives.
pub struct FrameInputs<'f> {
    /// Where the frame sits and how it is checked.
    pub setup: FrameSetup,
    /// The frame's prepared datapath.
    pub plan: &'f FramePlan<'f>,
    feed: &'f RowFeed,
    /// The rows of the trace received so far.
    rows: Vec<&'f RowTrace>,
    /// The frame's direction table.
    pub dir: &'f [[i64; 3]],
    /// Asset of each instance.
    pub instance_asset: &'f [usize],
    /// Where each asset's image is in node memory.
    pub layout: &'f SceneLayout,
}

impl<'f> FrameInputs<'f> {
    /// The inputs of a frame; the trace feed must have one row per frame row and the direction
    /// table one entry per pixel.
    pub fn new(
        setup: FrameSetup,
        plan: &'f FramePlan<'f>,
        feed: &'f RowFeed,
        dir: &'f [[i64; 3]],
        instance_asset: &'f [usize],
        layout: &'f SceneLayout,
    ) -> Result<Self, CycleError> {
        let pixels = u64::from(setup.width) * u64::from(setup.height);
        if feed.len() != setup.height as usize || dir.len() as u64 != pixels {
            return Err(CycleError::Internal(
                "trace or direction table does not match the frame size".into(),
            ));
        }
        Ok(Self {
            setup,
            plan,
            feed,
            rows: Vec::with_capacity(setup.height as usize),
            dir,
            instance_asset,
            layout,
        })
    }

    /// Pixels in the frame.
    pub fn pixels(&self) -> u64 {
        u64::from(self.setup.width) * u64::from(self.setup.height)
    }

    /// A disagreement with the functional model at `pixel`.
    pub fn mismatch(&self, pixel: u32, what: String) -> CycleError {
        let w = self.setup.width.max(1);
        CycleError::Mismatch {
            frame: self.setup.frame,
            i: pixel % w,
            j: pixel / w,
            what,
        }
    }

    /// The trace of pixel `p` (its row, its work and its column) from the rows received.
    #[inline]
    pub fn trace_at(&self, p: u32) -> Result<(&'f RowTrace, &'f PixelWork, usize), CycleError> {
        let width = self.setup.width;
        let (i, j) = ((p % width) as usize, (p / width) as usize);
        let row = self.rows.get(j).copied().ok_or_else(|| {
            CycleError::Internal(format!("pixel {p} used before its row {j} was received"))
        })?;
        let work = row.pixels.get(i).ok_or_else(|| {
            CycleError::Internal(format!("row {j} of the trace has no pixel {i}"))
        })?;
        Ok((row, work, i))
    }

    /// Rows received so far.
    pub fn rows(&self) -> &[&'f RowTrace] {
        &self.rows
    }

    /// Makes sure row `row` has been received: waits for it (wall time only) and takes every
    /// row published up to it, checking each is a whole row.
    pub fn need_row(&mut self, row: usize) -> Result<(), CycleError> {
        if row < self.rows.len() {
            return Ok(());
        }
        let width = self.setup.width;
        let published = self
            .feed
            .wait_for(row)
            .map_err(|e| CycleError::Internal(format!("trace feed: {e}")))?;
        for j in self.rows.len()..published {
            let t = self
                .feed
                .get(j)
                .ok_or_else(|| CycleError::Internal(format!("row {j} announced but absent")))?;
            if t.pixels.len() != width as usize || t.words.len() != width as usize {
                return Err(CycleError::Internal(format!(
                    "row {j} of the trace has {} pixels and {} words, the frame is {width} wide",
                    t.pixels.len(),
                    t.words.len()
                )));
            }
            self.rows.push(t);
        }
        Ok(())
    }
}

/// What has passed each point of the pipeline this frame: what the stages' states and the
/// stuck check read, and the report's counts.
#[derive(Clone, Debug, Default)]
pub struct FrameCounts {
    /// Pixels in the frame.
    pub pixels: u64,
    /// Rays that left raygen, sphere, sorter and check.
    pub passed: [u64; 4],
    /// Records written to the hit buffer.
    pub written: u64,
    /// Rays that entered the walk section (the report's `traced`).
    pub walks_entered: u64,
    /// Rays that stopped with candidates left.
    pub early: u64,
    /// Pixels reused from the hit buffer.
    pub reused: u64,
}

impl FrameCounts {
    /// Counts of a frame of `pixels` pixels, all zero.
    pub fn new(pixels: u64) -> Self {
        Self {
            pixels,
            ..Self::default()
        }
    }

    /// Whether walks are in the walk section or may still come: a ray has entered it, or the
    /// check stage still has rays to pass.
    #[inline]
    pub fn more_walks(&self) -> bool {
        self.walks_entered > 0 || self.passed[3] < self.pixels
    }
}
