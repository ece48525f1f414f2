//! The walker-root unit's outputs for one walk, as the RTL unit (`testbench/rtl/svo_walker_root.v`)
//! registers them: the mirrored origin, the root node's slab times of every axis (the ±∞
//! sentinels on zero axes) and whether the walk enters the root.
//!
//! Pipeline position: after the reciprocal units, before the walker's dispatcher (the cycle
//! model's `root` stage); k of them in a k-wide walk issue. Its vectors
//! (`vectors::stage::walker_root`) drive k instances side by side.
//!
//! Arithmetic: exactly the first part of [`crate::units::walker::walk_fixed_observed`]
//! (mirroring, exact ±e − o', one rounding of the product into `t`, the entry test), but over
//! all three axes: the walker stops at the first zero axis whose slab misses, while the unit
//! computes every axis in parallel and its `enter` says the walk misses. So the walker's
//! overflow counts stay those of its early exit, and this unit's outputs are every wire the
//! RTL drives.

use crate::fixed::{Overflows, SignalId};
use crate::units::walker::{WalkerConfig, WalkerInput, WalkerPos, WalkerT};

/// One walk's root, as the unit hands it on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RootSlabs {
    /// The origin, negated on negative axes (exact: one bit wider than `pos`).
    pub origin: [WalkerPos; 3],
    /// Slab entry times per axis, [`WalkerT::NEG_INF`] on zero axes.
    pub t0: [WalkerT; 3],
    /// Slab exit times per axis, [`WalkerT::POS_INF`] on zero axes.
    pub t1: [WalkerT; 3],
    /// max(t0) < min(t1), min(t1) > 0 and no zero axis outside its slab: the walk enters.
    pub enter: bool,
}

/// The root unit of `cfg` on `inp`; saturations of the slab times are counted on `sig`.
pub fn root_slabs(
    inp: &WalkerInput,
    cfg: &WalkerConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> RootSlabs {
    let mut r = RootSlabs {
        origin: [WalkerPos::default(); 3],
        t0: [WalkerT::ZERO; 3],
        t1: [WalkerT::ZERO; 3],
        enter: true,
    };
    for k in 0..3 {
        let o = if inp.negative[k] {
            -i128::from(inp.origin[k].raw)
        } else {
            i128::from(inp.origin[k].raw)
        };
        // `WalkerConfig::validate` keeps `pos` within 61 bits: o' and ±e − o' fit 64.
        r.origin[k] = WalkerPos { raw: o as i64 };
        let e = i128::from(inp.half[k].raw);
        if inp.zero[k] {
            r.enter &= -e <= o && o < e;
            r.t0[k] = WalkerT::NEG_INF;
            r.t1[k] = WalkerT::POS_INF;
        } else {
            r.t0[k] = cfg.slab_t(
                WalkerPos {
                    raw: (-e - o) as i64,
                },
                inp.inv[k],
                ov,
                sig,
            );
            r.t1[k] = cfg.slab_t(
                WalkerPos {
                    raw: (e - o) as i64,
                },
                inp.inv[k],
                ov,
                sig,
            );
        }
    }
    let enter_t = r.t0.iter().max().copied().unwrap_or(WalkerT::NEG_INF);
    let exit_t = r.t1.iter().min().copied().unwrap_or(WalkerT::POS_INF);
    r.enter &= enter_t < exit_t && exit_t > WalkerT::ZERO;
    r
}
