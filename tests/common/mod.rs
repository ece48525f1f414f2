//! Helpers shared by the integration tests: the run seed, a seeded RNG (`rtl_model`'s), proptest
//! configuration, and construction of test assets (random voxel sets and SDF shapes voxelised
//! through the real builder).
//!
//! Nothing here traverses an octree: the oracles live in [`oracle`] and only read voxel
//! coordinates, never the reference renderer.

// Every test binary that includes this module uses a different subset of it, so unused items
// are expected in each one.
#![allow(dead_code)]

pub mod bad_input;
pub mod cache_bench;
pub mod cocotb;
pub mod mem_bench;
pub mod oracle;
pub mod process;
pub mod report;
pub mod skip;
pub mod traversal;
pub mod vox;

// Not every test binary reaches the shared models.
#[allow(unused_imports)]
pub use skip::shared_vox_dir;

use proptest::test_runner::{Config, RngAlgorithm, TestRng};
use rtl_model::svo::{LeafAttr, LeafSet, SvoImage};
use svo_sim::world::sdf::{Sdf, Shape};

/// Seed used when `SVO_TEST_SEED` is not set (any fixed value would do).
pub const DEFAULT_SEED: u64 = 0x5EED_0C7B_EE00_2019;

/// The run's seed: `SVO_TEST_SEED` (decimal or `0x` hex) or [`DEFAULT_SEED`]. Every random
/// choice in the tests derives from it, so a printed seed reproduces a run exactly.
pub fn test_seed() -> u64 {
    match std::env::var("SVO_TEST_SEED") {
        Ok(s) => {
            let s = s.trim();
            let parsed = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
                Some(hex) => u64::from_str_radix(hex, 16),
                None => s.parse(),
            };
            parsed.unwrap_or_else(|e| panic!("SVO_TEST_SEED={s:?} is not a u64: {e}"))
        }
        Err(_) => DEFAULT_SEED,
    }
}

/// Cases per property: `SVO_PROPTEST_CASES` or `default`.
pub fn proptest_cases(default: u32) -> u32 {
    match std::env::var("SVO_PROPTEST_CASES") {
        Ok(s) => s
            .trim()
            .parse()
            .unwrap_or_else(|e| panic!("SVO_PROPTEST_CASES={s:?} is not a u32: {e}")),
        Err(_) => default,
    }
}

/// Proptest configuration: `cases` cases, no failure files (the seed is the reproduction
/// recipe), room for properties that reject part of what their strategy generates (up to
/// several per accepted case), and a bound on shrinking so that a failure is reported in
/// seconds.
pub fn proptest_config(cases: u32) -> Config {
    Config {
        cases,
        failure_persistence: None,
        max_global_rejects: cases.saturating_mul(4).max(1024),
        max_shrink_iters: 20_000,
        ..Config::default()
    }
}

/// A proptest RNG determined by `seed` and a per-test `stream` number, so that the tests of a
/// binary draw independent sequences from one printed seed.
pub fn proptest_rng(seed: u64, stream: u64) -> TestRng {
    let mut sm = SplitMix64::new(seed ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let mut bytes = [0u8; 32];
    for chunk in bytes.chunks_mut(8) {
        chunk.copy_from_slice(&sm.next_u64().to_le_bytes());
    }
    TestRng::from_seed(RngAlgorithm::ChaCha, &bytes)
}

/// SplitMix64 (Steele, Lea & Flood 2014) with the helpers the tests draw test data with. The
/// generator itself is `rtl_model`'s (`rtl_model::vectors::rng::Rng`, the one behind the
/// vectors, the crowds and the fuzzer), not a copy: it only picks test data, and no test here
/// checks that generator, so sharing it costs no oracle its independence.
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    rng: rtl_model::vectors::rng::Rng,
}

impl SplitMix64 {
    /// A generator starting from `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: rtl_model::vectors::rng::Rng::new(seed),
        }
    }

    /// A generator for a named sub-task, so that adding draws to one task does not shift the
    /// numbers every other task sees (FNV-1a of the label mixed into the seed).
    pub fn derive(seed: u64, label: &str) -> Self {
        Self {
            rng: rtl_model::vectors::rng::Rng::for_stage(seed, label),
        }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in 0..n (n > 0; the modulo bias is irrelevant for test data).
    pub fn below(&mut self, n: u64) -> u64 {
        assert!(n > 0);
        self.next_u64() % n
    }

    /// True with probability p.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// A uniformly chosen element.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len() as u64) as usize]
    }

    /// A unit vector, uniform on the sphere (rejection from the cube).
    pub fn unit_vector(&mut self) -> [f64; 3] {
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if l2 > 1e-4 && l2 <= 1.0 {
                let l = l2.sqrt();
                return [v[0] / l, v[1] / l, v[2] / l];
            }
        }
    }
}

/// A plain attribute: colour from the coordinates so that leaves are distinguishable.
pub fn attr_for(c: [u32; 3]) -> LeafAttr {
    LeafAttr::new([c[0] as u8, c[1] as u8, c[2] as u8, 255], [0.0, 0.0, 1.0])
}

/// Each voxel of a 2^depth grid is solid with probability `density`.
pub fn random_leaf_set(rng: &mut SplitMix64, depth: u8, density: f64) -> LeafSet {
    let n = 1u32 << depth;
    let mut leaves = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                if rng.chance(density) {
                    leaves.push(([x, y, z], attr_for([x, y, z])));
                }
            }
        }
    }
    LeafSet::from_coords(depth, leaves).expect("coordinates fit the depth")
}

/// `count` random axis-aligned blocks of solid voxels: structured content, so that whole
/// octree nodes are empty or full (unlike independent random voxels).
pub fn random_blocks(rng: &mut SplitMix64, depth: u8, count: usize) -> LeafSet {
    let n = u64::from(1u32 << depth);
    let mut leaves = Vec::new();
    for _ in 0..count {
        let mut lo = [0u32; 3];
        let mut hi = [0u32; 3];
        for k in 0..3 {
            let a = rng.below(n) as u32;
            let len = 1 + rng.below(n / 4 + 1) as u32;
            lo[k] = a;
            hi[k] = (a + len).min(n as u32);
        }
        for z in lo[2]..hi[2] {
            for y in lo[1]..hi[1] {
                for x in lo[0]..hi[0] {
                    leaves.push(([x, y, z], attr_for([x, y, z])));
                }
            }
        }
    }
    LeafSet::from_coords(depth, leaves).expect("coordinates fit the depth")
}

/// Every voxel solid.
pub fn full_leaf_set(depth: u8) -> LeafSet {
    let n = 1u32 << depth;
    let all = (0..n).flat_map(move |z| {
        (0..n).flat_map(move |y| (0..n).map(move |x| ([x, y, z], attr_for([x, y, z]))))
    });
    LeafSet::from_coords(depth, all).expect("coordinates fit the depth")
}

/// Exactly the listed voxels.
pub fn leaf_set_of(depth: u8, coords: &[[u32; 3]]) -> LeafSet {
    LeafSet::from_coords(depth, coords.iter().map(|&c| (c, attr_for(c))))
        .expect("coordinates fit the depth")
}

/// A procedural shape voxelised by the real asset builder in a cube of half-size `half`.
pub fn sdf_leaf_set(shape: &Shape, half: f64, depth: u8) -> LeafSet {
    let sdf = Sdf::new(shape, "test shape").expect("valid test shape");
    let leaves = svo_sim::world::assets::voxelize::voxelize(&sdf, half, depth);
    LeafSet::from_sorted_codes(depth, leaves).expect("voxeliser output is valid")
}

/// The memory image of a leaf set.
pub fn build_image(set: &LeafSet) -> SvoImage {
    SvoImage::build(set).expect("small test images always fit")
}

/// `{:e}` of each component plus its exact bit pattern, for failure messages that reproduce
/// a ray exactly.
pub fn fmt_vec(v: [f64; 3]) -> String {
    format!(
        "[{:e}, {:e}, {:e}] (bits [{:#018x}, {:#018x}, {:#018x}])",
        v[0],
        v[1],
        v[2],
        v[0].to_bits(),
        v[1].to_bits(),
        v[2].to_bits()
    )
}
