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
///
/// Besides the lanes it keeps what the stage asks about every cycle, so that asking costs no
/// scan of the lanes (issue 30): the earliest head result, the transactions inside and
/// whether one entered this cycle. They are brought up to date on every accept and pop, the
/// only changes to the lanes, so every answer is the one the scan would give.
#[derive(Clone, Debug)]
pub struct UnitLanes<T> {
    lanes: Vec<UnitPipe<T>>,
    /// The earliest cycle a lane's head result is ready (`u64::MAX`: every lane empty).
    first_ready: u64,
    /// Transactions inside all lanes.
    len: usize,
    /// A transaction entered since the last [`UnitLanes::state`] (what it reports as busy).
    accepted: bool,
}

impl<T> UnitLanes<T> {
    /// `n` (at least 1) units of `latency` cycles and initiation interval `ii` each.
    pub fn new(n: u32, latency: u32, ii: u32) -> Self {
        Self {
            lanes: (0..n.max(1)).map(|_| UnitPipe::new(latency, ii)).collect(),
            first_ready: u64::MAX,
            len: 0,
            accepted: false,
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
            // The lane's head is unchanged unless it was empty: the earliest head is the
            // old one or this lane's.
            if let Some(r) = l.ready_at() {
                self.first_ready = self.first_ready.min(r);
            }
            self.len += 1;
            self.accepted = true;
        }
    }

    /// Whether some lane's head result is ready in cycle `now` (no scan).
    #[inline]
    pub fn has_ready(&self, now: u64) -> bool {
        self.first_ready <= now
    }

    /// The lane whose head is ready in `now` and became ready first (ties: lowest lane).
    #[inline]
    fn oldest_ready(&self, now: u64) -> Option<usize> {
        if !self.has_ready(now) {
            return None;
        }
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
        let item = self.lanes.get_mut(i).and_then(|l| l.pop(now));
        if item.is_some() {
            self.len -= 1;
            // The popped lane's head moved on: the earliest head is found again.
            self.first_ready = self
                .lanes
                .iter()
                .filter_map(UnitPipe::ready_at)
                .min()
                .unwrap_or(u64::MAX);
        }
        item
    }

    /// Transactions inside all lanes.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether every lane is empty.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The first cycle after `now` in which any lane can change by itself.
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.lanes.iter().filter_map(|l| l.next_change(now)).min()
    }

    /// The stage's state in `now` (as [`UnitPipe::state`] of each lane, combined):
    /// back-pressured if a ready result stayed in any lane because `output_blocked`, else busy
    /// if any lane took a transaction this cycle or holds one, else starved or idle. Clears
    /// the per-cycle flag.
    #[inline]
    pub fn state(&mut self, now: u64, output_blocked: bool, more_upstream: bool) -> StageState {
        let accepted = std::mem::take(&mut self.accepted);
        if output_blocked && self.has_ready(now) {
            StageState::Backpressured
        } else if accepted || self.len > 0 {
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

    /// A reference of `n` lanes written from the module doc alone (no `UnitPipe`): each lane
    /// a list of (ready cycle, item), its reopening cycle and its registers.
    struct Reference {
        lanes: Vec<(Vec<(u64, u32)>, u64)>,
        latency: u64,
        ii: u64,
        registers: usize,
        accepted: bool,
    }

    impl Reference {
        fn free(&self, l: usize, now: u64) -> bool {
            let (items, next) = &self.lanes[l];
            now >= *next && items.len() < self.registers
        }
        fn accept(&mut self, now: u64, item: u32, passes: u64) {
            let l = (0..self.lanes.len())
                .find(|&l| self.free(l, now))
                .expect("a free lane");
            let (items, next) = &mut self.lanes[l];
            let ready = items.last().map_or(now + self.latency, |&(r, _)| {
                (now + self.latency).max(r + 1)
            });
            items.push((ready, item));
            *next = now + self.ii * passes;
            self.accepted = true;
        }
        fn oldest(&self, now: u64) -> Option<usize> {
            let mut best = None;
            for (l, (items, _)) in self.lanes.iter().enumerate() {
                if let Some(&(r, _)) = items.first() {
                    if r <= now && best.is_none_or(|(b, _)| r < b) {
                        best = Some((r, l));
                    }
                }
            }
            best.map(|(_, l)| l)
        }
    }

    #[test]
    fn cached_answers_match_a_reference_of_the_lanes() {
        let seed = 0x5eed_0030u64;
        println!("seed {seed:#x}");
        let mut rng = crate::cycle::test_rng::TestRng::new(seed);
        for case in 0..40 {
            let (n, latency, ii) = (1 + rng.below(4), 1 + rng.below(6), 1 + rng.below(3));
            let mut u = UnitLanes::new(n as u32, latency as u32, ii as u32);
            let mut r = Reference {
                lanes: vec![(Vec::new(), 0); n as usize],
                latency,
                ii,
                registers: latency.div_ceil(ii) as usize,
                accepted: false,
            };
            let mut next_item = 0u32;
            for now in 0..400u64 {
                let blocked = rng.below(3) == 0;
                while !blocked && rng.below(4) != 0 {
                    let want = r.oldest(now).map(|l| r.lanes[l].0[0].1);
                    assert_eq!(u.has_ready(now), want.is_some(), "case {case} cycle {now}");
                    assert_eq!(u.ready(now).copied(), want, "case {case} cycle {now}");
                    let got = u.pop(now);
                    assert_eq!(got, want, "case {case} cycle {now}: pop");
                    let Some(l) = r.oldest(now) else { break };
                    r.lanes[l].0.remove(0);
                }
                // The flag is the cycle's, cleared whatever the state.
                let accepted = std::mem::take(&mut r.accepted);
                let want = if blocked && r.oldest(now).is_some() {
                    StageState::Backpressured
                } else if accepted || r.lanes.iter().any(|l| !l.0.is_empty()) {
                    StageState::Busy
                } else {
                    StageState::Starved
                };
                assert_eq!(
                    u.state(now, blocked, true),
                    want,
                    "case {case} cycle {now}: state"
                );
                while rng.below(3) != 0 {
                    let free = (0..r.lanes.len()).any(|l| r.free(l, now));
                    assert_eq!(
                        u.can_accept(now),
                        free,
                        "case {case} cycle {now}: can_accept"
                    );
                    if !free {
                        break;
                    }
                    let passes = 1 + rng.below(2);
                    u.accept(now, next_item, passes, 0);
                    r.accept(now, next_item, passes);
                    next_item += 1;
                }
                let inside: usize = r.lanes.iter().map(|l| l.0.len()).sum();
                assert_eq!(
                    (u.len(), u.is_empty()),
                    (inside, inside == 0),
                    "case {case}"
                );
            }
        }
    }
}
