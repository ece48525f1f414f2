//! Shared by the walker-vs-oracle tests (`tests/traversal_oracle.rs`, property tests;
//! `tests/traversal_fixed.rs`, fixed regression cases): the test assets (random and
//! procedural voxel sets with anisotropic half extents, each as an SVO image and as the dense
//! grid oracle A walks), and the comparison [`judge`], which walks one ray with the octree
//! walker (`svo_sim::models::reference::walk::walk`) and with oracle A ([`super::oracle`]) and
//! accepts the same answer, an exact tie, or a graze that rounding decides.

use std::collections::HashMap;
use std::sync::OnceLock;

use glam::DVec3;
use rtl_model::svo::{LeafAttr, LeafSet, SvoImage};
use svo_sim::models::reference::walk::{walk, WalkCounters, WalkHit};
use svo_sim::world::sdf::{Axis, Shape};

use super::oracle::{self, tol, DenseGrid, GridHit};
use super::{fmt_vec, SplitMix64};

// ---------------------------------------------------------------------------------------------
// Test assets

/// One octree with everything the comparison needs.
pub struct TestAsset {
    /// Name in failure messages.
    pub name: String,
    /// Octree depth.
    pub depth: u8,
    /// Cells per axis, 2^depth.
    pub n: u32,
    /// Per-axis half extents. Every one used here makes every grid plane −h + i·2h/n an exact
    /// double (h·k/64 with small k), so "origin on a plane" is unambiguous for both sides.
    pub half: [f64; 3],
    /// The memory image the walker reads.
    pub image: SvoImage,
    /// The same voxels as a flat grid, for the oracle.
    pub grid: DenseGrid,
    /// Each solid leaf's attribute.
    pub attrs: HashMap<[u32; 3], LeafAttr>,
}

impl TestAsset {
    /// The asset of a leaf set in a box of half extents `half`.
    pub fn new(name: impl Into<String>, set: &LeafSet, half: [f64; 3]) -> Self {
        let depth = set.depth();
        Self {
            name: name.into(),
            depth,
            n: 1u32 << depth,
            half,
            image: super::build_image(set),
            grid: DenseGrid::from_coords(depth, set.coords().map(|(c, _)| c)),
            attrs: set.coords().collect(),
        }
    }

    /// One line for failure messages.
    pub fn describe(&self) -> String {
        format!(
            "asset {:?} (depth {}, {} solid of {}, half {:?})",
            self.name,
            self.depth,
            self.grid.count(),
            u64::from(self.n).pow(3),
            self.half
        )
    }
}

/// Anisotropic half extents with exact grid planes (see [`TestAsset::half`]); the first is
/// the brief's example, the second is isotropic (so unit diagonals tie exactly), the others
/// have power-of-two cell ratios between some axes and not others.
pub const HALVES: [[f64; 3]; 6] = [
    [1.0, 0.25, 3.0],
    [1.0, 1.0, 1.0],
    [0.5, 2.0, 0.75],
    [2.0, 0.5, 0.125],
    [1.5, 0.375, 1.5],
    [0.75, 3.0, 0.1875],
];

/// The shared test assets, built once per test binary from the run seed.
pub fn assets() -> &'static [TestAsset] {
    static ASSETS: OnceLock<Vec<TestAsset>> = OnceLock::new();
    ASSETS.get_or_init(|| build_test_assets(super::test_seed()))
}

fn build_test_assets(seed: u64) -> Vec<TestAsset> {
    let mut rng = SplitMix64::derive(seed, "traversal assets");
    let mut out = Vec::new();
    let mut half = HALVES.iter().copied().cycle();
    let mut next_half = || half.next().expect("cycle never ends");
    // Random voxel sets: (depth, density).
    for (depth, density) in [
        (1, 0.5),
        (2, 0.3),
        (3, 0.15),
        (4, 0.6),
        (5, 0.05),
        (6, 0.003),
        (6, 0.02),
        (4, 0.95),
    ] {
        let set = super::random_leaf_set(&mut rng, depth, density);
        out.push(TestAsset::new(
            format!("random d{depth} p{density}"),
            &set,
            next_half(),
        ));
    }
    let set = super::random_blocks(&mut rng, 6, 6);
    out.push(TestAsset::new("blocks d6", &set, next_half()));
    let set = super::random_blocks(&mut rng, 5, 3);
    out.push(TestAsset::new("blocks d5", &set, next_half()));
    out.push(TestAsset::new(
        "empty d3",
        &LeafSet::empty(3).expect("valid depth"),
        next_half(),
    ));
    out.push(TestAsset::new(
        "full d4",
        &super::full_leaf_set(4),
        next_half(),
    ));
    let c = [0, 1, 2].map(|_| rng.below(32) as u32);
    out.push(TestAsset::new(
        format!("single {c:?} d5"),
        &super::leaf_set_of(5, &[c]),
        next_half(),
    ));
    out.push(TestAsset::new(
        "full d1",
        &super::full_leaf_set(1),
        next_half(),
    ));
    // Procedural shapes through the real voxeliser (a shell one voxel thick), in a unit cube
    // that the walker then stretches to the asset's anisotropic box.
    let shapes = [
        ("sphere d5", Shape::Sphere { radius: 0.9 }, 5),
        (
            "torus d6",
            Shape::Torus {
                major: 0.6,
                minor: 0.25,
                axis: Axis::Z,
            },
            6,
        ),
        (
            "hollow box d4",
            Shape::Difference {
                base: Box::new(Shape::Box {
                    half: [0.8, 0.8, 0.8],
                }),
                minus: vec![Shape::Sphere { radius: 0.95 }],
            },
            4,
        ),
        (
            "union d6",
            Shape::Union(vec![
                Shape::Cylinder {
                    radius: 0.3,
                    half_length: 0.9,
                    axis: Axis::X,
                },
                Shape::Moved {
                    offset: [0.2, 0.3, -0.1],
                    rotation_deg: [30.0, 45.0, 10.0],
                    shape: Box::new(Shape::Box {
                        half: [0.4, 0.2, 0.5],
                    }),
                },
            ]),
            6,
        ),
    ];
    for (name, shape, depth) in shapes {
        let set = super::sdf_leaf_set(&shape, 1.0, depth);
        assert!(!set.is_empty(), "{name} voxelised to nothing");
        out.push(TestAsset::new(name, &set, next_half()));
    }
    out
}

// ---------------------------------------------------------------------------------------------
// The comparison

/// How a case passed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Same answer (both miss, or same voxel with t within tolerance).
    Agree,
    /// Different voxels, both solid, both proper (longer than the tolerance), entered at t
    /// within tolerance of each other.
    Tie,
    /// One side reported a voxel whose interval is no longer than the tolerance (a graze
    /// that rounding decides), and the rest is consistent.
    Graze,
}

/// A walker answer for failure messages, t with its bit pattern.
pub fn fmt_walk(h: &Option<WalkHit>) -> String {
    match h {
        None => "miss".into(),
        Some(h) => format!(
            "hit voxel {:?} level {} t = {:e} ({:#018x})",
            h.voxel,
            h.level,
            h.t,
            h.t.to_bits()
        ),
    }
}

/// An oracle answer for failure messages, t with its bit pattern.
pub fn fmt_grid(h: &Option<GridHit>) -> String {
    match h {
        None => "miss".into(),
        Some(h) => format!(
            "hit voxel {:?} t = {:e} ({:#018x})",
            h.voxel,
            h.t,
            h.t.to_bits()
        ),
    }
}

/// max(entry, 0) and exit of a cell by the oracle's own slab test, if the ray reaches it.
fn cell_span(a: &TestAsset, c: [u32; 3], o: [f64; 3], d: [f64; 3]) -> Option<(f64, f64)> {
    oracle::cell_interval(a.n, a.half, c, o, d).map(|(enter, exit)| (enter.max(0.0), exit))
}

/// The cell is entered at (about) `t`.
fn entered_at(a: &TestAsset, c: [u32; 3], o: [f64; 3], d: [f64; 3], t: f64) -> bool {
    cell_span(a, c, o, d)
        .is_some_and(|(enter, exit)| (enter - t).abs() <= tol(t) && exit - enter >= -tol(t))
}

/// The cell is touched at (about) `t` only for an interval no longer than the tolerance.
fn grazed_at(a: &TestAsset, c: [u32; 3], o: [f64; 3], d: [f64; 3], t: f64) -> bool {
    cell_span(a, c, o, d)
        .is_some_and(|(enter, exit)| (enter - t).abs() <= tol(t) && (exit - enter).abs() <= tol(t))
}

/// Walks the asset with the walker and oracle A and judges the pair (see the module doc of
/// `oracle` and the brief: same answer, a tie, or a graze).
pub fn judge(a: &TestAsset, o: [f64; 3], d: [f64; 3]) -> Result<(Verdict, bool), String> {
    let mut cnt = WalkCounters::default();
    let w = walk(
        &a.image,
        DVec3::from_array(a.half),
        DVec3::from_array(o),
        DVec3::from_array(d),
        &mut cnt,
    );
    let fail = |why: &str, r: &Option<GridHit>| {
        Err(format!(
            "{why}\n  {}\n  o = {}\n  d = {}\n  walker: {}\n  oracle: {}",
            a.describe(),
            fmt_vec(o),
            fmt_vec(d),
            fmt_walk(&w),
            fmt_grid(r)
        ))
    };
    // Sanity of the walker's own answer, independent of the oracle.
    if let Some(h) = &w {
        if h.level != a.depth || !a.grid.get(h.voxel) {
            return fail("walker reported a voxel that is not a solid leaf", &None);
        }
        if !(h.t >= 0.0 && h.t.is_finite()) {
            return fail("walker reported a negative or non-finite t", &None);
        }
        if a.image.attrs().get(h.attr as usize) != a.attrs.get(&h.voxel) {
            return fail("walker's attribute index is not this leaf's", &None);
        }
    }
    // Grazes the oracle took that the walker may have skipped: drop them one by one and
    // re-ask (a handful at most in practice).
    let mut skipped: Vec<[u32; 3]> = Vec::new();
    loop {
        let r = oracle::amanatides_woo(a.n, a.half, o, d, |c| {
            a.grid.get(c) && !skipped.contains(&c)
        });
        let verdict = match (&w, &r) {
            (None, None) => Some(Verdict::Agree),
            (Some(wh), Some(rh)) if wh.voxel == rh.voxel => {
                if (wh.t - rh.t).abs() <= tol(rh.t) {
                    Some(Verdict::Agree)
                } else {
                    return fail("same voxel, different t", &r);
                }
            }
            (Some(wh), Some(rh))
                if (wh.t - rh.t).abs() <= tol(rh.t)
                    && entered_at(a, wh.voxel, o, d, wh.t)
                    && entered_at(a, rh.voxel, o, d, rh.t) =>
            {
                // Two cells entered at the same t: one of them can only be a sliver (cells
                // along a ray do not overlap), which makes it a graze; a tie proper is two
                // proper cells entered within the tolerance of each other.
                if grazed_at(a, wh.voxel, o, d, wh.t) || grazed_at(a, rh.voxel, o, d, rh.t) {
                    Some(Verdict::Graze)
                } else {
                    Some(Verdict::Tie)
                }
            }
            _ => None,
        };
        if let Some(v) = verdict {
            let v = if skipped.is_empty() {
                v
            } else {
                Verdict::Graze
            };
            return Ok((v, w.is_some() || r.is_some()));
        }
        // The walker stopped at a graze in front of (or instead of) the oracle's answer.
        if let Some(wh) = &w {
            let before = r.as_ref().is_none_or(|rh| wh.t <= rh.t + tol(rh.t));
            if before && grazed_at(a, wh.voxel, o, d, wh.t) {
                return Ok((Verdict::Graze, true));
            }
        }
        // The oracle stopped at a graze: retry without it.
        match &r {
            Some(rh) if skipped.len() < 4 && grazed_at(a, rh.voxel, o, d, rh.t) => {
                skipped.push(rh.voxel);
            }
            _ => return fail("walker and oracle disagree", &r),
        }
    }
}

/// `v` scaled to unit length; an all-zero `v` becomes +x (keeping the signs of its y and z
/// zeros).
pub fn normalise(v: [f64; 3]) -> [f64; 3] {
    let v = if v.iter().all(|&c| c == 0.0) {
        [1.0, v[1], v[2]]
    } else {
        v
    };
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len.is_normal() {
        v.map(|c| c / len)
    } else {
        [1.0, 0.0, 0.0]
    }
}

// ---------------------------------------------------------------------------------------------
// Fixed expectations

/// The walker on plain arrays.
fn walk_arrays(a: &TestAsset, o: [f64; 3], d: [f64; 3]) -> Option<WalkHit> {
    walk(
        &a.image,
        DVec3::from_array(a.half),
        DVec3::from_array(o),
        DVec3::from_array(d),
        &mut WalkCounters::default(),
    )
}

/// Asserts the walker's answer is `expect` ((voxel, t) or miss), exactly in the voxel and to
/// tolerance in t, and that the oracle agrees.
pub fn expect_walk(a: &TestAsset, o: [f64; 3], d: [f64; 3], expect: Option<([u32; 3], f64)>) {
    let w = walk_arrays(a, o, d);
    let got = w.map(|h| (h.voxel, h.t));
    let ok = match (got, expect) {
        (None, None) => true,
        (Some((gv, gt)), Some((ev, et))) => gv == ev && (gt - et).abs() <= tol(et),
        _ => false,
    };
    assert!(
        ok,
        "{}\n  o = {}\n  d = {}\n  expected {expect:?}, walker {}",
        a.describe(),
        fmt_vec(o),
        fmt_vec(d),
        fmt_walk(&w)
    );
    let (v, _) = judge(a, o, d).unwrap_or_else(|m| panic!("{m}"));
    assert_eq!(
        v,
        Verdict::Agree,
        "oracle needed a tie/graze on a fixed case"
    );
}
