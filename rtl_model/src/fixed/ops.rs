//! Exact arithmetic on raw values, requantised into an explicit result format.
//!
//! Every operation first computes the exact result as an `i128` with a known number of
//! fraction bits (sums align to the larger fraction count; products add them), then
//! [`quantize`] rounds it into the result format by that format's quantisation mode and
//! resolves overflow by its overflow mode, counting any saturation or wrap on the signal.

use super::{Format, OverflowMode, Overflows, Quant, SignalId};

/// Largest right shift done directly; larger ones first shift with a sticky bit, which keeps
/// every rounding decision (below, at or above half; exact or not) intact.
const MAX_DIRECT_SHIFT: i32 = 120;

/// Rounds `raw · 2^−from_frac` into `out`: quantisation by `out.quant`, then overflow by
/// `out.overflow`. Any saturation or wrap is counted on `sig`.
///
/// Always inlined: it is the datapath's rounding step, called per transform, reciprocal and
/// slab product, and its fast paths are a handful of instructions (the functional model's
/// speed, docs/cycle-model.md §2.7).
#[inline(always)]
pub fn quantize(raw: i128, from_frac: i32, out: Format, ov: &mut Overflows, sig: SignalId) -> i64 {
    let shift = from_frac - i32::from(out.frac);
    // Fast path, the datapath's common case: a right shift of under 64 bits whose result is
    // strictly inside the range (so no overflow mode can apply). Same result as the general
    // path (`quantize_matches_general_path`).
    if shift > 0 && shift < 64 {
        let q = round_shift_small(raw, (shift & 63) as u32, out.quant);
        if q > i128::from(out.min_raw()) && q <= i128::from(out.max_raw()) {
            return q as i64;
        }
    } else if shift <= 0 && shift > -64 {
        // Fast path for an exact left shift (the reciprocal's output, for one): a raw value
        // within i64 shifted by under 64 bits cannot overflow i128, so when the result lies
        // strictly inside the range (hence also inside a symmetric one) it is the general
        // path's result, with nothing to count.
        if let Ok(r) = i64::try_from(raw) {
            let v = i128::from(r) << (-shift) as u32;
            if v > i128::from(out.min_raw()) && v <= i128::from(out.max_raw()) {
                return v as i64;
            }
        }
    }
    quantize_general(raw, from_frac, out, ov, sig)
}

/// [`round_shift`] for 1 ≤ s ≤ 63: the dropped bits fit one word, so the remainder and the
/// half are `u64` and the shift a single funnel shift. Same result
/// (`round_shift_small_matches_round_shift`).
#[inline(always)]
fn round_shift_small(raw: i128, s: u32, quant: Quant) -> i128 {
    let floor = raw >> s;
    if quant == Quant::Trn {
        return floor;
    }
    // raw − floor·2^s: the low s bits of raw (two's complement), in [0, 2^s).
    let rem = (raw as u64) & ((1u64 << s) - 1);
    if rem == 0 {
        return floor;
    }
    let up = rounds_up(quant, rem.cmp(&(1u64 << (s - 1))), raw < 0, floor & 1 == 1);
    floor + i128::from(up)
}

/// Whether `quant` rounds a value up from its floor, given its dropped bits against half an
/// LSB (`rem_vs_half`, the dropped bits not all zero), its sign and the floor's parity: the
/// one rule of both shifts ([`round_shift_small`], [`round_shift`]).
#[inline(always)]
fn rounds_up(quant: Quant, rem_vs_half: std::cmp::Ordering, neg: bool, odd: bool) -> bool {
    use std::cmp::Ordering::{Equal, Greater, Less};
    match quant {
        Quant::Trn => false,
        Quant::TrnZero => neg,
        Quant::Rnd => rem_vs_half != Less,
        Quant::RndZero => rem_vs_half == Greater || (rem_vs_half == Equal && neg),
        Quant::RndMinInf => rem_vs_half == Greater,
        Quant::RndInf => rem_vs_half == Greater || (rem_vs_half == Equal && !neg),
        Quant::RndConv => rem_vs_half == Greater || (rem_vs_half == Equal && odd),
    }
}

/// The general path of [`quantize`]: any shift, overflow resolution and counting.
#[inline(never)]
fn quantize_general(
    raw: i128,
    from_frac: i32,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    let shift = from_frac - i32::from(out.frac);
    let q: Option<i128> = if shift <= 0 {
        let k = (-shift) as u32;
        if raw == 0 {
            Some(0)
        } else if k >= 127 {
            None
        } else {
            let v = raw << k;
            (v >> k == raw).then_some(v)
        }
    } else {
        let (mut r, mut s) = (raw, shift);
        if s > MAX_DIRECT_SHIFT {
            let pre = s - MAX_DIRECT_SHIFT;
            let dropped = if pre >= 127 {
                r
            } else {
                r & ((1i128 << pre) - 1)
            };
            r = if pre >= 127 { r >> 126 >> 1 } else { r >> pre };
            r = (r & !1) | i128::from(dropped != 0) | (r & 1);
            s = MAX_DIRECT_SHIFT;
        }
        Some(round_shift(r, s as u32, out.quant))
    };
    let (lo, hi) = (i128::from(out.min_raw()), i128::from(out.max_raw()));
    let lo_sym = if out.overflow == OverflowMode::SatSym && out.signed {
        -hi
    } else {
        lo
    };
    match q {
        Some(v) if v >= lo_sym && v <= hi => v as i64,
        Some(v) if out.overflow == OverflowMode::Wrap => {
            ov.hit(sig);
            wrap(v, out)
        }
        Some(v) => {
            ov.hit(sig);
            if v < lo_sym {
                lo_sym as i64
            } else {
                hi as i64
            }
        }
        None => {
            // The left shift itself overflowed i128: far outside any 64-bit format. Wrapping
            // keeps the low W bits of raw·2^k, which only involve raw's low W − k bits.
            ov.hit(sig);
            match out.overflow {
                OverflowMode::Wrap => {
                    let (w, k) = (u32::from(value_bits(out)), (-shift) as u32);
                    if k >= w {
                        0
                    } else {
                        wrap((raw & ((1i128 << (w - k)) - 1)) << k, out)
                    }
                }
                _ if raw < 0 => lo_sym as i64,
                _ => hi as i64,
            }
        }
    }
}

/// Bits a format's raw codes can hold: the width, except that unsigned 64-bit formats hold
/// 63 (raw codes are `i64`; see [`Format::max_raw`]).
fn value_bits(out: Format) -> u8 {
    if out.signed {
        out.width
    } else {
        out.width.min(63)
    }
}

/// Keeps the low W bits of `v` (sign-extended for signed formats).
fn wrap(v: i128, out: Format) -> i64 {
    let w = u32::from(value_bits(out));
    let mask: i128 = if w >= 127 { -1 } else { (1i128 << w) - 1 };
    let low = v & mask;
    if out.signed && w < 127 && low >> (w - 1) & 1 == 1 {
        (low - (1i128 << w)) as i64
    } else {
        low as i64
    }
}

/// `raw / 2^s` rounded by `quant` (1 ≤ s ≤ 120).
#[inline]
fn round_shift(raw: i128, s: u32, quant: Quant) -> i128 {
    let floor = raw >> s;
    if quant == Quant::Trn {
        return floor; // truncation toward −∞ is the arithmetic shift itself
    }
    let rem = raw - (floor << s); // 0 ≤ rem < 2^s
    if rem == 0 {
        return floor;
    }
    let up = rounds_up(quant, rem.cmp(&(1i128 << (s - 1))), raw < 0, floor & 1 == 1);
    floor + i128::from(up)
}

/// a and b as exact i128 values at the larger of their fraction counts (always a left
/// shift, exact for valid formats), with that count.
#[inline]
fn align(a: i64, fa: Format, b: i64, fb: Format) -> (i128, i128, i32) {
    let f = fa.frac.max(fb.frac);
    (
        i128::from(a) << (f - fa.frac),
        i128::from(b) << (f - fb.frac),
        i32::from(f),
    )
}

/// a + b into `out` (exact sum at the larger fraction count, then [`quantize`]).
#[inline]
pub fn add(
    a: i64,
    fa: Format,
    b: i64,
    fb: Format,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    let (a2, b2, f) = align(a, fa, b, fb);
    quantize(a2 + b2, f, out, ov, sig)
}

/// a − b into `out`.
#[inline]
pub fn sub(
    a: i64,
    fa: Format,
    b: i64,
    fb: Format,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    let (a2, b2, f) = align(a, fa, b, fb);
    quantize(a2 - b2, f, out, ov, sig)
}

/// a · b into `out` (the exact 128-bit product has fa.frac + fb.frac fraction bits).
#[inline]
pub fn mul(
    a: i64,
    fa: Format,
    b: i64,
    fb: Format,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    quantize(
        i128::from(a) * i128::from(b),
        i32::from(fa.frac) + i32::from(fb.frac),
        out,
        ov,
        sig,
    )
}

/// a · 2^−k into `out` (an arithmetic right shift by k when the formats match).
#[inline]
pub fn shift_right(
    a: i64,
    fa: Format,
    k: u8,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    quantize(
        i128::from(a),
        i32::from(fa.frac) + i32::from(k),
        out,
        ov,
        sig,
    )
}

/// Converts an f64 into `out`, rounded by its quantisation mode. NaN becomes 0 and ±∞ the
/// format's extreme; both count as an overflow on `sig`, so a bad input is never silent.
pub fn from_f64(x: f64, out: Format, ov: &mut Overflows, sig: SignalId) -> i64 {
    if x.is_nan() {
        ov.hit(sig);
        return 0;
    }
    // 2^F built from its exponent bits (exact; F is within ±62 for valid formats).
    let scaled = x * f64::from_bits(((1023 + i64::from(out.frac)) as u64) << 52);
    if x.is_infinite() || scaled.abs() >= 2f64.powi(126) {
        ov.hit(sig);
        if out.overflow == OverflowMode::Wrap && x.is_finite() {
            // |scaled| ≥ 2^126 is an integer m·2^e with e ≥ 74 > W: its low W bits are 0.
            return 0;
        }
        let lo = if out.overflow == OverflowMode::SatSym && out.signed {
            -out.max_raw()
        } else {
            out.min_raw()
        };
        return if x < 0.0 { lo } else { out.max_raw() };
    }
    if scaled == 0.0 && x != 0.0 {
        // x·2^F underflowed (F < 0): the exact value lies strictly between −1 and 1 LSB and is
        // not a tie, so only truncation toward −∞ of a negative value leaves a non-zero code.
        let q = if x < 0.0 && out.quant == Quant::Trn {
            -1
        } else {
            0
        };
        return quantize(q, i32::from(out.frac), out, ov, sig);
    }
    // `scaled` is exact (a power-of-two scaling); split it into integer and fraction parts,
    // both exact in f64, and round the way `round_shift` does.
    let floor = scaled.floor();
    let frac = scaled - floor;
    let mut q = floor as i128;
    if frac > 0.0 {
        let neg = scaled < 0.0;
        let up = match out.quant {
            Quant::Trn => false,
            Quant::TrnZero => neg,
            Quant::Rnd => frac >= 0.5,
            Quant::RndZero => frac > 0.5 || (frac == 0.5 && neg),
            Quant::RndMinInf => frac > 0.5,
            Quant::RndInf => frac > 0.5 || (frac == 0.5 && !neg),
            Quant::RndConv => frac > 0.5 || (frac == 0.5 && q & 1 == 1),
        };
        q += i128::from(up);
    }
    quantize(q, i32::from(out.frac), out, ov, sig)
}

/// The value of a raw code: raw · 2^−F (exact while |raw| < 2^53, else rounded to nearest).
#[inline]
pub fn to_f64(raw: i64, f: Format) -> f64 {
    raw as f64 * 2f64.powi(-i32::from(f.frac))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ov() -> (Overflows, SignalId) {
        (Overflows::new(&["s"]), SignalId(0))
    }

    #[test]
    fn rounding_modes_on_ties_and_signs() {
        let out = Format::sq(8, 0);
        // raw values with 1 fraction bit: 2.5, −2.5, 3.5, 2.25 (2 bits)
        let cases: [(i128, i32, [i64; 7]); 4] = [
            (5, 1, [2, 2, 3, 2, 2, 3, 2]),
            (-5, 1, [-3, -2, -2, -2, -3, -3, -2]),
            (7, 1, [3, 3, 4, 3, 3, 4, 4]),
            (9, 2, [2, 2, 2, 2, 2, 2, 2]),
        ];
        let modes = MODES;
        for (raw, f, want) in cases {
            for (m, w) in modes.iter().zip(want) {
                let (mut o, s) = ov();
                assert_eq!(
                    quantize(raw, f, out.with_quant(*m), &mut o, s),
                    w,
                    "{raw}/2^{f} {m:?}"
                );
            }
        }
    }

    #[test]
    fn saturation_and_wrap_are_counted() {
        let (mut o, s) = ov();
        let f = Format::sq(4, 4); // 8 bits, range −8 .. 7.9375
        assert_eq!(from_f64(100.0, f, &mut o, s), 127);
        assert_eq!(from_f64(-100.0, f, &mut o, s), -128);
        assert_eq!(
            from_f64(-100.0, f.with_overflow(OverflowMode::SatSym), &mut o, s),
            -127
        );
        assert_eq!(o.count(s), 3);
        let w = f.with_overflow(OverflowMode::Wrap);
        assert_eq!(add(127, f, 1, f, w, &mut o, s), -128);
        assert_eq!(o.count(s), 4);
        assert_eq!(from_f64(f64::NAN, f, &mut o, s), 0);
        assert_eq!(o.count(s), 5);
        assert_eq!(add(3, f, 4, f, f, &mut o, s), 7);
        assert_eq!(o.count(s), 5, "no overflow, no count");
    }

    #[test]
    fn products_and_conversions() {
        let (mut o, s) = ov();
        let a = Format::sq(2, 30);
        let x = from_f64(0.75, a, &mut o, s);
        let y = from_f64(-0.5, a, &mut o, s);
        assert_eq!(to_f64(mul(x, a, y, a, a, &mut o, s), a), -0.375);
        assert_eq!(to_f64(shift_right(x, a, 1, a, &mut o, s), a), 0.375);
        assert_eq!(to_f64(sub(x, a, y, a, a, &mut o, s), a), 1.25);
        assert_eq!(o.total(), 0);
        // Extreme valid formats do not overflow i128.
        let wide = Format {
            signed: true,
            width: 64,
            frac: 62,
            quant: Quant::Trn,
            overflow: OverflowMode::Sat,
        };
        let high = Format {
            signed: true,
            width: 64,
            frac: 0,
            quant: Quant::Trn,
            overflow: OverflowMode::Sat,
        };
        assert!(wide.is_valid() && high.is_valid());
        let r = add(i64::MIN, high, i64::MIN, wide, high, &mut o, s);
        assert_eq!(r, i64::MIN);
        let _ = mul(i64::MIN, high, i64::MIN, high, wide, &mut o, s);
        assert!(o.total() >= 1);
    }

    const MODES: [Quant; 7] = [
        Quant::Trn,
        Quant::TrnZero,
        Quant::Rnd,
        Quant::RndZero,
        Quant::RndMinInf,
        Quant::RndInf,
        Quant::RndConv,
    ];

    /// The seed of the random tests below: `SVO_TEST_SEED` (decimal) or a fixed default,
    /// printed so that a failure replays.
    fn seed(test: &str) -> u64 {
        let seed = std::env::var("SVO_TEST_SEED")
            .ok()
            .and_then(|s| s.trim().parse().ok())
            .unwrap_or(0x0F5_2030_0001);
        println!("{test}: seed = {seed} (SVO_TEST_SEED replays)");
        seed
    }

    /// SplitMix64 for these tests: the crate's own generator (`vectors::rng`) is in a layer
    /// above `fixed` (docs/architecture.md §1), which this module may not import.
    struct TestRng(u64);

    impl TestRng {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }

        /// Uniform in 0..n (n ≥ 1; the modulo bias is immaterial here).
        fn below(&mut self, n: u64) -> u64 {
            self.next_u64() % n
        }

        fn one_in(&mut self, n: u64) -> bool {
            self.below(n) == 0
        }
    }

    /// A raw value that reaches every branch: small, near the word and range boundaries,
    /// any i128.
    fn any_raw(rng: &mut TestRng) -> i128 {
        let wide = (i128::from(rng.next_u64() as i64) << 64) | i128::from(rng.next_u64());
        let k = rng.below(127) as u32;
        match rng.below(4) {
            0 => i128::from(rng.next_u64() as i64),
            1 => wide,
            2 => i128::from(rng.next_u64() as i64).wrapping_shl(k),
            _ => (1i128 << k) + (rng.below(9) as i128 - 4) * if rng.one_in(2) { -1 } else { 1 },
        }
    }

    /// The one-word rounding equals the general i128 one for every shift it takes.
    #[test]
    fn round_shift_small_matches_round_shift() {
        let seed = seed("round_shift_small_matches_round_shift");
        let mut rng = TestRng(seed);
        for case in 0..200_000 {
            let (raw, s) = (any_raw(&mut rng), 1 + rng.below(63) as u32);
            let m = MODES[rng.below(7) as usize];
            assert_eq!(
                round_shift_small(raw, s, m),
                round_shift(raw, s, m),
                "seed {seed} case {case}: {raw} >> {s} {m:?}"
            );
        }
    }

    /// `quantize` (its fast paths inlined) returns and counts exactly what its general path
    /// does, for every valid format, mode and shift.
    #[test]
    fn quantize_matches_general_path() {
        let seed = seed("quantize_matches_general_path");
        let mut rng = TestRng(seed);
        let mut fast_taken = 0u32;
        for case in 0..200_000 {
            let out = Format {
                signed: rng.one_in(2),
                width: 1 + rng.below(64) as u8,
                frac: rng.below(125) as i8 - 62,
                quant: MODES[rng.below(7) as usize],
                overflow: [OverflowMode::Sat, OverflowMode::SatSym, OverflowMode::Wrap]
                    [rng.below(3) as usize],
            };
            if !out.is_valid() {
                continue;
            }
            // Mostly shifts the fast paths take (−63..=63), some beyond.
            let shift = if rng.one_in(4) {
                rng.below(200) as i32 - 70
            } else {
                rng.below(127) as i32 - 63
            };
            let from_frac = i32::from(out.frac) + shift;
            let raw = any_raw(&mut rng);
            let (mut a, sig) = ov();
            let (mut b, _) = ov();
            let fast = quantize(raw, from_frac, out, &mut a, sig);
            let general = quantize_general(raw, from_frac, out, &mut b, sig);
            assert_eq!(
                (fast, a.total()),
                (general, b.total()),
                "seed {seed} case {case}: {raw} from {from_frac} into {out:?}"
            );
            fast_taken += u32::from(b.total() == 0);
        }
        assert!(fast_taken > 10_000, "the cases reach the in-range results");
    }
}
