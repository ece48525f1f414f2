//! Square root by the restoring radix-2 digit recurrence: one root bit per pipeline stage.
//!
//! Pipeline position: inside the bounding-sphere unit, once per (ray, instance), where the
//! entry distance t_enter = l·d − √(r² − p²) needs the root of a squared distance in m². It
//! uses no multiplier (each stage is one subtractor and a multiplexer), so it costs LUTs and
//! flip-flops, never DSPs.
//!
//! Two layers:
//! - [`isqrt`] / [`isqrt_digits`]: the integer core, ⌊√x⌋ and the remainder x − ⌊√x⌋², bit for
//!   bit what an N-bit pipelined RTL core computes (N = radicand bits, N/2 stages).
//! - [`sqrt_fx`]: the fixed-point wrapper. It aligns the input code so that the integer root
//!   carries the output's fraction bits, runs the core and rounds/saturates into the output
//!   format (truncation toward −∞ by default); [`sqrt_fx_ceil`] rounds up instead, for callers
//!   that need an upper bound. Negative inputs are clamped to 0 and counted.
//!
//! `docs/units/sqrt.md` has the stage-by-stage description, widths, latency and the error
//! bound's derivation ([`error_bound`]).

use crate::fixed::{quantize, Format, Overflows, Quant, SignalId};
use serde::{Deserialize, Serialize};

/// Widest radicand the model's core handles (bits): 64 digits. Formats are at most 64 bits
/// wide, so an alignment shift can only push a code past this if the root could not fit any
/// output format anyway (see [`sqrt_fx`]).
const MAX_RADICAND_BITS: u32 = 128;

/// One stage of the restoring recurrence: brings down the next radicand bit pair `pair`
/// (0..=3) and decides one root bit.
///
/// With j root bits decided, `root` < 2^j and the partial remainder `rem` ≤ 2·root < 2^(j+1)
/// (because (root + 1)² > the radicand prefix). The stage forms the (j+3)-bit shifted
/// remainder 4·rem + pair and subtracts the (j+2)-bit trial 4·root + 1; a non-negative
/// difference (no borrow) means the next root bit is 1 and the difference is kept, otherwise
/// the shifted remainder is restored (a multiplexer, not a second adder).
#[inline]
fn stage(root: u128, rem: u128, pair: u128) -> (u128, u128) {
    let shifted = (rem << 2) | pair;
    let trial = (root << 2) | 1;
    if shifted >= trial {
        ((root << 1) | 1, shifted - trial)
    } else {
        (root << 1, shifted)
    }
}

/// Runs `digits` stages on the radicand `x` (< 2^(2·digits)), most significant pair first.
/// Returns (⌊√x⌋, x − ⌊√x⌋²). `digits` ≤ 64.
#[inline]
fn recurrence(x: u128, digits: u32) -> (u128, u128) {
    let (mut root, mut rem) = (0u128, 0u128);
    for i in (0..digits.min(MAX_RADICAND_BITS / 2)).rev() {
        (root, rem) = stage(root, rem, (x >> (2 * i)) & 3);
    }
    (root, rem)
}

/// Digits (stages) a radicand of `bits` bits needs: ⌈bits/2⌉, capped at 64.
#[inline]
fn digits_for(bits: u32) -> u32 {
    bits.min(MAX_RADICAND_BITS).div_ceil(2)
}

/// ⌊√x⌋ for a 64-bit radicand: the 64-bit core, 32 stages (see [`isqrt_digits`]).
///
/// ```
/// use rtl_model::units::sqrt::isqrt;
/// assert_eq!(isqrt(0), 0);
/// assert_eq!(isqrt(99), 9);
/// assert_eq!(isqrt(100), 10);
/// assert_eq!(isqrt(u64::MAX), u64::from(u32::MAX));
/// ```
pub fn isqrt(x: u64) -> u64 {
    isqrt_digits(x, 64).0
}

/// (⌊√x⌋, x − ⌊√x⌋²) from an `in_bits`-wide core: `in_bits`/2 stages, one root bit each.
///
/// Hardware: the radicand port is `in_bits` wide, so bits of `x` at or above `in_bits` do not
/// exist in the RTL and are ignored here too (callers pass codes that fit). An odd `in_bits`
/// is zero-extended to the next even width (a leading zero bit changes no root bit), and
/// widths above 64 are taken as 64. The root has `in_bits`/2 bits, the remainder at most
/// `in_bits`/2 + 1 (it is ≤ 2·root); the widest intermediate, the shifted remainder of the
/// last stage, has `in_bits`/2 + 2 bits.
///
/// ```
/// use rtl_model::units::sqrt::isqrt_digits;
/// assert_eq!(isqrt_digits(200, 8), (14, 4)); // 14² = 196
/// assert_eq!(isqrt_digits(0x1_0000, 16), (0, 0)); // bit 16 is outside a 16-bit port
/// ```
pub fn isqrt_digits(x: u64, in_bits: u32) -> (u64, u64) {
    let bits = in_bits.min(64);
    let port = if bits >= 64 {
        x
    } else {
        x & ((1u64 << bits) - 1)
    };
    let (root, rem) = recurrence(u128::from(port), digits_for(bits));
    // root < 2^32 and rem ≤ 2·root < 2^33: both fit u64.
    (root as u64, rem as u64)
}

/// Formats of the fixed-point square-root unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SqrtConfig {
    /// Radicand in (should be unsigned; a signed format's negative codes are clamped to 0
    /// and counted).
    pub input: Format,
    /// Root out. Its quantisation mode picks the rounding: `Trn`/`TrnZero` truncate (the
    /// root is never above √x), the round-to-nearest modes round with one extra digit and a
    /// sticky bit. Its overflow mode resolves a root too large for it (counted).
    pub output: Format,
}

impl Default for SqrtConfig {
    /// uQ16.48 in, uQ8.24 out (truncating, saturating).
    ///
    /// Why: the radicand is a squared distance in m² from the sphere unit (its `sq` format,
    /// uQ16.48: up to 2^15 m² with a 64-bit unsigned code — spheres up to 181 m radius — and
    /// 2^-48 m² resolution). The root of a code with 48 fraction bits has exactly 24, so the
    /// output uQ8.24 (roots below 256 m, LSB 2^-24 m ≈ 60 nm) needs no alignment shift: the
    /// radicand is the input code itself and no input bit is dropped. Finer output bits
    /// would only resolve the input's quantisation (near 0, √(x + LSB_in) − √x can already be
    /// 2^-24 m). Cost: a 64-bit radicand, 32 stages, no DSP.
    fn default() -> Self {
        Self {
            input: Format::uq(16, 48),
            output: Format::uq(8, 24),
        }
    }
}

impl SqrtConfig {
    /// Checks that both formats are valid and that the aligned radicand fits the model's
    /// 128-bit core (input magnitude bits + alignment shift ≤ 128).
    pub fn validate(&self) -> Result<(), String> {
        for (name, f) in [("input", self.input), ("output", self.output)] {
            if !f.is_valid() {
                return Err(format!("sqrt.{name}: format {} is not valid", f.name()));
            }
        }
        let need = magnitude_bits(self.input) as i32 + alignment_shift(self);
        if need > MAX_RADICAND_BITS as i32 {
            return Err(format!(
                "sqrt: aligned radicand needs {need} bits (input {} → output {}), more than {MAX_RADICAND_BITS}",
                self.input.name(),
                self.output.name()
            ));
        }
        Ok(())
    }
}

/// Whether the output format rounds to nearest (any tie rule) rather than truncating.
fn rounds_to_nearest(out: Format) -> bool {
    !matches!(out.quant, Quant::Trn | Quant::TrnZero)
}

/// Extra root digits computed below the output LSB: one for the round-to-nearest modes.
fn extra_digits(cfg: &SqrtConfig) -> i32 {
    i32::from(rounds_to_nearest(cfg.output))
}

fn magnitude_bits(f: Format) -> u32 {
    u32::from(f.width) - u32::from(f.signed)
}

/// Left shift s = 2·(F_out + extra) − F_in that turns an input code into the integer radicand
/// whose root carries F_out + extra fraction bits (negative: a right shift that drops bits).
pub fn alignment_shift(cfg: &SqrtConfig) -> i32 {
    2 * (i32::from(cfg.output.frac) + extra_digits(cfg)) - i32::from(cfg.input.frac)
}

/// Radicand width N of the RTL core: the input's magnitude bits plus the alignment shift,
/// rounded up to even (at least 0, at most 128).
pub fn radicand_bits(cfg: &SqrtConfig) -> u32 {
    let n = (magnitude_bits(cfg.input) as i32 + alignment_shift(cfg)).clamp(0, 128) as u32;
    n + (n & 1)
}

/// Pipeline latency in cycles at one result per cycle: one stage per root digit (N/2), plus
/// one for the rounding incrementer when the output rounds to nearest. The alignment shift is
/// wiring and the negative-input clamp is folded into the first stage's multiplexer.
///
/// ```
/// use rtl_model::units::sqrt::{latency_cycles, SqrtConfig};
/// assert_eq!(latency_cycles(&SqrtConfig::default()), 32);
/// ```
pub fn latency_cycles(cfg: &SqrtConfig) -> u32 {
    radicand_bits(cfg) / 2 + u32::from(rounds_to_nearest(cfg.output))
}

/// DSP48E2 slices of the unit: none (subtractors and multiplexers only).
pub fn dsp48e2_count(_cfg: &SqrtConfig) -> u32 {
    0
}

/// Worst-case |result − √x| for a non-negative input code x whose root fits the output:
/// one output LSB for the truncating modes (and then 0 ≤ √x − result < LSB, one-sided; for
/// [`sqrt_fx_ceil`] 0 ≤ result − √x < LSB), half an LSB for round-to-nearest. Dropped input
/// bits (a negative [`alignment_shift`]) add nothing: ⌊√⌊y⌋⌋ = ⌊√y⌋ for every real y ≥ 0, and
/// the sticky bit keeps the nearest modes exact. Derivation in `docs/units/sqrt.md`.
///
/// ```
/// use rtl_model::units::sqrt::{error_bound, SqrtConfig};
/// assert_eq!(error_bound(&SqrtConfig::default()), 2f64.powi(-24));
/// ```
pub fn error_bound(cfg: &SqrtConfig) -> f64 {
    if rounds_to_nearest(cfg.output) {
        0.5 * cfg.output.lsb()
    } else {
        cfg.output.lsb()
    }
}

/// The aligned core's answer for a non-negative code.
enum Root {
    /// ⌊√v · 2^frac⌋ and whether it is inexact (√v · 2^frac not an integer).
    Value { root: u128, inexact: bool },
    /// The aligned radicand reaches 2^128: the root is ≥ 2^64, above every output format.
    TooLarge,
}

/// ⌊√(x · 2^−F_in) · 2^frac⌋ by the digit recurrence, for x ≥ 0.
fn aligned_root(x: u64, cfg: &SqrtConfig, frac: i32) -> Root {
    let s = 2 * frac - i32::from(cfg.input.frac);
    let a = u128::from(x);
    let (radicand, dropped) = if a == 0 {
        (0, false)
    } else if s >= 0 {
        let bits = 128 - a.leading_zeros() as i32;
        if bits + s > MAX_RADICAND_BITS as i32 {
            return Root::TooLarge;
        }
        (a << s, false)
    } else {
        let r = s.unsigned_abs();
        if r >= 128 {
            (0, true)
        } else {
            (a >> r, a & ((1u128 << r) - 1) != 0)
        }
    };
    // The model runs as many stages as this radicand needs; the RTL runs N/2 with N from the
    // formats. Leading zero digit pairs produce leading zero root bits, so both agree for
    // every code of the input format (and the model stays exact for codes outside it).
    let used = 128 - radicand.leading_zeros();
    let digits = digits_for(used.max(radicand_bits(cfg)));
    let (root, rem) = recurrence(radicand, digits);
    Root::Value {
        root,
        // √y is an integer exactly when nothing was dropped and the remainder is 0.
        inexact: rem != 0 || dropped,
    }
}

/// √x of an input code x into the output format.
///
/// - Alignment: with s = 2·(F_out + e) − F_in (e = 1 extra digit for round-to-nearest
///   outputs, else 0), the integer radicand is x·2^s (s ≥ 0, exact) or ⌊x·2^s⌋ (s < 0, the
///   low −s bits dropped); its integer root by the recurrence is ⌊√value · 2^(F_out+e)⌋.
/// - Rounding: truncating outputs take that root as is (truncation toward −∞, never above
///   √value). Round-to-nearest outputs append a sticky bit (remainder ≠ 0 or a dropped bit)
///   below the extra digit and round by the output's tie rule — exact, since the sticky bit
///   tells a true tie from a value above it.
/// - Overflow: a root above the output range is resolved by its overflow mode and counted
///   on `sig`.
/// - Negative input codes (a signed input format) have no real root: the result is 0 and
///   the clamp is counted on `sig`. Nothing panics on any code.
///
/// ```
/// use rtl_model::fixed::{from_f64, to_f64, Overflows, SignalId};
/// use rtl_model::units::sqrt::{sqrt_fx, SqrtConfig};
/// let cfg = SqrtConfig::default();
/// let mut ov = Overflows::new(&["sqrt"]);
/// let x_q16_48 = from_f64(2.25, cfg.input, &mut ov, SignalId(0));
/// let r_q8_24 = sqrt_fx(x_q16_48, &cfg, &mut ov, SignalId(0));
/// assert_eq!(to_f64(r_q8_24, cfg.output), 1.5);
/// assert_eq!(ov.total(), 0);
/// ```
pub fn sqrt_fx(x_raw: i64, cfg: &SqrtConfig, ov: &mut Overflows, sig: SignalId) -> i64 {
    let Ok(x) = u64::try_from(x_raw) else {
        ov.hit(sig);
        return 0;
    };
    let e = extra_digits(cfg);
    let frac = i32::from(cfg.output.frac) + e;
    match aligned_root(x, cfg, frac) {
        Root::TooLarge => saturate_high(cfg.output, ov, sig),
        Root::Value { root, inexact } => {
            // root < 2^64, so both codes below fit i128 exactly.
            let code = if e == 0 {
                root as i128
            } else {
                ((root << 1) | u128::from(inexact)) as i128
            };
            quantize(code, frac + e, cfg.output, ov, sig)
        }
    }
}

/// ⌈√x · 2^F_out⌉ · 2^−F_out: the square root rounded up (the output's quantisation mode is
/// ignored; its overflow mode applies). For callers that need √x from above, such as a
/// conservative entry distance l·d − √(…). Same alignment and core as [`sqrt_fx`] with no
/// extra digit: the result is the truncated root plus one when the remainder or a dropped
/// input bit is non-zero (one incrementer after the last stage). Negative codes give 0,
/// counted.
///
/// ```
/// use rtl_model::fixed::{Format, Overflows, SignalId};
/// use rtl_model::units::sqrt::{sqrt_fx_ceil, SqrtConfig};
/// let cfg = SqrtConfig { input: Format::uq(8, 0), output: Format::uq(4, 0) };
/// let mut ov = Overflows::new(&["sqrt"]);
/// assert_eq!(sqrt_fx_ceil(17, &cfg, &mut ov, SignalId(0)), 5);
/// assert_eq!(sqrt_fx_ceil(16, &cfg, &mut ov, SignalId(0)), 4);
/// ```
pub fn sqrt_fx_ceil(x_raw: i64, cfg: &SqrtConfig, ov: &mut Overflows, sig: SignalId) -> i64 {
    let Ok(x) = u64::try_from(x_raw) else {
        ov.hit(sig);
        return 0;
    };
    let frac = i32::from(cfg.output.frac);
    match aligned_root(x, cfg, frac) {
        Root::TooLarge => saturate_high(cfg.output, ov, sig),
        Root::Value { root, inexact } => {
            let code = root as i128 + i128::from(inexact);
            quantize(code, frac, cfg.output.with_quant(Quant::Trn), ov, sig)
        }
    }
}

/// A root beyond 2^64 output LSBs: above every 64-bit format, so it saturates (any overflow
/// mode: the wrapped bits of such a root are not computed by any realistic core) and counts.
fn saturate_high(out: Format, ov: &mut Overflows, sig: SignalId) -> i64 {
    ov.hit(sig);
    out.max_raw()
}

/// ⌊√x⌋ — the same value as [`isqrt`], bit for bit, computed faster for the model: an f64
/// estimate corrected by exact integer comparisons (the estimate is within one of the root,
/// and the loops move it to the unique r with r² ≤ x < (r + 1)²). The digit recurrence of
/// [`isqrt`] stays the specification the RTL follows; `rtl_model/tests/unit_sqrt.rs` pins the equality.
#[inline]
pub fn isqrt_fast(x: u64) -> u64 {
    let mut r = (x as f64).sqrt() as u64;
    while u128::from(r) * u128::from(r) > u128::from(x) {
        r -= 1;
    }
    while u128::from(r + 1) * u128::from(r + 1) <= u128::from(x) {
        r += 1;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_widths_hold() {
        // The remainder never exceeds 2·root, so the final one fits digits + 1 bits; the last
        // stage's shifted remainder (4 × the remainder of the radicand's prefix, plus the last
        // pair) fits digits + 2 bits. Checked at the worst radicands of each width.
        for bits in (2..=64).step_by(2) {
            let n = bits / 2;
            for x in [
                u64::MAX >> (64 - bits),
                (u64::MAX >> (64 - bits)) ^ 1 << (bits - 2),
            ] {
                let (r, rem) = isqrt_digits(x, bits);
                assert!(rem <= 2 * r && u128::from(rem) < 1u128 << (n + 1));
                let (_, rem_prefix) = isqrt_digits(x >> 2, bits - 2);
                assert!(u128::from(rem_prefix) * 4 + u128::from(x & 3) < 1u128 << (n + 2));
            }
        }
    }

    #[test]
    fn odd_and_oversized_widths_do_not_panic() {
        assert_eq!(isqrt_digits(49, 7), (7, 0));
        assert_eq!(
            isqrt_digits(u64::MAX, 200),
            (u64::from(u32::MAX), 2 * u64::from(u32::MAX))
        );
        assert_eq!(isqrt_digits(5, 0), (0, 0));
    }

    #[test]
    fn huge_alignment_saturates_and_counts() {
        let cfg = SqrtConfig {
            input: Format::uq(64, 0),
            output: Format::uq(2, 62),
        };
        assert!(cfg.validate().is_err());
        let mut ov = Overflows::new(&["s"]);
        assert_eq!(
            sqrt_fx(i64::MAX, &cfg, &mut ov, SignalId(0)),
            cfg.output.max_raw()
        );
        assert_eq!(ov.total(), 1);
        assert_eq!(sqrt_fx(0, &cfg, &mut ov, SignalId(0)), 0);
        assert_eq!(ov.total(), 1);
    }
}
