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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::datapath::DatapathConfig;
    use crate::svo::{LeafAttr, LeafSet, SvoImage};
    use crate::units::walker::{walk_fixed, WalkOutcome, WalkerInv, WalkerStats};

    /// The unit enters exactly when the walker gets past its root: a walk of a full one-level
    /// octree (every child solid) hits whenever it enters, and misses otherwise.
    #[test]
    fn enter_agrees_with_the_walkers_root() {
        let cfg = DatapathConfig::default().walker;
        let full = (0..8u32).map(|i| {
            (
                [i & 1, (i >> 1) & 1, i >> 2],
                LeafAttr::new([255; 4], [0.0, 0.0, 1.0]),
            )
        });
        let img = SvoImage::build(&LeafSet::from_coords(1, full).expect("8 leaves of depth 1"))
            .expect("a full octree of depth 1");
        let seed = 0x5eed_2028_u64;
        println!("seed {seed:#x}");
        let mut x = seed;
        let mut next = || {
            // xorshift64
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let one = 1i64 << cfg.pos.frac;
        let (mut entered, mut missed) = (0, 0);
        for _ in 0..2000 {
            let mut inp = WalkerInput {
                half: WalkerPos::of([one; 3]),
                ..WalkerInput::default()
            };
            for k in 0..3 {
                inp.origin[k].raw = (next() % (6 * one as u64)) as i64 - 3 * one;
                inp.inv[k] = WalkerInv {
                    raw: (next() % (8 << cfg.inv.frac)) as i64,
                };
                inp.zero[k] = next() % 5 == 0;
                inp.negative[k] = next() % 2 == 0;
            }
            let r = root_slabs(&inp, &cfg, &mut Overflows::new(&["r"]), SignalId(0));
            let w = walk_fixed(
                &img,
                &inp,
                &cfg,
                &mut Overflows::new(&["w"]),
                SignalId(0),
                &mut WalkerStats::default(),
            );
            assert_eq!(
                r.enter,
                w != WalkOutcome::Miss,
                "{inp:?}: {r:?}, walk {w:?}"
            );
            if r.enter {
                entered += 1;
            } else {
                missed += 1;
            }
        }
        assert!(
            entered > 100 && missed > 100,
            "{entered} entered, {missed} missed"
        );
    }
}
