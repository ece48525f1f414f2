//! The on-chip node store's read ports: `banks` word-interleaved banks of `ports_per_bank`
//! ports each, served first come first served, and the count of cycles in which a read waited
//! for one.
//!
//! Pipeline position: inside [`super::NodeMemory`]; step 2 of a simulated cycle gives every
//! on-chip read of the cycle its bank's next free port. A bank serves at a fixed rate, so a
//! read's service cycle is known the moment it joins the bank's queue: it needs no queue of
//! its own, only the bank's next free port.
//!
//! With `combine` the bank's queue is a CAM on word addresses: a read of a word that is
//! already queued at the bank (its read scheduled in this cycle or a later one) joins that
//! entry and is served by the same port read, the crossbar broadcasting the word to every
//! requester. Every walk reads its asset's root word and the first levels below it, so
//! without combining those few words' banks serve them `ports_per_bank` at a time.

use super::config::OnChipConfig;

/// The next free read port of an on-chip bank: `used` of its ports are taken in `cycle`.
#[derive(Clone, Copy, Debug, Default)]
struct BankSlot {
    cycle: u64,
    used: u32,
}

/// The banks' ports and the port-conflict cycles they cause.
#[derive(Clone, Debug)]
pub(super) struct Banks {
    /// Per bank, its next free port.
    slots: Vec<BankSlot>,
    /// Banks (word address mod banks picks one).
    count: u32,
    /// Reads a bank serves per cycle.
    ports: u32,
    /// The last cycle, plus one, in which some bank still has a request waiting for a port
    /// (among the requests arbitrated so far).
    busy_until: u64,
    /// Cycles before this one are counted in `port_conflict_cycles`.
    conflicts_counted: u64,
    /// Whether same-word reads queued at a bank share one port read.
    combine: bool,
    /// Per bank (with `combine`), the reads scheduled and not yet before the current cycle:
    /// (cycle served, word), in service order.
    queued: Vec<Scheduled>,
}

/// One bank's scheduled reads (cycle served, word), in service order, in one contiguous
/// buffer: the entries from `head` on are live, those before it were served in an earlier
/// cycle. Combining searches the live entries of every on-chip read's bank, so they are kept
/// as one slice (no ring-buffer wrap to handle); the dead prefix is dropped when the queue
/// empties or grows past half the buffer.
#[derive(Clone, Debug, Default)]
struct Scheduled {
    entries: Vec<(u64, u32)>,
    head: usize,
}

impl Scheduled {
    /// Drops the reads served before cycle `k` (they are at the front: service cycles only
    /// grow along a bank's queue).
    #[inline]
    fn retire_before(&mut self, k: u64) {
        let live = &self.entries[self.head..];
        let served = live.iter().take_while(|&&(s, _)| s < k).count();
        self.head += served;
        if self.head == self.entries.len() {
            self.entries.clear();
            self.head = 0;
        } else if self.head >= 64 && 2 * self.head >= self.entries.len() {
            self.entries.drain(..self.head);
            self.head = 0;
        }
    }

    /// The service cycle of the live read of `word`, if one is scheduled.
    #[inline]
    fn find(&self, word: u32) -> Option<u64> {
        self.entries[self.head..]
            .iter()
            .find(|&&(_, a)| a == word)
            .map(|&(s, _)| s)
    }
}

impl Banks {
    /// Idle banks of `cfg` at cycle 0.
    pub(super) fn new(cfg: &OnChipConfig) -> Self {
        Self {
            slots: vec![BankSlot::default(); cfg.banks as usize],
            count: cfg.banks,
            ports: cfg.ports_per_bank.max(1),
            busy_until: 0,
            conflicts_counted: 0,
            combine: cfg.combine,
            queued: vec![Scheduled::default(); if cfg.combine { cfg.banks as usize } else { 0 }],
        }
    }

    /// Gives a read of word `addr` arriving in cycle `k` its bank's next free port, in
    /// arrival order, or (with `combine`) the port read of the same word already queued:
    /// returns (bank, cycle served, combined). It waits in cycles `k .. served − 1`.
    #[inline]
    pub(super) fn serve(&mut self, addr: u32, k: u64) -> (u32, u64, bool) {
        let bank = addr % self.count;
        if self.combine {
            let q = &mut self.queued[bank as usize];
            q.retire_before(k);
            if let Some(s) = q.find(addr) {
                return (bank, s, true);
            }
        }
        let slot = &mut self.slots[bank as usize];
        if slot.cycle < k {
            *slot = BankSlot { cycle: k, used: 0 };
        }
        let served = slot.cycle;
        slot.used += 1;
        if slot.used == self.ports {
            *slot = BankSlot {
                cycle: served + 1,
                used: 0,
            };
        }
        self.busy_until = self.busy_until.max(served);
        if self.combine {
            self.queued[bank as usize].entries.push((served, addr));
        }
        (bank, served, false)
    }

    /// The last cycle in which a bank serves a read that waited (0 when none has).
    #[inline]
    pub(super) fn busy_until(&self) -> u64 {
        self.busy_until
    }

    /// Cycles from the last counted one to `end` in which a bank had a request waiting; valid
    /// when no request arrives in between (every bank interval then starts before them).
    #[inline]
    pub(super) fn conflicts_before(&self, end: u64) -> u64 {
        self.busy_until
            .min(end)
            .saturating_sub(self.conflicts_counted)
    }

    /// [`conflicts_before`](Self::conflicts_before) `k`, which are then counted: cycles
    /// skipped since the last step had no arrivals and no cache work, so they were conflict
    /// cycles exactly when a bank still had a request waiting.
    #[inline]
    pub(super) fn take_conflicts_before(&mut self, k: u64) -> u64 {
        let n = self.conflicts_before(k);
        self.conflicts_counted = k;
        n
    }

    /// Marks every cycle before `end` as counted (after a step, or at a new statistics
    /// window).
    #[inline]
    pub(super) fn counted_to(&mut self, end: u64) {
        self.conflicts_counted = self.conflicts_counted.max(end);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::VecDeque;

    /// A bank's scheduled reads against a ring buffer popped from the front (the arrangement
    /// before issue 30), on a seeded random schedule long enough to keep live entries behind
    /// more than 64 dead ones (the compaction path): the same service cycle found for every
    /// word asked.
    #[test]
    fn scheduled_matches_a_ring_buffer() {
        let seed = 0x0301_u64;
        println!("seed {seed}");
        let mut rng = crate::cycle::test_rng::TestRng::new(seed);
        let mut next = move || rng.next_bits();
        let mut q = Scheduled::default();
        let mut oracle: VecDeque<(u64, u32)> = VecDeque::new();
        let (mut k, mut served) = (0u64, 0u64);
        let mut compacted = false;
        for step in 0..50_000u32 {
            // Bursts that schedule far ahead (a long backlog), then cycles that drain it.
            if next() % 4 == 0 {
                k += 1 + next() % 3;
            }
            let before = q.entries.len();
            q.retire_before(k);
            // Dead entries dropped while live ones stay: the compaction path.
            compacted |= q.head == 0 && !q.entries.is_empty() && q.entries.len() < before;
            while oracle.front().is_some_and(|&(s, _)| s < k) {
                oracle.pop_front();
            }
            let word = (next() % 24) as u32;
            let want = oracle.iter().find(|&&(_, a)| a == word).map(|&(s, _)| s);
            assert_eq!(q.find(word), want, "step {step}, cycle {k}, word {word}");
            if want.is_none() {
                served = served.max(k) + next() % 2;
                q.entries.push((served, word));
                oracle.push_back((served, word));
            }
            assert_eq!(q.entries.len() - q.head, oracle.len(), "step {step}");
        }
        assert!(
            compacted,
            "the schedule never kept live entries across a compaction"
        );
    }
}
