//! `n` identical fixed-latency units side by side (the k-wide walk issue: transform,
//! reciprocal and walker-root units, record packing), as one stage that accepts up to `n`
//! transactions per cycle.
//!
//! Pipeline position: between two `n`-wide FIFOs of the walk section (docs/cycle-model.md
//! §2.1). Each lane is a [`UnitPipe`] with its own initiation interval and elastic registers; a
//! transaction enters the first lane that can take it, and ready results leave oldest first
//! (ties in lane order), so the order is a function of the cycle and the lanes only:
//! deterministic. With one lane it is exactly a [`UnitPipe`].

use super::stage_stats::StageState;
use super::unit_pipe::UnitPipe;

/// `n` units of one kind.
#[derive(Clone, Debug)]
pub struct UnitLanes<T> {
    lanes: Vec<UnitPipe<T>>,
}

impl<T> UnitLanes<T> {
    /// `n` (at least 1) units of `latency` cycles and initiation interval `ii` each.
    pub fn new(n: u32, latency: u32, ii: u32) -> Self {
        Self {
            lanes: (0..n.max(1)).map(|_| UnitPipe::new(latency, ii)).collect(),
        }
    }

    /// Units.
    pub fn width(&self) -> usize {
        self.lanes.len()
    }

    /// Whether a transaction can enter some lane in cycle `now`.
    #[inline]
    pub fn can_accept(&self, now: u64) -> bool {
        self.lanes.iter().any(|l| l.can_accept(now))
    }

    /// Enters `item` into the first lane that can take it in cycle `now` (the caller checks
    /// [`can_accept`](Self::can_accept)); as [`UnitPipe::accept`].
    #[inline]
    pub fn accept(&mut self, now: u64, item: T, passes: u64, extra_latency: u64) {
        if let Some(l) = self.lanes.iter_mut().find(|l| l.can_accept(now)) {
            l.accept(now, item, passes, extra_latency);
        }
    }

    /// The lane whose head is ready in `now` and became ready first (ties: lowest lane).
    #[inline]
    fn oldest_ready(&self, now: u64) -> Option<usize> {
        let mut best: Option<(u64, usize)> = None;
        for (i, l) in self.lanes.iter().enumerate() {
            if let Some(r) = l.ready_at().filter(|&r| r <= now) {
                if best.is_none_or(|(b, _)| r < b) {
                    best = Some((r, i));
                }
            }
        }
        best.map(|(_, i)| i)
    }

    /// The oldest ready result in cycle `now`.
    #[inline]
    pub fn ready(&self, now: u64) -> Option<&T> {
        let i = self.oldest_ready(now)?;
        self.lanes.get(i).and_then(|l| l.ready(now))
    }

    /// Takes the oldest ready result.
    #[inline]
    pub fn pop(&mut self, now: u64) -> Option<T> {
        let i = self.oldest_ready(now)?;
        self.lanes.get_mut(i).and_then(|l| l.pop(now))
    }

    /// Transactions inside all lanes.
    pub fn len(&self) -> usize {
        self.lanes.iter().map(UnitPipe::len).sum()
    }

    /// Whether every lane is empty.
    pub fn is_empty(&self) -> bool {
        self.lanes.iter().all(UnitPipe::is_empty)
    }

    /// The first cycle after `now` in which any lane can change by itself.
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.lanes.iter().filter_map(|l| l.next_change(now)).min()
    }

    /// The stage's state in `now` (as [`UnitPipe::state`]): back-pressured if a ready result
    /// stayed in any lane because `output_blocked`, else busy if any lane is, else starved or
    /// idle. Clears every lane's per-cycle flag.
    #[inline]
    pub fn state(&mut self, now: u64, output_blocked: bool, more_upstream: bool) -> StageState {
        let mut out = StageState::Idle;
        for l in &mut self.lanes {
            let s = l.state(now, output_blocked, more_upstream);
            out = match (out, s) {
                (StageState::Backpressured, _) | (_, StageState::Backpressured) => {
                    StageState::Backpressured
                }
                (StageState::Busy, _) | (_, StageState::Busy) => StageState::Busy,
                (_, s) => s,
            };
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_lanes_take_two_a_cycle_and_hand_out_oldest_first() {
        let mut u = UnitLanes::new(2, 3, 1);
        u.accept(0, 'a', 1, 0);
        assert!(u.can_accept(0), "the second lane is free");
        u.accept(0, 'b', 1, 0);
        assert!(!u.can_accept(0), "both lanes took one this cycle");
        u.accept(1, 'c', 1, 0);
        assert_eq!(u.pop(2), None);
        assert_eq!(u.pop(3), Some('a'), "tie: lane 0 first");
        assert_eq!(u.pop(3), Some('b'));
        assert_eq!(u.pop(3), None, "c is ready at 4");
        assert_eq!(u.pop(4), Some('c'));
        // One lane behaves as a UnitPipe: one a cycle.
        let mut one = UnitLanes::new(1, 3, 1);
        one.accept(0, 1, 1, 0);
        assert!(!one.can_accept(0));
    }
}
