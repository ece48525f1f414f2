//! What a stage kernel reads and what it returns: read-only ports on the FIFOs around it, a
//! view of the ray slots, and the cycle's effects — pops asked of each FIFO, items offered to
//! each, slot takes, writes and releases, hit-buffer reads and writes, count increments —
//! which the pipeline applies in one commit after every stage has been evaluated
//! (`super::super::commit`).
//!
//! Pipeline position: the joint between `stages/` and `pipeline.rs` (docs/cycle-model.md
//! §2.1, the stage interface). A kernel reads only registered state: a [`PopPort`] answers
//! from the FIFO's start-of-cycle items and counts the pops this stage has asked for, a
//! [`PushPort`] from its start-of-cycle occupancy plus the items offered so far this cycle;
//! no stage holds a `&mut` to a FIFO, the slot table or a memory. The one same-cycle signal
//! between stages, the record stage's, travels in the effects it has already returned: its
//! offers to `record_to_write` (the check stage's port on that FIFO counts them) and its slot
//! releases (the transform may take those slots). The effect buffers live as long as the
//! pipeline and are cleared, not freed, at each commit: no allocation per cycle.

use super::{internal, Ray, RaySlots};
use crate::models::cycle::error::CycleError;
use crate::models::fixed::plan::Best;
use rtl_model::cycle::clocked::{StageId, Stamped};
use rtl_model::cycle::fifo::Fifo;
use rtl_model::units::walker::WalkerT;

/// A stage's consumer side of a FIFO: the registered items, and the pops asked this cycle.
/// Pops behave as `Fifo::try_pop` would (an ask of an empty FIFO is a starved cycle), and the
/// same number of `try_pop`s is made on the FIFO itself at the commit.
pub struct PopPort<'a, T> {
    fifo: &'a Fifo<T>,
    asked: usize,
    got: usize,
}

impl<'a, T: Clone> PopPort<'a, T> {
    /// The consumer side of `fifo`, nothing asked yet.
    #[inline]
    pub fn new(fifo: &'a Fifo<T>) -> Self {
        Self {
            fifo,
            asked: 0,
            got: 0,
        }
    }

    /// `valid`: not empty at the start of the cycle.
    #[inline]
    pub fn valid(&self) -> bool {
        self.fifo.valid()
    }

    /// Whether one more pop would return an item this cycle (a port left, an item left).
    #[inline]
    pub fn can_pop(&self) -> bool {
        self.asked < self.fifo.ports() && self.got < self.fifo.occupancy()
    }

    /// The next item a pop would return, if any.
    #[inline]
    pub fn peek(&self) -> Option<&'a Stamped<T>> {
        if self.asked >= self.fifo.ports() {
            return None;
        }
        self.fifo.registered(self.got)
    }

    /// Asks for the next item: a copy of it, stamped as leaving the FIFO now (as the FIFO
    /// stamps its own at the commit), or `None` when none is left (a starved ask).
    #[inline(always)]
    pub fn pop(&mut self, now: u64) -> Result<Option<Stamped<T>>, CycleError> {
        if self.asked >= self.fifo.ports() {
            return Err(overdriven(self.fifo.stage(), now));
        }
        self.asked += 1;
        let Some(item) = self.fifo.registered(self.got) else {
            return Ok(None);
        };
        self.got += 1;
        let mut item = item.clone();
        // Only a tracked history keeps the exit: an untracked copy's latest visit is
        // overwritten by the stage's own `enter` before anything reads it.
        if item.is_tracked() {
            let _ = item.leave(self.fifo.stage(), now);
        }
        Ok(Some(item))
    }

    /// Pops asked this cycle (the commit's `try_pop` count).
    #[inline]
    pub fn asked(&self) -> usize {
        self.asked
    }
}

/// A consumer that asked more pops than the FIFO has ports (a model bug); out of line, so
/// that the pop itself stays small enough to inline.
#[cold]
#[inline(never)]
fn overdriven(stage: StageId, now: u64) -> CycleError {
    internal(format!(
        "consumer side of FIFO {stage:?} driven more than its ports in cycle {now}"
    ))
}

/// A FIFO that could not take an offered item (a model bug), out of line.
#[cold]
#[inline(never)]
fn refused(stage: StageId, inside: usize, offered: usize) -> CycleError {
    internal(format!(
        "FIFO {stage:?} offered an item it cannot take this cycle ({inside} inside, {offered} offered)"
    ))
}

/// A stage's producer side of a FIFO: its registered room, and the items offered this
/// cycle, kept in the FIFO's effect buffer until the commit pushes them. A FIFO with two
/// producers (`record_to_write`) shares one buffer: the second producer's port counts the
/// first's offers.
pub struct PushPort<'a, T> {
    fifo: &'a Fifo<T>,
    out: &'a mut FifoFx<T>,
}

impl<'a, T> PushPort<'a, T> {
    /// The producer side of `fifo`, offering into `out`.
    #[inline]
    pub fn new(fifo: &'a Fifo<T>, out: &'a mut FifoFx<T>) -> Self {
        Self { fifo, out }
    }

    /// `ready`: not full at the start of the cycle.
    #[inline]
    pub fn ready(&self) -> bool {
        self.fifo.ready()
    }

    /// Whether one more push would be taken this cycle (`Fifo::can_push`).
    #[inline]
    pub fn can_push(&self) -> bool {
        let n = self.out.pushes.len();
        n < self.fifo.ports() && self.fifo.occupancy() + n < self.fifo.depth()
    }

    /// Offers `item`; refused (a model bug) if the FIFO could not take it.
    #[inline(always)]
    pub fn push(&mut self, item: Stamped<T>) -> Result<(), CycleError> {
        if !self.can_push() {
            return Err(refused(
                self.fifo.stage(),
                self.fifo.occupancy(),
                self.out.pushes.len(),
            ));
        }
        self.out.pushes.push(item);
        Ok(())
    }

    /// The producer still holds an item ready to enter after its pushes of the cycle. A
    /// kernel only offers what the FIFO takes, so a full FIFO never sees the refused offer
    /// `Fifo::try_push` would count as back-pressure: the kernel says so here instead, and
    /// the commit counts it (`Fifo::note_full`: once a cycle, whichever producer said it).
    /// Marked full only when the FIFO has no room left after this cycle's offers (whether
    /// or not its ports were all used); an item held back only because the ports were all
    /// used while room was left is the datapath's width, not back-pressure
    /// (`FifoStats::full_cycles`).
    #[inline]
    pub fn note_full(&mut self) {
        if self.fifo.occupancy() + self.out.pushes.len() >= self.fifo.depth() {
            self.out.full = true;
        }
    }
}

/// A FIFO's effects in a cycle: pops asked, items offered, and whether a producer held an
/// item the FIFO had no room for.
pub struct FifoFx<T> {
    /// `try_pop`s asked.
    pub pops: usize,
    /// Items offered, in order.
    pub pushes: Vec<Stamped<T>>,
    /// A producer held a ready item back because the FIFO was full ([`PushPort::note_full`]).
    pub full: bool,
}

impl<T> Default for FifoFx<T> {
    fn default() -> Self {
        Self {
            pops: 0,
            pushes: Vec::new(),
            full: false,
        }
    }
}

/// A slot the record stage updates after a walk: its best hit and walks so far.
#[derive(Clone, Copy, Debug)]
pub struct SlotWrite {
    /// The slot.
    pub slot: u32,
    /// Best hit so far.
    pub best: Option<(WalkerT, u16)>,
    /// Walks done.
    pub walks: u16,
}

/// A slot the transform takes for a new ray.
#[derive(Debug)]
pub struct SlotTake {
    /// The slot the kernel expects the free list to give (checked at the commit).
    pub slot: u32,
    /// The ray's pixel.
    pub pixel: u32,
    /// The ray's stamps up to the check stage.
    pub stamps: Stamped<Ray>,
}

/// The slot table's effects in a cycle, applied in this order: the record stage's writes and
/// releases, the walker stage's cross-check results, the transform's takes.
#[derive(Default)]
pub struct SlotFx {
    /// Record: best hit and walk count per decided walk.
    pub writes: Vec<SlotWrite>,
    /// Record: slots freed (their records left).
    pub releases: Vec<u32>,
    /// Walkers, under cross-check: the walker's own best result per slot.
    pub best_full: Vec<(u32, Best)>,
    /// Transform: slots taken by new rays.
    pub takes: Vec<SlotTake>,
}

impl SlotFx {
    /// Whether nothing is pending.
    pub fn is_empty(&self) -> bool {
        self.writes.is_empty()
            && self.releases.is_empty()
            && self.best_full.is_empty()
            && self.takes.is_empty()
    }
}

/// The transform's view of the ray slots: the registered table and free list, plus the slots
/// the record stage frees this cycle (a same-cycle signal, docs/architecture.md §4) and the
/// ones the transform has taken so far this cycle.
pub struct SlotView<'a> {
    slots: &'a RaySlots,
    released: &'a [u32],
    taken: usize,
}

impl<'a> SlotView<'a> {
    /// The view over `slots` with `released` freed this cycle.
    #[inline]
    pub fn new(slots: &'a RaySlots, released: &'a [u32]) -> Self {
        Self {
            slots,
            released,
            taken: 0,
        }
    }

    /// Whether a slot is free for one more take.
    #[inline]
    pub fn has_free(&self) -> bool {
        self.taken < self.slots.free_count() + self.released.len()
    }

    /// The slot the next take gets: the free list is a stack, the released slots pushed on
    /// it in order before any take.
    #[inline]
    pub fn take(&mut self) -> Result<u32, CycleError> {
        let k = self.taken;
        let r = self.released.len();
        let slot = if k < r {
            self.released.get(r - 1 - k).copied()
        } else {
            self.slots.free_from_top(k - r)
        };
        self.taken += 1;
        slot.ok_or_else(|| CycleError::Internal("no ray slot".into()))
    }
}

/// The frame-level effects of a cycle: count increments, added to the frame's counts at the
/// commit, and the trace row ray generation needs received.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameFx {
    /// The row of the pixel ray generation took (received at the commit, before any later
    /// stage can read it: the ray is a cycle away from the first stage that reads the trace).
    pub need_row: Option<usize>,
    /// Rays that left raygen, sphere, sorter and check.
    pub passed: [u64; 4],
    /// Rays that entered the walk section.
    pub walks_entered: u64,
    /// Rays that stopped with candidates left.
    pub early: u64,
    /// Pixels reused from the hit buffer.
    pub reused: u64,
}

/// The hit-buffer memory's effects in a cycle: the write stage's records (written, logged
/// and counted at the commit) and the check stage's reads (a port each).
#[derive(Default)]
pub struct BramFx {
    /// Records written, in port order.
    pub writes: Vec<Stamped<super::Rec>>,
    /// Addresses read.
    pub reads: Vec<usize>,
}
