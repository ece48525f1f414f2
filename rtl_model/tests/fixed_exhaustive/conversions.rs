//! Exhaustive and seeded tests of the fixed-point layer's conversions from and to doubles
//! (`rtl_model::fixed::{from_f64, to_f64}`) against the integer oracle in `oracle.rs` beside
//! this file:
//!
//! - `from_f64`: every 6-bit format (all valid fraction counts −58..=62) and mode for every
//!   x = k/2^j (k in −300..300, j in 0..=9, exact binary fractions including exact ties), plus
//!   seeded random doubles (full range, moderate range, subnormal); NaN and ±∞.
//! - `to_f64`: exact for every code of every 6-bit format.
//!
//! Doubles are decomposed from their bit pattern into mantissa · 2^exponent, so the oracle sees
//! their exact value, never a scaled double. Every check compares the result code AND whether
//! the signal's overflow counter went up by exactly one or not at all; the `minimal case`
//! tests pin each bug found. The arithmetic and `quantize` are tested in `main.rs`, whose test
//! binary (`cargo test -p rtl_model --test fixed_exhaustive`) this module is part of.

use std::time::Instant;

use super::common::Rng;
use super::oracle::*;
use rtl_model::fixed::{from_f64, quantize, to_f64, OverflowMode, Overflows, Quant, SignalId};

// ---------------------------------------------------------------------------------------------
// from_f64 / to_f64
// ---------------------------------------------------------------------------------------------

/// Checks one finite double against every 6-bit format and mode.
fn check_f64_all_formats(ck: &mut Checker, x: f64, exact: Option<Rat>) {
    for of in ALL_FRACS_6 {
        for q in QUANTS {
            let rounded = match exact {
                Some(r) => Exact::Int(round_rat(r, of, q)),
                None => from_f64_oracle(x, of, q),
            };
            for signed in [false, true] {
                for m in OVERFLOWS {
                    let out = format(signed, W, of, q, m);
                    let exp = resolve(rounded, signed, W, m);
                    ck.run(
                        exp,
                        |ov, sig| from_f64(x, out, ov, sig),
                        || {
                            format!(
                                "from_f64({x:e} = bits {:#018x}) into {} {q:?} {m:?}",
                                x.to_bits(),
                                fmt_name(signed, W, of)
                            )
                        },
                    );
                }
            }
        }
    }
}

/// Exact binary fractions k / 2^j, including exact ties, against the division oracle applied
/// to the rational k / 2^j (not to the double).
#[test]
fn from_f64_binary_fractions() {
    let t0 = Instant::now();
    let mut ck = Checker::new();
    for j in 0..=9u32 {
        for k in -300i128..300 {
            let x = k as f64 / pow2(j) as f64;
            check_f64_all_formats(&mut ck, x, Some(Rat { n: k, k: j }));
        }
    }
    check_f64_all_formats(&mut ck, -0.0, Some(Rat { n: 0, k: 0 }));
    ck.finish("from_f64 binary fractions", t0);
}

/// Random doubles of moderate magnitude (|x| in about 2^−70 .. 2^10, where 6-bit formats of
/// some fraction count resolve them), against the exact value mantissa · 2^exponent.
#[test]
fn from_f64_random_moderate() {
    let t0 = Instant::now();
    let seed = seed();
    println!("from_f64_random_moderate: seed {seed:#x}");
    let mut rng = Rng::new(seed ^ 0x00f6_4a0d);
    let mut ck = Checker::new();
    for _ in 0..6_000 {
        let mant = rng.next() >> 11; // 53 bits
        let e = rng.range(-123, -43) as i32;
        let x = mant as f64 * 2f64.powi(e); // exact: 53-bit integer times a power of two
        let x = if rng.below(2) == 0 { -x } else { x };
        check_f64_all_formats(&mut ck, x, None);
    }
    ck.finish("from_f64 random moderate", t0);
}

/// Random bit patterns over the whole finite range (including huge values beyond 2^126 after
/// scaling, where the exact value wraps to 0 in Wrap mode and saturates otherwise).
#[test]
fn from_f64_random_full_range() {
    let t0 = Instant::now();
    let seed = seed();
    println!("from_f64_random_full_range: seed {seed:#x}");
    let mut rng = Rng::new(seed ^ 0xf_0111);
    let mut ck = Checker::new();
    let mut n = 0;
    while n < 6_000 {
        let x = f64::from_bits(rng.next());
        if x.is_finite() {
            check_f64_all_formats(&mut ck, x, None);
            n += 1;
        }
    }
    ck.finish("from_f64 random full range", t0);
}

/// Subnormal and near-subnormal doubles: scaling them by 2^F with F < 0 must not lose their
/// sign or non-zeroness (floor of a tiny negative value is −1).
#[test]
fn from_f64_random_subnormal() {
    let t0 = Instant::now();
    let seed = seed();
    println!("from_f64_random_subnormal: seed {seed:#x}");
    let mut rng = Rng::new(seed ^ 0x5ab_0000);
    let mut ck = Checker::new();
    for i in 0..3_000u64 {
        let bits = match i % 3 {
            0 => rng.next() & ((1 << 52) - 1), // subnormal
            1 => rng.next() & ((1 << 55) - 1), // smallest normals
            _ => rng.below(16),                // the very smallest subnormals
        };
        let sign = rng.below(2) << 63;
        check_f64_all_formats(&mut ck, f64::from_bits(bits | sign), None);
    }
    ck.finish("from_f64 random subnormal", t0);
}

/// NaN becomes 0, ±∞ the format's extreme (the most negative code for −∞, or −max under
/// SatSym; the extreme also under Wrap, as documented); each counts exactly once.
#[test]
fn from_f64_nan_and_infinities() {
    let t0 = Instant::now();
    let mut ck = Checker::new();
    for of in ALL_FRACS_6 {
        for q in QUANTS {
            for signed in [false, true] {
                for m in OVERFLOWS {
                    let out = format(signed, W, of, q, m);
                    let (lo, hi) = code_range(signed, W);
                    let lo = if signed && m == OverflowMode::SatSym {
                        lo + 1
                    } else {
                        lo
                    };
                    for (x, code) in [(f64::NAN, 0), (f64::INFINITY, hi), (f64::NEG_INFINITY, lo)] {
                        let exp = Expected {
                            code: code as i64,
                            counted: true,
                        };
                        ck.run(
                            exp,
                            |ov, sig| from_f64(x, out, ov, sig),
                            || {
                                format!(
                                    "from_f64({x}) into {} {q:?} {m:?}",
                                    fmt_name(signed, W, of)
                                )
                            },
                        );
                    }
                }
            }
        }
    }
    ck.finish("from_f64 NaN / inf", t0);
}

/// Minimal case: a finite double far beyond the range converts by its exact value, so in
/// Wrap mode its low bits (all zero) are kept, as `quantize` does for the same value.
#[test]
fn from_f64_huge_finite_wraps_like_quantize() {
    let (mut ov, sig) = (Overflows::new(&["s"]), SignalId(0));
    let out = format(true, W, 0, Quant::Trn, OverflowMode::Wrap);
    // 2^125 (an i128) wraps to 0 in both.
    assert_eq!(quantize(pow2(125), 0, out, &mut ov, sig), 0);
    assert_eq!(from_f64(2f64.powi(125), out, &mut ov, sig), 0);
    // 2^126 must too: its low 6 bits are zero.
    assert_eq!(quantize(pow2(126), 0, out, &mut ov, sig), 0);
    assert_eq!(
        from_f64(2f64.powi(126), out, &mut ov, sig),
        0,
        "from_f64(2^126) into s6f0 Wrap"
    );
    assert_eq!(ov.count(sig), 4);
}

/// Minimal case: −2^−1074 (the smallest negative subnormal) is below zero, so truncation
/// toward −∞ into a format with F = −1 gives −1 (and, unsigned, saturates to 0 with a count).
#[test]
fn from_f64_tiny_negative_truncates_down() {
    let (mut ov, sig) = (Overflows::new(&["s"]), SignalId(0));
    let x = -f64::from_bits(1);
    // F = 0: correct already.
    let f0 = format(true, W, 0, Quant::Trn, OverflowMode::Sat);
    assert_eq!(from_f64(x, f0, &mut ov, sig), -1);
    let f = format(true, W, -1, Quant::Trn, OverflowMode::Sat);
    assert_eq!(
        from_f64(x, f, &mut ov, sig),
        -1,
        "from_f64(-2^-1074) into s6f-1 Trn"
    );
    assert_eq!(ov.count(sig), 0);
    let u = format(false, W, -1, Quant::Trn, OverflowMode::Sat);
    assert_eq!(from_f64(x, u, &mut ov, sig), 0);
    assert_eq!(
        ov.count(sig),
        1,
        "u6f-1 Trn: −1 saturates to 0 with a count"
    );
}

/// to_f64 is exact for every code of every 6-bit format: the double's exact value
/// (mantissa · 2^exponent from its bits) equals code · 2^−F.
#[test]
fn to_f64_exact_for_all_6bit_codes() {
    let mut n = 0u64;
    for of in ALL_FRACS_6 {
        for signed in [false, true] {
            let f = format(signed, W, of, Quant::Trn, OverflowMode::Sat);
            for code in codes(signed) {
                let v = to_f64(code, f);
                let (negative, m, e) = decompose(v);
                // m · 2^e == |code| · 2^−of  ⇔  m · 2^(e + of) == |code|
                let t = e + of;
                let lhs_is_code = if code == 0 {
                    m == 0
                } else if t >= 0 {
                    t < 64 && i128::from(m) * pow2(t as u32) == i128::from(code.unsigned_abs())
                } else {
                    t > -70
                        && i128::from(m) == i128::from(code.unsigned_abs()) * pow2(t.unsigned_abs())
                };
                assert!(
                    lhs_is_code && (negative == (code < 0) || code == 0),
                    "to_f64({code}) in {} = {v:e}",
                    fmt_name(signed, W, of)
                );
                n += 1;
            }
        }
    }
    println!("to_f64: {n} codes exact");
}
