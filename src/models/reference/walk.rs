//! Revelles et al. (2000) parametric octree traversal as an iterative loop with an explicit
//! stack, in an instance's local frame with per-axis extents (paper §3.2).
//!
//! Conventions (all tested against an independent Amanatides–Woo walk):
//! - The octree occupies the box [−e, e]; child labels are x = 4, y = 2, z = 1.
//! - Negative direction components, −0.0 included, are mirrored (§3.4): o ← min + max − o,
//!   d ← −d, and the label of a child in the mirrored walk is XOR-ed with
//!   a = 4·sx + 2·sy + sz to find the real child.
//! - A zero component (after mirroring: +0.0, or a component so small that its reciprocal
//!   would overflow the t-range) follows §3.3: the slab is (−∞, +∞) if the origin is inside
//!   the half-open interval [min, max) of the mirrored frame, otherwise the ray misses; a
//!   midpoint is −∞ if the origin lies at or above the node's centre plane, +∞ below it. It is
//!   never computed as (t0 + t1)/2, which would be (−∞ + ∞)/2 = NaN. On the other axes too,
//!   midpoints come from the centre plane's coordinate, t = (x_mid − o)/d, which keeps full
//!   precision for tiny |d| where the average of two huge t-values would not. So a ray lying in a grid
//!   plane belongs to the cell on the side its zero's sign points to (+0: upper, −0: lower).
//! - A child is entered only if its t-interval has positive length and ends after t = 0
//!   (max t0 < min t1, min t1 > 0): touching an edge or corner is not a hit, and nodes behind
//!   an origin inside the octree are never visited.
//! - The first solid leaf reached is the nearest (children are visited front to back); its
//!   t is max(entry, 0) and its entry face is the axis of the largest t0 (ties: x, then y).

use super::octree::{Child, Octree};
use glam::DVec3;
use rtl_model::svo::MAX_DEPTH;

/// Components below this magnitude are treated as zero (§3.3): |t| would exceed ~1e150 and
/// midpoint sums could overflow.
pub const ZERO_DIR: f64 = 1e-150;

/// The nearest solid leaf along a ray; `L` is the octree's leaf handle (for a memory image,
/// the attribute index).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkHit<L = u32> {
    /// Ray parameter of the hit (entry into the leaf, or 0 if the origin is inside it).
    pub t: f64,
    /// Integer coordinates of the leaf at `level`.
    pub voxel: [u32; 3],
    /// Level of the leaf (the asset's depth for every builder here).
    pub level: u8,
    /// The leaf (for a memory image: index into the attribute array).
    pub attr: L,
    /// Entry face as a local unit normal (opposes the ray on its entry axis).
    pub face_normal: DVec3,
}

/// Work done by walks, for reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkCounters {
    /// Loop iterations: one child examined each.
    pub steps: u64,
    /// Descriptor fetches (root and every descent).
    pub fetches: u64,
    /// Deepest stack a walk keeping every ancestor would reach (frames): the deepest node
    /// entered's level + 1.
    pub max_stack: u32,
}

#[derive(Clone, Copy, Default)]
struct Frame<N> {
    t0: [f64; 3],
    t1: [f64; 3],
    tm: [f64; 3],
    node: N,
    /// Next child label to examine, in the mirrored frame; 8 when done.
    next: u8,
    level: u8,
    /// Real (unmirrored) coordinates of this node at its level.
    coords: [u32; 3],
}

/// The larger of two t-values, as a plain compare-select (one `maxsd` on x86-64).
/// `f64::max` also returns the other operand when one is NaN, and that NaN handling costs a
/// compare and a blend per call (about 13 % of the walk's instructions, measured with
/// callgrind). No t-value the walk compares is NaN ([`walk_core`] rejects a ray whose root
/// t-values hold one, and every other t follows from the same finite planes, origin and 1/d),
/// so this is `f64::max`'s value, except that of two zeros of opposite sign it returns `b`
/// where `f64::max` may return either: no comparison tells them apart, and the hit's t is
/// `tmax(enter, 0.0)`, +0.0 for a zero.
#[inline(always)]
fn tmax(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The smaller of two t-values; see [`tmax`].
#[inline(always)]
fn tmin(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

#[inline]
fn max3(v: [f64; 3]) -> f64 {
    tmax(tmax(v[0], v[1]), v[2])
}

#[inline]
fn min3(v: [f64; 3]) -> f64 {
    tmin(tmin(v[0], v[1]), v[2])
}

/// `max3` of a node's or child's t0 in a walk of `ONLY` (see [`walk_loop`]): with
/// `ONLY` < 3 the other two axes are zero axes whose t0 is −∞ in every node the walk examines,
/// so the maximum is axis `ONLY`'s value, bit for bit (max(−∞, x) = x).
#[inline]
fn enter_of<const ONLY: usize>(t0: [f64; 3]) -> f64 {
    if ONLY < 3 {
        t0[ONLY]
    } else {
        max3(t0)
    }
}

/// `min3` of t1 in a walk of `ONLY`: the zero axes' t1 are +∞ (min(+∞, x) = x).
#[inline]
fn exit_of<const ONLY: usize>(t1: [f64; 3]) -> f64 {
    if ONLY < 3 {
        t1[ONLY]
    } else {
        min3(t1)
    }
}

/// Table 1/2 of Revelles: the first child crossed. The entry plane is that of the largest
/// t0; for each other axis, the upper half is entered if that axis' midpoint was crossed
/// before the entry, i.e. tm < max t0.
#[inline]
fn first_child<const ONLY: usize>(t0: [f64; 3], tm: [f64; 3]) -> u8 {
    let enter = enter_of::<ONLY>(t0);
    (u8::from(tm[0] < enter) << 2) | (u8::from(tm[1] < enter) << 1) | u8::from(tm[2] < enter)
}

/// Table 3 of Revelles: the next child after `c`, from the exit plane (the smallest t1);
/// 8 when the ray leaves the parent.
#[inline]
fn next_child<const ONLY: usize>(c: u8, t1: [f64; 3]) -> u8 {
    if ONLY < 3 {
        // Only axis ONLY moves: the other two t1 are +∞ and every t1 of ONLY is finite
        // (`walk_loop`'s guard), so the exit plane is always ONLY's.
        let bit = 4 >> ONLY;
        return if c & bit != 0 { 8 } else { c | bit };
    }
    // Both flags first, then a select the compiler can make without branches: the exit
    // axis is data-dependent and a branch on it mispredicts often.
    let x = t1[0] <= t1[1] && t1[0] <= t1[2];
    let y = !x && t1[1] <= t1[2];
    let bit = if x {
        4
    } else if y {
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

/// Per-ray constants of a walk in the mirrored frame.
struct RayFrame {
    /// Mirrored origin.
    o: [f64; 3],
    /// Which axes have a zero direction.
    zero: [bool; 3],
    /// Mirror mask a = 4·sx + 2·sy + sz.
    a: u8,
    lo: [f64; 3],
    size: [f64; 3],
    /// 1/d of the mirrored direction (unused on zero axes).
    inv: [f64; 3],
}

impl RayFrame {
    /// Midpoint t of axis k for the node at `level` with real coordinate `real_coord`: the
    /// parameter at which the ray crosses the node's centre plane. Computed from the plane's
    /// coordinate, t = (x_mid − o)·(1/d), not as Revelles' (t0 + t1)/2: the average of two
    /// large t-values loses the absolute precision a plane near the origin needs (with
    /// |d| ≈ 1e-20, t0 and t1 are ≈ 1e20 and a crossing at exactly t = 0 came out as 1024).
    /// Zero axes use the origin's side of the centre plane (Revelles Eq. 12).
    #[inline]
    fn mid(&self, k: usize, level: u8, real_coord: u32) -> f64 {
        let n = 1u32 << level;
        let mirrored = if self.a & (4 >> k) != 0 {
            n - 1 - real_coord
        } else {
            real_coord
        };
        // (2m + 1) is an exact integer and size / 2^(level+1) an exact power-of-two scaling,
        // so the plane coordinate is rounded once in the product and once in the sum.
        // size · 2^−(level+1) by a multiplication: the same correctly rounded value as the
        // division by 2^(level+1) (both scale by an exact power of two), without its latency.
        let scale = f64::from_bits((1022 - u64::from(level)) << 52);
        let centre = self.lo[k] + f64::from(2 * mirrored + 1) * (self.size[k] * scale);
        if self.zero[k] {
            if self.o[k] < centre {
                f64::INFINITY
            } else {
                f64::NEG_INFINITY
            }
        } else {
            (centre - self.o[k]) * self.inv[k]
        }
    }
}

/// Walks the octree `tree` occupying [−half, half] for the ray o + t·d (local frame).
/// Returns the nearest solid leaf with t ≥ 0, or `None`.
pub fn walk<T: Octree>(
    tree: &T,
    half: DVec3,
    o: DVec3,
    d: DVec3,
    cnt: &mut WalkCounters,
) -> Option<WalkHit<T::Leaf>> {
    walk_visiting(tree, half, o, d, cnt, &mut |_, _| {})
}

/// [`walk`], calling `visit(level, coords)` for every node it enters (internal nodes it
/// descends into and the leaf it stops at), in order. Used to compare walks node by node.
pub fn walk_visiting<T: Octree, V: FnMut(u8, [u32; 3])>(
    tree: &T,
    half: DVec3,
    o: DVec3,
    d: DVec3,
    cnt: &mut WalkCounters,
    visit: &mut V,
) -> Option<WalkHit<T::Leaf>> {
    walk_box_visiting(tree, -half, half, o, d, cnt, visit)
}

/// [`walk`] for an octree occupying the box [lo, hi] instead of [−half, half]: `sim render`
/// walks a bare model in its own voxel coordinates, where the box is
/// [base, base + 2^depth] and the ray needs no translation (so a ray lying in a voxel plane
/// stays exactly in it). With lo = −half and hi = half this is [`walk`], operation for
/// operation.
pub fn walk_box<T: Octree>(
    tree: &T,
    lo: DVec3,
    hi: DVec3,
    o: DVec3,
    d: DVec3,
    cnt: &mut WalkCounters,
) -> Option<WalkHit<T::Leaf>> {
    walk_box_visiting(tree, lo, hi, o, d, cnt, &mut |_, _| {})
}

/// [`walk_box`], calling `visit(level, coords)` for every node it enters.
pub fn walk_box_visiting<T: Octree, V: FnMut(u8, [u32; 3])>(
    tree: &T,
    lo: DVec3,
    hi: DVec3,
    o: DVec3,
    d: DVec3,
    cnt: &mut WalkCounters,
    visit: &mut V,
) -> Option<WalkHit<T::Leaf>> {
    let mut stack = [Frame::default(); STACK_FRAMES];
    walk_core::<T, V, false>(tree, lo, hi, [lo, hi], o, d, cnt, visit, &mut stack)
}

/// [`walk_box`] clipped to `solid` = [solid_lo, solid_hi], a box holding every leaf (for
/// `sim render`, the model's solid box): a ray that misses it is rejected before the walk,
/// and a node whose t-interval does not overlap the ray's t-interval in it is skipped without
/// a fetch. The hit is bit-identical to [`walk_box`]'s (t, voxel, level, leaf, face); only the
/// counters (fewer steps and fetches) differ.
///
/// Precondition (for exactness): every plane coordinate the walk computes is exact, i.e. `lo`,
/// `hi`, `solid_lo` and `solid_hi` are integers of magnitude below 2^52 with hi − lo the
/// same power of two on every axis (the octree's cells then have integer or half-integer
/// planes), and `solid` lies inside [lo, hi] on voxel planes. Why the result cannot change:
/// in the mirrored frame each t the walk compares is fl(fl(p − o)·(1/d)) for a plane p, and
/// that expression is non-decreasing in p (rounding is monotone and 1/d > 0). A leaf lies
/// inside `solid` and inside each of its ancestors, so per axis its t0 is ≥ the solid box's
/// and the ancestor's, its t1 ≤ both; hence if the walk enters a leaf (max t0 < min t1,
/// min t1 > 0), then max(max t0(node), t0_solid) ≤ max t0(leaf) < min t1(leaf) ≤
/// min(min t1(node), t1_solid) for the leaf and every ancestor, and the ray passes the solid
/// box test too. On a zero axis the walk enters only cells whose half-open interval holds the
/// origin (mid-plane rule, §3.3), so a ray whose origin is outside the solid box's half-open
/// interval enters no leaf. Skipping only subtrees that hold no enterable leaf keeps the order
/// of the rest, so the first leaf reached — the hit — is the same, with the same t0/t1.
#[allow(clippy::too_many_arguments)]
pub fn walk_box_clipped<T: Octree>(
    tree: &T,
    lo: DVec3,
    hi: DVec3,
    solid_lo: DVec3,
    solid_hi: DVec3,
    o: DVec3,
    d: DVec3,
    cnt: &mut WalkCounters,
) -> Option<WalkHit<T::Leaf>> {
    let mut stack = [Frame::default(); STACK_FRAMES];
    let solid = [solid_lo, solid_hi];
    walk_core::<T, _, true>(tree, lo, hi, solid, o, d, cnt, &mut |_, _| {}, &mut stack)
}

/// Frames a walk's stack needs: the root and one per level.
const STACK_FRAMES: usize = MAX_DEPTH as usize + 1;

/// A walk's stack, kept between walks: a walk writes only the frames it uses, so a caller
/// that traces many rays (`sim render`, one per worker row) does not clear
/// `STACK_FRAMES` frames (about 2 KB) for every ray.
pub struct WalkStack<N> {
    frames: Vec<Frame<N>>,
}

impl<N: Copy + Default> Default for WalkStack<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<N: Copy + Default> WalkStack<N> {
    /// A stack for octrees of any depth up to `MAX_DEPTH`.
    pub fn new() -> Self {
        Self {
            frames: vec![Frame::default(); STACK_FRAMES],
        }
    }

    /// [`walk_box_clipped`] on this stack.
    #[allow(clippy::too_many_arguments)]
    pub fn walk_box_clipped<T: Octree<Node = N>>(
        &mut self,
        tree: &T,
        lo: DVec3,
        hi: DVec3,
        solid_lo: DVec3,
        solid_hi: DVec3,
        o: DVec3,
        d: DVec3,
        cnt: &mut WalkCounters,
    ) -> Option<WalkHit<T::Leaf>> {
        walk_core::<T, _, true>(
            tree,
            lo,
            hi,
            [solid_lo, solid_hi],
            o,
            d,
            cnt,
            &mut |_, _| {},
            &mut self.frames,
        )
    }
}

/// The walk; with `CLIP`, clipped to `solid` as [`walk_box_clipped`] says (without, `solid`
/// is unused and the walk is the unclipped one, operation for operation).
#[allow(clippy::too_many_arguments)]
#[inline]
fn walk_core<T: Octree, V: FnMut(u8, [u32; 3]), const CLIP: bool>(
    tree: &T,
    lo: DVec3,
    hi: DVec3,
    solid: [DVec3; 2],
    o: DVec3,
    d: DVec3,
    cnt: &mut WalkCounters,
    visit: &mut V,
    stack: &mut [Frame<T::Node>],
) -> Option<WalkHit<T::Leaf>> {
    let lo = lo.to_array();
    let hi = hi.to_array();
    let (o, d) = (o.to_array(), d.to_array());
    let mut rf = RayFrame {
        o: [0.0; 3],
        zero: [false; 3],
        a: 0,
        lo,
        size: [0.0; 3],
        inv: [0.0; 3],
    };
    let mut t0 = [0.0; 3];
    let mut t1 = [0.0; 3];
    for k in 0..3 {
        rf.size[k] = hi[k] - lo[k];
        let (mut ok, mut dk) = (o[k], d[k]);
        if dk.is_sign_negative() {
            // General mirror about the box centre (not `size − p`, which assumes min = 0).
            ok = lo[k] + hi[k] - ok;
            dk = -dk;
            rf.a |= 4 >> k;
        }
        rf.o[k] = ok;
        if dk < ZERO_DIR {
            rf.zero[k] = true;
            if !(lo[k] <= ok && ok < hi[k]) {
                return None;
            }
            t0[k] = f64::NEG_INFINITY;
            t1[k] = f64::INFINITY;
        } else {
            let inv = 1.0 / dk;
            rf.inv[k] = inv;
            t0[k] = (lo[k] - ok) * inv;
            t1[k] = (hi[k] - ok) * inv;
        }
    }
    // A NaN t (a NaN component, or an infinite origin on an axis whose 1/d is 0) would make
    // `tmax`/`tmin` depend on operand order: such a ray hits nothing. Every later t of the
    // walk is (p − o)·(1/d) for a finite plane p with the same o and 1/d, or ±∞ on a zero
    // axis, so none is NaN once these six are not.
    if t0.iter().chain(&t1).any(|t| t.is_nan()) {
        return None;
    }
    if !(max3(t0) < min3(t1) && min3(t1) > 0.0) {
        return None;
    }
    // The ray's t-interval in the solid box, in the mirrored frame (see `walk_box_clipped`).
    let (mut ts0, mut ts1) = (f64::NEG_INFINITY, f64::INFINITY);
    if CLIP {
        let (s_lo, s_hi) = (solid[0].to_array(), solid[1].to_array());
        let mut s0 = [0.0; 3];
        let mut s1 = [0.0; 3];
        for k in 0..3 {
            // Exact under the precondition: integers below 2^52.
            let (a, b) = if rf.a & (4 >> k) != 0 {
                (lo[k] + hi[k] - s_hi[k], lo[k] + hi[k] - s_lo[k])
            } else {
                (s_lo[k], s_hi[k])
            };
            if rf.zero[k] {
                if !(a <= rf.o[k] && rf.o[k] < b) {
                    return None;
                }
                s0[k] = f64::NEG_INFINITY;
                s1[k] = f64::INFINITY;
            } else {
                s0[k] = (a - rf.o[k]) * rf.inv[k];
                s1[k] = (b - rf.o[k]) * rf.inv[k];
            }
        }
        (ts0, ts1) = (max3(s0), min3(s1));
        if !(ts0 < ts1 && ts1 > 0.0) {
            return None;
        }
    }
    cnt.fetches += 1;
    cnt.max_stack = cnt.max_stack.max(1);
    let root = Frame {
        t0,
        t1,
        node: tree.root(),
        ..Frame::default()
    };
    // A ray along a grid axis (an orthographic camera looking along x, y or z, or a pinhole's
    // centre ray) moves on one axis only: the loop specialised for it drops the two zero axes'
    // child selection and interval work, which are constants there. Only when that axis' t0
    // and t1 at the root are finite (then so is every t of it below, by monotonicity), which
    // is what makes the specialised loop take the same steps to the same hit.
    let zero = u8::from(rf.zero[0]) << 2 | u8::from(rf.zero[1]) << 1 | u8::from(rf.zero[2]);
    let finite = |k: usize| t0[k].is_finite() && t1[k].is_finite();
    let clip = (ts0, ts1);
    match zero {
        0b011 if finite(0) => walk_loop::<T, V, CLIP, 0>(tree, &rf, root, clip, cnt, visit, stack),
        0b101 if finite(1) => walk_loop::<T, V, CLIP, 1>(tree, &rf, root, clip, cnt, visit, stack),
        0b110 if finite(2) => walk_loop::<T, V, CLIP, 2>(tree, &rf, root, clip, cnt, visit, stack),
        _ => walk_loop::<T, V, CLIP, 3>(tree, &rf, root, clip, cnt, visit, stack),
    }
}

/// The walk's loop from the root frame `root` (its t0 and t1 set), clipped to the ray's
/// t-interval `clip` in the solid box with `CLIP`. `ONLY` < 3: the ray moves on axis `ONLY`
/// alone (the other two are zero axes) and its t-values on it are finite; 3: any ray.
///
/// Why `ONLY` < 3 takes the same steps to the same hit as 3: on a zero axis every node the
/// walk examines has t0 = −∞ and t1 = +∞ there, and its midpoint is ±∞ by the origin's side
/// (§3.3). `first_child` then picks the origin's side on the zero axes, and `next_child` never
/// leaves through a zero axis (its t1 = +∞ exceeds the finite t1 of `ONLY`), so no child on
/// the other side is ever examined; the children examined have t0 = −∞, t1 = +∞ on the zero
/// axes, so max t0 and min t1 are `ONLY`'s values and the entry face is `ONLY`'s.
#[allow(clippy::too_many_arguments)]
#[inline]
fn walk_loop<T: Octree, V: FnMut(u8, [u32; 3]), const CLIP: bool, const ONLY: usize>(
    tree: &T,
    rf: &RayFrame,
    root: Frame<T::Node>,
    (ts0, ts1): (f64, f64),
    cnt: &mut WalkCounters,
    visit: &mut V,
    stack: &mut [Frame<T::Node>],
) -> Option<WalkHit<T::Leaf>> {
    let mut f = root;
    for k in 0..3 {
        f.tm[k] = rf.mid(k, 0, 0);
    }
    f.next = first_child::<ONLY>(f.t0, f.tm);
    // The current frame lives in a local (registers), not in `stack`: the next child label is
    // carried from one step to the next, and through memory that chain would pay a store and
    // a reload every step. `stack[..sp]` holds the ancestors with children left to examine.
    let mut top = f;
    let mut sp = 0usize;
    loop {
        let c = top.next;
        if c >= 8 {
            if sp == 0 {
                return None;
            }
            sp -= 1;
            top = stack[sp];
            continue;
        }
        cnt.steps += 1;
        let mut ct0 = [0.0; 3];
        let mut ct1 = [0.0; 3];
        for k in 0..3 {
            if ONLY < 3 && k != ONLY {
                // A zero axis: constants in every child examined (see above).
                ct0[k] = f64::NEG_INFINITY;
                ct1[k] = f64::INFINITY;
            } else if c & (4 >> k) != 0 {
                ct0[k] = top.tm[k];
                ct1[k] = top.t1[k];
            } else {
                ct0[k] = top.t0[k];
                ct1[k] = top.tm[k];
            }
        }
        top.next = next_child::<ONLY>(c, ct1);
        let real = c ^ rf.a;
        // An empty child is skipped whatever its interval: test the cheap bit first.
        if !tree.may_have_child(&top.node, real) {
            continue;
        }
        let enter = enter_of::<ONLY>(ct0);
        let exit = exit_of::<ONLY>(ct1);
        if !(enter < exit && exit > 0.0) {
            continue;
        }
        // ts1 > 0 here, so min(exit, ts1) > 0 already holds; no t is NaN (finite planes and
        // 1/d, or ±∞ on zero axes), so ≥ is the negation of <.
        if CLIP && tmax(enter, ts0) >= tmin(exit, ts1) {
            continue;
        }
        let child = tree.child(&top.node, real);
        if matches!(child, Child::Empty) {
            continue;
        }
        let level = top.level + 1;
        let coords = [
            (top.coords[0] << 1) | u32::from((real >> 2) & 1),
            (top.coords[1] << 1) | u32::from((real >> 1) & 1),
            (top.coords[2] << 1) | u32::from(real & 1),
        ];
        visit(level, coords);
        let node = match child {
            Child::Empty => continue,
            Child::Node(n) => n,
            Child::Leaf(leaf) => {
                let axis = if ONLY < 3 {
                    ONLY
                } else if ct0[0] >= ct0[1] && ct0[0] >= ct0[2] {
                    0
                } else if ct0[1] >= ct0[2] {
                    1
                } else {
                    2
                };
                let mut n = [0.0; 3];
                n[axis] = if rf.a & (4 >> axis) != 0 { 1.0 } else { -1.0 };
                return Some(WalkHit {
                    t: tmax(enter, 0.0),
                    voxel: coords,
                    level,
                    attr: leaf,
                    face_normal: DVec3::from_array(n),
                });
            }
        };
        cnt.fetches += 1;
        let mut child = Frame {
            t0: ct0,
            t1: ct1,
            tm: [0.0; 3],
            node,
            next: 0,
            level,
            coords,
        };
        child.tm = std::array::from_fn(|k| rf.mid(k, level, coords[k]));
        child.next = first_child::<ONLY>(child.t0, child.tm);
        // A parent with no child left to examine is not kept: the walk would only pop it and
        // move on to its parent. (The stack then holds fewer frames than the level; the
        // counter still reports the depth, root and every ancestor, as before.)
        if top.next < 8 {
            stack[sp] = top;
            sp += 1;
        }
        top = child;
        cnt.max_stack = cnt.max_stack.max(u32::from(level) + 1);
    }
}
