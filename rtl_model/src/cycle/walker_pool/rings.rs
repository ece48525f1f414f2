//! Each walker's issue queue in one fixed ring: its ready contexts (round robin in the order
//! they became ready) followed by the contexts whose slot issued and whose run goes on, ready
//! again `step_latency` cycles later.
//!
//! Pipeline position: inside the walker pool (`walker_pool.rs`), between its issue phase and its
//! wake-up. Why one ring instead of a ready queue fed by the pool's wake-up wheel: a context
//! whose issue run goes on touches nothing but its own walker's ready queue when its step
//! latency ends (no read, no finish, nothing another walker or the node memory sees), so
//! it need not be woken in the pool-wide order. It goes straight back to the ring's tail
//! with the key of the cycle it is ready in, and the ring stays sorted by key:
//!
//! `key = 4·cycle + phase`, the phase ranking what becomes ready in one cycle as the wake-up
//! does (module doc of `walker_pool.rs`): 0 a walk dispatched in the cycle before when the step
//! latency is 1 (it was put on the wheel before that cycle's slots issued), 1 a step that
//! ends, 2 everything else that the wake-up makes ready (in the order it does: a new entry
//! goes behind every entry of its key or lower). A context is ready in cycle `c` when its
//! key is below `4·(c + 1)`; the walker issues the ring's head. Only the steps still under
//! way (at most `step_latency / step_cycles` of them, at the tail) are ever passed by an
//! insert, so an insert moves a few entries at most.
//!
//! The ring holds at most R entries (a context is in it once), so all walkers' rings live in
//! one flat array of W·R' slots (R' = R rounded up to a power of two: an index is a shift, an
//! or and a mask), with no growth and no per-push allocation check.

/// The phase of a walk dispatched in the cycle before, at a step latency of 1 (module doc).
pub(super) const PHASE_DISPATCH_LAT1: u64 = 0;
/// The phase of a step that ends.
pub(super) const PHASE_STEP: u64 = 1;
/// The phase of everything else the wake-up makes ready.
pub(super) const PHASE_WAKE: u64 = 2;

/// The key of `phase` in cycle `cycle` (module doc).
#[inline]
pub(super) fn key(cycle: u64, phase: u64) -> u64 {
    4 * cycle + phase
}

/// A walker's ring's head and length (the entries live in [`Rings`]), and its head's key.
#[derive(Clone, Copy, Debug)]
pub(super) struct RingPos {
    head: u32,
    pub(super) len: u32,
    /// The head entry's key; `u64::MAX` when empty.
    pub(super) front: u64,
}

impl Default for RingPos {
    fn default() -> Self {
        Self {
            head: 0,
            len: 0,
            front: u64::MAX,
        }
    }
}

/// Every walker's ring (see the module doc).
#[derive(Clone, Debug)]
pub(super) struct Rings {
    /// log2 of R' (each walker's share of the array).
    shift: u32,
    /// R' − 1.
    mask: u32,
    /// `ring[w·R' + i]`: walker `w`'s ring, (key, context).
    ring: Vec<(u64, u32)>,
}

impl Rings {
    pub(super) fn new(walkers: usize, r: u32) -> Self {
        let cap = r.max(1).next_power_of_two();
        Self {
            shift: cap.trailing_zeros(),
            mask: cap - 1,
            ring: vec![(0, 0); walkers * cap as usize],
        }
    }

    /// Index of ring slot `head + k` of walker `w`.
    #[inline]
    fn at(&self, w: usize, head: u32, k: u32) -> usize {
        (w << self.shift) | ((head + k) & self.mask) as usize
    }

    /// Puts `ctx` with `key` into walker `w`'s ring behind every entry whose key is not
    /// above it.
    #[inline]
    pub(super) fn insert(&mut self, w: usize, p: &mut RingPos, key: u64, ctx: u32) {
        debug_assert!(p.len <= self.mask, "ring of walker {w} full");
        let mut k = p.len;
        while k > 0 {
            let prev = self.ring[self.at(w, p.head, k - 1)];
            if prev.0 <= key {
                break;
            }
            let i = self.at(w, p.head, k);
            self.ring[i] = prev;
            k -= 1;
        }
        let i = self.at(w, p.head, k);
        self.ring[i] = (key, ctx);
        p.len += 1;
        if k == 0 {
            p.front = key;
        }
    }

    /// Issues the head of walker `w`'s ring (the caller has looked at [`RingPos::front`]):
    /// takes it, and if `goes_on(ctx)` puts it back at the tail with `key` (a step under
    /// way: no entry's key is above it). Returns the context and whether it went back. The
    /// issue phase's one ring operation per slot, so written against the array directly.
    #[inline(always)]
    pub(super) fn issue_head(
        &mut self,
        w: usize,
        p: &mut RingPos,
        key: u64,
        goes_on: impl FnOnce(u32) -> bool,
    ) -> (u32, bool) {
        let mask = self.mask;
        let ring = &mut self.ring[w << self.shift..(w + 1) << self.shift];
        let head = p.head as usize;
        let ctx = ring[head].1;
        let back = goes_on(ctx);
        let next = (p.head + 1) & mask;
        if back {
            // Head to tail: the tail slot is `head + len`, the head moves on by one.
            let tail = ((p.head + p.len) & mask) as usize;
            ring[tail] = (key, ctx);
        } else {
            p.len -= 1;
        }
        p.head = next;
        p.front = if p.len == 0 {
            u64::MAX
        } else {
            ring[next as usize].0
        };
        (ctx, back)
    }

    /// The keys in walker `w`'s ring, head first.
    pub(super) fn keys(&self, w: usize, p: &RingPos) -> impl Iterator<Item = u64> + '_ {
        let p = *p;
        (0..p.len).map(move |k| self.ring[self.at(w, p.head, k)].0)
    }
}
