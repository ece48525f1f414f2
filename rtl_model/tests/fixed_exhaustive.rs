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
//! - `from_f64`: every 6-bit format (all valid fraction counts −58..=62) and mode for every
//!   x = k/2^j (k in −300..300, j in 0..=9, exact binary fractions including exact ties), plus
//!   seeded random doubles (full range, moderate range, subnormal); NaN and ±∞.
//! - `to_f64`: exact for every code of every 6-bit format.
//! - Edges: `Format::is_valid` boundaries, `min_raw` / `max_raw` at widths 1, 2, 63, 64, and
//!   results within [min_raw, max_raw] at every width 1..=64.
//!
//! Every check compares the result code AND whether the signal's overflow counter went up by
//! exactly one (saturation or wrap) or not at all (in range), with no other signal touched.
//! Failures list the first disagreeing cases; the `minimal case` tests pin each bug found.
//!
//! Why the oracle is independent of `ops.rs`: it shares no code with it and uses a different
//! method. Values are exact rationals n / 2^k (i128 n); rounding takes `div_euclid` /
//! `rem_euclid` against the divisor and compares twice the remainder with the divisor, then
//! applies each mode from its definition (floor, toward zero, ties toward +∞ / zero / −∞ /
//! away from zero / even). Where an i128 rational would overflow (large shifts, random
//! doubles) a second oracle reads the dropped bits by position (bit s−1 = "half", any lower
//! bit = "more than half") on the infinite two's-complement extension; that oracle is itself
//! checked against the division oracle below. Overflow is an explicit range comparison against
//! ranges built from powers of two, and wrap is `rem_euclid(2^W)` then sign adjustment (beyond
//! i128, from the exact low 64 bits). Doubles are decomposed from their bit pattern into
//! mantissa · 2^exponent, so the oracle sees their exact value, never a scaled double.
//!
//! Runs with `cargo test -p rtl_model --test fixed_exhaustive` (add `-- --nocapture` to see
//! the case counts, times and seed). `SVO_TEST_SEED` overrides the default seed.

use std::cmp::Ordering;
use std::time::Instant;

use rtl_model::fixed::{
    add, from_f64, mul, quantize, sub, to_f64, Format, OverflowMode, Overflows, Quant, SignalId,
};

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

/// Width of the exhaustively tested formats.
const W: u8 = 6;
/// Operand fraction counts of the exhaustive add / sub / mul tests.
const OPERAND_FRACS: [i32; 5] = [0, 2, 5, 7, -1];
/// Result fraction counts of the exhaustive add / sub / mul tests.
const OUT_FRACS: [i32; 6] = [-3, 0, 2, 5, 8, 11];
/// Every valid fraction count of a 6-bit format (F ≥ −58 keeps W − F ≤ 64).
const ALL_FRACS_6: std::ops::RangeInclusive<i32> = -58..=62;

fn seed() -> u64 {
    std::env::var("SVO_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5eed_f1ed_2024)
}

/// splitmix64.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn range(&mut self, lo: i64, hi_incl: i64) -> i64 {
        lo + self.below((hi_incl - lo + 1) as u64) as i64
    }
    fn i128(&mut self) -> i128 {
        ((u128::from(self.next()) << 64) | u128::from(self.next())) as i128
    }
    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len() as u64) as usize]
    }
}

fn format(signed: bool, width: u8, frac: i32, quant: Quant, overflow: OverflowMode) -> Format {
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
fn pow2(e: u32) -> i128 {
    assert!(e <= 126, "2^{e} does not fit i128");
    1i128 << e
}

/// Picks floor or ceil of an inexact value from the mode's definition. `vs_half` compares the
/// dropped fraction (value − floor) with one half.
fn choose(floor: i128, negative: bool, vs_half: Ordering, quant: Quant) -> i128 {
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
fn round_div(num: i128, den: i128, quant: Quant) -> i128 {
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
fn bit_at(raw: i128, i: u32) -> bool {
    if i >= 127 {
        raw < 0
    } else {
        (raw >> i) & 1 == 1
    }
}

/// Whether any of bits 0..i of the infinite two's-complement extension of `raw` is set.
fn any_below(raw: i128, i: u32) -> bool {
    match i {
        0 => false,
        1..=126 => raw & (pow2(i) - 1) != 0,
        127 => raw & i128::MAX != 0,
        // Bits 127.. are sign copies: set for negative raw, and raw ≠ 0 otherwise.
        _ => raw != 0,
    }
}

/// `raw / 2^s` rounded by `quant`, for any s, by bit positions (i128-safe).
fn round_shift_bits(raw: i128, s: u32, quant: Quant) -> i128 {
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
struct Rat {
    n: i128,
    k: u32,
}

/// raw · 2^−frac.
fn rat(raw: i128, frac: i32) -> Rat {
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

fn rat_add(a: Rat, b: Rat) -> Rat {
    let k = a.k.max(b.k);
    Rat {
        n: a.n * pow2(k - a.k) + b.n * pow2(k - b.k),
        k,
    }
}

fn rat_neg(a: Rat) -> Rat {
    Rat { n: -a.n, k: a.k }
}

fn rat_mul(a: Rat, b: Rat) -> Rat {
    Rat {
        n: a.n * b.n,
        k: a.k + b.k,
    }
}

/// x · 2^frac rounded to an integer (the code of x in a format with `frac` fraction bits).
fn round_rat(x: Rat, frac: i32, quant: Quant) -> i128 {
    let (num, den) = if frac >= 0 {
        (x.n * pow2(frac as u32), pow2(x.k))
    } else {
        (x.n, pow2(x.k + frac.unsigned_abs()))
    };
    round_div(num, den, quant)
}

/// A rounded code before overflow handling.
#[derive(Clone, Copy, Debug)]
enum Exact {
    Int(i128),
    /// Beyond i128 (≥ 2^70 in magnitude here): only the sign and the low 64 bits matter.
    Huge {
        negative: bool,
        low64: u64,
    },
}

/// Expected outcome: result code and whether the overflow counter goes up (by one).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Expected {
    code: i64,
    counted: bool,
}

/// The code range of a format, from its definition (unsigned 64-bit is capped at i64::MAX
/// because raw codes are i64; see `edges`).
fn code_range(signed: bool, width: u8) -> (i128, i128) {
    let w = u32::from(width);
    if signed {
        (-pow2(w - 1), pow2(w - 1) - 1)
    } else {
        (0, (pow2(w) - 1).min(i128::from(i64::MAX)))
    }
}

fn wrap_to(v: i128, signed: bool, width: u8) -> i128 {
    let w = u32::from(width);
    let r = v.rem_euclid(pow2(w));
    if signed && r >= pow2(w - 1) {
        r - pow2(w)
    } else {
        r
    }
}

/// Overflow handling of a rounded code by explicit range comparison.
fn resolve(x: Exact, signed: bool, width: u8, mode: OverflowMode) -> Expected {
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
fn quantize_oracle_wide(raw: i128, from_frac: i32, out_frac: i32, quant: Quant) -> Exact {
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
fn decompose(x: f64) -> (bool, u64, i32) {
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
fn from_f64_oracle(x: f64, frac: i32, quant: Quant) -> Exact {
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
struct Checker {
    ov: Overflows,
    sig: SignalId,
    cases: u64,
    failures: u64,
    first: Vec<String>,
}

impl Checker {
    fn new() -> Self {
        Self {
            ov: Overflows::new(&["before", "dut", "after"]),
            sig: SignalId(1),
            cases: 0,
            failures: 0,
            first: Vec::new(),
        }
    }

    fn run(
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

    fn finish(self, group: &str, t0: Instant) {
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
fn codes(signed: bool) -> std::ops::RangeInclusive<i64> {
    let (lo, hi) = code_range(signed, W);
    lo as i64..=hi as i64
}

fn fmt_name(signed: bool, width: u8, frac: i32) -> String {
    format!("{}{}f{}", if signed { "s" } else { "u" }, width, frac)
}

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
    let mut rng = Rng(seed());
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
    let mut rng = Rng(seed ^ 0x1a46_e541);
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
    let mut rng = Rng(seed ^ 0x1ef7);
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
    let mut rng = Rng(seed ^ 0x00f6_4a0d);
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
    let mut rng = Rng(seed ^ 0xf_0111);
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
    let mut rng = Rng(seed ^ 0x5ab_0000);
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
