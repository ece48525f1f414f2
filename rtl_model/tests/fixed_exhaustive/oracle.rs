//! The oracle and checking harness of the fixed-point tests (`main.rs` and `conversions.rs` of
//! this folder): plain integer maths that computes, from each operation's definition, the code
//! and the overflow count `rtl_model::fixed` must give; and a [`Checker`] that runs cases
//! against it and reports the first disagreements.
//!
//! Why the oracle is independent of `ops.rs`: it shares no code with it and uses a different
//! method. Values are exact rationals n / 2^k (i128 n); rounding takes `div_euclid` /
//! `rem_euclid` against the divisor and compares twice the remainder with the divisor, then
//! applies each mode from its definition (floor, toward zero, ties toward +∞ / zero / −∞ /
//! away from zero / even). Where an i128 rational would overflow (large shifts, random
//! doubles) a second oracle reads the dropped bits by position (bit s−1 = "half", any lower
//! bit = "more than half") on the infinite two's-complement extension; that oracle is itself
//! checked against the division oracle (`oracle_bit_positions_match_division` in `main.rs`). Overflow is an explicit range comparison against
//! ranges built from powers of two, and wrap is `rem_euclid(2^W)` then sign adjustment (beyond
//! i128, from the exact low 64 bits). Doubles are decomposed from their bit pattern into
//! mantissa · 2^exponent, so the oracle sees their exact value, never a scaled double.

use std::cmp::Ordering;
use std::time::Instant;

use rtl_model::fixed::{Format, OverflowMode, Overflows, Quant, SignalId};

/// Every quantisation mode.
pub const QUANTS: [Quant; 7] = [
    Quant::Trn,
    Quant::TrnZero,
    Quant::Rnd,
    Quant::RndZero,
    Quant::RndMinInf,
    Quant::RndInf,
    Quant::RndConv,
];
/// Every overflow mode.
pub const OVERFLOWS: [OverflowMode; 3] =
    [OverflowMode::Sat, OverflowMode::SatSym, OverflowMode::Wrap];

/// Width of the exhaustively tested formats.
pub const W: u8 = 6;
/// Operand fraction counts of the exhaustive add / sub / mul tests.
pub const OPERAND_FRACS: [i32; 5] = [0, 2, 5, 7, -1];
/// Result fraction counts of the exhaustive add / sub / mul tests.
pub const OUT_FRACS: [i32; 6] = [-3, 0, 2, 5, 8, 11];
/// Every valid fraction count of a 6-bit format (F ≥ −58 keeps W − F ≤ 64).
pub const ALL_FRACS_6: std::ops::RangeInclusive<i32> = -58..=62;

/// The run's seed: `SVO_TEST_SEED` or this suite's default.
pub fn seed() -> u64 {
    super::common::seed(0x5eed_f1ed_2024)
}

/// A format from its fields (`frac` as an i32, checked to fit).
pub fn format(signed: bool, width: u8, frac: i32, quant: Quant, overflow: OverflowMode) -> Format {
    Format {
        signed,
        width,
        frac: i8::try_from(frac).expect("frac fits i8"),
        quant,
        overflow,
    }
}

// ---------------------------------------------------------------------------------------------
// Oracle
// ---------------------------------------------------------------------------------------------

/// 2^e (e ≤ 126).
pub fn pow2(e: u32) -> i128 {
    assert!(e <= 126, "2^{e} does not fit i128");
    1i128 << e
}

/// Picks floor or ceil of an inexact value from the mode's definition. `vs_half` compares the
/// dropped fraction (value − floor) with one half.
pub fn choose(floor: i128, negative: bool, vs_half: Ordering, quant: Quant) -> i128 {
    let ceil = floor + 1;
    let toward_zero = if negative { ceil } else { floor };
    let away_from_zero = if negative { floor } else { ceil };
    match quant {
        Quant::Trn => floor,
        Quant::TrnZero => toward_zero,
        _ => match vs_half {
            Ordering::Less => floor,
            Ordering::Greater => ceil,
            Ordering::Equal => match quant {
                Quant::Rnd => ceil,
                Quant::RndZero => toward_zero,
                Quant::RndMinInf => floor,
                Quant::RndInf => away_from_zero,
                Quant::RndConv => {
                    if floor.rem_euclid(2) == 0 {
                        floor
                    } else {
                        ceil
                    }
                }
                Quant::Trn | Quant::TrnZero => unreachable!(),
            },
        },
    }
}

/// `num / den` (den > 0) rounded to an integer by `quant`: Euclidean division, then twice the
/// remainder against the divisor.
pub fn round_div(num: i128, den: i128, quant: Quant) -> i128 {
    assert!(den > 0);
    // Hardware i64 division when both fit (the exhaustive groups), i128 otherwise.
    let (floor, rem) = match (i64::try_from(num), i64::try_from(den)) {
        (Ok(n), Ok(d)) => (i128::from(n.div_euclid(d)), i128::from(n.rem_euclid(d))),
        _ => (num.div_euclid(den), num.rem_euclid(den)),
    };
    if rem == 0 {
        return floor;
    }
    choose(floor, num < 0, (2 * rem).cmp(&den), quant)
}

/// Bit i of the infinite two's-complement extension of `raw`.
pub fn bit_at(raw: i128, i: u32) -> bool {
    if i >= 127 {
        raw < 0
    } else {
        (raw >> i) & 1 == 1
    }
}

/// Whether any of bits 0..i of the infinite two's-complement extension of `raw` is set.
pub fn any_below(raw: i128, i: u32) -> bool {
    match i {
        0 => false,
        1..=126 => raw & (pow2(i) - 1) != 0,
        127 => raw & i128::MAX != 0,
        // Bits 127.. are sign copies: set for negative raw, and raw ≠ 0 otherwise.
        _ => raw != 0,
    }
}

/// `raw / 2^s` rounded by `quant`, for any s, by bit positions (i128-safe).
pub fn round_shift_bits(raw: i128, s: u32, quant: Quant) -> i128 {
    let floor = raw >> s.min(127);
    if !any_below(raw, s) {
        return floor;
    }
    let vs_half = match (bit_at(raw, s - 1), any_below(raw, s - 1)) {
        (false, _) => Ordering::Less,
        (true, false) => Ordering::Equal,
        (true, true) => Ordering::Greater,
    };
    choose(floor, raw < 0, vs_half, quant)
}

/// Exact value n / 2^k.
#[derive(Clone, Copy, Debug)]
pub struct Rat {
    /// Numerator.
    pub n: i128,
    /// Power of two of the denominator.
    pub k: u32,
}

/// raw · 2^−frac.
pub fn rat(raw: i128, frac: i32) -> Rat {
    if frac >= 0 {
        Rat {
            n: raw,
            k: frac as u32,
        }
    } else {
        Rat {
            n: raw * pow2(frac.unsigned_abs()),
            k: 0,
        }
    }
}

/// a + b, exactly.
pub fn rat_add(a: Rat, b: Rat) -> Rat {
    let k = a.k.max(b.k);
    Rat {
        n: a.n * pow2(k - a.k) + b.n * pow2(k - b.k),
        k,
    }
}

/// −a, exactly.
pub fn rat_neg(a: Rat) -> Rat {
    Rat { n: -a.n, k: a.k }
}

/// a · b, exactly.
pub fn rat_mul(a: Rat, b: Rat) -> Rat {
    Rat {
        n: a.n * b.n,
        k: a.k + b.k,
    }
}

/// x · 2^frac rounded to an integer (the code of x in a format with `frac` fraction bits).
pub fn round_rat(x: Rat, frac: i32, quant: Quant) -> i128 {
    let (num, den) = if frac >= 0 {
        (x.n * pow2(frac as u32), pow2(x.k))
    } else {
        (x.n, pow2(x.k + frac.unsigned_abs()))
    };
    round_div(num, den, quant)
}

/// A rounded code before overflow handling.
#[derive(Clone, Copy, Debug)]
pub enum Exact {
    Int(i128),
    /// Beyond i128 (≥ 2^70 in magnitude here): only the sign and the low 64 bits matter.
    Huge {
        negative: bool,
        low64: u64,
    },
}

/// Expected outcome: result code and whether the overflow counter goes up (by one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Expected {
    /// The result code.
    pub code: i64,
    /// The overflow counter goes up by one.
    pub counted: bool,
}

/// The code range of a format, from its definition (unsigned 64-bit is capped at i64::MAX
/// because raw codes are i64; see `edges`).
pub fn code_range(signed: bool, width: u8) -> (i128, i128) {
    let w = u32::from(width);
    if signed {
        (-pow2(w - 1), pow2(w - 1) - 1)
    } else {
        (0, (pow2(w) - 1).min(i128::from(i64::MAX)))
    }
}

/// `v` wrapped into the code range of a `width`-bit format (two's complement if signed).
pub fn wrap_to(v: i128, signed: bool, width: u8) -> i128 {
    let w = u32::from(width);
    let r = v.rem_euclid(pow2(w));
    if signed && r >= pow2(w - 1) {
        r - pow2(w)
    } else {
        r
    }
}

/// Overflow handling of a rounded code by explicit range comparison.
pub fn resolve(x: Exact, signed: bool, width: u8, mode: OverflowMode) -> Expected {
    let (lo, hi) = code_range(signed, width);
    // SatSym: a signed result never takes the most negative code.
    let lo_ok = if mode == OverflowMode::SatSym && signed {
        lo + 1
    } else {
        lo
    };
    let (code, counted) = match x {
        Exact::Int(v) if (lo_ok..=hi).contains(&v) => (v, false),
        Exact::Int(v) => match mode {
            OverflowMode::Wrap => (wrap_to(v, signed, width), true),
            _ if v < lo_ok => (lo_ok, true),
            _ => (hi, true),
        },
        Exact::Huge { negative, low64 } => match mode {
            OverflowMode::Wrap => (wrap_to(i128::from(low64), signed, width), true),
            _ if negative => (lo_ok, true),
            _ => (hi, true),
        },
    };
    Expected {
        code: i64::try_from(code).expect("expected code fits i64"),
        counted,
    }
}

/// Rounded code of raw · 2^−from_frac in a format with `out_frac` fraction bits, i128-safe for
/// any shift (bit-position oracle).
pub fn quantize_oracle_wide(raw: i128, from_frac: i32, out_frac: i32, quant: Quant) -> Exact {
    let shift = from_frac - out_frac;
    if shift >= 0 {
        return Exact::Int(round_shift_bits(raw, shift as u32, quant));
    }
    let k = shift.unsigned_abs();
    if raw == 0 {
        return Exact::Int(0);
    }
    match (k <= 126).then(|| raw.checked_mul(pow2(k))).flatten() {
        Some(v) => Exact::Int(v),
        None => Exact::Huge {
            negative: raw < 0,
            low64: if k >= 64 {
                0
            } else {
                ((raw as u128) << k) as u64
            },
        },
    }
}

/// |x| = m · 2^e, exactly, from the bit pattern of a finite double.
pub fn decompose(x: f64) -> (bool, u64, i32) {
    let bits = x.to_bits();
    let negative = bits >> 63 == 1;
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let mant = bits & ((1u64 << 52) - 1);
    assert!(biased != 0x7ff, "finite doubles only");
    if biased == 0 {
        (negative, mant, -1074)
    } else {
        (negative, mant | (1u64 << 52), biased - 1075)
    }
}

/// Rounded code of the exact value of a finite double in a format with `frac` fraction bits.
pub fn from_f64_oracle(x: f64, frac: i32, quant: Quant) -> Exact {
    let (negative, m, e) = decompose(x);
    let n = if negative {
        -i128::from(m)
    } else {
        i128::from(m)
    };
    let t = e + frac; // value · 2^frac = n · 2^t
    if m == 0 {
        Exact::Int(0)
    } else if t >= 0 {
        if t <= 70 {
            Exact::Int(n * pow2(t as u32))
        } else {
            // n · 2^t with t ≥ 64: the low 64 bits are zero.
            Exact::Huge { negative, low64: 0 }
        }
    } else {
        Exact::Int(round_shift_bits(n, t.unsigned_abs(), quant))
    }
}

// ---------------------------------------------------------------------------------------------
// Checking harness
// ---------------------------------------------------------------------------------------------

/// Runs cases, compares code and counter change with the oracle, keeps the first failures.
pub struct Checker {
    ov: Overflows,
    sig: SignalId,
    cases: u64,
    failures: u64,
    first: Vec<String>,
}

impl Checker {
    /// A checker with a fresh set of overflow counters.
    pub fn new() -> Self {
        Self {
            ov: Overflows::new(&["before", "dut", "after"]),
            sig: SignalId(1),
            cases: 0,
            failures: 0,
            first: Vec::new(),
        }
    }

    /// Runs one case: `call` computes the result on the shared counters, `ctx` names the case
    /// for a failure message.
    pub fn run(
        &mut self,
        exp: Expected,
        call: impl FnOnce(&mut Overflows, SignalId) -> i64,
        ctx: impl FnOnce() -> String,
    ) {
        self.cases += 1;
        let (before, total_before) = (self.ov.count(self.sig), self.ov.total());
        let got = call(&mut self.ov, self.sig);
        let delta = self.ov.count(self.sig) - before;
        let total_delta = self.ov.total() - total_before;
        if got != exp.code || delta != u64::from(exp.counted) || total_delta != delta {
            self.failures += 1;
            if self.first.len() < 12 {
                self.first.push(format!(
                    "{}: expected code {} counted {}, got code {} counter +{} (all signals +{})",
                    ctx(),
                    exp.code,
                    u8::from(exp.counted),
                    got,
                    delta,
                    total_delta
                ));
            }
        }
    }

    /// Prints the counts and fails with the first disagreements, if any.
    pub fn finish(self, group: &str, t0: Instant) {
        println!(
            "{group}: {} cases, {} failures, {:.2?}",
            self.cases,
            self.failures,
            t0.elapsed()
        );
        assert!(
            self.failures == 0,
            "{group}: {} of {} cases disagree with the oracle; first ones:\n{}",
            self.failures,
            self.cases,
            self.first.join("\n")
        );
    }
}

/// Every code of a 6-bit format, from the definition.
pub fn codes(signed: bool) -> std::ops::RangeInclusive<i64> {
    let (lo, hi) = code_range(signed, W);
    lo as i64..=hi as i64
}

/// `s6f2`-style name of a format for messages.
pub fn fmt_name(signed: bool, width: u8, frac: i32) -> String {
    format!("{}{}f{}", if signed { "s" } else { "u" }, width, frac)
}
