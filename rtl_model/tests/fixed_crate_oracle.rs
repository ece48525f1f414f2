//! The `fixed` crate as an independent oracle of the fixed-point layer (`rtl_model::fixed`):
//! rounding, saturation, wrap and exact products, for every format of the default datapath.
//!
//! The project keeps its own run-time formats (widths such as 41 or 48 bits that `fixed`'s
//! 8/16/32/64/128-bit storage with compile-time fraction bits cannot express;
//! `docs/number-formats.md` §1 says why). This test shares no code with that layer: a raw code
//! is read as a `fixed::FixedI128` whose fraction bits are the bits a result drops, `fixed`'s
//! own `floor`, `ceil`, `round`, `round_to_zero` and `round_ties_even` round it, products are
//! `fixed`'s exact integer products, and the ranges of a W-bit format are written out here
//! from W alone. Every default format (found by walking the serialised default datapath, so a
//! new signal is covered without editing this file) is checked with every quantisation and
//! overflow mode, on seeded random codes and on the codes at each rounding and range edge.
//!
//! Seeded: the seed is printed; `SVO_TEST_SEED` replays a failure.

use fixed::types::extra::LeEqU128;
mod common;

use common::Rng;
use fixed::types::extra::*;
use fixed::FixedI128;
use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::{add, mul, quantize, Format, OverflowMode, Overflows, Quant, SignalId};

const QUANTS: [Quant; 7] = [
    Quant::Trn,
    Quant::TrnZero,
    Quant::Rnd,
    Quant::RndZero,
    Quant::RndMinInf,
    Quant::RndInf,
    Quant::RndConv,
];
const OVERFLOWS: [OverflowMode; 3] = [OverflowMode::Sat, OverflowMode::SatSym, OverflowMode::Wrap];

/// `x` = raw · 2^−K rounded to an integer by `q`, with `fixed`'s rounding methods.
fn round_k<K: LeEqU128>(raw: i128, q: Quant) -> i128 {
    let x = FixedI128::<K>::from_bits(raw);
    if K::U32 == 0 {
        return raw; // an integer already: every mode leaves it alone
    }
    let half = FixedI128::<K>::from_bits(1i128 << (K::U32 - 1));
    let r = match q {
        Quant::Trn => x.floor(),
        Quant::TrnZero => x.round_to_zero(),
        Quant::RndInf => x.round(),
        Quant::RndConv => x.round_ties_even(),
        Quant::Rnd => (x + half).floor(),
        Quant::RndMinInf => (x - half).ceil(),
        Quant::RndZero => {
            if x >= 0 {
                (x - half).ceil()
            } else {
                (x + half).floor()
            }
        }
    };
    r.to_num::<i128>()
}

/// raw · 2^−k rounded by `q` (k may be negative: an exact left shift).
fn round_bits(raw: i128, k: i32, q: Quant) -> i128 {
    if k < 0 {
        return raw << (-k);
    }
    match k {
        0 => round_k::<U0>(raw, q),
        1 => round_k::<U1>(raw, q),
        2 => round_k::<U2>(raw, q),
        3 => round_k::<U3>(raw, q),
        4 => round_k::<U4>(raw, q),
        5 => round_k::<U5>(raw, q),
        6 => round_k::<U6>(raw, q),
        7 => round_k::<U7>(raw, q),
        8 => round_k::<U8>(raw, q),
        9 => round_k::<U9>(raw, q),
        10 => round_k::<U10>(raw, q),
        11 => round_k::<U11>(raw, q),
        12 => round_k::<U12>(raw, q),
        13 => round_k::<U13>(raw, q),
        14 => round_k::<U14>(raw, q),
        15 => round_k::<U15>(raw, q),
        16 => round_k::<U16>(raw, q),
        17 => round_k::<U17>(raw, q),
        18 => round_k::<U18>(raw, q),
        19 => round_k::<U19>(raw, q),
        20 => round_k::<U20>(raw, q),
        21 => round_k::<U21>(raw, q),
        22 => round_k::<U22>(raw, q),
        23 => round_k::<U23>(raw, q),
        24 => round_k::<U24>(raw, q),
        25 => round_k::<U25>(raw, q),
        26 => round_k::<U26>(raw, q),
        27 => round_k::<U27>(raw, q),
        28 => round_k::<U28>(raw, q),
        29 => round_k::<U29>(raw, q),
        30 => round_k::<U30>(raw, q),
        31 => round_k::<U31>(raw, q),
        32 => round_k::<U32>(raw, q),
        33 => round_k::<U33>(raw, q),
        34 => round_k::<U34>(raw, q),
        35 => round_k::<U35>(raw, q),
        36 => round_k::<U36>(raw, q),
        37 => round_k::<U37>(raw, q),
        38 => round_k::<U38>(raw, q),
        39 => round_k::<U39>(raw, q),
        40 => round_k::<U40>(raw, q),
        41 => round_k::<U41>(raw, q),
        42 => round_k::<U42>(raw, q),
        43 => round_k::<U43>(raw, q),
        44 => round_k::<U44>(raw, q),
        45 => round_k::<U45>(raw, q),
        46 => round_k::<U46>(raw, q),
        47 => round_k::<U47>(raw, q),
        48 => round_k::<U48>(raw, q),
        49 => round_k::<U49>(raw, q),
        50 => round_k::<U50>(raw, q),
        51 => round_k::<U51>(raw, q),
        52 => round_k::<U52>(raw, q),
        53 => round_k::<U53>(raw, q),
        54 => round_k::<U54>(raw, q),
        55 => round_k::<U55>(raw, q),
        56 => round_k::<U56>(raw, q),
        57 => round_k::<U57>(raw, q),
        58 => round_k::<U58>(raw, q),
        59 => round_k::<U59>(raw, q),
        60 => round_k::<U60>(raw, q),
        61 => round_k::<U61>(raw, q),
        62 => round_k::<U62>(raw, q),
        63 => round_k::<U63>(raw, q),
        64 => round_k::<U64>(raw, q),
        65 => round_k::<U65>(raw, q),
        66 => round_k::<U66>(raw, q),
        67 => round_k::<U67>(raw, q),
        68 => round_k::<U68>(raw, q),
        69 => round_k::<U69>(raw, q),
        70 => round_k::<U70>(raw, q),
        71 => round_k::<U71>(raw, q),
        72 => round_k::<U72>(raw, q),
        73 => round_k::<U73>(raw, q),
        74 => round_k::<U74>(raw, q),
        75 => round_k::<U75>(raw, q),
        76 => round_k::<U76>(raw, q),
        77 => round_k::<U77>(raw, q),
        78 => round_k::<U78>(raw, q),
        79 => round_k::<U79>(raw, q),
        80 => round_k::<U80>(raw, q),
        81 => round_k::<U81>(raw, q),
        82 => round_k::<U82>(raw, q),
        83 => round_k::<U83>(raw, q),
        84 => round_k::<U84>(raw, q),
        85 => round_k::<U85>(raw, q),
        86 => round_k::<U86>(raw, q),
        87 => round_k::<U87>(raw, q),
        88 => round_k::<U88>(raw, q),
        89 => round_k::<U89>(raw, q),
        90 => round_k::<U90>(raw, q),
        91 => round_k::<U91>(raw, q),
        92 => round_k::<U92>(raw, q),
        93 => round_k::<U93>(raw, q),
        94 => round_k::<U94>(raw, q),
        95 => round_k::<U95>(raw, q),
        96 => round_k::<U96>(raw, q),
        97 => round_k::<U97>(raw, q),
        98 => round_k::<U98>(raw, q),
        99 => round_k::<U99>(raw, q),
        100 => round_k::<U100>(raw, q),
        101 => round_k::<U101>(raw, q),
        102 => round_k::<U102>(raw, q),
        103 => round_k::<U103>(raw, q),
        104 => round_k::<U104>(raw, q),
        105 => round_k::<U105>(raw, q),
        106 => round_k::<U106>(raw, q),
        107 => round_k::<U107>(raw, q),
        108 => round_k::<U108>(raw, q),
        109 => round_k::<U109>(raw, q),
        110 => round_k::<U110>(raw, q),
        111 => round_k::<U111>(raw, q),
        112 => round_k::<U112>(raw, q),
        113 => round_k::<U113>(raw, q),
        114 => round_k::<U114>(raw, q),
        115 => round_k::<U115>(raw, q),
        116 => round_k::<U116>(raw, q),
        117 => round_k::<U117>(raw, q),
        118 => round_k::<U118>(raw, q),
        119 => round_k::<U119>(raw, q),
        120 => round_k::<U120>(raw, q),
        121 => round_k::<U121>(raw, q),
        122 => round_k::<U122>(raw, q),
        123 => round_k::<U123>(raw, q),
        124 => round_k::<U124>(raw, q),
        125 => round_k::<U125>(raw, q),
        126 => round_k::<U126>(raw, q),
        127 => round_k::<U127>(raw, q),
        _ => panic!("a format pair dropping {k} bits is outside this oracle"),
    }
}

/// The value bits of a format: W, except that raw codes are `i64`, so an unsigned format of
/// 63 or 64 bits holds 63 (the documented limit of `Format::max_raw`).
fn value_bits(f: Format) -> u32 {
    let w = u32::from(f.width);
    if f.signed {
        w
    } else {
        w.min(63)
    }
}

/// The format's range, written from its width alone.
fn range(f: Format) -> (i128, i128) {
    let w = value_bits(f);
    if f.signed {
        (-(1i128 << (w - 1)), (1i128 << (w - 1)) - 1)
    } else {
        (0, (1i128 << w) - 1)
    }
}

/// The code `v` (an exact integer) takes in `f` by its overflow mode, and whether it overflowed.
fn fit(v: i128, f: Format) -> (i64, bool) {
    let (lo, hi) = range(f);
    let lo_sym = if f.signed { lo + 1 } else { lo };
    match f.overflow {
        OverflowMode::Sat => (v.clamp(lo, hi) as i64, v < lo || v > hi),
        OverflowMode::SatSym => (v.clamp(lo_sym, hi) as i64, v < lo_sym || v > hi),
        OverflowMode::Wrap => {
            let m = 1i128 << value_bits(f);
            let mut r = v.rem_euclid(m);
            if f.signed && r > hi {
                r -= m;
            }
            (r as i64, v < lo || v > hi)
        }
    }
}

/// Every format of the default datapath, by walking its serialised form.
fn default_formats() -> Vec<Format> {
    fn walk(v: &serde_json::Value, out: &mut Vec<Format>) {
        match v {
            serde_json::Value::Object(m) => {
                if m.contains_key("width") && m.contains_key("frac") && m.contains_key("signed") {
                    if let Ok(f) = serde_json::from_value::<Format>(v.clone()) {
                        if !out.contains(&f) {
                            out.push(f);
                        }
                        return;
                    }
                }
                m.values().for_each(|x| walk(x, out));
            }
            serde_json::Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
            _ => {}
        }
    }
    let v = serde_json::to_value(DatapathConfig::default()).expect("the default serialises");
    let mut out = Vec::new();
    walk(&v, &mut out);
    out
}

/// A code of `f` (any of its value bits), biased towards the range's edges and small values.
fn code(rng: &mut Rng, f: Format) -> i64 {
    let (lo, hi) = range(f);
    let r = rng.next();
    let v = match r % 8 {
        0 => lo + (r >> 8) as i128 % 4,
        1 => hi - (r >> 8) as i128 % 4,
        2 => (r >> 8) as i128 % 64 - if f.signed { 32 } else { 0 },
        _ => lo + (u128::from(rng.next()) % ((hi - lo) as u128 + 1)) as i128,
    };
    v as i64
}

fn seed(test: &str) -> u64 {
    common::printed_seed(test, 0x0F1C_ED00_2019_0001)
}

/// Checks one quantisation of `raw` (with `from_frac` fraction bits) into `out`.
fn check_quantize(raw: i128, from_frac: i32, out: Format, what: &str) {
    let mut ov = Overflows::new(&["s"]);
    let got = quantize(raw, from_frac, out, &mut ov, SignalId(0));
    let exact = round_bits(raw, from_frac - i32::from(out.frac), out.quant);
    let (want, overflowed) = fit(exact, out);
    assert_eq!(
        got,
        want,
        "{what}: raw {raw} · 2^-{from_frac} into {} ({:?}, {:?}): rounds to {exact}",
        out.name(),
        out.quant,
        out.overflow
    );
    assert_eq!(
        ov.total() > 0,
        overflowed,
        "{what}: overflow count of {raw} · 2^-{from_frac} into {}",
        out.name()
    );
}

#[test]
fn quantize_matches_the_fixed_crate_for_every_default_format_and_mode() {
    let mut rng = Rng::new(seed("quantize_matches_the_fixed_crate"));
    let formats = default_formats();
    assert!(
        formats.len() >= 8,
        "found only {} default formats",
        formats.len()
    );
    let mut checked = 0u64;
    for &f in &formats {
        for q in QUANTS {
            for o in OVERFLOWS {
                let out = f.with_quant(q).with_overflow(o);
                // From 0 to 40 extra fraction bits, values around and beyond the range.
                for extra in [0, 1, 2, 3, 7, 16, 31, 40] {
                    let from_frac = i32::from(out.frac) + extra;
                    for _ in 0..200 {
                        let base = i128::from(code(&mut rng, out)) << extra;
                        // Every remainder class near the rounding edges: exact, just below,
                        // at and just above one half.
                        let half = if extra > 0 { 1i128 << (extra - 1) } else { 0 };
                        let r = rng.next();
                        let low = match r % 5 {
                            0 => 0,
                            1 => half - 1,
                            2 => half,
                            3 => half + 1,
                            _ => (u128::from(rng.next()) % (1u128 << extra)) as i128,
                        };
                        let low = if extra == 0 {
                            0
                        } else {
                            low.clamp(0, (1i128 << extra) - 1)
                        };
                        let raw = base + low + if r % 13 == 0 { 3i128 << (extra + 2) } else { 0 };
                        check_quantize(raw, from_frac, out, "quantize");
                        checked += 1;
                    }
                }
            }
        }
    }
    println!(
        "{checked} quantisations over {} default formats",
        formats.len()
    );
}

/// Exact left shifts (a source with fewer fraction bits than the result, as the reciprocal's
/// output stage has): codes of the result shifted back down, so most land inside the range and
/// some at its edges, with a few beyond it.
#[test]
fn left_shifts_match_the_fixed_crate() {
    let mut rng = Rng::new(seed("left_shifts_match_the_fixed_crate") ^ 0x3C3C);
    let mut checked = 0u64;
    for &f in &default_formats() {
        for q in QUANTS {
            for o in OVERFLOWS {
                let out = f.with_quant(q).with_overflow(o);
                for k in [1i32, 2, 5, 17, 40, 62, 63, 64, 70] {
                    let from_frac = i32::from(out.frac) - k;
                    for _ in 0..100 {
                        let c = i128::from(code(&mut rng, out));
                        let r = rng.next();
                        // Mostly in range (floor of a code), sometimes one past either edge.
                        let raw = (c >> k)
                            + match r % 7 {
                                0 => 1,
                                1 => -1,
                                _ => 0,
                            };
                        check_quantize(raw, from_frac, out, "left shift");
                        checked += 1;
                    }
                }
            }
        }
    }
    println!("{checked} left-shift quantisations");
}

#[test]
fn products_and_sums_match_the_fixed_crate() {
    let mut rng = Rng::new(seed("products_and_sums_match_the_fixed_crate") ^ 0x5555);
    let formats = default_formats();
    let mut checked = 0u64;
    for &fa in &formats {
        for &fb in &formats {
            // Result formats: each operand's own, rounded by every mode.
            for out in [fa, fb] {
                for q in QUANTS {
                    let out = out.with_quant(q);
                    for _ in 0..40 {
                        let (a, b) = (code(&mut rng, fa), code(&mut rng, fb));
                        let mut ov = Overflows::new(&["s"]);
                        // The exact product as `fixed` computes it: integers (no fraction
                        // bits), so the product of the codes is exact in 128 bits.
                        let p = FixedI128::<U0>::from_bits(i128::from(a))
                            * FixedI128::<U0>::from_bits(i128::from(b));
                        let pf = i32::from(fa.frac) + i32::from(fb.frac);
                        let want = fit(round_bits(p.to_bits(), pf - i32::from(out.frac), q), out).0;
                        assert_eq!(
                            mul(a, fa, b, fb, out, &mut ov, SignalId(0)),
                            want,
                            "{a} ({}) × {b} ({}) into {} {q:?}",
                            fa.name(),
                            fb.name(),
                            out.name()
                        );
                        // The exact sum at the larger fraction count.
                        let f = fa.frac.max(fb.frac);
                        let (sa, sb) = (i32::from(f - fa.frac), i32::from(f - fb.frac));
                        let s = FixedI128::<U0>::from_bits(i128::from(a) << sa)
                            + FixedI128::<U0>::from_bits(i128::from(b) << sb);
                        let want = fit(
                            round_bits(s.to_bits(), i32::from(f) - i32::from(out.frac), q),
                            out,
                        )
                        .0;
                        assert_eq!(
                            add(a, fa, b, fb, out, &mut ov, SignalId(0)),
                            want,
                            "{a} ({}) + {b} ({}) into {} {q:?}",
                            fa.name(),
                            fb.name(),
                            out.name()
                        );
                        checked += 2;
                    }
                }
            }
        }
    }
    println!(
        "{checked} products and sums over {} default formats",
        formats.len()
    );
}

/// The oracle itself against values worked by hand, so a wrong oracle cannot pass silently.
#[test]
fn oracle_rounds_the_worked_cases() {
    // 2.5, −2.5, 2.25, −2.75 with 2 fraction bits dropped to integers.
    let cases: [(i128, [i128; 7]); 4] = [
        // Trn, TrnZero, Rnd, RndZero, RndMinInf, RndInf, RndConv
        (10, [2, 2, 3, 2, 2, 3, 2]),
        (-10, [-3, -2, -2, -2, -3, -3, -2]),
        (9, [2, 2, 2, 2, 2, 2, 2]),
        (-11, [-3, -2, -3, -3, -3, -3, -3]),
    ];
    for (raw, want) in cases {
        for (q, w) in QUANTS.iter().zip(want) {
            assert_eq!(round_bits(raw, 2, *q), w, "{raw}/4 by {q:?}");
        }
    }
    let s8 = Format::sq(4, 4); // 8 bits signed
    assert_eq!(range(s8), (-128, 127));
    assert_eq!(fit(130, s8.with_overflow(OverflowMode::Wrap)), (-126, true));
    assert_eq!(
        fit(-128, s8.with_overflow(OverflowMode::SatSym)),
        (-127, true)
    );
    assert_eq!(fit(-128, s8), (-128, false));
}
