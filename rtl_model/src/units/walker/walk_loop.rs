//! The octree walker's loop (Revelles et al. 2000 on integer codes): the explicit stack of
//! node frames, the per-step child selection (tables 1–3) and the descent.
//!
//! Pipeline position: inside the walker unit ([`super::walk_fixed_observed`] sets up the
//! root frame from the walker-root unit's slab times and runs this loop), once per
//! (ray, candidate). Every step is one issue slot of the hardware walker; the observer sees
//! the steps, pops, reads and nodes entered in the hardware's order.
//!
//! Written for the functional model's speed (docs/cycle-model.md §2.7): a frame keeps its
//! descriptor unpacked (valid and leaf masks, the pointer's word address), an empty child is
//! passed over before its entry times are formed (neither an empty child nor an empty
//! interval has any effect), midpoints of walks without a zero axis skip the zero-axis rule,
//! and the counters are added once per walk. Same outcome, counters and observer events as
//! the loop it replaced (`rtl_model/tests/walker_loop_oracle.rs` keeps that loop and compares).

use super::{WalkObserver, WalkOutcome, WalkerConfig, WalkerHit, WalkerPos, WalkerStats, WalkerT};
use crate::svo::{ChildDescriptor, FetchKind};

/// One stack frame: a node's slab times (entry, midpoint, exit per axis), where it lives in
/// memory and its descriptor unpacked, the next child to examine, and its level and
/// coordinates.
#[derive(Clone, Copy, Default)]
pub(super) struct Frame {
    t0: [WalkerT; 3],
    tm: [WalkerT; 3],
    t1: [WalkerT; 3],
    /// The node's word address.
    addr: u32,
    /// addr + the descriptor's pointer: the children's group (near) or the far word (far).
    ptr_addr: u32,
    /// The descriptor's valid and leaf masks and far flag.
    valid: u8,
    leaf: u8,
    far: bool,
    /// Next child label (mirrored); 8 when every child is done.
    next: u8,
    level: u8,
    coords: [u32; 3],
}

impl Frame {
    /// The frame of the node at `addr` with descriptor word `desc` and slab times `t0`, `t1`,
    /// at `level` with real coordinates `coords`: its midpoints and first child.
    #[inline(always)]
    pub(super) fn new(
        ax: &Axes,
        addr: u32,
        desc: u32,
        t0: [WalkerT; 3],
        t1: [WalkerT; 3],
        level: u8,
        coords: [u32; 3],
    ) -> Self {
        let d = ChildDescriptor::unpack(desc);
        let tm = if ax.any_zero {
            std::array::from_fn(|k| ax.mid(k, t0[k], t1[k], level, coords[k]))
        } else {
            std::array::from_fn(|k| t0[k].midpoint(t1[k]))
        };
        Self {
            t0,
            tm,
            t1,
            addr,
            ptr_addr: addr.wrapping_add(u32::from(d.ptr)),
            valid: d.valid,
            leaf: d.leaf,
            far: d.far,
            next: first_child(t0, tm),
            level,
            coords,
        }
    }
}

#[inline(always)]
fn max3(v: [WalkerT; 3]) -> WalkerT {
    v[0].max(v[1]).max(v[2])
}

#[inline(always)]
fn min3(v: [WalkerT; 3]) -> WalkerT {
    v[0].min(v[1]).min(v[2])
}

/// The walk's per-axis constants: the mirrored origin, the zero flags (and whether any is
/// set), the mirror mask `a` (bit 2 − k set when axis k is mirrored) and the box's half
/// extents.
pub(super) struct Axes {
    pub(super) o: [WalkerPos; 3],
    pub(super) zero: [bool; 3],
    pub(super) any_zero: bool,
    pub(super) a: u8,
    pub(super) half: [WalkerPos; 3],
}

impl Axes {
    /// Midpoint of axis k for the node at `level` with real coordinate `c`.
    #[inline]
    fn mid(&self, k: usize, t0: WalkerT, t1: WalkerT, level: u8, c: u32) -> WalkerT {
        if !self.zero[k] {
            return t0.midpoint(t1);
        }
        let n = 1u64 << level;
        let m = if self.a & (4 >> k) != 0 {
            n - 1 - u64::from(c)
        } else {
            u64::from(c)
        };
        // Centre plane −e + (2m + 1)·2e / 2^(level+1) (a `pos` code), exact in i128 before
        // the floor shift.
        let e = i128::from(self.half[k].raw);
        let centre = -e + ((i128::from(2 * m + 1) * (2 * e)) >> (level + 1));
        if i128::from(self.o[k].raw) < centre {
            WalkerT::POS_INF
        } else {
            WalkerT::NEG_INF
        }
    }
}

/// The walker's loop over `stack`, whose only frame is the root's. `nodes` is the image's
/// node memory. The root's fetch and stack frame are counted by the caller.
#[inline]
pub(super) fn walk_loop<O: WalkObserver>(
    nodes: &[u32],
    ax: &Axes,
    cfg: &WalkerConfig,
    st: &mut WalkerStats,
    obs: &mut O,
    stack: &mut Vec<Frame>,
) -> WalkOutcome {
    let mut steps = 0u32;
    let mut fetches = 0u64;
    let mut deepest = stack.len();
    let out = loop {
        let Some(top) = stack.last_mut() else {
            break WalkOutcome::Miss;
        };
        let c = top.next;
        if c >= 8 {
            stack.pop();
            obs.pop();
            continue;
        }
        steps += 1;
        obs.step();
        if steps > cfg.max_steps {
            st.step_limit_hits += 1;
            break WalkOutcome::StepLimit;
        }
        // Child c's exit times decide the next child whatever it holds.
        let ct1: [WalkerT; 3] = std::array::from_fn(|k| {
            if c & (4 >> k) != 0 {
                top.t1[k]
            } else {
                top.tm[k]
            }
        });
        top.next = next_child(c, ct1);
        let real = c ^ ax.a;
        let bit = 1u8 << real;
        if top.valid & bit == 0 {
            continue; // no child: nothing to read or enter
        }
        let ct0: [WalkerT; 3] = std::array::from_fn(|k| {
            if c & (4 >> k) != 0 {
                top.tm[k]
            } else {
                top.t0[k]
            }
        });
        let enter = max3(ct0);
        let exit = min3(ct1);
        if !(enter < exit && exit > WalkerT::ZERO) {
            continue;
        }
        let level = top.level + 1;
        let coords = [
            (top.coords[0] << 1) | u32::from((real >> 2) & 1),
            (top.coords[1] << 1) | u32::from((real >> 1) & 1),
            (top.coords[2] << 1) | u32::from(real & 1),
        ];
        // The reads this child costs (docs/svo-format.md §12): the far word when the parent
        // uses the far escape, then the child's slot (descriptor or leaf slot).
        let base = if top.far {
            obs.read(FetchKind::Far, top.ptr_addr);
            top.addr + nodes[top.ptr_addr as usize]
        } else {
            top.ptr_addr
        };
        let slot = base + u32::from(POPCOUNT[usize::from(top.valid & (bit - 1))]);
        obs.read(FetchKind::Node, slot);
        obs.enter(level, coords);
        if top.leaf & bit != 0 {
            let attr = nodes[slot as usize];
            let entry_axis = if ct0[0] >= ct0[1] && ct0[0] >= ct0[2] {
                0
            } else if ct0[1] >= ct0[2] {
                1
            } else {
                2
            };
            obs.read(FetchKind::Attr, attr);
            break WalkOutcome::Hit(WalkerHit {
                t: enter.max(WalkerT::ZERO),
                voxel: coords,
                level,
                attr,
                entry_axis,
            });
        }
        fetches += 1;
        let child = Frame::new(ax, slot, nodes[slot as usize], ct0, ct1, level, coords);
        stack.push(child);
        deepest = deepest.max(stack.len());
    };
    st.steps += u64::from(steps);
    st.fetches += fetches;
    st.max_stack = st.max_stack.max(deepest as u32);
    out
}

/// Set bits of every byte: the child's slot is the number of valid children below its
/// label (a table, since the build targets x86-64 without the `popcnt` instruction).
const POPCOUNT: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = (i as u8).count_ones() as u8;
        i += 1;
    }
    t
};

/// Revelles tables 1 and 2: the first child, from the entry plane (largest t0) and the
/// midpoints crossed before it.
#[inline(always)]
fn first_child(t0: [WalkerT; 3], tm: [WalkerT; 3]) -> u8 {
    let enter = max3(t0);
    (u8::from(tm[0] < enter) << 2) | (u8::from(tm[1] < enter) << 1) | u8::from(tm[2] < enter)
}

/// Revelles table 3: the next child from the exit plane (smallest t1; ties x, y, z); 8 ends.
#[inline(always)]
fn next_child(c: u8, t1: [WalkerT; 3]) -> u8 {
    let bit = if t1[0] <= t1[1] && t1[0] <= t1[2] {
        4
    } else if t1[1] <= t1[2] {
        2
    } else {
        1
    };
    if c & bit != 0 {
        8
    } else {
        c | bit
    }
}
