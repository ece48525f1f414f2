//! A seeded stimulus stream for the cycle layer's own unit tests (FIFOs, unit lanes, the
//! node memory's MSHR table and bank schedule).
//!
//! Pipeline position: none — test support only. The project's seeded generator
//! (`vectors::rng`) lives in the layer above `cycle`, which `cycle` may not import
//! (docs/architecture.md §1, `tests/layering.rs`); the tests here need only a reproducible
//! stream, not that generator's per-stage streams, so a 64-bit LCG (Knuth's MMIX constants,
//! high bits taken) serves.

/// A reproducible stream of pseudo-random numbers from a printed seed.
pub(crate) struct TestRng(u64);

impl TestRng {
    /// The stream of `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 31 bits (the state's high bits).
    pub(crate) fn next_bits(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }

    /// Uniform enough in `0..n` for test stimulus (`n` of 0 is taken as 1).
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        self.next_bits() % n.max(1)
    }
}
