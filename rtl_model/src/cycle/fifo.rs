//! Bounded FIFO with valid/ready handshakes, the joint between every two pipeline stages.
//!
//! Where it sits: between ray generation and the transform, the transform and the sphere
//! units, the sorter and the walker dispatcher, and in front of the hit buffer. The stages on
//! either side are evaluated in the same cycle; the FIFO decouples them, and its counters are
//! where the report's "back-pressured" and "starved" cycles and FIFO occupancy come from.
//!
//! # Handshake, as a synchronous FIFO in RTL has it
//!
//! All signals a neighbour sees come from registered state (start of the cycle), so the
//! FIFO follows the two-phase discipline of [`super::clocked`]:
//!
//! - `ready` (to the producer) = occupancy < depth. **A pop in the same cycle does not free a
//!   slot for a push in that cycle**: `ready` is the registered not-full flag, as in a
//!   standard synchronous FIFO. Letting `ready` depend on the consumer's `ready` would be a
//!   combinational path from the far end of a chain of stages back to its start, the long path
//!   that FIFOs are put in to cut. The cost, made visible here: a depth-1 FIFO passes at most
//!   one item every two cycles; depth 2 sustains one per cycle.
//! - `valid` (to the consumer) = occupancy > 0, and the data is the registered head. There is
//!   no fall-through: an item pushed in cycle `c` can leave in cycle `c + 1` at the earliest,
//!   so every item spends at least one cycle inside.
//! - A push happens in a cycle when the producer offers an item ([`Fifo::try_push`]: valid)
//!   and `ready`; a pop when the consumer asks ([`Fifo::try_pop`]: ready) and `valid`. Both
//!   may happen in one cycle (occupancy then stays). A side that is not driven in a cycle has
//!   its signal low.
//! - The pointer update happens at the edge ([`Commit::commit`], via
//!   [`super::clocked::Clock::edge`]); a pushed item is stored at once, behind the items of
//!   the start of the cycle, where no pop of the cycle reaches it (a pop only takes those, all
//!   in front of it), and the edge makes it visible. The popped item is handed to the
//!   consumer during the cycle (it is the registered head, which the consumer captures at the
//!   same edge), but `ready`, `valid` and [`Fifo::occupancy`] keep their start-of-cycle values
//!   until the edge, so the producer and consumer may be evaluated in either order.
//!
//! # Stamps
//!
//! An item enters the FIFO's stage ([`Fifo::stage`]) in the cycle of its push and leaves in the
//! cycle of its pop, so `left ≥ entered + 1`. A [`forward`] from one FIFO to the next makes the
//! first's exit cycle the second's entry cycle.
//!
//! # Misuse
//!
//! Nothing panics. Driving a side twice in one cycle (two producers, or one producer pushing
//! twice) is refused, counted in [`FifoStats::misuse`], and hands the item back. A FIFO that is
//! committed outside the clock's edge goes out of step, which the next edge reports.
//!
//! # Example
//!
//! ```
//! use rtl_model::cycle::clocked::{Clock, StageId, Stamped};
//! use rtl_model::cycle::fifo::Fifo;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut clock = Clock::new();
//! let mut fifo = Fifo::new(StageId(3), 2)?;
//! // Cycle 0: push; the consumer asks but the FIFO is empty at the start of the cycle.
//! assert!(fifo.try_push(Stamped::new(7u32)).is_ok());
//! assert!(fifo.try_pop()?.is_none());
//! clock.edge(&mut [&mut fifo])?;
//! // Cycle 1: the item is visible now.
//! let item = fifo.try_pop()?.ok_or("empty")?;
//! assert_eq!((item.payload, item.latency_in(StageId(3))), (7, Some(1)));
//! clock.edge(&mut [&mut fifo])?;
//! assert_eq!(fifo.stats().starved_cycles, 1);
//! # Ok(())
//! # }
//! ```

use std::collections::VecDeque;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::clocked::{Commit, StageId, Stamped};

/// Deepest FIFO accepted. 65 536 entries of a 64-bit word is already about 114 BRAM36, more
/// than any inter-stage FIFO of the pipeline needs; the bound keeps the occupancy histogram
/// (one counter per level) small.
pub const MAX_DEPTH: usize = 1 << 16;

/// Errors from building or driving a FIFO.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum FifoError {
    /// Depth 0: a FIFO that can never accept anything.
    #[error("FIFO depth must be at least 1")]
    ZeroDepth,
    /// Depth above [`MAX_DEPTH`].
    #[error("FIFO depth {0} is above the maximum {MAX_DEPTH}")]
    TooDeep(usize),
    /// The consumer side was driven twice in one cycle.
    #[error("consumer side driven twice in cycle {cycle}")]
    PopSideDriven {
        /// The cycle.
        cycle: u64,
    },
    /// The producer side was driven twice in one cycle.
    #[error("producer side driven twice in cycle {cycle}")]
    PushSideDriven {
        /// The cycle.
        cycle: u64,
    },
    /// [`Fifo::note_full`] on a FIFO that still had room for the held item.
    #[error(
        "producer reported back-pressure in cycle {cycle}, but the FIFO had room ({room} left)"
    )]
    NotFull {
        /// The cycle.
        cycle: u64,
        /// Entries still free after this cycle's pushes.
        room: usize,
    },
    /// [`forward`] between FIFOs that are on different cycles.
    #[error("FIFOs are on different cycles ({from} and {to})")]
    OutOfStep {
        /// Cycle of the upstream FIFO.
        from: u64,
        /// Cycle of the downstream FIFO.
        to: u64,
    },
}

/// Why [`Fifo::try_push`] did not take an item.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// The FIFO was full at the start of the cycle: back-pressure, the producer keeps the
    /// item and offers it again. Counted in [`FifoStats::full_cycles`].
    Full,
    /// The producer side was already driven this cycle: misuse, counted in
    /// [`FifoStats::misuse`].
    AlreadyDriven,
}

/// An item [`Fifo::try_push`] did not take, handed back to the producer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rejected<T> {
    /// The item, unchanged (no stamp added).
    pub item: Stamped<T>,
    /// Why it was not taken.
    pub reason: Refusal,
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::Full => write!(f, "FIFO full"),
            Refusal::AlreadyDriven => write!(f, "FIFO producer side driven twice in one cycle"),
        }
    }
}

impl<T> std::fmt::Display for Rejected<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.reason.fmt(f)
    }
}

impl<T: std::fmt::Debug> std::error::Error for Rejected<T> {}

/// Counters of one FIFO. Occupancy samples are the registered occupancy of each cycle (the
/// value the handshake used), taken once per edge.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FifoStats {
    /// Edges taken (cycles evaluated).
    pub cycles: u64,
    /// Items accepted.
    pub pushes: u64,
    /// Items handed out.
    pub pops: u64,
    /// Back-pressure: cycles in which the producer held an item ready to enter and the FIFO
    /// had no room for it (registered occupancy plus this cycle's pushes at the depth) —
    /// offered and refused ([`Fifo::try_push`]), or held back and reported
    /// ([`Fifo::note_full`]). At most one per cycle, whatever the ports: a `k`-port FIFO
    /// that took some of a cycle's ready items (even all `k`) and was left with no room for
    /// the rest counts the cycle; one whose producer had more ready than its `k` ports but
    /// room left does not (that is the datapath's width, not back-pressure).
    pub full_cycles: u64,
    /// Starvation: cycles in which the consumer was ready and the FIFO was empty.
    pub starved_cycles: u64,
    /// Highest occupancy the FIFO has held (including the current one).
    pub max_occupancy: u64,
    /// Sum of the per-cycle occupancy samples; divided by `cycles`, the mean occupancy.
    pub occupancy_sum: u64,
    /// Cycles spent at each occupancy, index 0 to depth; sums to `cycles`.
    pub occupancy_histogram: Vec<u64>,
    /// Sum over popped items of the cycles each spent inside (exit − entry).
    pub latency_sum: u64,
    /// Longest time an item spent inside.
    pub latency_max: u64,
    /// Refused misuse: a side driven twice in one cycle, or an item whose stamps did not
    /// show it inside this FIFO when it left (cannot happen through this API).
    pub misuse: u64,
}

impl FifoStats {
    /// Mean occupancy per cycle, 0 before the first edge.
    pub fn mean_occupancy(&self) -> f64 {
        if self.cycles == 0 {
            0.0
        } else {
            self.occupancy_sum as f64 / self.cycles as f64
        }
    }

    /// Mean cycles an item spent inside, 0 before the first pop.
    pub fn mean_latency(&self) -> f64 {
        if self.pops == 0 {
            0.0
        } else {
            self.latency_sum as f64 / self.pops as f64
        }
    }
}

/// A bounded FIFO of stamped transactions with registered valid/ready (see the module doc).
#[derive(Clone, Debug)]
pub struct Fifo<T> {
    stage: StageId,
    depth: usize,
    now: u64,
    /// Storage; the front is the head. During a cycle its first `occupancy - taken` items are
    /// those of the start of the cycle not yet handed out, and this cycle's pushes follow them
    /// (`pending` of them), invisible to the consumer until the edge: a pop only takes items
    /// of the start of the cycle, which are all in front of them.
    items: VecDeque<Stamped<T>>,
    /// Registered occupancy: what `ready`, `valid` and the counters use all cycle.
    occupancy: usize,
    /// Pushes of this cycle, at the back of `items`, waiting for the edge (stored in place,
    /// so that the edge moves no item: issue 30).
    pending: usize,
    /// Pushes and pops a cycle may drive (1 for an ordinary FIFO; `k` for the k-wide FIFOs of
    /// the walk section, docs/cycle-model.md §2.1).
    ports: usize,
    /// Times the producer / consumer side was driven this cycle.
    pushes_now: usize,
    pops_now: usize,
    /// Items handed out this cycle.
    taken: usize,
    /// This cycle's consumer asked while empty / producer offered while full.
    starved_now: bool,
    full_now: bool,
    /// The same for the last committed cycle (what [`Fifo::skip_idle`] repeats).
    last_starved: bool,
    last_full: bool,
    /// Cycles at the current registered occupancy not yet added to the occupancy counters
    /// (`cycles`, `occupancy_sum`, the histogram): they are added in bulk when the occupancy
    /// changes, and [`Fifo::stats`] includes them.
    unsampled: u64,
    stats: FifoStats,
}

impl<T> Fifo<T> {
    /// An empty FIFO of `depth` entries at cycle 0, stamping items with `stage`.
    pub fn new(stage: StageId, depth: usize) -> Result<Self, FifoError> {
        Self::new_wide(stage, depth, 1)
    }

    /// An empty FIFO of `depth` entries at cycle 0 whose producer may push, and consumer pop,
    /// up to `ports` items per cycle (at least 1): the joint of a `ports`-wide datapath. Each
    /// push and pop of a cycle sees the registered occupancy less what that side has already
    /// done in the cycle, never the other side's moves (the module doc's rule, per port).
    pub fn new_wide(stage: StageId, depth: usize, ports: usize) -> Result<Self, FifoError> {
        if depth == 0 {
            return Err(FifoError::ZeroDepth);
        }
        if depth > MAX_DEPTH {
            return Err(FifoError::TooDeep(depth));
        }
        Ok(Self {
            stage,
            depth,
            now: 0,
            items: VecDeque::with_capacity(depth),
            occupancy: 0,
            pending: 0,
            ports: ports.max(1),
            pushes_now: 0,
            pops_now: 0,
            taken: 0,
            starved_now: false,
            full_now: false,
            last_starved: false,
            last_full: false,
            unsampled: 0,
            stats: FifoStats {
                occupancy_histogram: vec![0; depth + 1],
                ..FifoStats::default()
            },
        })
    }

    /// An empty FIFO that comes out of reset at cycle `cycle` (a pipeline rebuilt between
    /// frames while the clock and the memories keep running).
    pub fn new_at(stage: StageId, depth: usize, cycle: u64) -> Result<Self, FifoError> {
        Self::new_wide_at(stage, depth, 1, cycle)
    }

    /// [`Fifo::new_wide`] out of reset at cycle `cycle`.
    pub fn new_wide_at(
        stage: StageId,
        depth: usize,
        ports: usize,
        cycle: u64,
    ) -> Result<Self, FifoError> {
        let mut f = Self::new_wide(stage, depth, ports)?;
        f.now = cycle;
        Ok(f)
    }

    /// Pushes and pops per cycle.
    pub fn ports(&self) -> usize {
        self.ports
    }

    /// Whether one more push would be taken this cycle: a producer port is left and the
    /// registered occupancy plus this cycle's pushes is below the depth.
    #[inline]
    pub fn can_push(&self) -> bool {
        self.pushes_now < self.ports && self.occupancy + self.pending < self.depth
    }

    /// Whether one more pop would return an item this cycle: a consumer port is left and an
    /// item that was inside at the start of the cycle has not been handed out.
    #[inline]
    pub fn can_pop(&self) -> bool {
        self.pops_now < self.ports && self.taken < self.occupancy
    }

    /// The stage id this FIFO stamps items with.
    pub fn stage(&self) -> StageId {
        self.stage
    }

    /// Capacity in items.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Items inside at the start of this cycle (registered; unchanged until the edge).
    pub fn occupancy(&self) -> usize {
        self.occupancy
    }

    /// `ready` to the producer: not full at the start of the cycle. A pop in this cycle does
    /// not make it true (see the module doc).
    pub fn ready(&self) -> bool {
        self.occupancy < self.depth
    }

    /// `valid` to the consumer: not empty at the start of the cycle.
    pub fn valid(&self) -> bool {
        self.occupancy > 0
    }

    /// The head item, for a consumer that decides on its content before asking. `None` when
    /// empty, and also once the head has been popped this cycle (it has been handed over).
    pub fn peek(&self) -> Option<&Stamped<T>> {
        if self.pops_now >= self.ports || self.taken >= self.occupancy {
            None
        } else {
            self.items.front()
        }
    }

    /// The `i`-th item (0: the head) of those inside at the start of the cycle, if not yet
    /// handed out: what a consumer evaluated as a pure kernel reads (a wide consumer reads
    /// beyond the head) before its pops are applied at the edge.
    #[inline]
    pub fn registered(&self, i: usize) -> Option<&Stamped<T>> {
        if i >= self.occupancy {
            return None;
        }
        i.checked_sub(self.taken).and_then(|k| self.items.get(k))
    }

    /// The counters so far.
    pub fn stats(&self) -> FifoStats {
        let mut s = self.stats.clone();
        Self::sample(&mut s, self.occupancy, self.unsampled);
        s
    }

    /// Items pushed plus items popped so far: changes whenever an item moves.
    #[inline]
    pub fn moved(&self) -> u64 {
        self.stats.pushes + self.stats.pops
    }

    /// Adds `k` cycles at occupancy `occupancy` to the occupancy counters.
    #[inline]
    fn sample(s: &mut FifoStats, occupancy: usize, k: u64) {
        s.cycles = s.cycles.saturating_add(k);
        s.occupancy_sum = s
            .occupancy_sum
            .saturating_add((occupancy as u64).saturating_mul(k));
        if let Some(h) = s.occupancy_histogram.get_mut(occupancy) {
            *h = h.saturating_add(k);
        }
    }

    /// The producer offers `item` this cycle (asserts valid). Taken if the FIFO was not full at
    /// the start of the cycle; it is stamped as entering now and becomes visible after the
    /// edge. Otherwise the item comes back with the reason.
    #[inline]
    pub fn try_push(&mut self, item: Stamped<T>) -> Result<(), Rejected<T>> {
        match self.push_admitted() {
            Ok(()) => {
                self.accept(item);
                Ok(())
            }
            Err(reason) => Err(Rejected { item, reason }),
        }
    }

    /// [`Fifo::try_push`] for a driver that treats a refusal as an error: the same handshake
    /// and counters, but a refused item is dropped and only the reason comes back (no item
    /// travels back through the result).
    #[inline]
    pub fn push_driven(&mut self, item: Stamped<T>) -> Result<(), Refusal> {
        self.push_admitted()?;
        self.accept(item);
        Ok(())
    }

    /// The push side's handshake, shared by [`try_push`](Self::try_push) and
    /// [`push_driven`](Self::push_driven): a port used (or misuse when none is left), then
    /// room at the start of the cycle, a full cycle counted (once a cycle) when there is none.
    #[inline]
    fn push_admitted(&mut self) -> Result<(), Refusal> {
        if self.pushes_now >= self.ports {
            self.stats.misuse = self.stats.misuse.saturating_add(1);
            return Err(Refusal::AlreadyDriven);
        }
        self.pushes_now += 1;
        if self.occupancy + self.pending >= self.depth {
            if !self.full_now {
                self.stats.full_cycles = self.stats.full_cycles.saturating_add(1);
            }
            self.full_now = true;
            return Err(Refusal::Full);
        }
        Ok(())
    }

    /// The producer holds an item ready to enter that it did not offer this cycle because
    /// the FIFO has no room for it (a driver that checks [`Fifo::can_push`] before it offers,
    /// so never offers into a full FIFO): counted in [`FifoStats::full_cycles`] as a refused
    /// [`Fifo::try_push`] would be — once a cycle, and repeated by [`Fifo::skip_idle`].
    /// Call it after the cycle's pushes. A FIFO with room left is refused (the producer
    /// could have pushed: a driver bug), with nothing counted.
    #[inline]
    pub fn note_full(&mut self) -> Result<(), FifoError> {
        let inside = self.occupancy + self.pending;
        if inside < self.depth {
            return Err(FifoError::NotFull {
                cycle: self.now,
                room: self.depth - inside,
            });
        }
        if !self.full_now {
            self.stats.full_cycles = self.stats.full_cycles.saturating_add(1);
        }
        self.full_now = true;
        Ok(())
    }

    /// [`Fifo::try_pop`] for a driver whose consumer already holds a copy of the head: the
    /// same handshake and counters, the item dropped in place. Whether an item left.
    #[inline]
    pub fn pop_driven(&mut self) -> Result<bool, FifoError> {
        if !self.pop_admitted()? {
            return Ok(false);
        }
        let Some(item) = self.items.front_mut() else {
            return Ok(false);
        };
        self.taken += 1;
        self.stats.pops = self.stats.pops.saturating_add(1);
        let (stage, now) = (self.stage, self.now);
        Self::leave_counted(&mut self.stats, item, stage, now);
        self.items.pop_front();
        Ok(true)
    }

    /// A cycle's pops (the consumer holds copies: dropped in place, as by
    /// [`pop_driven`](Self::pop_driven)) and then pushes, as one batch, when every one of them
    /// fires: a port left for each, each pop an item of the start of the cycle, room for every
    /// push. Then the counters and stamps are those of the calls one by one, with the
    /// handshake checked once (issue 30). Returns `false`, with nothing done, otherwise: the
    /// caller makes the calls one by one, which count or refuse what does not fire.
    #[inline]
    pub fn drive_batch(&mut self, pops: usize, pushes: &mut Vec<Stamped<T>>) -> bool {
        let n = pushes.len();
        let fires = self.pops_now + pops <= self.ports
            && self.taken + pops <= self.occupancy
            && self.pushes_now + n <= self.ports
            && self.occupancy + self.pending + n <= self.depth;
        if !fires {
            return false;
        }
        // The handshakes fired: each half as one call would complete it (`take`, `accept`).
        self.pops_now += pops;
        for _ in 0..pops {
            self.take();
        }
        self.pushes_now += n;
        for item in pushes.drain(..) {
            self.accept(item);
        }
        true
    }

    /// The consumer asserts ready this cycle. Returns the head, stamped as leaving now, if the
    /// FIFO was not empty at the start of the cycle; `Ok(None)` (a starved cycle) otherwise.
    #[inline]
    pub fn try_pop(&mut self) -> Result<Option<Stamped<T>>, FifoError> {
        if !self.pop_admitted()? {
            return Ok(None);
        }
        Ok(self.take())
    }

    /// The pop side's handshake, shared by [`try_pop`](Self::try_pop) and
    /// [`pop_driven`](Self::pop_driven): a port used (or misuse when none is left), and
    /// whether an item present at the start of the cycle can leave; a starved cycle counted
    /// otherwise.
    #[inline]
    fn pop_admitted(&mut self) -> Result<bool, FifoError> {
        if self.pops_now >= self.ports {
            self.stats.misuse = self.stats.misuse.saturating_add(1);
            return Err(FifoError::PopSideDriven { cycle: self.now });
        }
        self.pops_now += 1;
        if self.taken >= self.occupancy {
            // Starved only when nothing was inside at all; a wide consumer that asks for more
            // than there is has not starved.
            if self.occupancy == 0 && !self.starved_now {
                self.stats.starved_cycles = self.stats.starved_cycles.saturating_add(1);
                self.starved_now = true;
            }
            return Ok(false);
        }
        Ok(true)
    }

    /// Push half of a handshake that has fired: stamp and hold for the edge.
    #[inline]
    fn accept(&mut self, mut item: Stamped<T>) {
        item.enter(self.stage, self.now);
        self.items.push_back(item);
        self.pending += 1;
        self.stats.pushes = self.stats.pushes.saturating_add(1);
    }

    /// Pop half of a handshake that has fired: hand out the head, stamped.
    #[inline]
    fn take(&mut self) -> Option<Stamped<T>> {
        // The caller checked `taken < occupancy`: storage holds the items of the start of the
        // cycle not yet handed out. `?` keeps the impossible case quiet instead of panicking.
        let mut item = self.items.pop_front()?;
        self.taken += 1;
        self.stats.pops = self.stats.pops.saturating_add(1);
        self.stamp_leave(&mut item);
        Some(item)
    }

    /// Stamps `item` as leaving now and counts its time inside (or a misuse).
    #[inline]
    fn stamp_leave(&mut self, item: &mut Stamped<T>) {
        Self::leave_counted(&mut self.stats, item, self.stage, self.now);
    }

    #[inline]
    fn leave_counted(s: &mut FifoStats, item: &mut Stamped<T>, stage: StageId, now: u64) {
        match item.leave(stage, now) {
            Ok(latency) => {
                s.latency_sum = s.latency_sum.saturating_add(latency);
                s.latency_max = s.latency_max.max(latency);
            }
            Err(_) => s.misuse = s.misuse.saturating_add(1),
        }
    }
}

/// One cycle of a plain wire between two FIFOs (`from` → `to`): `from`'s consumer is ready
/// when `to` is ready, `to`'s producer is valid when `from` is valid, both read from registered
/// state. Returns whether an item moved; it leaves `from` and enters `to` in this cycle. Drives
/// both sides, so neither may be driven again this cycle; if either already was, or the two
/// are on different cycles, nothing moves and an error says why.
pub fn forward<T>(from: &mut Fifo<T>, to: &mut Fifo<T>) -> Result<bool, FifoError> {
    if from.now != to.now {
        return Err(FifoError::OutOfStep {
            from: from.now,
            to: to.now,
        });
    }
    if from.pops_now >= from.ports {
        from.stats.misuse = from.stats.misuse.saturating_add(1);
        return Err(FifoError::PopSideDriven { cycle: from.now });
    }
    if to.pushes_now >= to.ports {
        to.stats.misuse = to.stats.misuse.saturating_add(1);
        return Err(FifoError::PushSideDriven { cycle: to.now });
    }
    let (valid, ready) = (
        from.taken < from.occupancy,
        to.occupancy + to.pending < to.depth,
    );
    from.pops_now += 1;
    to.pushes_now += 1;
    if valid && !ready {
        to.stats.full_cycles = to.stats.full_cycles.saturating_add(1);
        to.full_now = true;
    }
    if ready && !valid {
        from.stats.starved_cycles = from.stats.starved_cycles.saturating_add(1);
        from.starved_now = true;
    }
    if valid && ready {
        if let Some(item) = from.take() {
            to.accept(item);
            return Ok(true);
        }
    }
    Ok(false)
}

impl<T> Commit for Fifo<T> {
    #[inline]
    fn cycle(&self) -> u64 {
        self.now
    }

    #[inline]
    fn commit(&mut self) {
        // This cycle's occupancy sample, in bulk with the cycles before it at the same level.
        self.unsampled += 1;
        // A FIFO whose sides were not driven this cycle — most of them, most cycles — has
        // nothing pending, nothing handed out and no starved flag (only a driven side sets
        // it), and no full flag unless a held item was reported (`note_full`, which drives
        // neither side): the edge only clears the last cycle's flags and counts the cycle.
        if self.pushes_now == 0 && self.pops_now == 0 && !self.full_now {
            self.last_starved = false;
            self.last_full = false;
            self.now = self.now.saturating_add(1);
            return;
        }
        // This cycle's pushes are already in storage, behind the items left of the start of
        // the cycle: the edge makes them visible.
        self.pending = 0;
        let occupancy = self.items.len();
        if occupancy != self.occupancy {
            let s = &mut self.stats;
            Self::sample(s, self.occupancy, self.unsampled);
            self.unsampled = 0;
            self.occupancy = occupancy;
            s.max_occupancy = s.max_occupancy.max(occupancy as u64);
        }
        self.pushes_now = 0;
        self.pops_now = 0;
        self.taken = 0;
        self.last_starved = std::mem::take(&mut self.starved_now);
        self.last_full = std::mem::take(&mut self.full_now);
        self.now = self.now.saturating_add(1);
    }
}

impl<T> Fifo<T> {
    /// Takes `k` idle cycles at once, as `k` cycles in which the FIFO's sides are driven as
    /// in the last committed one and nothing is pushed or popped: the counters (cycles,
    /// occupancy, histogram, starved and full cycles) are credited as if stepped. For the
    /// pipeline's idle-cycle skipping (docs/cycle-model.md §3.3); call it between edges,
    /// only after a cycle in which nothing moved through this FIFO.
    pub fn skip_idle(&mut self, k: u64) {
        self.unsampled = self.unsampled.saturating_add(k);
        let s = &mut self.stats;
        if self.last_starved {
            s.starved_cycles = s.starved_cycles.saturating_add(k);
        }
        if self.last_full {
            s.full_cycles = s.full_cycles.saturating_add(k);
        }
        self.now = self.now.saturating_add(k);
    }
}

#[cfg(test)]
#[path = "fifo_tests.rs"]
mod tests;
