//! The seeded generator behind every random transaction: splitmix64, with one independent
//! stream per stage derived from the run's seed and the stage's name, so that adding rows to
//! one stage never changes the rows of another.

/// splitmix64 (Steele, Lea & Flood 2014): every seed, 0 included, gives a full-period stream.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator starting from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The stream of the stage called `label` for the run's `seed` (FNV-1a of the label mixed
    /// into the seed).
    pub fn for_stage(seed: u64, label: &str) -> Self {
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        for byte in label.bytes() {
            h = (h ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
        let mut r = Self(seed ^ h);
        r.next_u64();
        r
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (n > 0; the modulo bias is irrelevant for test stimulus).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }

    /// True with probability 1/n.
    pub fn one_in(&mut self, n: u64) -> bool {
        self.below(n) == 0
    }

    /// A value with a uniformly random number of significant bits (0..=bits, bits ≤ 64), so
    /// small and large magnitudes are equally likely.
    pub fn bits_up_to(&mut self, bits: u32) -> u64 {
        let b = self.below(u64::from(bits.min(64)) + 1) as u32;
        if b == 0 {
            0
        } else {
            self.next_u64() >> (64 - b)
        }
    }

    /// A signed code of a `width`-bit two's-complement field with a random number of
    /// significant bits and a random sign.
    pub fn signed_code(&mut self, width: u32) -> i64 {
        let mag = self.bits_up_to(width.saturating_sub(1)) as i64;
        if self.one_in(2) {
            -mag
        } else {
            mag
        }
    }

    /// A unit vector, uniform on the sphere.
    pub fn unit_vector(&mut self) -> [f64; 3] {
        loop {
            let v = [0, 1, 2].map(|_| self.range(-1.0, 1.0));
            let l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if l2 > 1e-4 && l2 <= 1.0 {
                let l = l2.sqrt();
                return v.map(|c| c / l);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_independent() {
        let a: Vec<u64> = (0..4)
            .map({
                let mut r = Rng::for_stage(7, "sqrt");
                move |_| r.next_u64()
            })
            .collect();
        let mut r = Rng::for_stage(7, "sqrt");
        assert_eq!(a, (0..4).map(|_| r.next_u64()).collect::<Vec<_>>());
        let mut other = Rng::for_stage(7, "reciprocal");
        assert_ne!(a[0], other.next_u64());
        let mut z = Rng::new(0);
        assert!((0..100).all(|_| z.signed_code(40).unsigned_abs() < 1 << 39));
    }
}
