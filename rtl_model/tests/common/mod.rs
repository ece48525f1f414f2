//! Helpers shared by `rtl_model`'s integration tests: the run seed and a seeded RNG (the crate's).
//! Every random test prints its seed; `SVO_TEST_SEED` (decimal) replays a run.

// Each test binary uses a different subset.
#![allow(dead_code)]

/// `SVO_TEST_SEED` if set, else the test's own default.
pub fn seed(default: u64) -> u64 {
    std::env::var("SVO_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// [`seed`] for the test `test`, printed so that a failing run can be replayed.
pub fn printed_seed(test: &str, default: u64) -> u64 {
    let s = seed(default);
    println!("{test}: SVO_TEST_SEED={s}");
    s
}

/// splitmix64 with the helpers the tests draw stimulus with. The generator is the crate's own
/// (`rtl_model::vectors::rng::Rng`, behind the HDL vectors), not a copy: it only picks test
/// inputs, and no test here checks that generator, so sharing it costs no oracle its
/// independence.
pub struct Rng(rtl_model::vectors::rng::Rng);

impl Rng {
    /// A generator starting from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(rtl_model::vectors::rng::Rng::new(seed))
    }

    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in 0..n (n > 0; the modulo bias is irrelevant for tests).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    /// Uniform in lo..=hi_incl.
    pub fn range(&mut self, lo: i64, hi_incl: i64) -> i64 {
        lo + self.below((hi_incl - lo + 1) as u64) as i64
    }

    /// 128 random bits: two draws, the first in the high half.
    pub fn i128(&mut self) -> i128 {
        ((u128::from(self.next()) << 64) | u128::from(self.next())) as i128
    }

    /// A uniformly chosen element.
    pub fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len() as u64) as usize]
    }

    /// True with probability `p_percent` / 100.
    pub fn chance_percent(&mut self, p_percent: u64) -> bool {
        self.next() % 100 < p_percent
    }

    /// Uniform in [lo, hi).
    pub fn f(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A value with a random number of significant bits (0..=bits), so small and large
    /// magnitudes are equally likely.
    pub fn bits_up_to(&mut self, bits: u32) -> u64 {
        let b = self.below(u64::from(bits) + 1) as u32;
        if b == 0 {
            0
        } else {
            self.next() >> (64 - b)
        }
    }
}
