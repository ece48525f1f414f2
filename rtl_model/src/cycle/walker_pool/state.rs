//! The walker pool's per-walker and per-context state and its counters: what each context
//! is doing, each walker's counts and class, the pool's class counts and walker sets, and the
//! frame's walker-cycles by class.
//!
//! Pipeline position: inside the walker pool (`walker_pool.rs`, which drives them per cycle);
//! kept apart from its phases so that each file holds one concept.

use std::collections::VecDeque;

use super::rings::RingPos;
use crate::cycle::memory::FetchKind;
use serde::{Deserialize, Serialize};

/// Walker-cycles of a frame by what the walker did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PoolCycles {
    /// Issued a step or pop.
    pub issuing: u64,
    /// No ready context; at least one waits on a node read.
    pub memory_wait: u64,
    /// No ready context; all busy ones wait on the step pipeline.
    pub latency_wait: u64,
    /// Only finished walks the record stage could not take.
    pub backpressured: u64,
    /// No context busy.
    pub empty: u64,
    /// Walks dispatched.
    pub walks: u64,
    /// Issue slots used (steps and pops).
    pub slots: u64,
    /// Reads made.
    pub reads: u64,
    /// Sum over cycles of busy contexts (mean occupancy = this / cycles / (W·R)).
    pub busy_context_cycles: u64,
    /// Cycles a walk waited in front of the dispatcher with no free context.
    pub dispatch_stalls: u64,
    /// Context-cycles a read waited in its walker's send queue for a request port
    /// (`walker_pool.read_ports`): the report's `stalls.walker_read_port`.
    pub read_port_waits: u64,
}

impl PoolCycles {
    /// Adds another frame's counts.
    pub fn add(&mut self, o: &Self) {
        self.issuing += o.issuing;
        self.memory_wait += o.memory_wait;
        self.latency_wait += o.latency_wait;
        self.backpressured += o.backpressured;
        self.empty += o.empty;
        self.walks += o.walks;
        self.slots += o.slots;
        self.reads += o.reads;
        self.busy_context_cycles += o.busy_context_cycles;
        self.dispatch_stalls += o.dispatch_stalls;
        self.read_port_waits += o.read_port_waits;
    }
}

#[derive(Clone, Debug, Default)]
pub(super) struct Context {
    pub(super) walker: u32,
    pub(super) busy: bool,
    pub(super) tag: u64,
    pub(super) ops: Vec<u64>,
    pub(super) pc: usize,
    pub(super) in_issue: bool,
    pub(super) waiting_mem: bool,
    pub(super) finished: bool,
}

#[derive(Clone, Debug, Default)]
pub(super) struct Walker {
    /// Its issue ring: ready contexts, then steps under way (`rings.rs`).
    pub(super) pos: RingPos,
    pub(super) free: Vec<u32>,
    pub(super) busy: u32,
    pub(super) waiting_mem: u32,
    pub(super) finished: u32,
    pub(super) next_issue: u64,
    /// The cycle it last issued in (`u64::MAX`: never).
    pub(super) issued_at: u64,
    /// Its [`Class`] from its counts, kept with them ([`Walker::reclass`]): the issue phase
    /// reads it for every slot, and every count change starts from it.
    pub(super) class: Class,
    /// Reads waiting for a request port, oldest first, with the context that waits for each
    /// (`read_ports` > 0 only).
    pub(super) send: VecDeque<(u32, FetchKind, u32)>,
    /// Reads sent in cycle `sent_at` (so no per-cycle reset of every walker is needed).
    pub(super) sent: u32,
    pub(super) sent_at: u64,
}

/// What a walker that does not issue in a cycle is doing, from its context counts alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) enum Class {
    #[default]
    Empty = 0,
    MemoryWait = 1,
    Backpressured = 2,
    LatencyWait = 3,
}

impl Walker {
    /// The class its counts give now.
    #[inline]
    pub(super) fn classify(&self) -> Class {
        if self.busy == 0 {
            Class::Empty
        } else if self.waiting_mem > 0 {
            Class::MemoryWait
        } else if self.finished == self.busy {
            Class::Backpressured
        } else {
            Class::LatencyWait
        }
    }

    /// After a change of its counts: its class again, moved in `counts`.
    #[inline]
    pub(super) fn reclass(&mut self, counts: &mut ClassCounts) {
        let to = self.classify();
        counts.moved(self.class, to);
        self.class = to;
    }
}

/// Walkers per [`Class`], kept up to date as contexts change state, so that classifying a
/// cycle's idle walkers costs nothing per walker: only the walkers that issued are
/// subtracted.
#[derive(Clone, Debug, Default)]
pub(super) struct ClassCounts(pub(super) [u32; 4]);

impl ClassCounts {
    /// Moves one walker from class `from` to class `to`.
    pub(super) fn moved(&mut self, from: Class, to: Class) {
        if from != to {
            self.0[from as usize] -= 1;
            self.0[to as usize] += 1;
        }
    }
}

/// A set of walker indices as bits, iterated in ascending order.
#[derive(Clone, Debug, Default)]
pub(super) struct WalkerSet(pub(super) Vec<u64>);

impl WalkerSet {
    pub(super) fn new(walkers: usize) -> Self {
        Self(vec![0; walkers.div_ceil(64)])
    }

    pub(super) fn insert(&mut self, w: usize) {
        self.0[w / 64] |= 1 << (w % 64);
    }

    pub(super) fn remove(&mut self, w: usize) {
        self.0[w / 64] &= !(1 << (w % 64));
    }

    /// The lowest walker in the set.
    pub(super) fn first(&self) -> Option<usize> {
        self.0
            .iter()
            .enumerate()
            .find(|(_, &b)| b != 0)
            .map(|(i, b)| i * 64 + b.trailing_zeros() as usize)
    }
}
