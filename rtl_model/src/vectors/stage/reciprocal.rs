//! Reciprocal vectors: 1/d of one direction component (`units::reciprocal::reciprocal`:
//! leading-zero normalisation, seed ROM, Newton–Raphson, rounding), with the sign bit that
//! carries −0 from the transform. Also the seed ROM itself as a memory table
//! (`reciprocal_seed.hex`), generated from the model, which the RTL loads with `$readmemh`.
//!
//! Adversarial cases: +0 and −0 (code 0 with either sign bit), the zero threshold and its
//! neighbours (flagged or not), ±1.0, −2.0 and the extreme codes, every power of two and its
//! neighbours, both ends of every fourth ROM interval, and a sign bit that disagrees with a
//! non-zero code (the code's sign must win).

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::fixed::{Format, Overflows, SignalId};
use crate::units::reciprocal::{self, seed_frac_bits, seed_table, ReciprocalConfig};
use crate::vectors::layout::{b, s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Origin, Timing, VectorTable};

/// The reciprocal stage for a datapath configuration.
pub struct ReciprocalStage {
    cfg: ReciprocalConfig,
    unit: reciprocal::ReciprocalUnit,
}

/// One transaction: the direction code and the sign of the value it was rounded from.
pub type ReciprocalTxn = (i64, bool);

impl ReciprocalStage {
    /// The reciprocal unit of `dp`.
    pub fn new(dp: &DatapathConfig) -> Self {
        Self {
            cfg: dp.reciprocal,
            unit: reciprocal::ReciprocalUnit::new(&dp.reciprocal),
        }
    }

    /// Magnitude integer bits k of the output: |d| ≤ 2^−k is flagged zero.
    fn zero_code(&self) -> i64 {
        let out = self.cfg.output;
        let k = i32::from(out.width) - i32::from(out.frac) - i32::from(out.signed);
        let e = i32::from(self.cfg.input.frac) - k;
        if (0..62).contains(&e) {
            1i64 << e
        } else {
            0
        }
    }

    /// The seed ROM as a memory table: entry i in uQ0.(t+2) (top bit always set).
    pub fn seed_rom(&self) -> VectorTable {
        let t = self.cfg.table_bits;
        let bits = seed_frac_bits(t);
        let mut l = Layout::new();
        l.fixed(
            "seed",
            Output,
            Format::uq(0, bits as u8),
            "reciprocal seed for mantissa interval i",
        );
        let mut table = VectorTable::new(
            "reciprocal_seed",
            "seed ROM of the reciprocal unit, 2^table_bits entries, indexed by the mantissa bits after the leading one",
            l.clone(),
        );
        table.package = false;
        table.push_block(
            Origin::Table,
            seed_table(t).into_iter().map(|v| l.pack(&[u(v)])).collect(),
        );
        table.param("table_bits", t);
        table
    }
}

impl Stage for ReciprocalStage {
    type Txn = ReciprocalTxn;

    fn name(&self) -> &'static str {
        "reciprocal"
    }

    fn description(&self) -> &'static str {
        "one reciprocal per row: direction component and its sign bit in; 1/d and the zero, negative, flushed and overflow flags out"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.fixed(
            "d",
            Input,
            self.cfg.input,
            "direction component (local frame)",
        );
        l.flag(
            "sign_negative",
            Input,
            "sign of the unrounded component (decides the sign of a zero code: -0)",
        );
        l.fixed(
            "inv",
            Output,
            self.cfg.output,
            "1/d; +-max when zero is set",
        );
        l.flag(
            "zero",
            Output,
            "|d| at or below the zero threshold: treat as 1/0",
        );
        l.flag(
            "negative",
            Output,
            "d is negative (the code's sign, or sign_negative for code 0)",
        );
        l.flag("flushed", Output, "a non-zero code flagged zero");
        l.flag("ov", Output, "the final rounding saturated");
        l
    }

    fn adversarial(&self) -> Vec<ReciprocalTxn> {
        let inp = self.cfg.input;
        let (lo, hi) = (inp.min_raw(), inp.max_raw());
        let z = self.zero_code();
        let one = 1i64 << inp.frac.clamp(0, 62);
        let mut v: Vec<ReciprocalTxn> = vec![(0, false), (0, true)];
        for c in [
            1,
            2,
            3,
            z - 1,
            z,
            z + 1,
            z + 2,
            one - 1,
            one,
            one + 1,
            hi,
            hi - 1,
        ] {
            v.extend([(c, false), (-c, true), (c, true), (-c, false)]);
        }
        v.extend([(lo, true), (lo + 1, true)]);
        for k in 0..63 {
            let p = 1i64 << k;
            v.extend([(p - 1, false), (p, false), (p + 1, false), (-p, true)]);
        }
        // Both ends of every fourth seed-ROM interval, at a mid-range exponent.
        let t = u32::from(self.cfg.table_bits.min(16));
        let lead = (inp.width as u32).saturating_sub(12).max(t + 1);
        for idx in (0..1i64 << t).step_by(4) {
            let start = ((1i64 << t) + idx) << (lead - t);
            let end = (((1i64 << t) + idx + 1) << (lead - t)) - 1;
            v.extend([(start, false), (-end, true)]);
        }
        dedup(v.into_iter().filter(|&(c, _)| c >= lo && c <= hi).collect())
    }

    fn random(&self, rng: &mut Rng) -> ReciprocalTxn {
        let inp = self.cfg.input;
        let c = rng
            .signed_code(u32::from(inp.width))
            .clamp(inp.min_raw(), inp.max_raw());
        (c, if c == 0 { rng.one_in(2) } else { c < 0 })
    }

    fn encode(&self, &(d, neg): &ReciprocalTxn) -> Vec<u128> {
        let mut ov = Overflows::new(&["reciprocal"]);
        let r = self.unit.eval(d, neg, &mut ov, SignalId(0));
        vec![
            s(d),
            b(neg),
            s(r.raw),
            b(r.zero),
            b(r.negative),
            b(r.flushed),
            b(ov.total() > 0),
        ]
    }

    fn timing(&self) -> Option<Timing> {
        Some(Timing {
            latency_cycles: reciprocal::latency_cycles(&self.cfg),
            ii: 1,
        })
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", self.cfg);
        t.param(
            "mantissa_frac_bits",
            reciprocal::mantissa_frac_bits(&self.cfg),
        );
        t.param("zero_threshold_code", self.zero_code());
        t.param("seed_rom_file", "reciprocal_seed.hex");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_decode_to_the_model() {
        let st = ReciprocalStage::new(&DatapathConfig::default());
        let l = st.layout();
        let cases = st.adversarial();
        assert!(cases.contains(&(0, true)) && cases.contains(&(0, false)));
        for (d, neg) in cases {
            let w = l.pack(&st.encode(&(d, neg)));
            assert_eq!(l.read(&w, "d"), Some(i128::from(d)));
            let inv = l.read(&w, "inv").unwrap_or(0);
            let zero = l.read(&w, "zero") == Some(1);
            // Independent check: a non-zero result is within 2^-20 relative of 1/d.
            if !zero {
                let exact = (1u64 << 30) as f64 / d as f64;
                let got = inv as f64 / (1u64 << 30) as f64; // sQ22.30
                assert!((got - exact).abs() <= exact.abs() * 1e-6 + 1e-7, "d = {d}");
            } else {
                assert!(d.unsigned_abs() <= 1 << 9, "d = {d}");
            }
        }
        assert_eq!(st.seed_rom().rows.len(), 256);
    }
}
