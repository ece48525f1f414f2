//! A fixed-latency pipelined unit (ray generation, sphere tests with their square roots, the
//! sorter, transform, reciprocals, walker root, record packing) as the cycle model sees it:
//! it accepts a transaction every `ii` cycles (or every `occupancy × ii` for a transaction
//! that takes several passes, e.g. a ray with more candidates than sphere lanes), and the
//! result is ready `latency` cycles later, in order.
//!
//! Pipeline position: between two valid/ready FIFOs. When the result at the head cannot leave
//! (the output FIFO is full) it waits, and the transactions behind it close up behind it (an
//! elastic pipeline: a valid bit per register and a stall that only reaches the registers
//! that are full); once all `capacity` registers are full the unit stops accepting. This is
//! where downstream backpressure reaches the front of the pipeline, cycle by cycle.

use std::collections::VecDeque;

use super::stage_stats::StageState;

/// A pipelined unit holding transactions of type `T`.
#[derive(Clone, Debug)]
pub struct UnitPipe<T> {
    latency: u64,
    ii: u64,
    capacity: usize,
    next_accept: u64,
    items: VecDeque<(u64, T)>,
    accepted_this_cycle: bool,
}

impl<T> UnitPipe<T> {
    /// A unit of `latency` cycles (at least 1: outputs are registered) and initiation
    /// interval `ii` (at least 1). It holds `⌈latency / ii⌉` transactions, one per pipeline
    /// register that can be valid at once.
    pub fn new(latency: u32, ii: u32) -> Self {
        let latency = u64::from(latency.max(1));
        let ii = u64::from(ii.max(1));
        Self {
            latency,
            ii,
            capacity: latency.div_ceil(ii) as usize,
            next_accept: 0,
            items: VecDeque::new(),
            accepted_this_cycle: false,
        }
    }

    /// Whether a transaction can enter in cycle `now`: the initiation interval has passed and a
    /// pipeline register is free.
    #[inline]
    pub fn can_accept(&self, now: u64) -> bool {
        now >= self.next_accept && self.items.len() < self.capacity
    }

    /// Whether the unit's input is closed in cycle `now` by its own initiation window: the
    /// last transaction's interval (its `ii`, times its passes, e.g. a ray with more
    /// candidates than lanes) is not over. The bound line counts such cycles against the unit
    /// when a transaction waits for it and the work after it starves (docs/cycle-model.md §2.2).
    #[inline]
    pub fn in_interval(&self, now: u64) -> bool {
        now < self.next_accept
    }

    /// Transactions inside.
    #[inline]
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether it is empty.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Enters `item` in cycle `now`; it occupies the input for `passes` initiation intervals
    /// and is ready `extra_latency` cycles after the unit's latency. The caller checks
    /// [`can_accept`](Self::can_accept) first.
    #[inline]
    pub fn accept(&mut self, now: u64, item: T, passes: u64, extra_latency: u64) {
        let ready = now + self.latency + extra_latency;
        // In order: a transaction never overtakes the one ahead of it.
        let ready = self.items.back().map_or(ready, |&(r, _)| ready.max(r + 1));
        self.items.push_back((ready, item));
        self.next_accept = now + self.ii * passes.max(1);
        self.accepted_this_cycle = true;
    }

    /// The cycle the head transaction's result is (or was) ready, if there is a head.
    #[inline]
    pub fn ready_at(&self) -> Option<u64> {
        self.items.front().map(|&(r, _)| r)
    }

    /// The head transaction if its result is ready in cycle `now`.
    #[inline]
    pub fn ready(&self, now: u64) -> Option<&T> {
        self.items
            .front()
            .filter(|(r, _)| *r <= now)
            .map(|(_, t)| t)
    }

    /// The first cycle after `now` in which what the unit shows its neighbours can change
    /// with time alone: the head's result becomes ready, or the initiation interval ends.
    /// `None` when neither lies ahead. For idle-cycle skipping: with no transaction moving,
    /// every cycle before it looks like `now`.
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        let head = self.items.front().map(|&(r, _)| r).filter(|&r| r > now);
        let accept = Some(self.next_accept).filter(|&a| a > now);
        match (head, accept) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Takes the ready head (after the output FIFO took it).
    #[inline]
    pub fn pop(&mut self, now: u64) -> Option<T> {
        if self.items.front().is_some_and(|&(r, _)| r <= now) {
            self.items.pop_front().map(|(_, t)| t)
        } else {
            None
        }
    }

    /// The unit's state in cycle `now`, after the stage logic ran: back-pressured if a ready
    /// result stayed inside because `output_blocked`, busy if it took a transaction or has any
    /// in flight, starved if it was empty with `more_upstream` work to come, else idle. Clears
    /// the per-cycle flag.
    #[inline]
    pub fn state(&mut self, now: u64, output_blocked: bool, more_upstream: bool) -> StageState {
        let accepted = std::mem::take(&mut self.accepted_this_cycle);
        if output_blocked && self.ready(now).is_some() {
            StageState::Backpressured
        } else if accepted || !self.items.is_empty() {
            StageState::Busy
        } else if more_upstream {
            StageState::Starved
        } else {
            StageState::Idle
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latency_ii_and_capacity() {
        let mut p = UnitPipe::new(3, 1);
        assert!(p.can_accept(0));
        p.accept(0, 'a', 1, 0);
        p.accept(1, 'b', 1, 0);
        p.accept(2, 'c', 1, 0);
        assert!(!p.can_accept(3), "three registers full");
        assert_eq!(p.ready(2), None);
        assert_eq!(p.pop(3), Some('a'));
        assert_eq!(p.pop(3), None, "b is ready at 4");
        assert_eq!(p.pop(4), Some('b'));
        let mut q = UnitPipe::new(4, 2);
        q.accept(0, 1, 1, 0);
        assert!(!q.can_accept(1));
        assert!(q.can_accept(2));
        q.accept(2, 2, 3, 0);
        assert!(!q.can_accept(7), "three passes of II 2 from cycle 2");
        assert!(!q.can_accept(8), "two registers full");
        assert_eq!(q.pop(4), Some(1));
        assert!(q.can_accept(8));
    }

    #[test]
    fn a_blocked_head_stalls_and_backpressures() {
        let mut p = UnitPipe::new(2, 1);
        p.accept(0, 1, 1, 0);
        p.accept(1, 2, 1, 0);
        assert_eq!(p.state(1, false, true), StageState::Busy);
        // Output blocked from cycle 2: both results stay; the unit is full.
        assert_eq!(p.state(2, true, true), StageState::Backpressured);
        assert!(!p.can_accept(3));
        assert_eq!(p.pop(3), Some(1));
        assert_eq!(p.pop(3), Some(2), "the second closed up behind the first");
        assert_eq!(p.state(4, false, true), StageState::Starved);
        assert_eq!(p.state(5, false, false), StageState::Idle);
    }

    #[test]
    fn extra_latency_keeps_order() {
        let mut p = UnitPipe::new(2, 1);
        p.accept(0, 'x', 1, 10);
        p.accept(1, 'y', 1, 0);
        assert_eq!(p.pop(3), None, "y may not overtake x");
        assert_eq!(p.pop(12), Some('x'));
        assert_eq!(p.pop(12), None);
        assert_eq!(p.pop(13), Some('y'));
    }
}
