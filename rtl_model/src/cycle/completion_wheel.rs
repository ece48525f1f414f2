//! The node memory's queue of reads that have been served and wait for their data cycle.
//!
//! Pipeline position: inside [`super::memory::NodeMemory`], between the arbitration of a read
//! (it knows when the data will be valid) and [`super::memory::NodeMemory::tick_into`] (which hands
//! the completions of a cycle to the walker pool).
//!
//! # Why a timing wheel
//!
//! Almost every read completes a few cycles after it is served (block RAM 3, cache hit 4,
//! DRAM about 60–100), and the pool collects completions once per cycle. A binary heap pays
//! `log n` cache-missing moves per push and per pop with a few hundred reads in flight; a
//! wheel of per-cycle buckets pays a push onto a short vector and one look per cycle. The
//! rare completion beyond the wheel's span (a long DRAM queue) waits in a heap and moves
//! into the wheel when its cycle comes within the span.
//!
//! Order is part of the model's contract: completions leave ordered by (cycle done, request
//! id), exactly as the heap this replaced gave them, so the walker pool wakes its contexts in
//! the same order and every cycle count stays the same.

use super::memory::Completion;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Cycles covered by the wheel's buckets (a power of two). Longer waits use the heap.
const SPAN: u64 = 512;

/// A completion ordered by (cycle done, id), for the overflow heap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ByDone(Completion);

impl Ord for ByDone {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        (self.0.cycle_done, self.0.id).cmp(&(other.0.cycle_done, other.0.id))
    }
}

impl PartialOrd for ByDone {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

/// Completions waiting for their cycle (see the module doc).
#[derive(Clone, Debug)]
pub struct CompletionWheel {
    /// `buckets[c % SPAN]` holds the completions done in cycle `c`, for `base ≤ c < base + SPAN`.
    buckets: Vec<Vec<Completion>>,
    /// Every completion done before `base` has been handed out.
    base: u64,
    /// Completions in the buckets.
    in_wheel: usize,
    /// Completions done at or after `base + SPAN`, or (defensively) before `base`.
    far: BinaryHeap<Reverse<ByDone>>,
}

impl Default for CompletionWheel {
    fn default() -> Self {
        Self {
            buckets: vec![Vec::new(); SPAN as usize],
            base: 0,
            in_wheel: 0,
            far: BinaryHeap::new(),
        }
    }
}

impl CompletionWheel {
    /// Completions waiting.
    pub fn len(&self) -> usize {
        self.in_wheel + self.far.len()
    }

    /// Whether none waits.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The earliest cycle a waiting completion is done in, if any (for idle-cycle skipping:
    /// nothing comes back before it). Scans at most the wheel's span of buckets.
    pub fn next_due(&self) -> Option<u64> {
        let far = self.far.peek().map(|Reverse(ByDone(c))| c.cycle_done);
        let near = (self.in_wheel > 0)
            .then(|| {
                (self.base..self.base + SPAN)
                    .find(|&c| !self.buckets[(c % SPAN) as usize].is_empty())
            })
            .flatten();
        match (near, far) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Queues `c` for its cycle `c.cycle_done`. Inlined into the node memory's completion, so
    /// that the record is written once, into its bucket (issue 30).
    #[inline]
    pub fn push(&mut self, c: Completion) {
        let done = c.cycle_done;
        if done >= self.base && done - self.base < SPAN {
            self.buckets[(done % SPAN) as usize].push(c);
            self.in_wheel += 1;
        } else {
            self.far.push(Reverse(ByDone(c)));
        }
    }

    /// Appends to `out` every completion done by `cycle` (`cycle_done ≤ cycle`), ordered by
    /// (cycle done, id).
    pub fn pop_due(&mut self, cycle: u64, out: &mut Vec<Completion>) {
        self.pop_due_with(cycle, |c| out.push(*c));
    }

    /// [`pop_due`](Self::pop_due) handing each completion to `emit` instead, in the same
    /// order: a caller that needs one field (the walker pool: who asked) takes it without
    /// copying the whole record into a buffer first.
    #[inline]
    pub fn pop_due_with(&mut self, cycle: u64, mut emit: impl FnMut(&Completion)) {
        // Heap entries below `base` (none in the model's use) are due before any bucket.
        while let Some(Reverse(ByDone(c))) = self.far.peek().copied() {
            if c.cycle_done >= self.base || c.cycle_done > cycle {
                break;
            }
            self.far.pop();
            emit(&c);
        }
        while self.base <= cycle {
            if self.in_wheel == 0 {
                // Nothing in the buckets: jump to the next heap entry's cycle (or past `cycle`).
                let next = self.far.peek().map(|Reverse(ByDone(c))| c.cycle_done);
                let Some(next) = next.filter(|&n| n <= cycle) else {
                    self.base = cycle.saturating_add(1);
                    self.refill();
                    return;
                };
                self.base = next;
                self.refill();
            }
            let bucket = &mut self.buckets[(self.base % SPAN) as usize];
            if !bucket.is_empty() {
                // Pushed in service order, which is not always id order (banks before the
                // cache, a merged miss served late): sort the few entries of the cycle.
                // Usually already in order: checking is cheaper than sorting.
                if !bucket.is_sorted_by_key(|c| c.id) {
                    bucket.sort_unstable_by_key(|c| c.id);
                }
                self.in_wheel -= bucket.len();
                bucket.iter().for_each(&mut emit);
                bucket.clear();
            }
            // `cycle` may be u64::MAX (a caller skipping to the end): stop rather than wrap.
            if self.base == cycle {
                self.base = cycle.saturating_add(1);
                self.refill();
                return;
            }
            self.base += 1;
            self.refill();
        }
    }

    /// Every completion still waiting, ordered by (cycle done, id); the wheel is then empty.
    pub fn drain_all(&mut self, out: &mut Vec<Completion>) {
        let from = out.len();
        for b in &mut self.buckets {
            out.append(b);
        }
        out.extend(self.far.drain().map(|Reverse(ByDone(c))| c));
        self.in_wheel = 0;
        out[from..].sort_unstable_by_key(|c| (c.cycle_done, c.id));
    }

    /// Moves heap entries whose cycle is now within the span into their buckets.
    fn refill(&mut self) {
        while let Some(Reverse(ByDone(c))) = self.far.peek().copied() {
            if c.cycle_done < self.base || c.cycle_done - self.base >= SPAN {
                break;
            }
            self.far.pop();
            self.buckets[(c.cycle_done % SPAN) as usize].push(c);
            self.in_wheel += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cycle::memory::{FetchKind, RequestId, Source};

    fn comp(id: u64, done: u64) -> Completion {
        Completion {
            id: RequestId(id),
            requester: 0,
            kind: FetchKind::Node,
            addr: 0,
            cycle_requested: 0,
            cycle_served: 0,
            cycle_done: done,
            source: Source::CacheHit,
        }
    }

    /// Against a sorted list, with waits inside and far beyond the span, ids pushed out of
    /// order, and polls that skip cycles.
    #[test]
    fn hands_out_in_done_then_id_order() {
        let seed = 0x5eed_0001u64;
        println!("seed {seed:#x}");
        let mut x = seed;
        let mut rnd = move |n: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % n
        };
        let mut wheel = CompletionWheel::default();
        let mut oracle: Vec<(u64, u64)> = Vec::new();
        let mut got: Vec<(u64, u64)> = Vec::new();
        let mut out = Vec::new();
        let mut now = 0u64;
        let mut next_id = 0u64;
        for _ in 0..20_000 {
            for _ in 0..rnd(4) {
                let wait = if rnd(50) == 0 {
                    1 + rnd(5000)
                } else {
                    1 + rnd(100)
                };
                // Ids are not in done order: a later id may complete earlier.
                let id = next_id + rnd(3);
                next_id += 3;
                wheel.push(comp(id, now + wait));
                oracle.push((now + wait, id));
            }
            now += 1 + rnd(3) * rnd(2);
            out.clear();
            wheel.pop_due(now, &mut out);
            for c in &out {
                assert!(c.cycle_done <= now);
                got.push((c.cycle_done, c.id.0));
            }
        }
        out.clear();
        wheel.drain_all(&mut out);
        got.extend(out.iter().map(|c| (c.cycle_done, c.id.0)));
        oracle.sort_unstable();
        assert_eq!(got, oracle);
        assert!(wheel.is_empty());
    }

    /// A poll at the end of time (an idle memory skipped to u64::MAX) returns at once and
    /// still hands out what is due, with or without entries waiting.
    #[test]
    fn polling_at_the_end_of_time_terminates() {
        let mut empty = CompletionWheel::default();
        let mut out = Vec::new();
        empty.pop_due(u64::MAX, &mut out);
        assert!(out.is_empty());
        let mut wheel = CompletionWheel::default();
        wheel.push(comp(2, 7));
        wheel.push(comp(1, 100_000));
        wheel.pop_due(u64::MAX, &mut out);
        let got: Vec<(u64, u64)> = out.iter().map(|c| (c.cycle_done, c.id.0)).collect();
        assert_eq!(got, vec![(7, 2), (100_000, 1)]);
        assert!(wheel.is_empty());
        // And again, with the wheel already at the end.
        wheel.pop_due(u64::MAX, &mut out);
        assert_eq!(out.len(), 2);
    }
}
