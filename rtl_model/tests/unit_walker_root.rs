//! The walker-root unit (`rtl_model::units::walker_root`) against the walker it stands in
//! front of: on seeded rays into a full one-level octree, the root's `enter` is exactly
//! whether the walk gets past its root (a hit here), with no code shared beyond the inputs.
//! (Here rather than beside the unit: it needs the datapath's default formats, a layer above
//! `units`, docs/architecture.md §1.)

use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::{Overflows, SignalId};
use rtl_model::svo::{LeafAttr, LeafSet, SvoImage};
use rtl_model::units::walker::{
    walk_fixed, WalkOutcome, WalkerInput, WalkerInv, WalkerPos, WalkerStats,
};
use rtl_model::units::walker_root::root_slabs;

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
