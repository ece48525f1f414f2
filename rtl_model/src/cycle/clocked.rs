//! The clock of the cycle model: one commit point per clock edge, and cycle stamps on
//! transactions.
//!
//! Where it sits: under everything in [`crate::cycle`]. The FIFOs between the pipeline's
//! stages ([`super::fifo`]) and the block RAMs ([`super::bram`]) are parts that the [`Clock`]
//! commits once per cycle; the transactions that flow through them (rays, walks, records) are
//! wrapped in [`Stamped`] so that the report can say how long each spent in each stage.
//!
//! # The discipline
//!
//! The frame pipeline (`svo_sim::models::cycle::pipeline`; docs/cycle-model.md §2.1, and
//! docs/architecture.md, "The cycle model's clocking discipline") runs a cycle in two phases:
//!
//! 1. **Evaluate.** Every stage runs once, consumers first (the write port first, ray
//!    generation last). A stage's own registers — the transactions in its fixed-latency unit
//!    ([`super::unit_pipe`]), its counters — change in place as it runs. What it hands its
//!    neighbours goes through the FIFOs and memories, which hold this cycle's pushes, pops and
//!    writes aside: their `ready`, `valid` and occupancy, and a block RAM's contents, keep
//!    their start-of-cycle values until the edge (Moore outputs, as in a synchronous FIFO).
//! 2. **Commit** (the clock edge). [`Clock::edge`] first checks that every part is on the
//!    clock's cycle and then commits all of them in one place; the cycle counter advances.
//!
//! Because stages see each other through registered signals only, a stage cannot tell whether
//! its neighbour on the other side of a FIFO has been evaluated yet: a path from one stage's
//! inputs to another's in the same cycle would be a combinational path between stages, which
//! is what the FIFOs exist to cut, and the model keeps the same rule so that its cycle counts
//! are the ones the hardware would have. The few signals that do cross within a cycle are
//! arbitration inside one block of hardware, and the fixed evaluation order states them: the
//! record stage's claim of the write FIFO's port, which the check stage evaluated after it
//! must respect, and a ray slot the record stage frees, which the transform may take in the
//! same cycle.
//!
//! Stages are not pure `(inputs, registers) → (outputs, next registers)` kernels with a
//! second copy of their registers: copying a unit's in-flight transactions or a walker's
//! contexts every cycle would cost more than the behaviour needs, and updating them in place
//! gives the same cycles as long as no other stage reads them during the evaluate phase,
//! which the rule above guarantees. Memories take the same route with their storage: they
//! record the cycle's writes and apply them in [`Commit::commit`].
//!
//! # Example
//!
//! ```
//! use rtl_model::cycle::clocked::{Clock, StageId, Stamped};
//! use rtl_model::cycle::fifo::Fifo;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // Producer → FIFO → consumer, the consumer evaluated first.
//! let mut clock = Clock::new();
//! let mut fifo = Fifo::new(StageId(1), 2)?;
//! let (mut sent, mut got) = (0u32, Vec::new());
//! for _ in 0..4 {
//!     // Consumer: sees the FIFO as it was at the start of the cycle.
//!     if let Some(item) = fifo.try_pop()? {
//!         got.push(item.payload);
//!     }
//!     // Producer: its push is held until the edge, whatever the consumer did.
//!     if fifo.ready() && fifo.try_push(Stamped::new(sent)).is_ok() {
//!         sent += 1;
//!     }
//!     clock.edge(&mut [&mut fifo])?;
//! }
//! assert_eq!((clock.now(), got), (4, vec![0, 1, 2]));
//! # Ok(())
//! # }
//! ```

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A part that the clock edge commits: a FIFO, a block RAM, a register bank.
///
/// The edge is split into a check and a commit so that [`Clock::edge`] can refuse a
/// misconfigured cycle before *any* part has changed, keeping every part on the same cycle.
pub trait Commit {
    /// The cycle this part is evaluating (the number of edges it has seen).
    fn cycle(&self) -> u64;
    /// Whether the part can take the edge that ends cycle `now`: its own cycle is `now`.
    /// Written once here for every part (a FIFO, a block RAM and a register need no
    /// evaluation to take the edge: an undriven port or side is idle).
    fn check(&self, now: u64) -> Result<(), ClockError> {
        let part = self.cycle();
        if part == now {
            Ok(())
        } else {
            Err(ClockError::OutOfStep { part, clock: now })
        }
    }
    /// Applies this cycle's next state and advances the part's cycle. Called by
    /// [`Clock::edge`] after every part has passed [`Commit::check`]; calling it directly
    /// skips that check, and a later edge will then report the part out of step.
    fn commit(&mut self);
}

/// Why a part cannot take the edge.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum ClockError {
    /// The part is on a different cycle than the clock (committed outside [`Clock::edge`], or
    /// created after the clock had started).
    #[error("part is at cycle {part}, clock at cycle {clock}")]
    OutOfStep {
        /// The part's own cycle.
        part: u64,
        /// The clock's cycle.
        clock: u64,
    },
}

/// A failed edge: which part (index into the slice given to [`Clock::edge`]) and why.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
#[error("clock edge refused by part {part}: {cause}")]
pub struct EdgeError {
    /// Index of the first part that failed its check.
    pub part: usize,
    /// What was wrong with it.
    pub cause: ClockError,
}

/// The clock: the cycle counter and the single place where all parts commit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Clock {
    now: u64,
}

impl Clock {
    /// A clock at cycle 0, the reset state of every part.
    pub fn new() -> Self {
        Self { now: 0 }
    }

    /// The cycle being evaluated.
    pub fn now(&self) -> u64 {
        self.now
    }

    /// The clock edge that ends cycle [`Clock::now`]: checks every part, then commits every
    /// part, then advances. If any check fails nothing is committed and the clock stays, so a
    /// mistake never leaves some parts a cycle ahead of others. Returns the new cycle.
    pub fn edge(&mut self, parts: &mut [&mut dyn Commit]) -> Result<u64, EdgeError> {
        for (part, p) in parts.iter().enumerate() {
            p.check(self.now)
                .map_err(|cause| EdgeError { part, cause })?;
        }
        for p in parts.iter_mut() {
            p.commit();
        }
        // Saturating rather than wrapping: 2^64 cycles is never reached, and if it were, a
        // stuck clock is easier to notice than stamps that jump back to 0.
        self.now = self.now.saturating_add(1);
        Ok(self.now)
    }

    /// Skips `k` idle cycles: the caller has taken them on every part (e.g.
    /// `Fifo::skip_idle`), as `k` edges in which nothing changed would have. Returns the new
    /// cycle.
    pub fn skip(&mut self, k: u64) -> u64 {
        self.now = self.now.saturating_add(k);
        self.now
    }
}

/// Identifies a pipeline stage (or FIFO) in cycle stamps. The pipeline assigns the numbers and
/// names them in its report; a small integer keeps stamps cheap to copy and compare.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
pub struct StageId(pub u16);

/// One visit of a transaction to one stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageStamp {
    /// The stage visited.
    pub stage: StageId,
    /// The cycle in which the transaction was accepted by the stage (its input handshake).
    pub entered: u64,
    /// The cycle in which it was handed on (its output handshake); `None` while inside.
    pub left: Option<u64>,
}

impl StageStamp {
    /// Cycles spent in the stage (`left − entered`), once it has left.
    pub fn latency(&self) -> Option<u64> {
        self.left.map(|l| l.saturating_sub(self.entered))
    }
}

/// Why a stamp could not be recorded, or why a stamp list is inconsistent.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum StampError {
    /// `leave` for a stage the transaction is not currently inside (its last stamp is for
    /// another stage, or already closed, or there is none).
    #[error("transaction is not inside stage {0:?}")]
    NotInside(StageId),
    /// `leave` at a cycle before the one the transaction entered.
    #[error("stage {stage:?}: left at cycle {left}, before entering at cycle {entered}")]
    LeftBeforeEntered {
        /// The stage.
        stage: StageId,
        /// Entry cycle.
        entered: u64,
        /// Requested exit cycle.
        left: u64,
    },
    /// A stage entered while an earlier stage was still open, or before the earlier one was
    /// left: a transaction is in one stage at a time.
    #[error("stage {stage:?} entered at cycle {entered} while the previous stage was open or left later")]
    Overlap {
        /// The later stage.
        stage: StageId,
        /// Its entry cycle.
        entered: u64,
    },
}

/// A transaction with the cycles it entered and left each stage it has visited, in order.
///
/// The stamp list grows by one entry per stage visited; the pipeline's stages record entry at
/// their input handshake and exit at their output handshake, so a hand-over from one stage to
/// the next gives the same cycle for the first's exit and the second's entry.
///
/// A transaction made with [`Stamped::untracked`] keeps only its latest visit, inline (no
/// list, no heap allocation): what a FIFO needs for its latency counters. The cycle model uses
/// it unless a transaction log asks for the whole history (docs/cycle-model.md §3.2). Its
/// [`stamps`](Stamped::stamps) are empty; [`last`](Stamped::last), [`inside`](Stamped::inside),
/// [`leave`](Stamped::leave) and [`latency_in`](Stamped::latency_in) of the latest visit
/// answer as for a tracked one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stamped<T> {
    /// The transaction itself.
    pub payload: T,
    // Private so that only `enter` and `leave` write them: they keep the visits in order.
    /// Every visit, oldest first, when tracked. Boxed so that an untracked transaction, the
    /// common case, carries one null pointer instead of an empty `Vec`'s three words through
    /// every FIFO and unit register it passes.
    #[allow(clippy::box_collection)]
    history: Option<Box<Vec<StageStamp>>>,
    /// The latest visit: its stage (`NO_STAGE` before any), entry and exit (`OPEN` while
    /// inside). Kept for tracked transactions too, so both kinds leave the same way.
    stage: StageId,
    entered: u64,
    left: u64,
}

/// `Stamped::stage` before any visit.
const NO_STAGE: StageId = StageId(u16::MAX);
/// `Stamped::left` while inside.
const OPEN: u64 = u64::MAX;

impl<T> Stamped<T> {
    /// A transaction that has not entered any stage yet, keeping its whole history.
    pub fn new(payload: T) -> Self {
        Self {
            payload,
            // A ray visits about a dozen stages and FIFOs: one allocation up front instead of
            // a few regrowths on the way.
            history: Some(Box::new(Vec::with_capacity(12))),
            stage: NO_STAGE,
            entered: 0,
            left: OPEN,
        }
    }

    /// A transaction that keeps only its latest visit (no allocation).
    #[inline]
    pub fn untracked(payload: T) -> Self {
        Self {
            payload,
            history: None,
            stage: NO_STAGE,
            entered: 0,
            left: OPEN,
        }
    }

    /// [`Stamped::new`] when `tracked`, else [`Stamped::untracked`].
    #[inline]
    pub fn with_history(payload: T, tracked: bool) -> Self {
        if tracked {
            Self::new(payload)
        } else {
            Self::untracked(payload)
        }
    }

    /// Whether the whole history is kept.
    pub fn is_tracked(&self) -> bool {
        self.history.is_some()
    }

    /// Every stage visit so far, oldest first (none if untracked).
    pub fn stamps(&self) -> &[StageStamp] {
        self.history.as_deref().map_or(&[], |h| h.as_slice())
    }

    /// The last visit, if any.
    #[inline]
    pub fn last(&self) -> Option<StageStamp> {
        (self.stage != NO_STAGE).then_some(StageStamp {
            stage: self.stage,
            entered: self.entered,
            left: (self.left != OPEN).then_some(self.left),
        })
    }

    /// The stage the transaction is inside (its last stamp, if still open).
    pub fn inside(&self) -> Option<StageId> {
        (self.stage != NO_STAGE && self.left == OPEN).then_some(self.stage)
    }

    /// Records entry to `stage` at cycle `cycle`. Never refused, so a stage can always accept
    /// what its handshake accepted; a misordered history shows up in [`Stamped::check`].
    #[inline]
    pub fn enter(&mut self, stage: StageId, cycle: u64) {
        self.stage = stage;
        self.entered = cycle;
        self.left = OPEN;
        if let Some(h) = self.history.as_mut() {
            h.push(StageStamp {
                stage,
                entered: cycle,
                left: None,
            });
        }
    }

    /// Records exit from `stage` at cycle `cycle` and returns the cycles spent inside. The
    /// transaction must be inside `stage` (its last stamp open and for that stage) and `cycle`
    /// must not be before the entry; otherwise nothing changes.
    #[inline]
    pub fn leave(&mut self, stage: StageId, cycle: u64) -> Result<u64, StampError> {
        if self.stage != stage || stage == NO_STAGE || self.left != OPEN {
            return Err(StampError::NotInside(stage));
        }
        if cycle < self.entered {
            return Err(StampError::LeftBeforeEntered {
                stage,
                entered: self.entered,
                left: cycle,
            });
        }
        self.left = cycle;
        if let Some(last) = self.history.as_mut().and_then(|h| h.last_mut()) {
            last.left = Some(cycle);
        }
        Ok(cycle - self.entered)
    }

    /// Checks that the history is one visit at a time: every stamp but the last is closed,
    /// each exit is at or after its entry, and each entry is at or after the previous exit.
    pub fn check(&self) -> Result<(), StampError> {
        let mut prev_left: Option<u64> = None;
        for (i, s) in self.stamps().iter().enumerate() {
            if i > 0 && prev_left.is_none_or(|l| s.entered < l) {
                return Err(StampError::Overlap {
                    stage: s.stage,
                    entered: s.entered,
                });
            }
            // An open stamp followed by another is caught above at the next entry, since
            // `prev_left` is then `None`.
            if let Some(l) = s.left.filter(|&l| l < s.entered) {
                return Err(StampError::LeftBeforeEntered {
                    stage: s.stage,
                    entered: s.entered,
                    left: l,
                });
            }
            prev_left = s.left;
        }
        Ok(())
    }

    /// Cycles spent in the most recent completed visit to `stage` (of an untracked
    /// transaction: only if that is its latest visit).
    pub fn latency_in(&self, stage: StageId) -> Option<u64> {
        if !self.is_tracked() {
            return self
                .last()
                .filter(|s| s.stage == stage)
                .and_then(|s| s.latency());
        }
        self.stamps()
            .iter()
            .rev()
            .filter(|s| s.stage == stage)
            .find_map(StageStamp::latency)
    }

    /// The payload, dropping the stamps.
    pub fn into_payload(self) -> T {
        self.payload
    }

    /// A new payload with the same history, for a stage that transforms its transaction
    /// (a ray becoming a candidate list) while keeping where and when it has been.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Stamped<U> {
        Stamped {
            payload: f(self.payload),
            history: self.history,
            stage: self.stage,
            entered: self.entered,
            left: self.left,
        }
    }
}
