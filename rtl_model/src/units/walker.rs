//! Octree walker in fixed point: Revelles et al. (2000) as the hardware computes it.
//!
//! Pipeline position: after the transform and reciprocal units, once per (ray, candidate);
//! it reads the SVO memory image (one descriptor fetch per descent) and returns the nearest
//! solid leaf. The f64 reference (`svo_sim::models::reference::walk`) is its oracle.
//!
//! Arithmetic:
//! - Mirroring (§3.4): an axis whose direction is negative (the sign bit from the transform,
//!   so −0 counts) negates the origin (the box is centred on 0: min + max − o = −o, exact).
//! - Root slabs: t0 = (−e − o)·(1/|d|), t1 = (e − o)·(1/|d|): an exact subtraction and an
//!   exact product, rounded once into the `t` format. Zero axes (flagged by the reciprocal
//!   unit, |d| below what 1/d can hold) get t0 = −∞, t1 = +∞ if −e ≤ o < e, else the ray
//!   misses (§3.3). ±∞ are the sentinels [`WalkerT::NEG_INF`] / [`WalkerT::POS_INF`]
//!   (`i64::MIN` / `i64::MAX`), outside every t format, so no computed t can be mistaken for
//!   them.
//! - Midpoints: tm = ⌊(t0 + t1)/2⌋ — one adder and a shift per axis and level. Fixed point
//!   keeps absolute precision, so the f64 reference's problem with huge t-values does not
//!   arise; the floor loses at most half an LSB per level. Zero axes take ±∞ from the origin's
//!   side of the node's centre plane, computed from the node's integer coordinates (§3.3,
//!   Eq. 12).
//! - Children, entry and exit: exactly the reference's rules (tables 1–3, positive-length
//!   intervals that end after t = 0), on integer codes.
//! - A step limit stops a walk that runs too long (it cannot happen with a well-formed image,
//!   but the hardware needs the guard); it is reported, never silent.
//!
//! Values carry their role: [`WalkerPos`] (a code of `pos`), [`WalkerInv`] (of `inv`) and
//! [`WalkerT`] (of `t`). The formats are run-time configurable ([`WalkerConfig`]), so the
//! types name the role and the configuration holds the format; the one change of format in
//! the walker, position × reciprocal into t, is [`WalkerConfig::slab_t`].
//!
//! This file holds the walk's set-up (mirroring, root slabs, the root frame); the loop over
//! the stack is `walker/walk_loop.rs`.

use crate::fixed::{quantize, to_f64, Format, Overflows, SignalId};
use crate::svo::FetchKind;
use crate::svo::{SvoImage, MAX_DEPTH};
use crate::units::reciprocal::Reciprocal;
use serde::{Deserialize, Serialize};
use walk_loop::{walk_loop, Axes, Frame};

mod walk_loop;

/// A t-value of the walker (metres along the unit direction): a raw code of
/// [`WalkerConfig::t`] (default sQ31.31), or one of the ±∞ sentinels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct WalkerT {
    /// The code.
    pub raw: i64,
}

impl WalkerT {
    /// −∞: below every code of any t format (at most 62 bits, [`WalkerConfig::validate`]).
    pub const NEG_INF: Self = Self { raw: i64::MIN };
    /// +∞ (see [`WalkerT::NEG_INF`]).
    pub const POS_INF: Self = Self { raw: i64::MAX };
    /// t = 0.
    pub const ZERO: Self = Self { raw: 0 };

    /// ⌊(a + b)/2⌋ of two t codes (a zero axis never reaches here): the halves plus the
    /// carry of the two low bits, so no wider adder is needed.
    #[inline]
    fn midpoint(self, other: Self) -> Self {
        let (a, b) = (self.raw, other.raw);
        Self {
            raw: (a >> 1) + (b >> 1) + (a & b & 1),
        }
    }

    /// Metres, for `cfg`'s t format.
    pub fn to_f64(self, cfg: &WalkerConfig) -> f64 {
        to_f64(self.raw, cfg.t)
    }

    /// Whether this t (a code of `t_fmt`) is at most `other`, a code of `other_fmt` (the
    /// sorter's entry key, say): both are aligned exactly, by left shifts, to the larger
    /// fraction count, as a comparator on the two buses would after wiring them to a common
    /// binary point.
    #[inline]
    pub fn at_most(self, t_fmt: Format, other: i64, other_fmt: Format) -> bool {
        let (t, o) = (t_fmt.frac, other_fmt.frac);
        let f = t.max(o);
        (i128::from(self.raw) << (f - t)) <= (i128::from(other) << (f - o))
    }
}

/// A local position or a box half extent: a raw code of [`WalkerConfig::pos`] (default
/// sQ8.32, the transform's local position format).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct WalkerPos {
    /// The code.
    pub raw: i64,
}

impl WalkerPos {
    /// Three codes as positions.
    pub fn of(raw: [i64; 3]) -> [Self; 3] {
        raw.map(|raw| Self { raw })
    }
}

/// A reciprocal magnitude 1/|d|: a raw code of [`WalkerConfig::inv`] (default sQ22.30, the
/// reciprocal unit's output), non-negative.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct WalkerInv {
    /// The code.
    pub raw: i64,
}

/// Formats and limits of the walker.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WalkerConfig {
    /// Local positions in (origin, box half extents), metres.
    pub pos: Format,
    /// Reciprocals 1/|d| in (the reciprocal unit's output).
    pub inv: Format,
    /// Ray parameter t (metres along the unit direction).
    pub t: Format,
    /// Walker loop iterations allowed per walk before it is stopped and reported.
    pub max_steps: u32,
}

impl WalkerConfig {
    /// Checks the formats: valid, t narrower than 64 bits (the ±∞ sentinels must lie outside
    /// it), and the root product within the 127-bit accumulator.
    pub fn validate(&self) -> Result<(), String> {
        for (name, f) in [("pos", self.pos), ("inv", self.inv), ("t", self.t)] {
            if !f.is_valid() {
                return Err(format!("walker.{name}: format {} is not valid", f.name()));
            }
        }
        if !self.t.signed || self.t.width > 62 {
            return Err(format!(
                "walker.t: {} must be signed and at most 62 bits wide",
                self.t.name()
            ));
        }
        if self.pos.width > 61 {
            return Err(format!(
                "walker.pos: {} is wider than 61 bits (±e − o must fit 64)",
                self.pos.name()
            ));
        }
        if u32::from(self.pos.width) + 1 + u32::from(self.inv.width) > 126 {
            return Err("walker: pos width + inv width exceed the 127-bit product".into());
        }
        if self.max_steps == 0 {
            return Err("walker.max_steps must be positive".into());
        }
        Ok(())
    }

    /// A root slab time (b − o)·(1/|d|): the signed distance `dist` from the origin to a slab
    /// plane (a `pos` code, up to one bit wider: ±e − o) times the reciprocal `inv`, an exact
    /// 64×64 → 128-bit product with `pos.frac + inv.frac` fraction bits, rounded once into
    /// `t`.
    #[inline]
    pub fn slab_t(
        &self,
        dist: WalkerPos,
        inv: WalkerInv,
        ov: &mut Overflows,
        sig: SignalId,
    ) -> WalkerT {
        let prod_frac = i32::from(self.pos.frac) + i32::from(self.inv.frac);
        WalkerT {
            raw: quantize(
                i128::from(dist.raw) * i128::from(inv.raw),
                prod_frac,
                self.t,
                ov,
                sig,
            ),
        }
    }
}

/// One walk's inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct WalkerInput {
    /// Local origin.
    pub origin: [WalkerPos; 3],
    /// 1/|d| per axis; ignored on zero axes.
    pub inv: [WalkerInv; 3],
    /// Axis direction too small for 1/d: treated as zero (§3.3).
    pub zero: [bool; 3],
    /// Axis direction negative (sign bit, so −0 is negative): mirrored (§3.4).
    pub negative: [bool; 3],
    /// Half extents of the octree's box.
    pub half: [WalkerPos; 3],
}

impl WalkerInput {
    /// Sets axis `k`'s direction from the reciprocal unit's result: 1/|d| (the magnitude of
    /// its signed output), the zero flag and the sign.
    #[inline]
    pub fn set_axis(&mut self, k: usize, r: &Reciprocal) {
        self.inv[k] = WalkerInv {
            raw: r.raw.saturating_abs(),
        };
        self.zero[k] = r.zero;
        self.negative[k] = r.negative;
    }
}

/// The nearest solid leaf.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WalkerHit {
    /// max(entry, 0), in the walker's `t` format.
    pub t: WalkerT,
    /// Leaf coordinates (real, unmirrored) at `level`.
    pub voxel: [u32; 3],
    /// Level of the leaf.
    pub level: u8,
    /// Attribute index.
    pub attr: u32,
    /// Entry axis (0 = x, 1 = y, 2 = z): largest t0, ties x then y.
    pub entry_axis: u8,
}

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WalkOutcome {
    /// A solid leaf.
    Hit(WalkerHit),
    /// No leaf along the ray.
    Miss,
    /// Stopped by the step limit.
    StepLimit,
}

/// Counters of walks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkerStats {
    /// Loop iterations (children examined).
    pub steps: u64,
    /// Descriptor fetches (root and descents).
    pub fetches: u64,
    /// Deepest stack, frames.
    pub max_stack: u32,
    /// Walks stopped by the step limit.
    pub step_limit_hits: u64,
}

/// Walks `img` for one (ray, instance).
pub fn walk_fixed(
    img: &SvoImage,
    inp: &WalkerInput,
    cfg: &WalkerConfig,
    ov: &mut Overflows,
    sig: SignalId,
    st: &mut WalkerStats,
) -> WalkOutcome {
    walk_fixed_observed(img, inp, cfg, ov, sig, st, &mut NoObserver)
}

/// What a walk does, event by event, for the cycle model's timing and for node-by-node
/// comparisons. Every method has an empty default, so an observer implements only what it
/// needs; the calls come in the order the hardware walker performs them.
pub trait WalkObserver {
    /// A node is entered (an internal node or the final leaf): its level and coordinates.
    #[inline]
    fn enter(&mut self, _level: u8, _coords: [u32; 3]) {}
    /// One loop iteration: a child examined (one issue slot of the walker's datapath).
    #[inline]
    fn step(&mut self) {}
    /// A frame popped off the stack (the parent's next child follows).
    #[inline]
    fn pop(&mut self) {}
    /// A memory read, in the order the walker needs them: a descriptor or leaf slot
    /// ([`FetchKind::Node`], word address), a far word ([`FetchKind::Far`]) or the hit leaf's
    /// attribute record ([`FetchKind::Attr`], attribute index).
    #[inline]
    fn read(&mut self, _kind: FetchKind, _addr: u32) {}
}

/// An observer that ignores everything.
pub struct NoObserver;

impl WalkObserver for NoObserver {}

/// Adapts a `visit(level, coords)` closure to [`WalkObserver`].
struct Visiting<'v, V>(&'v mut V);

impl<V: FnMut(u8, [u32; 3])> WalkObserver for Visiting<'_, V> {
    #[inline]
    fn enter(&mut self, level: u8, coords: [u32; 3]) {
        (self.0)(level, coords);
    }
}

/// [`walk_fixed`], calling `visit(level, coords)` for every node it enters (internal nodes
/// and the final leaf), in order, to compare with the f64 reference node by node.
pub fn walk_fixed_visiting<V: FnMut(u8, [u32; 3])>(
    img: &SvoImage,
    inp: &WalkerInput,
    cfg: &WalkerConfig,
    ov: &mut Overflows,
    sig: SignalId,
    st: &mut WalkerStats,
    visit: &mut V,
) -> WalkOutcome {
    walk_fixed_observed(img, inp, cfg, ov, sig, st, &mut Visiting(visit))
}

/// [`walk_fixed`], reporting every step, pop, node entered and memory read to `obs`.
pub fn walk_fixed_observed<O: WalkObserver>(
    img: &SvoImage,
    inp: &WalkerInput,
    cfg: &WalkerConfig,
    ov: &mut Overflows,
    sig: SignalId,
    st: &mut WalkerStats,
    obs: &mut O,
) -> WalkOutcome {
    let mut ax = Axes {
        o: [WalkerPos::default(); 3],
        zero: inp.zero,
        any_zero: inp.zero.iter().any(|&z| z),
        a: 0,
        half: inp.half,
    };
    let mut t0 = [WalkerT::ZERO; 3];
    let mut t1 = [WalkerT::ZERO; 3];
    for k in 0..3 {
        let mut o = i128::from(inp.origin[k].raw);
        if inp.negative[k] {
            o = -o;
            ax.a |= 4 >> k;
        }
        // The mirrored origin is within one bit of `pos`; keep it exact.
        ax.o[k] = WalkerPos {
            raw: o.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64,
        };
        let e = i128::from(inp.half[k].raw);
        if inp.zero[k] {
            if !(-e <= o && o < e) {
                return WalkOutcome::Miss;
            }
            t0[k] = WalkerT::NEG_INF;
            t1[k] = WalkerT::POS_INF;
        } else {
            // `validate` keeps `pos` within 61 bits, so ±e − o fits 64 bits.
            let (lo, hi) = ((-e - o) as i64, (e - o) as i64);
            t0[k] = cfg.slab_t(WalkerPos { raw: lo }, inp.inv[k], ov, sig);
            t1[k] = cfg.slab_t(WalkerPos { raw: hi }, inp.inv[k], ov, sig);
        }
    }
    let (enter, exit) = (t0[0].max(t0[1]).max(t0[2]), t1[0].min(t1[1]).min(t1[2]));
    if !(enter < exit && exit > WalkerT::ZERO) {
        return WalkOutcome::Miss;
    }
    st.fetches += 1;
    st.max_stack = st.max_stack.max(1);
    let root = SvoImage::root();
    obs.read(FetchKind::Node, root);
    let nodes = img.nodes();
    let f = Frame::new(&ax, root, nodes[root as usize], t0, t1, 0, [0; 3]);
    // The explicit stack (at most MAX_DEPTH + 1 frames) lives in a per-thread buffer: a fresh
    // array per walk would clear ~2 KB each time. The hardware keeps it in registers/LUTRAM.
    STACK.with(|cell| {
        let mut stack = cell.borrow_mut();
        stack.clear();
        stack.push(f);
        walk_loop(nodes, &ax, cfg, st, obs, &mut stack)
    })
}

thread_local! {
    static STACK: std::cell::RefCell<Vec<Frame>> = std::cell::RefCell::new(Vec::with_capacity(MAX_DEPTH as usize + 1));
}

/// Bound on how far (metres, per axis) the ray the fixed walker effectively follows can lie
/// from the exact ray, over a path of length `reach`: the origin's error, the direction's
/// error stretched over the path (`dir_err` includes the reciprocal's relative error times
/// |d|), and the t-values' rounding (one LSB at the root, half an LSB of floor per level, one
/// for the final comparison). A node that one walk enters and the other does not must lie
/// within this distance of the exact ray's boundary crossings (`tests/fixed_walker.rs`).
pub fn spatial_error_bound(
    cfg: &WalkerConfig,
    origin_err: f64,
    dir_err: f64,
    reach: f64,
    depth: u8,
) -> f64 {
    origin_err + reach * dir_err + cfg.t.lsb() * (2.0 + f64::from(depth))
}

/// Bound on the error of any t-value of a walk, in metres, for an axis with 1/|d| ≤ `inv_max`:
///
/// ```text
/// root:      |Δt| ≤ Δo·inv + (e + |o|)·Δinv + lsb_t        (Δo: origin error, Δinv: 1/d error)
/// per level: the floor of a midpoint adds at most one LSB below the exact average
/// leaf at depth D: |Δt| ≤ root + D·lsb_t
/// ```
/// `origin_err` is the local origin's error (the transform unit's bound), `inv_err` the
/// reciprocal's, `reach` a bound on e + |o| (metres).
pub fn t_error_bound(
    cfg: &WalkerConfig,
    origin_err: f64,
    inv_err: f64,
    inv_max: f64,
    reach: f64,
    depth: u8,
) -> f64 {
    origin_err * inv_max + reach * inv_err + cfg.t.lsb() * (1.0 + f64::from(depth))
}

/// The products of the walker-root unit: the 6 slab products (±e − o)·(1/|d|) side by side,
/// ±e − o the exact difference ([`Format::exact_difference`]) of `pos`.
pub fn root_products(w: &WalkerConfig) -> crate::fixed::Products {
    crate::fixed::Products::new(6, w.pos.exact_difference(), w.inv)
}

/// DSP48E2 of one walker-root unit: the tiles of its [`root_products`] (36 by default). The
/// walker's steps use none (midpoints are adders).
pub fn root_dsp48e2_count(w: &WalkerConfig) -> u32 {
    root_products(w).dsp48e2()
}

/// Latency of the walker-root unit, as stages: ±e − o with the mirroring negation (1); the
/// six products in parallel (one product); rounding into `t` (1); max of t0 and min of t1
/// over the axes (2). 8 for the default.
pub fn root_latency_cycles(w: &WalkerConfig) -> u32 {
    1 + root_products(w).latency_cycles() + 1 + 2
}
