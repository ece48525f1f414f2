//! Property tests of the octree walker (`svo_sim::models::reference::walk::walk`) against oracle A, an
//! Amanatides–Woo walk over the dense voxel grid (`tests/common/oracle.rs`).
//!
//! What is checked: for random and adversarial rays in an instance's local frame (origins
//! outside, inside, on grid planes, on grid points and box faces; directions random, with
//! exact ±0.0 and ±1e-20 components, exact edge/corner diagonals, grazing along faces) the
//! walker's nearest solid leaf and its t agree with the oracle's, on random voxel sets of
//! depth 1 to 6 (empty, full, single voxel, sparse to dense, blocks) and on procedural shapes
//! voxelised by the real builder, all with anisotropic half extents. The fixed regression tests
//! of the documented conventions are in `tests/traversal_fixed.rs`; the assets and the
//! comparison are shared in `tests/common/traversal.rs`.
//!
//! Why the oracle is independent: it shares no code with `src/models/reference` and never reads the
//! SVO image; it walks a flat `Vec<bool>` grid made from the leaf coordinates, computes every
//! crossing time by division from the plane positions, and resolves ties by comparing those
//! times, where the walker recurses through the octree with midpoint times, reciprocals and a
//! mirrored frame.
//!
//! Reproduce a run with `SVO_TEST_SEED=<seed>` (printed at the start of each test); set
//! `SVO_PROPTEST_CASES` to change the number of cases per property (default 10 000).

mod common;

use common::oracle;
use common::traversal::{assets, judge, normalise, TestAsset, Verdict};
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use std::cell::Cell;
use std::time::Instant;

// ---------------------------------------------------------------------------------------------
// Counting acceptances

/// Counts of one group of cases.
#[derive(Default)]
struct Counts {
    cases: Cell<u64>,
    hits: Cell<u64>,
    ties: Cell<u64>,
    grazes: Cell<u64>,
}

impl Counts {
    fn add(&self, v: Verdict, hit: bool) {
        self.cases.set(self.cases.get() + 1);
        self.hits.set(self.hits.get() + u64::from(hit));
        match v {
            Verdict::Agree => {}
            Verdict::Tie => self.ties.set(self.ties.get() + 1),
            Verdict::Graze => self.grazes.set(self.grazes.get() + 1),
        }
    }

    fn accepted(&self) -> u64 {
        self.ties.get() + self.grazes.get()
    }

    fn line(&self) -> String {
        format!(
            "{} cases, {} hits, {} accepted ties, {} accepted grazes",
            self.cases.get(),
            self.hits.get(),
            self.ties.get(),
            self.grazes.get()
        )
    }
}

/// Counts over a property run, in two groups.
///
/// Rays that start exactly on a grid plane of an axis they move along are counted apart: the
/// walker's time for that plane is a chain of midpoints (t0 + t1)/2 that lands a few ulps off
/// 0, so whenever the cell on the far side of the plane is solid the walker may report it
/// for a sliver [0, ~1e-17] (an accepted graze) where the exact walk starts one cell over.
/// The same holds later along such rays where they pass exactly through a cell edge or
/// corner (only rays from grid points do): the walker's midpoint chains for the two axes
/// round differently, so it may step through a corner-adjacent cell for a sliver. That is
/// expected rounding, common for such rays, and bounded separately. For every other ray
/// acceptances must stay below 1 % (in practice there are none).
#[derive(Default)]
struct Tally {
    general: Counts,
    plane_start: Counts,
}

/// Upper bound on accepted ties + grazes among rays starting on a grid plane (see [`Tally`]).
/// Measured over 13 seeds (1 to 13) of the four ray sets: at most 0.32 % (31 grazes in 9,736
/// rays), never a tie; 1 % keeps a 3× margin for other seeds while a walker that mishandled
/// plane starts systematically (about half of such rays meet a solid far-side cell) would
/// exceed it many times over. It was 15 % before it was measured.
const PLANE_START_LIMIT_PERCENT: u64 = 1;

impl Tally {
    fn add(&self, plane_start: bool, v: Verdict, hit: bool) {
        if plane_start {
            self.plane_start.add(v, hit);
        } else {
            self.general.add(v, hit);
        }
    }

    /// Prints the counts and checks that tie/graze acceptances stay rare.
    fn report(&self, name: &str, seed: u64, secs: f64) {
        println!(
            "{name}: seed = {seed}, {secs:.2} s\n  general rays:        {}\n  rays from grid planes: {}",
            self.general.line(),
            self.plane_start.line()
        );
        let (g, p) = (&self.general, &self.plane_start);
        assert!(
            g.accepted() * 100 < g.cases.get().max(1),
            "{name} (seed = {seed}): {} ties/grazes in {} general cases is not rare (≥ 1 %)",
            g.accepted(),
            g.cases.get()
        );
        assert!(
            p.accepted() * 100 < p.cases.get().max(1) * PLANE_START_LIMIT_PERCENT,
            "{name} (seed = {seed}): {} ties/grazes in {} cases from grid planes (≥ {PLANE_START_LIMIT_PERCENT} %)",
            p.accepted(),
            p.cases.get()
        );
    }
}

/// Does the ray start exactly on a grid plane (faces included) of an axis it moves along?
fn plane_start(a: &TestAsset, o: [f64; 3], d: [f64; 3]) -> bool {
    (0..3).any(|k| d[k] != 0.0 && (0..=a.n).any(|i| oracle::plane(a.half[k], a.n, i) == o[k]))
}

// ---------------------------------------------------------------------------------------------
// Ray strategies

/// How one origin component is made.
#[derive(Clone, Copy, Debug)]
enum AxisOrigin {
    /// o = f·h.
    Free(f64),
    /// o on grid plane i mod (n + 1): faces, centre planes and every finer plane.
    Plane(u32),
}

/// How one direction component is made (before normalising).
#[derive(Clone, Copy, Debug)]
enum AxisDir {
    Free(f64),
    PosZero,
    NegZero,
    /// ±1e-20.
    Tiny(bool),
    /// ± the cell size of this axis: diagonals through cell edges and corners, exact ties
    /// where the cell sizes of the axes differ by a power of two.
    Cell(bool),
    /// ±1: the unit diagonals (1,1,0)/√2, (1,1,1)/√3 and their mirrors.
    Unit(bool),
}

#[derive(Clone, Debug)]
enum Recipe {
    PerAxis {
        o: [AxisOrigin; 3],
        d: [AxisDir; 3],
    },
    /// From far away toward a target point (in units of the half extents), or away from it.
    Aimed {
        target: [f64; 3],
        dir: [f64; 3],
        /// Distance in units of the largest half extent.
        dist: f64,
        away: bool,
    },
}

#[derive(Clone, Debug)]
struct Case {
    asset: usize,
    recipe: Recipe,
}

/// The ray of a case.
fn realise(a: &TestAsset, r: &Recipe) -> ([f64; 3], [f64; 3]) {
    match r {
        Recipe::PerAxis { o, d } => {
            let o = std::array::from_fn(|k| match o[k] {
                AxisOrigin::Free(f) => f * a.half[k],
                AxisOrigin::Plane(i) => oracle::plane(a.half[k], a.n, i % (a.n + 1)),
            });
            let cell = a.half.map(|h| 2.0 * h / f64::from(a.n));
            let sign = |neg: bool, x: f64| if neg { -x } else { x };
            let d = std::array::from_fn(|k| match d[k] {
                AxisDir::Free(f) => f,
                AxisDir::PosZero => 0.0,
                AxisDir::NegZero => -0.0,
                AxisDir::Tiny(neg) => sign(neg, 1e-20),
                AxisDir::Cell(neg) => sign(neg, cell[k]),
                AxisDir::Unit(neg) => sign(neg, 1.0),
            });
            (o, normalise(d))
        }
        Recipe::Aimed {
            target,
            dir,
            dist,
            away,
        } => {
            let u = normalise(*dir);
            let scale = a.half.iter().copied().fold(0.0, f64::max) * dist;
            let o = std::array::from_fn(|k| target[k] * a.half[k] - u[k] * scale);
            (o, if *away { u.map(|c| -c) } else { u })
        }
    }
}

fn axis_origin(free: f64) -> impl Strategy<Value = AxisOrigin> + Clone {
    prop_oneof![
        3 => (-free..free).prop_map(AxisOrigin::Free),
        2 => (0u32..=64).prop_map(AxisOrigin::Plane),
    ]
}

fn axis_dir() -> impl Strategy<Value = AxisDir> + Clone {
    prop_oneof![
        5 => (-1.0f64..1.0).prop_map(AxisDir::Free),
        1 => Just(AxisDir::PosZero),
        1 => Just(AxisDir::NegZero),
        1 => any::<bool>().prop_map(AxisDir::Tiny),
        1 => any::<bool>().prop_map(AxisDir::Cell),
        1 => any::<bool>().prop_map(AxisDir::Unit),
    ]
}

/// Directions for grid-aligned rays: only the exact kinds (zeros, ties, tiny).
fn axis_dir_exact() -> impl Strategy<Value = AxisDir> + Clone {
    prop_oneof![
        1 => Just(AxisDir::PosZero),
        1 => Just(AxisDir::NegZero),
        1 => any::<bool>().prop_map(AxisDir::Tiny),
        3 => any::<bool>().prop_map(AxisDir::Cell),
        2 => any::<bool>().prop_map(AxisDir::Unit),
        1 => (-1.0f64..1.0).prop_map(AxisDir::Free),
    ]
}

fn vec3(lo: f64, hi: f64) -> impl Strategy<Value = [f64; 3]> {
    [lo..hi, lo..hi, lo..hi]
}

fn aimed() -> impl Strategy<Value = Recipe> {
    (
        vec3(-1.3, 1.3),
        vec3(-1.0, 1.0),
        0.0f64..60.0,
        any::<bool>(),
    )
        .prop_map(|(target, dir, dist, away)| Recipe::Aimed {
            target,
            dir,
            dist,
            away,
        })
}

fn per_axis(
    o: impl Strategy<Value = AxisOrigin> + Clone,
    d: impl Strategy<Value = AxisDir> + Clone,
) -> impl Strategy<Value = Recipe> {
    ([o.clone(), o.clone(), o], [d.clone(), d.clone(), d])
        .prop_map(|(o, d)| Recipe::PerAxis { o, d })
}

fn with_asset(recipe: impl Strategy<Value = Recipe>) -> impl Strategy<Value = Case> {
    (0..assets().len(), recipe).prop_map(|(asset, recipe)| Case { asset, recipe })
}

/// Does the ray start exactly on a grid plane (faces included) of an axis along which it
/// moves only by a tiny non-zero amount (0 < |d_k| < 1e-6)?
///
/// That is where the walker's midpoint times (t0 + t1)/2 go wrong: their absolute error is
/// about ε·2h/|d_k| (≈ 1000 for |d_k| = 1e-20), so the plane the origin sits on is crossed
/// at some t ≠ 0 instead of t = 0 and the walker puts the ray on the wrong side of it for
/// that long. See `tiny_component_from_a_grid_plane_keeps_its_side` for the minimal case;
/// the other properties leave this class to
/// `walker_matches_oracle_with_tiny_components_on_grid_planes`, so that it does not mask
/// everything else.
fn tiny_on_plane(a: &TestAsset, o: [f64; 3], d: [f64; 3]) -> bool {
    (0..3).any(|k| {
        d[k] != 0.0
            && d[k].abs() < 1e-6
            && (0..=a.n).any(|i| oracle::plane(a.half[k], a.n, i) == o[k])
    })
}

/// Which rays a property keeps.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Keep {
    /// All but [`tiny_on_plane`] ones.
    AllButTinyOnPlane,
    /// Only [`tiny_on_plane`] ones.
    OnlyTinyOnPlane,
}

/// Runs one property: `cases` cases from the run seed, each judged by [`judge`].
fn run_property(name: &str, stream: u64, keep: Keep, strategy: impl Strategy<Value = Case>) {
    let seed = common::test_seed();
    println!("seed = {seed} ({name}; set SVO_TEST_SEED to reproduce)");
    let cases = common::proptest_cases(10_000);
    let start = Instant::now();
    let tally = Tally::default();
    let mut runner = TestRunner::new_with_rng(
        common::proptest_config(cases),
        common::proptest_rng(seed, stream),
    );
    let result = runner.run(&strategy, |case| {
        let a = &assets()[case.asset];
        let (o, d) = realise(a, &case.recipe);
        if tiny_on_plane(a, o, d) != (keep == Keep::OnlyTinyOnPlane) {
            return Err(TestCaseError::reject("not this property's class of rays"));
        }
        match judge(a, o, d) {
            Ok((v, hit)) => {
                tally.add(plane_start(a, o, d), v, hit);
                Ok(())
            }
            Err(msg) => Err(TestCaseError::fail(format!("seed = {seed}: {msg}"))),
        }
    });
    if let Err(e) = result {
        panic!("{name} failed with seed = {seed} (SVO_TEST_SEED={seed} reproduces it):\n{e}");
    }
    tally.report(name, seed, start.elapsed().as_secs_f64());
}

#[test]
fn walker_matches_oracle_on_mixed_rays() {
    run_property(
        "mixed rays",
        1,
        Keep::AllButTinyOnPlane,
        with_asset(prop_oneof![
            3 => per_axis(axis_origin(2.5), axis_dir()),
            2 => aimed(),
        ]),
    );
}

#[test]
fn walker_matches_oracle_from_inside() {
    run_property(
        "origins inside",
        2,
        Keep::AllButTinyOnPlane,
        with_asset(per_axis(axis_origin(1.0), axis_dir())),
    );
}

#[test]
fn walker_matches_oracle_on_grid_aligned_rays() {
    // Origins on grid planes on every axis (grid points, box edges and corners included) with
    // exact diagonal, zero and tiny direction components: the tie and boundary cases.
    let on_planes = (0u32..=64).prop_map(AxisOrigin::Plane);
    let mostly_planes = prop_oneof![
        4 => (0u32..=64).prop_map(AxisOrigin::Plane),
        1 => (-1.5f64..1.5).prop_map(AxisOrigin::Free),
    ];
    run_property(
        "grid-aligned rays",
        3,
        Keep::AllButTinyOnPlane,
        with_asset(prop_oneof![
            1 => per_axis(on_planes, axis_dir_exact()),
            1 => per_axis(mostly_planes, axis_dir_exact()),
        ]),
    );
}

#[test]
fn walker_matches_oracle_with_tiny_components_on_grid_planes() {
    // Origins on grid planes with ±1e-20 components along those axes: the ray leaves the
    // plane at once, to the side of the component's sign, and must be in that cell.
    let origin = prop_oneof![
        3 => (0u32..=64).prop_map(AxisOrigin::Plane),
        1 => (-1.5f64..1.5).prop_map(AxisOrigin::Free),
    ];
    let dir = prop_oneof![
        3 => any::<bool>().prop_map(AxisDir::Tiny),
        2 => (-1.0f64..1.0).prop_map(AxisDir::Free),
        1 => any::<bool>().prop_map(AxisDir::Cell),
        1 => Just(AxisDir::PosZero),
        1 => Just(AxisDir::NegZero),
    ];
    run_property(
        "tiny components on grid planes",
        4,
        Keep::OnlyTinyOnPlane,
        with_asset(per_axis(origin, dir)),
    );
}
