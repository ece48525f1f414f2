//! Two-phase clocking for the cycle model: stages as pure step functions, one commit point per
//! clock edge, and cycle stamps on transactions.
//!
//! Where it sits: under everything in [`crate::cycle`]. Every stage of the pipeline (ray
//! generation, transform, sphere tests, sorter, walkers, hit buffer) and every FIFO between
//! them ([`super::fifo`]) is a part that the [`Clock`] commits once per cycle. The transactions
//! that flow through them (rays, candidates, node requests) are wrapped in [`Stamped`] so that
//! the report can say how long each spent in each stage.
//!
//! # The discipline (DESIGN §6, STYLE "rhdl")
//!
//! A cycle has two phases:
//!
//! 1. **Evaluate.** Every part computes its outputs and its *next* registers from its inputs
//!    and its *current* registers. Nothing visible changes: a part that reads a neighbour's
//!    registers during this phase sees the value they had at the start of the cycle, whether
//!    the neighbour has already been evaluated or not.
//! 2. **Commit** (the clock edge). [`Clock::edge`] first checks that every part is ready for
//!    the edge and then commits all of them in one place; the cycle counter advances.
//!
//! Because evaluation only ever reads current registers, the order in which parts are
//! evaluated cannot change any result. That holds as long as signals that cross from one part
//! to another within a cycle come from the source's *registers* (a Moore output such as a
//! FIFO's `ready` and `valid`), never from its freshly computed outputs. A path from one
//! part's inputs to another part's inputs in the same cycle would be a combinational path
//! between stages, which is what the FIFOs between stages exist to cut; the model keeps the
//! same rule so that its cycle counts are the ones the hardware would have.
//!
//! Memories (FIFO storage, block RAMs) are parts too, but not through [`Clocked`]: cloning a
//! whole RAM as its "next registers" every cycle would cost far more than the hardware
//! behaviour needs. They record this cycle's writes and apply them in [`Commit::commit`],
//! which is the same edge with a cheaper representation of "next state".
//!
//! # Example
//!
//! ```
//! use rtl_model::cycle::clocked::{Clock, Clocked, Commit, Registered};
//!
//! /// A counter that adds its input each cycle and shows its current value.
//! struct Accumulate;
//!
//! impl Clocked for Accumulate {
//!     type In = u32;
//!     type Out = u32;
//!     type Regs = u32;
//!     fn step(&self, add: u32, sum: &u32) -> (u32, u32) {
//!         (*sum, sum.wrapping_add(add))
//!     }
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut clock = Clock::new();
//! let mut a = Registered::new(Accumulate, 0);
//! let mut b = Registered::new(Accumulate, 100);
//! for _ in 0..4 {
//!     // Each reads the other's *current* register, so the order of these two lines is free.
//!     let from_b = *b.regs();
//!     let from_a = *a.regs();
//!     a.eval(from_b % 7)?;
//!     b.eval(from_a % 5)?;
//!     clock.edge(&mut [&mut a, &mut b])?;
//! }
//! assert_eq!(clock.now(), 4);
//! # Ok(())
//! # }
//! ```

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A clocked component as a pure kernel: (inputs, current registers) → (outputs, next
/// registers).
///
/// `step` must not depend on anything but its arguments and `self` (which holds fixed
/// parameters: latencies, depths, tables), so that the same stimulus gives the same cycles on
/// every run and the [`Registered`] holder can apply the result at the edge.
///
/// Inputs are taken by value so that a transaction handed over this cycle (say, popped from a
/// FIFO) moves into the next registers without a copy; the current registers are only
/// borrowed, because other parts may still read them during the same evaluate phase.
pub trait Clocked {
    /// This cycle's inputs: handshake signals and data from neighbours.
    type In;
    /// This cycle's outputs. A neighbour that needs a signal in the *same* cycle must read it
    /// from [`Registered::regs`] instead, or evaluation order would matter.
    type Out;
    /// The register state; `Regs` returned by `step` become current at the next edge.
    type Regs;
    /// One clock cycle of the component.
    fn step(&self, inputs: Self::In, regs: &Self::Regs) -> (Self::Out, Self::Regs);
}

/// A part that the clock edge commits: a [`Registered`] kernel, a FIFO, a block RAM.
///
/// The edge is split into a check and a commit so that [`Clock::edge`] can refuse a
/// misconfigured cycle before *any* part has changed, keeping every part on the same cycle.
pub trait Commit {
    /// The cycle this part is evaluating (the number of edges it has seen).
    fn cycle(&self) -> u64;
    /// Whether the part can take the edge that ends cycle `now`: its own cycle is `now` and
    /// it has been evaluated as its contract requires.
    fn check(&self, now: u64) -> Result<(), ClockError>;
    /// Applies this cycle's next state and advances the part's cycle. Called by
    /// [`Clock::edge`] after every part has passed [`Commit::check`]; calling it directly
    /// skips that check, and a later edge will then report the part out of step.
    fn commit(&mut self);
}

/// Why a part cannot be evaluated or take the edge.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum ClockError {
    /// A [`Registered`] kernel was evaluated twice in one cycle: a stage steps once per clock.
    #[error("evaluated twice in cycle {cycle}")]
    AlreadyEvaluated {
        /// The cycle of the second evaluation.
        cycle: u64,
    },
    /// A [`Registered`] kernel reached the edge without being evaluated. A stage that should
    /// hold its registers models that with a clock-enable input, so a missing evaluation is a
    /// wiring mistake, not a stall.
    #[error("not evaluated in cycle {cycle}")]
    NotEvaluated {
        /// The cycle that ended without an evaluation.
        cycle: u64,
    },
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
}

/// A [`Clocked`] kernel with its registers: the current ones, visible all cycle, and the next
/// ones, held until the edge.
#[derive(Clone, Debug)]
pub struct Registered<C: Clocked> {
    kernel: C,
    regs: C::Regs,
    next: Option<C::Regs>,
    now: u64,
}

impl<C: Clocked> Registered<C> {
    /// A kernel at cycle 0 with its reset registers.
    pub fn new(kernel: C, reset: C::Regs) -> Self {
        Self {
            kernel,
            regs: reset,
            next: None,
            now: 0,
        }
    }

    /// The kernel (its fixed parameters).
    pub fn kernel(&self) -> &C {
        &self.kernel
    }

    /// The current registers: the start-of-cycle values, unchanged by [`Registered::eval`]
    /// until the edge. This is what neighbours read during the evaluate phase.
    pub fn regs(&self) -> &C::Regs {
        &self.regs
    }

    /// The cycle being evaluated.
    pub fn now(&self) -> u64 {
        self.now
    }

    /// Whether [`Registered::eval`] has run this cycle.
    pub fn evaluated(&self) -> bool {
        self.next.is_some()
    }

    /// Steps the kernel from the current registers and holds the next registers for the edge.
    /// A second call in the same cycle is refused (the first result stands), since a stage
    /// that stepped twice per clock would be a different piece of hardware.
    pub fn eval(&mut self, inputs: C::In) -> Result<C::Out, ClockError> {
        if self.next.is_some() {
            return Err(ClockError::AlreadyEvaluated { cycle: self.now });
        }
        let (out, next) = self.kernel.step(inputs, &self.regs);
        self.next = Some(next);
        Ok(out)
    }
}

impl<C: Clocked> Commit for Registered<C> {
    fn cycle(&self) -> u64 {
        self.now
    }

    fn check(&self, now: u64) -> Result<(), ClockError> {
        if self.now != now {
            return Err(ClockError::OutOfStep {
                part: self.now,
                clock: now,
            });
        }
        if self.next.is_none() {
            return Err(ClockError::NotEvaluated { cycle: self.now });
        }
        Ok(())
    }

    fn commit(&mut self) {
        // Without an evaluation (only reachable by calling commit directly) the registers
        // hold, which is what a flip-flop with its enable low does.
        if let Some(next) = self.next.take() {
            self.regs = next;
        }
        self.now = self.now.saturating_add(1);
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
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stamped<T> {
    /// The transaction itself.
    pub payload: T,
    // Private so that only `enter` and `leave` write it: they keep it in visit order.
    stamps: Vec<StageStamp>,
}

impl<T> Stamped<T> {
    /// A transaction that has not entered any stage yet.
    pub fn new(payload: T) -> Self {
        Self {
            payload,
            // A ray visits about a dozen stages and FIFOs: one allocation up front instead of
            // a few regrowths on the way.
            stamps: Vec::with_capacity(12),
        }
    }

    /// Every stage visit so far, oldest first.
    pub fn stamps(&self) -> &[StageStamp] {
        &self.stamps
    }

    /// The last visit, if any.
    pub fn last(&self) -> Option<&StageStamp> {
        self.stamps.last()
    }

    /// The stage the transaction is inside (its last stamp, if still open).
    pub fn inside(&self) -> Option<StageId> {
        self.stamps
            .last()
            .filter(|s| s.left.is_none())
            .map(|s| s.stage)
    }

    /// Records entry to `stage` at cycle `cycle`. Never refused, so a stage can always accept
    /// what its handshake accepted; a misordered history shows up in [`Stamped::check`].
    pub fn enter(&mut self, stage: StageId, cycle: u64) {
        self.stamps.push(StageStamp {
            stage,
            entered: cycle,
            left: None,
        });
    }

    /// Records exit from `stage` at cycle `cycle` and returns the cycles spent inside. The
    /// transaction must be inside `stage` (its last stamp open and for that stage) and `cycle`
    /// must not be before the entry; otherwise nothing changes.
    pub fn leave(&mut self, stage: StageId, cycle: u64) -> Result<u64, StampError> {
        match self.stamps.last_mut() {
            Some(s) if s.stage == stage && s.left.is_none() => {
                if cycle < s.entered {
                    return Err(StampError::LeftBeforeEntered {
                        stage,
                        entered: s.entered,
                        left: cycle,
                    });
                }
                s.left = Some(cycle);
                Ok(cycle - s.entered)
            }
            _ => Err(StampError::NotInside(stage)),
        }
    }

    /// Checks that the history is one visit at a time: every stamp but the last is closed,
    /// each exit is at or after its entry, and each entry is at or after the previous exit.
    pub fn check(&self) -> Result<(), StampError> {
        let mut prev_left: Option<u64> = None;
        for (i, s) in self.stamps.iter().enumerate() {
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

    /// Cycles spent in the most recent completed visit to `stage`.
    pub fn latency_in(&self, stage: StageId) -> Option<u64> {
        self.stamps
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
            stamps: self.stamps,
        }
    }
}
