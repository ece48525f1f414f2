//! Exhaustive small-width tests of the fixed-point layer (`rtl_model::fixed`) against an
//! oracle of plain integer maths.
//!
//! What is tested, and how much:
//! - `add`, `sub`, `mul`: every operand pair of 6-bit formats (signed and unsigned, operand
//!   fraction counts {0, 2, 5, 7, −1}) into 6-bit results with fraction counts
//!   {−3, 0, 2, 5, 8, 11} (so requantisation shifts both ways and overflow all happen), for every
//!   quantisation mode × overflow mode × result signedness.
//! - `quantize`: every raw value in −4096..4096 with `from_frac` in −3..=12 into 6-bit formats
//!   with fraction counts −6..=16, every mode.
//! - Large shifts: seeded random `i128` raw values (plus special values, crafted ties and
//!   sticky-bit patterns) with `from_frac` up to 200, so `from_frac − out.frac > 120` takes
//!   `quantize`'s sticky pre-shift path; and left shifts whose exact result exceeds i128.
//! - Edges: `Format::is_valid` boundaries, `min_raw` / `max_raw` at widths 1, 2, 63, 64, and
//!   results within [min_raw, max_raw] at every width 1..=64.
//!
//! `from_f64` and `to_f64` are tested the same way in `conversions.rs` of this folder (one test
//! binary, so that its tests share the two cores with the long exhaustive ones).
//!
//! Every check compares the result code AND whether the signal's overflow counter went up by
//! exactly one (saturation or wrap) or not at all (in range), with no other signal touched.
//! Failures list the first disagreeing cases; the `minimal case` tests pin each bug found.
//! The oracle (`oracle.rs` of this folder, whose module documentation says why it is
//! independent of `ops.rs`) is itself checked here against hand-worked cases, and its
//! bit-position rounding against its division rounding.
//!
//! Runs with `cargo test -p rtl_model --test fixed_exhaustive` (add `-- --nocapture` to see
//! the case counts, times and seed). `SVO_TEST_SEED` overrides the default seed.

#[path = "../common/mod.rs"]
mod common;
mod conversions;
mod oracle;

use std::time::Instant;

use common::Rng;
use oracle::*;
use rtl_model::fixed::{add, mul, quantize, sub, OverflowMode, Overflows, Quant, SignalId};

// ---------------------------------------------------------------------------------------------
// Oracle self-checks
// ---------------------------------------------------------------------------------------------

/// The oracle against hand-worked ap_fixed cases (2.5, −2.5, 3.5, −3.5, 2.25, −2.75, 0.5).
#[test]
fn oracle_matches_hand_worked_cases() {
    // (numerator, fraction bits, expected per mode in QUANTS order)
    let cases: [(i128, u32, [i128; 7]); 7] = [
        (5, 1, [2, 2, 3, 2, 2, 3, 2]),
        (-5, 1, [-3, -2, -2, -2, -3, -3, -2]),
        (7, 1, [3, 3, 4, 3, 3, 4, 4]),
        (-7, 1, [-4, -3, -3, -3, -4, -4, -4]),
        (9, 2, [2, 2, 2, 2, 2, 2, 2]),
        (-11, 2, [-3, -2, -3, -3, -3, -3, -3]),
        (1, 1, [0, 0, 1, 0, 0, 1, 0]),
    ];
    for (n, k, want) in cases {
        for (q, w) in QUANTS.iter().zip(want) {
            assert_eq!(round_div(n, pow2(k), *q), w, "{n}/2^{k} {q:?}");
            assert_eq!(round_shift_bits(n, k, *q), w, "{n}>>{k} {q:?}");
        }
    }
    // Overflow oracle on a 6-bit signed format.
    let e = |v, m| resolve(Exact::Int(v), true, 6, m);
    assert_eq!(e(32, OverflowMode::Wrap).code, -32);
    assert_eq!(e(-33, OverflowMode::Wrap).code, 31);
    assert_eq!(e(-32, OverflowMode::SatSym).code, -31);
    assert!(e(-32, OverflowMode::SatSym).counted && !e(-32, OverflowMode::Sat).counted);
    assert_eq!(e(100, OverflowMode::Sat).code, 31);
    assert_eq!(
        resolve(Exact::Int(-1), false, 6, OverflowMode::Wrap).code,
        63
    );
}

/// The bit-position oracle agrees with the division oracle wherever both apply, and handles
/// shifts at and beyond the i128 width.
#[test]
fn oracle_bit_positions_match_division() {
    let mut n = 0u64;
    for raw in -4096i128..4096 {
        for s in 0..=14 {
            for q in QUANTS {
                assert_eq!(
                    round_shift_bits(raw, s, q),
                    round_div(raw, pow2(s), q),
                    "{raw}>>{s} {q:?}"
                );
                n += 1;
            }
        }
    }
    let mut rng = Rng::new(seed());
    for _ in 0..200_000 {
        let raw = rng.i128() >> rng.below(128);
        let s = rng.below(126) as u32;
        let q = rng.pick(&QUANTS);
        assert_eq!(
            round_shift_bits(raw, s, q),
            round_div(raw, pow2(s), q),
            "{raw}>>{s} {q:?}"
        );
        n += 1;
    }
    // Beyond the width: −2^127 / 2^128 is an exact tie at −1/2; other values are below half.
    let tie = |q| round_shift_bits(i128::MIN, 128, q);
    assert_eq!(tie(Quant::Rnd), 0);
    assert_eq!(tie(Quant::RndZero), 0);
    assert_eq!(tie(Quant::RndMinInf), -1);
    assert_eq!(tie(Quant::RndInf), -1);
    assert_eq!(tie(Quant::RndConv), 0);
    assert_eq!(round_shift_bits(i128::MIN, 129, Quant::RndMinInf), 0);
    assert_eq!(round_shift_bits(i128::MAX, 127, Quant::Rnd), 1);
    assert_eq!(round_shift_bits(i128::MAX, 128, Quant::Rnd), 0);
    assert_eq!(round_shift_bits(-1, 1000, Quant::Trn), -1);
    assert_eq!(round_shift_bits(-1, 1000, Quant::TrnZero), 0);
    assert_eq!(round_shift_bits(1, 1000, Quant::TrnZero), 0);
    println!("oracle self-check: {n} cases");
}

// ---------------------------------------------------------------------------------------------
// Exhaustive add / sub / mul
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug)]
enum Op {
    Add,
    Sub,
    Mul,
}

/// One operand: code, signedness, fraction count.
type Operand = (i64, bool, i32);

/// One operand pair into every result format and mode.
fn check_binary(ck: &mut Checker, op: Op, (a, a_signed, fa): Operand, (b, b_signed, fb): Operand) {
    let fmt_a = format(a_signed, W, fa, Quant::Trn, OverflowMode::Sat);
    let fmt_b = format(b_signed, W, fb, Quant::Trn, OverflowMode::Sat);
    let (xa, xb) = (rat(i128::from(a), fa), rat(i128::from(b), fb));
    let exact = match op {
        Op::Add => rat_add(xa, xb),
        Op::Sub => rat_add(xa, rat_neg(xb)),
        Op::Mul => rat_mul(xa, xb),
    };
    for of in OUT_FRACS {
        for q in QUANTS {
            let rounded = round_rat(exact, of, q);
            for out_signed in [false, true] {
                for m in OVERFLOWS {
                    let out = format(out_signed, W, of, q, m);
                    let exp = resolve(Exact::Int(rounded), out_signed, W, m);
                    let call = |ov: &mut Overflows, sig| match op {
                        Op::Add => add(a, fmt_a, b, fmt_b, out, ov, sig),
                        Op::Sub => sub(a, fmt_a, b, fmt_b, out, ov, sig),
                        Op::Mul => mul(a, fmt_a, b, fmt_b, out, ov, sig),
                    };
                    let ctx = || {
                        format!(
                            "{op:?} a={a} ({}) b={b} ({}) into {} {q:?} {m:?}",
                            fmt_name(a_signed, W, fa),
                            fmt_name(b_signed, W, fb),
                            fmt_name(out_signed, W, of)
                        )
                    };
                    ck.run(exp, call, ctx);
                }
            }
        }
    }
}

fn exhaustive_binary(op: Op) {
    let t0 = Instant::now();
    let mut ck = Checker::new();
    let operand_formats: Vec<(bool, i32)> = [false, true]
        .into_iter()
        .flat_map(|signed| OPERAND_FRACS.map(|f| (signed, f)))
        .collect();
    for &(a_signed, fa) in &operand_formats {
        for &(b_signed, fb) in &operand_formats {
            for a in codes(a_signed) {
                for b in codes(b_signed) {
                    check_binary(&mut ck, op, (a, a_signed, fa), (b, b_signed, fb));
                }
            }
        }
    }
    ck.finish(&format!("exhaustive {op:?}"), t0);
}

#[test]
fn exhaustive_add() {
    exhaustive_binary(Op::Add);
}

#[test]
fn exhaustive_sub() {
    exhaustive_binary(Op::Sub);
}

#[test]
fn exhaustive_mul() {
    exhaustive_binary(Op::Mul);
}

// ---------------------------------------------------------------------------------------------
// quantize
// ---------------------------------------------------------------------------------------------

#[test]
fn exhaustive_quantize() {
    let t0 = Instant::now();
    let mut ck = Checker::new();
    for from_frac in -3..=12 {
        for raw in -4096i128..4096 {
            let x = rat(raw, from_frac);
            for of in -6..=16 {
                for q in QUANTS {
                    let rounded = round_rat(x, of, q);
                    for out_signed in [false, true] {
                        for m in OVERFLOWS {
                            let out = format(out_signed, W, of, q, m);
                            let exp = resolve(Exact::Int(rounded), out_signed, W, m);
                            ck.run(
                                exp,
                                |ov, sig| quantize(raw, from_frac, out, ov, sig),
                                || {
                                    format!(
                                        "quantize {raw}/2^{from_frac} into {} {q:?} {m:?}",
                                        fmt_name(out_signed, W, of)
                                    )
                                },
                            );
                        }
                    }
                }
            }
        }
    }
    ck.finish("exhaustive quantize", t0);
}

/// Output formats of the wide-value quantize tests: (signed, width, frac). Three quarters of the
/// draws are 6-bit formats of any valid fraction count, the rest a few wide formats.
fn random_out_format(rng: &mut Rng) -> (bool, u8, i32) {
    const WIDE: [(bool, u8, i32); 6] = [
        (true, 64, 62),
        (true, 64, 0),
        (false, 63, 10),
        (true, 33, -20),
        (false, 17, 40),
        (true, 40, 30),
    ];
    if rng.below(4) == 0 {
        rng.pick(&WIDE)
    } else {
        let (lo, hi) = (*ALL_FRACS_6.start(), *ALL_FRACS_6.end());
        (rng.below(2) == 0, W, rng.range(lo.into(), hi.into()) as i32)
    }
}

/// A random i128 of random magnitude (1 to 128 significant bits, either sign).
fn random_raw(rng: &mut Rng) -> i128 {
    rng.i128() >> rng.below(128)
}

/// Checks quantize(raw, from_frac) into one format shape in every mode against the
/// bit-position oracle.
fn check_quantize_wide(
    ck: &mut Checker,
    (signed, width, out_frac): (bool, u8, i32),
    raw: i128,
    from_frac: i32,
) {
    for q in QUANTS {
        let rounded = quantize_oracle_wide(raw, from_frac, out_frac, q);
        for m in OVERFLOWS {
            let out = format(signed, width, out_frac, q, m);
            let exp = resolve(rounded, signed, width, m);
            ck.run(
                exp,
                |ov, sig| quantize(raw, from_frac, out, ov, sig),
                || {
                    format!(
                        "quantize({raw}, from_frac {from_frac}) into {} {q:?} {m:?}",
                        fmt_name(signed, width, out_frac)
                    )
                },
            );
        }
    }
}

/// Right shifts of random raw values, special values and crafted ties, up to and past the
/// i128 width (from_frac up to 200), including quantize's sticky pre-shift path
/// (from_frac − out.frac > 120), into 6-bit formats of every fraction count and a few wide
/// formats.
#[test]
fn quantize_large_right_shifts() {
    let t0 = Instant::now();
    let seed = seed();
    println!("quantize_large_right_shifts: seed {seed:#x}");
    let mut rng = Rng::new(seed ^ 0x1a46_e541);
    let mut ck = Checker::new();
    let specials: Vec<i128> = {
        let mut v = vec![0, 1, -1, 2, -2, 3, -3, i128::MIN, i128::MAX, i128::MIN + 1];
        for k in [60u32, 63, 64, 100, 119, 120, 121, 125, 126] {
            for d in [-1i128, 0, 1] {
                v.push(pow2(k).saturating_add(d));
                v.push((-pow2(k)).saturating_add(d));
                v.push(pow2(k).saturating_mul(3).saturating_add(d));
                v.push(pow2(k).saturating_mul(-3).saturating_add(d));
            }
        }
        v
    };
    let mut sticky_path = 0u64;
    for i in 0..400_000u64 {
        let shape = random_out_format(&mut rng);
        let out_frac = shape.2;
        let (raw, from_frac) = match i % 4 {
            // Any magnitude, any right shift (from_frac up to 200).
            0 => (random_raw(&mut rng), rng.range(out_frac.into(), 200) as i32),
            // Special values, shifts around and past the sticky threshold.
            1 => (rng.pick(&specials), out_frac + rng.range(110, 138) as i32),
            // Crafted ties and near-ties at shift s in 118..=130: j · 2^(s−1) plus a nudge in
            // the bits the pre-shift drops (0, ±1, or at the pre-shift boundary).
            2 => {
                let s = rng.range(118, 130) as u32;
                let j = rng.range(-120, 120) as i128;
                let pre = s.saturating_sub(120);
                let nudges = [0i128, 1, -1, pow2(pre), pow2(pre) - 1, -pow2(pre)];
                let base = match s - 1 {
                    // j · 2^(s−1) with j clamped into i128.
                    e @ ..=125 => j.clamp(-pow2(126 - e), pow2(126 - e) - 1) * pow2(e),
                    // Only ±2^126 and −2^127 are left: ties at s = 127 and 128.
                    126 => j.signum() * pow2(126),
                    127 if j < 0 => i128::MIN,
                    _ => -pow2(126) * i128::from(j < 0),
                };
                let raw = base.saturating_add(rng.pick(&nudges));
                (raw, out_frac + s as i32)
            }
            // Shifts well past the width, for every output fraction count.
            _ => (
                random_raw(&mut rng),
                rng.range(i64::from(out_frac) + 121, 200) as i32,
            ),
        };
        if from_frac - out_frac > 120 {
            sticky_path += 1;
        }
        check_quantize_wide(&mut ck, shape, raw, from_frac);
    }
    println!("quantize_large_right_shifts: {sticky_path} inputs took the sticky path");
    ck.finish("quantize large right shifts", t0);
}

/// Left shifts of random raw values of any magnitude, so that raw · 2^k often exceeds i128.
/// Saturation then goes by the sign; Wrap keeps the low W bits of the exact product, which
/// are zero only when k ≥ W.
#[test]
fn quantize_left_shifts_past_i128() {
    let t0 = Instant::now();
    let seed = seed();
    println!("quantize_left_shifts_past_i128: seed {seed:#x}");
    let mut rng = Rng::new(seed ^ 0x1ef7);
    let mut ck = Checker::new();
    let mut past_i128 = 0u64;
    for _ in 0..100_000u64 {
        let shape = random_out_format(&mut rng);
        let out_frac = shape.2;
        let raw = random_raw(&mut rng);
        let from_frac = rng.range(-70, i64::from(out_frac) - 1) as i32;
        if let Exact::Huge { .. } = quantize_oracle_wide(raw, from_frac, out_frac, Quant::Trn) {
            past_i128 += 1;
        }
        check_quantize_wide(&mut ck, shape, raw, from_frac);
    }
    println!("quantize_left_shifts_past_i128: {past_i128} inputs beyond i128 after the shift");
    ck.finish("quantize left shifts", t0);
}

/// Minimal case of a left shift past i128 in Wrap mode, reached through `mul` of two valid
/// 64-bit operands: (2^33 + 1)² = 2^66 + 2^34 + 1 into sQ2.62, i.e. shifted left by 62. The
/// exact value's low 64 bits are 1 · 2^62 (a wrap), not 0.
#[test]
fn wrap_after_left_shift_past_i128_keeps_low_bits() {
    let (mut ov, sig) = (Overflows::new(&["s"]), SignalId(0));
    let a = format(true, 64, 0, Quant::Trn, OverflowMode::Sat);
    let out = format(true, 64, 62, Quant::Trn, OverflowMode::Wrap);
    let x = (1i64 << 33) + 1;
    assert_eq!(
        mul(x, a, x, a, out, &mut ov, sig),
        1i64 << 62,
        "mul(2^33+1, 2^33+1) s64f0 into s64f62 Wrap"
    );
    assert_eq!(ov.count(sig), 1);
    // The same at 6 bits: (2^122 + 1) · 2^5 has low 6 bits 100000 = −32.
    let out6 = format(true, W, 5, Quant::Trn, OverflowMode::Wrap);
    assert_eq!(
        quantize(pow2(122) + 1, 0, out6, &mut ov, sig),
        -32,
        "quantize(2^122+1, 0) into s6f5 Wrap"
    );
    assert_eq!(ov.count(sig), 2);
}

// ---------------------------------------------------------------------------------------------
// Edges
// ---------------------------------------------------------------------------------------------

#[test]
fn format_validity_boundaries() {
    let f = |signed, width, frac| format(signed, width, frac, Quant::Trn, OverflowMode::Sat);
    // Width: unsigned 1..=64, signed 2..=64.
    assert!(f(false, 1, 0).is_valid());
    assert!(!f(true, 1, 0).is_valid());
    assert!(f(true, 2, 0).is_valid());
    assert!(!f(false, 0, 0).is_valid());
    assert!(!f(true, 0, 0).is_valid());
    assert!(f(false, 64, 0).is_valid() && f(true, 64, 0).is_valid());
    assert!(!f(false, 65, 0).is_valid() && !f(true, 65, 0).is_valid());
    // Fraction bits: −62..=62.
    assert!(f(true, 64, 62).is_valid());
    assert!(!f(true, 64, 63).is_valid());
    assert!(f(false, 1, -62).is_valid()); // W − F = 63
    assert!(!f(false, 1, -63).is_valid());
    // Integer bits W − F ≤ 64.
    assert!(f(true, 64, 0).is_valid()); // 64
    assert!(!f(true, 64, -1).is_valid()); // 65
    assert!(f(false, 2, -62).is_valid()); // 64
    assert!(!f(false, 3, -62).is_valid()); // 65
    assert!(f(true, 6, -58).is_valid() && !f(true, 6, -59).is_valid());
    // W − F ≥ −62 never binds: F ≤ 62 and W ≥ 1 give W − F ≥ −61.
    assert!(f(false, 1, 62).is_valid()); // W − F = −61
}

#[test]
fn min_and_max_raw() {
    let f = |signed, width| format(signed, width, 0, Quant::Trn, OverflowMode::Sat);
    let cases: [(bool, u8, i64, i64); 8] = [
        (false, 1, 0, 1),
        // Signed width 1 is not a valid format, but its two's-complement range is still −1..0.
        (true, 1, -1, 0),
        (false, 2, 0, 3),
        (true, 2, -2, 1),
        (false, 63, 0, i64::MAX),
        (true, 63, -(1 << 62), (1 << 62) - 1),
        // Unsigned 64-bit: raw codes are i64, so the largest code is i64::MAX (63 value bits),
        // not 2^64 − 1 — by design (format.rs).
        (false, 64, 0, i64::MAX),
        (true, 64, i64::MIN, i64::MAX),
    ];
    for (signed, width, lo, hi) in cases {
        let fm = f(signed, width);
        assert_eq!((fm.min_raw(), fm.max_raw()), (lo, hi), "{signed} {width}");
    }
    // And every other width agrees with the oracle's range from the definition.
    for width in 1..=64u8 {
        for signed in [false, true] {
            let fm = f(signed, width);
            let (lo, hi) = code_range(signed, width);
            assert_eq!(
                (i128::from(fm.min_raw()), i128::from(fm.max_raw())),
                (lo, hi),
                "{signed} {width}"
            );
        }
    }
}

/// Every result lies in [min_raw, max_raw] at every width, for values just past either end of
/// the range in every overflow mode, and the counter moves once per overflow.
#[test]
fn results_stay_in_range_at_every_width() {
    let mut failures = Vec::new();
    let (mut ov, sig) = (Overflows::new(&["s"]), SignalId(0));
    for width in 1..=64u8 {
        for signed in [false, true] {
            if signed && width == 1 {
                continue;
            }
            for m in OVERFLOWS {
                let out = format(signed, width, 0, Quant::Trn, m);
                let (lo, hi) = (i128::from(out.min_raw()), i128::from(out.max_raw()));
                for v in [lo - 1, lo, hi, hi + 1, hi + 2, lo - 2, 2 * hi + 7] {
                    let before = ov.count(sig);
                    let got = quantize(v, 0, out, &mut ov, sig);
                    let counted = ov.count(sig) - before;
                    let in_range =
                        (lo..=hi).contains(&v) && !(m == OverflowMode::SatSym && signed && v == lo);
                    if !(out.min_raw()..=out.max_raw()).contains(&got)
                        || counted != u64::from(!in_range)
                    {
                        let name = fmt_name(signed, width, 0);
                        failures.push(format!(
                            "quantize({v}, 0) into {name} {m:?}: got {got} \
                             (range {lo}..={hi}), counter +{counted}"
                        ));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Minimal case: an unsigned 64-bit format holds codes 0..=i64::MAX (see `min_and_max_raw`),
/// so a wrapped result must stay in that range too; a wrap must not hand back a negative code
/// (which `to_f64` would read as a negative value of an unsigned format).
#[test]
fn unsigned_64_wrap_gives_non_negative_codes() {
    let (mut ov, sig) = (Overflows::new(&["s"]), SignalId(0));
    let u = format(false, 64, 0, Quant::Trn, OverflowMode::Wrap);
    let sum = add(i64::MAX, u, 1, u, u, &mut ov, sig);
    assert!(sum >= 0, "add(i64::MAX, 1) u64f0 Wrap gave {sum}");
    let diff = sub(0, u, 1, u, u, &mut ov, sig);
    assert!(diff >= 0, "sub(0, 1) u64f0 Wrap gave {diff}");
    assert_eq!(ov.count(sig), 2);
}
