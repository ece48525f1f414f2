//! Square-root vectors: the digit-recurrence unit inside the sphere test, √ of a squared
//! distance (`units::sqrt::sqrt_fx` with the sphere's square-root configuration,
//! uQ16.48 → uQ8.24 truncating by default).
//!
//! Adversarial cases: 0, 1, the largest code, every power of two and its neighbours, perfect
//! squares and their neighbours up to the largest root (the cases where one more or one less
//! root bit is decided by a borrow of exactly zero).

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::fixed::{Overflows, SignalId};
use crate::units::sqrt::{self, sqrt_fx, SqrtConfig};
use crate::vectors::layout::{b, s, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// The square-root stage for a datapath configuration.
pub struct SqrtStage {
    cfg: SqrtConfig,
    timing: Timing,
}

impl SqrtStage {
    /// The sphere unit's square root of `dp`, with the model's latency.
    pub fn new(dp: &DatapathConfig) -> Self {
        let cfg = crate::units::sphere::sqrt_config(&dp.sphere);
        Self {
            cfg,
            timing: Timing {
                latency_cycles: sqrt::latency_cycles(&cfg),
                ii: 1,
            },
        }
    }

    fn valid(&self, x: i64) -> bool {
        x >= self.cfg.input.min_raw() && x <= self.cfg.input.max_raw()
    }
}

impl Stage for SqrtStage {
    type Txn = i64;

    fn name(&self) -> &'static str {
        "sqrt"
    }

    fn description(&self) -> &'static str {
        "one square root per row: radicand in, truncated root and overflow flag out"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.fixed("x", Input, self.cfg.input, "radicand, m^2");
        l.fixed(
            "root",
            Output,
            self.cfg.output,
            "floor of the square root, m",
        );
        l.flag(
            "ov",
            Output,
            "root saturated or negative radicand clamped (never with the default formats)",
        );
        l
    }

    fn adversarial(&self) -> Vec<i64> {
        let max = self.cfg.input.max_raw();
        let mut v = vec![0, 1, 2, 3, 4, 5, max, max - 1, max - 2];
        for k in 0..63 {
            let p = 1i64 << k;
            v.extend([p - 1, p, p + 1]);
        }
        // Perfect squares r² and r² ± 1, from small roots to the largest whose square fits.
        let r_max = max.isqrt();
        let mut roots = vec![1, 2, 3, 7, 255, 256, 65_535, 65_536, r_max, r_max - 1];
        roots.extend((1..32).map(|k| (1i64 << k) - 1));
        roots.extend((1..32).map(|k| 1i64 << k).filter(|&r| r <= r_max));
        for r in roots {
            let sq = r.saturating_mul(r);
            v.extend([sq - 1, sq, sq.saturating_add(1)]);
        }
        dedup(v.into_iter().filter(|&x| self.valid(x)).collect())
    }

    fn random(&self, rng: &mut Rng) -> i64 {
        let max = self.cfg.input.max_raw();
        match rng.below(3) {
            0 => {
                let r = (rng.bits_up_to(32) as i64).min(max.isqrt());
                (r * r + rng.below(3) as i64 - 1).clamp(0, max)
            }
            _ => (rng.bits_up_to(64) as i64).clamp(0, max),
        }
    }

    fn encode(&self, &x: &i64) -> Vec<u128> {
        let mut ov = Overflows::new(&["sqrt"]);
        let root = sqrt_fx(x, &self.cfg, &mut ov, SignalId(0));
        vec![s(x), s(root), b(ov.total() > 0)]
    }

    fn timing(&self) -> Option<Timing> {
        Some(self.timing)
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("radicand_bits", sqrt::radicand_bits(&self.cfg));
        t.param("alignment_shift", sqrt::alignment_shift(&self.cfg));
        t.param("config", self.cfg);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_decode_to_the_model() {
        let st = SqrtStage::new(&DatapathConfig::default());
        let l = st.layout();
        assert_eq!(l.word_bits(), 64 + 32 + 1);
        for x in st.adversarial() {
            let w = l.pack(&st.encode(&x));
            let root = l.read(&w, "root").unwrap_or(-1);
            assert_eq!(l.read(&w, "x"), Some(i128::from(x)));
            // Independent check: root² ≤ x < (root + 1)² (48 → 24 fraction bits, no shift).
            let (r, xx) = (root as u128, x as u128);
            assert!(r * r <= xx && (r + 1) * (r + 1) > xx, "x = {x}, root = {r}");
        }
        assert_eq!(st.timing.latency_cycles, 32);
    }
}
