//! The clipped reference walk (`walk_box_clipped`, used by `sim render`) against the unclipped
//! one (`walk_box`) on the same octrees and rays: every hit must be bit-identical (t, voxel,
//! level, leaf, face normal) and every miss a miss; only the work may shrink.
//!
//! Octrees: random leaf clusters in a sub-box of a 2^depth cube whose corner sits at an integer
//! offset (negative, zero, positive), as `sim render` places a model. Rays: oblique rays aimed
//! into the solid box, random rays around the octree, axis-aligned rays from voxel planes, edge
//! lines and cell centres (exact-zero components of both signs, rays in voxel planes), tiny
//! components (below and above the walk's zero threshold) and origins inside the model; and
//! the same rays made meaningless (a NaN t), which must hit nothing. Seeded:
//! the seed is printed; `SVO_TEST_SEED=<seed>` reproduces a run.

mod common;

use common::SplitMix64;
use glam::DVec3;
use rtl_model::svo::{LeafAttr, LeafSet, SvoImage};
use svo_sim::models::reference::walk::{walk_box, walk_box_clipped, WalkCounters, WalkHit};

/// A uniform f64 in [0, 1).
fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn below(r: &mut SplitMix64, n: u64) -> u64 {
    r.next_u64() % n
}

/// A direction component: ordinary, exactly ±0, or tiny (either side of 1e-150).
fn component(r: &mut SplitMix64) -> f64 {
    let sign = if r.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
    match below(r, 10) {
        0 => 0.0 * sign,
        1 => 1e-160 * sign,
        2 => 1e-20 * sign,
        _ => (unit(r) * 2.0 - 1.0).max(-1.0),
    }
}

/// One random model: (image, octree corner, solid box lo, solid box hi), in model coordinates.
fn model(r: &mut SplitMix64) -> (SvoImage, DVec3, DVec3, DVec3) {
    let depth = 3 + below(r, 3) as u8;
    let side = 1u32 << depth;
    // A cluster box [c0, c1) inside the cube, from one voxel to the whole cube.
    let mut c0 = [0u32; 3];
    let mut c1 = [0u32; 3];
    for k in 0..3 {
        let a = below(r, u64::from(side)) as u32;
        let b = below(r, u64::from(side)) as u32;
        c0[k] = a.min(b);
        c1[k] = a.max(b) + 1;
    }
    let density = 0.05 + unit(r) * 0.5;
    let mut leaves = Vec::new();
    for x in c0[0]..c1[0] {
        for y in c0[1]..c1[1] {
            for z in c0[2]..c1[2] {
                if unit(r) < density {
                    leaves.push((
                        [x, y, z],
                        LeafAttr::new([200, 100, 50, 255], [0.0, 0.0, 1.0]),
                    ));
                }
            }
        }
    }
    if leaves.is_empty() {
        leaves.push((c0, LeafAttr::new([1, 2, 3, 255], [1.0, 0.0, 0.0])));
    }
    let mut smin = [u32::MAX; 3];
    let mut smax = [0u32; 3];
    for (c, _) in &leaves {
        for k in 0..3 {
            smin[k] = smin[k].min(c[k]);
            smax[k] = smax[k].max(c[k]);
        }
    }
    let set = LeafSet::from_coords(depth, leaves).expect("coordinates fit the depth");
    let image = SvoImage::build(&set).expect("small leaf set builds");
    let base: [f64; 3] = std::array::from_fn(|_| below(r, 41) as f64 - 20.0);
    let base = DVec3::from_array(base);
    let solid_lo = base + DVec3::from_array(smin.map(f64::from));
    let solid_hi = base + DVec3::from_array(smax.map(|v| f64::from(v + 1)));
    (image, base, solid_lo, solid_hi)
}

/// A ray for the model: one of the families in the module doc.
fn ray(r: &mut SplitMix64, lo: DVec3, hi: DVec3, s_lo: DVec3, s_hi: DVec3) -> (DVec3, DVec3) {
    let side = hi.x - lo.x;
    let in_box = |r: &mut SplitMix64, a: DVec3, b: DVec3| {
        DVec3::new(
            a.x + unit(r) * (b.x - a.x),
            a.y + unit(r) * (b.y - a.y),
            a.z + unit(r) * (b.z - a.z),
        )
    };
    // An integer or half-integer point of the expanded box (voxel planes, edges, centres).
    let grid = |r: &mut SplitMix64| {
        DVec3::from_array(std::array::from_fn(|k| {
            let v = (lo[k] - 2.0) + below(r, 2 * (side as u64 + 4)) as f64 * 0.5;
            if k == 0 {
                v
            } else {
                v.floor() + if r.next_u64() & 3 == 0 { 0.5 } else { 0.0 }
            }
        }))
    };
    match below(r, 5) {
        0 => {
            // Oblique, from outside, aimed into the solid box.
            let o = in_box(r, lo - side, hi + side);
            let target = in_box(r, s_lo, s_hi);
            (o, target - o)
        }
        1 => {
            // Anywhere, any direction (tiny and zero components included).
            let o = in_box(r, lo - side * 0.5, hi + side * 0.5);
            (o, DVec3::new(component(r), component(r), component(r)))
        }
        2 | 3 => {
            // From the grid, axis-aligned or with zero components of either sign.
            let o = grid(r);
            let mut d = DVec3::new(component(r), component(r), component(r));
            if below(r, 2) == 0 {
                let k = below(r, 3) as usize;
                let s = if r.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
                d = DVec3::ZERO;
                d[k] = s;
                for j in 0..3 {
                    if j != k && r.next_u64() & 1 == 0 {
                        d[j] = -0.0;
                    }
                }
            }
            (o, d)
        }
        _ => {
            // Inside the solid box.
            let o = in_box(r, s_lo, s_hi);
            (o, DVec3::new(component(r), component(r), component(r)))
        }
    }
}

fn same(a: &Option<WalkHit>, b: &Option<WalkHit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.t.to_bits() == b.t.to_bits()
                && a.voxel == b.voxel
                && a.level == b.level
                && a.attr == b.attr
                && a.face_normal.to_array().map(f64::to_bits)
                    == b.face_normal.to_array().map(f64::to_bits)
        }
        _ => false,
    }
}

#[test]
fn clipped_walk_is_bit_identical_to_the_unclipped_walk() {
    let seed = common::test_seed();
    println!("seed = {seed} (SVO_TEST_SEED reproduces it)");
    let mut r = SplitMix64::derive(seed, "walk_clip");
    let (mut rays, mut hits) = (0u64, 0u64);
    let mut full = WalkCounters::default();
    let mut clipped = WalkCounters::default();
    for m in 0..60 {
        let (image, lo, s_lo, s_hi) = model(&mut r);
        let hi = lo + DVec3::splat(f64::from(1u32 << image.depth()));
        for _ in 0..1500 {
            let (o, d) = ray(&mut r, lo, hi, s_lo, s_hi);
            let a = walk_box(&image, lo, hi, o, d, &mut full);
            let b = walk_box_clipped(&image, lo, hi, s_lo, s_hi, o, d, &mut clipped);
            assert!(
                same(&a, &b),
                "seed = {seed}, model {m}: octree [{lo}, {hi}], solid [{s_lo}, {s_hi}], \
                 ray o = {o:?}, d = {d:?}: unclipped {a:?}, clipped {b:?}"
            );
            rays += 1;
            hits += u64::from(a.is_some());
        }
    }
    println!(
        "{rays} rays, {hits} hits; steps {} → {}, fetches {} → {}",
        full.steps, clipped.steps, full.fetches, clipped.fetches
    );
    // Enough hits for the comparison to mean something, and the clip must do work.
    assert!(hits * 5 > rays, "only {hits} hits in {rays} rays");
    assert!(clipped.steps < full.steps && clipped.fetches < full.fetches);
}

/// A ray whose t-values at the root hold a NaN (a NaN origin or direction component, or an
/// infinite origin on an axis whose direction is infinite too: t = ∞·0) hits nothing in either
/// walk and takes no step: the walk's compare-selects (`tmax`, `tmin`) rely on no t being NaN,
/// and `f64::max` would instead drop the NaN axis and walk on with NaN midpoints.
#[test]
fn rays_with_a_nan_t_hit_nothing() {
    let seed = common::test_seed();
    println!("seed = {seed} (SVO_TEST_SEED reproduces it)");
    let mut r = SplitMix64::derive(seed, "walk_clip_nan");
    let mut rays = 0u64;
    for m in 0..20 {
        let (image, lo, s_lo, s_hi) = model(&mut r);
        let hi = lo + DVec3::splat(f64::from(1u32 << image.depth()));
        for _ in 0..200 {
            let (o, d) = ray(&mut r, lo, hi, s_lo, s_hi);
            let k = below(&mut r, 3) as usize;
            let sign = if r.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
            let (mut o, mut d) = (o.to_array(), d.to_array());
            match below(&mut r, 3) {
                0 => o[k] = f64::NAN,
                1 => d[k] = f64::NAN * sign,
                _ => (o[k], d[k]) = (f64::INFINITY * sign, f64::INFINITY * sign),
            }
            let (o, d) = (DVec3::from_array(o), DVec3::from_array(d));
            let mut cnt = WalkCounters::default();
            let a = walk_box(&image, lo, hi, o, d, &mut cnt);
            let b = walk_box_clipped(&image, lo, hi, s_lo, s_hi, o, d, &mut cnt);
            assert!(
                a.is_none() && b.is_none() && cnt.steps == 0,
                "seed = {seed}, model {m}: octree [{lo}, {hi}], ray o = {o:?}, d = {d:?}: \
                 unclipped {a:?}, clipped {b:?}, {} steps (expected no hit, no step)",
                cnt.steps
            );
            rays += 1;
        }
    }
    println!("{rays} rays with a NaN t, none walked");
}
