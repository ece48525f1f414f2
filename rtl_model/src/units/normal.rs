//! Normal unit: the hit record's octahedral normal code from the leaf's stored normal and a
//! per-instance fixed-point matrix, in integers (no f64, no square root).
//!
//! Pipeline position: the record stage, in front of the packer (`hit_record::pack`): once a
//! ray's best hit is decided, the leaf attribute's snorm16 octahedral normal goes through the
//! instance's normal matrix (R·diag(1/scale), quantised by the host when it builds the frame)
//! and is re-encoded as the record's `normal_bits` octahedral (u, v). `docs/units/normal.md`
//! has the stages, widths, latency and the error derivation.
//!
//! Octahedral encoding is scale-invariant (oct(k·w) = oct(w) for k > 0), so neither the
//! attribute's direction nor the matrix product is normalised: the unfolded attribute point
//! p (|p|₁ = 32767 exactly, integers) and a matrix scaled so that its largest element is
//! ±1 give w = M·p up to a positive factor, and the projection needs one L1 norm and one
//! rounded division per component.
//!
//! Stages (LATENCY_CYCLES = 13, each within the clock rule's 300 MHz): (1a, 1b) unfold the attribute
//! code; (2) 9 products sQ2.16 × int17; (3) the three sums w; (4) |w|; (5) the L1 norm and the
//! two numerators; (6)–(7) the normalisation: l1 and both numerators shifted right together
//! until l1 has at most [`DIV_BITS`] bits; (8) the dividends; (9)–(12) the rounded restoring
//! division, two quotient bits a stage, the sign in the last. The RTL is
//! `testbench/rtl/svo_normal.v`.

use crate::fixed::Format;

/// Format of a matrix element: sQ2.16, 18 bits with the sign (one DSP48E2 B port), so that
/// ±1.0 (±65536) fits.
pub const MAT_FORMAT: Format = Format::sq(2, 16);
/// Fraction bits of a matrix element.
pub const MAT_FRAC: u32 = 16;
/// DSP48E2 per unit: the 9 products of stage 1 (18 × 17 bits each fit one 27 × 18).
pub const DSP48E2_COUNT: u32 = 9;
/// Latency in cycles (II = 1).
pub const LATENCY_CYCLES: u32 = 13;
/// Bits of the divisor the division keeps: l1 and the numerators are cut to l1's top
/// `DIV_BITS` bits (truncated) before dividing, so the divider is `DIV_BITS` + `normal_bits`
/// bits wide whatever the matrix's anisotropy, at an error of the ratio of at most
/// 2^(2 − DIV_BITS), 127 · 2^−16 ≈ 0.002 code (`docs/units/normal.md`).
pub const DIV_BITS: u32 = 18;
/// The snorm16 scale of the attribute code: value = code / 32767.
const SNORM16_ONE: i64 = 32767;

/// The per-instance normal matrix, row-major (`m_q2_16[i][j]` multiplies component j into
/// world component i), sQ2.16, scaled so that its largest element is ±1.0 (±65536).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NormalMatrix {
    /// Elements, sQ2.16 codes in −65536..=65536.
    pub m_q2_16: [[i32; 3]; 3],
}

impl NormalMatrix {
    /// The host's quantisation of an f64 normal matrix `m` (row-major): divided by its
    /// largest absolute element (the unit's output does not depend on a positive factor),
    /// then rounded to nearest into sQ2.16. A matrix with a non-finite element or no nonzero
    /// element becomes the zero matrix, whose every output is the zero vector's code (0, 0).
    pub fn quantise(m: [[f64; 3]; 3]) -> Self {
        let flat = m.iter().flatten();
        let max = flat.clone().fold(0.0f64, |a, &x| a.max(x.abs()));
        if !(max > 0.0 && max.is_finite()) || flat.clone().any(|x| !x.is_finite()) {
            return Self::default();
        }
        let one = f64::from(1u32 << MAT_FRAC);
        Self {
            m_q2_16: m.map(|row| row.map(|x| ((x / max) * one).round() as i32)),
        }
    }

    /// The 9 elements row-major, as the vectors and the RTL port carry them.
    pub fn elements(&self) -> [i32; 9] {
        let m = self.m_q2_16;
        [
            m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2],
        ]
    }
}

/// Stage 1's input: the attribute's octahedral code (u in bits 15..0, v in 31..16, snorm16)
/// unfolded to the octahedron point p in units of 1/32767, exactly: |p|₁ = 32767. The code
/// −32768 reads as −32767 (−1), as `hit_record::normal_from_snorm16` reads it.
pub fn unfold_int16(oct16: u32) -> [i64; 3] {
    let u = i64::from(oct16 as u16 as i16).max(-SNORM16_ONE);
    let v = i64::from((oct16 >> 16) as u16 as i16).max(-SNORM16_ONE);
    let z = SNORM16_ONE - u.abs() - v.abs();
    if z < 0 {
        // The lower hemisphere, folded back over the diagonals; u = 0 counts as positive.
        let sx = if u < 0 { -1 } else { 1 };
        let sy = if v < 0 { -1 } else { 1 };
        [
            sx * (SNORM16_ONE - v.abs()),
            sy * (SNORM16_ONE - u.abs()),
            z,
        ]
    } else {
        [u, v, z]
    }
}

/// w = M·p in units of 2^−16 / 32767 (|w_i| < 3·2^31: 34 bits signed).
pub fn product(m: &NormalMatrix, p: [i64; 3]) -> [i64; 3] {
    m.m_q2_16
        .map(|row| (0..3).map(|j| i64::from(row[j]) * p[j]).sum())
}

/// Stage 4: the shift that leaves l1 at most [`DIV_BITS`] bits (0 when it has fewer).
pub fn normalise_shift(l1: i64) -> u32 {
    (64 - l1.leading_zeros()).saturating_sub(DIV_BITS)
}

/// round(s·a / l1) for 0 ≤ a ≤ l1, l1 > 0, ties away from zero: ⌊(2·s·a + l1) / (2·l1)⌋,
/// the restoring division's quotient (at most s).
fn rounded_ratio(a: i64, l1: i64, s: i64) -> i64 {
    (2 * s * a + l1) / (2 * l1)
}

/// The record's octahedral normal (u, v), signed `bits`-bit codes (value = code / (2^(bits−1)
/// − 1)), of the attribute normal `oct16` through `m`: what the record stage packs. A zero
/// product (a zero matrix) encodes (0, 0), +z, as `hit_record::encode_normal` does a zero
/// vector.
pub fn normal_code(oct16: u32, m: &NormalMatrix, bits: u8) -> [i32; 2] {
    let s = (1i64 << (bits.clamp(2, 16) - 1)) - 1;
    let [x, y, z] = product(m, unfold_int16(oct16));
    let l1 = x.abs() + y.abs() + z.abs();
    if l1 == 0 {
        return [0, 0];
    }
    // Upper hemisphere: (x, y) / l1. Lower: folded, u = sign(x)·(1 − |y|/l1) =
    // sign(x)·(|x| + |z|)/l1 (and v alike), so every numerator is non-negative and ≤ l1.
    let (au, av) = if z < 0 {
        (x.abs() + z.abs(), y.abs() + z.abs())
    } else {
        (x.abs(), y.abs())
    };
    // Truncating both keeps a ≤ l1, and l1 ≥ 2^(DIV_BITS−1) > 0 after a shift.
    let sh = normalise_shift(l1);
    let (l1, au, av) = (l1 >> sh, au >> sh, av >> sh);
    let sgn = |c: i64| if c < 0 { -1 } else { 1 };
    [
        (sgn(x) * rounded_ratio(au, l1, s)) as i32,
        (sgn(y) * rounded_ratio(av, l1, s)) as i32,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64, seeded; the seed is printed by each test.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    // ---- the f64 oracle: shares no code with the unit or with hit_record ----
    fn oracle_decode16(w: u32) -> [f64; 3] {
        let u = f64::from(w as u16 as i16) / 32767.0;
        let v = f64::from((w >> 16) as u16 as i16) / 32767.0;
        let z = 1.0 - u.abs() - v.abs();
        let (x, y) = if z < 0.0 {
            ((1.0 - v.abs()) * u.signum(), (1.0 - u.abs()) * v.signum())
        } else {
            (u, v)
        };
        let l = (x * x + y * y + z * z).sqrt();
        [x / l, y / l, z / l]
    }
    fn oracle_encode(n: [f64; 3], s: f64) -> [i32; 2] {
        let l1 = n[0].abs() + n[1].abs() + n[2].abs();
        if l1 == 0.0 {
            return [0, 0];
        }
        let (x, y, z) = (n[0] / l1, n[1] / l1, n[2] / l1);
        let (u, v) = if z < 0.0 {
            (
                (1.0 - y.abs()) * if x >= 0.0 { 1.0 } else { -1.0 },
                (1.0 - x.abs()) * if y >= 0.0 { 1.0 } else { -1.0 },
            )
        } else {
            (x, y)
        };
        [(u * s).round() as i32, (v * s).round() as i32]
    }
    fn oracle_dir(c: [i32; 2], s: f64) -> [f64; 3] {
        let (u, v) = (f64::from(c[0]) / s, f64::from(c[1]) / s);
        let z = 1.0 - u.abs() - v.abs();
        let (x, y) = if z < 0.0 {
            (
                (1.0 - v.abs()) * if u >= 0.0 { 1.0 } else { -1.0 },
                (1.0 - u.abs()) * if v >= 0.0 { 1.0 } else { -1.0 },
            )
        } else {
            (u, v)
        };
        let l = (x * x + y * y + z * z).sqrt();
        [x / l, y / l, z / l]
    }
    fn mat_vec(m: [[f64; 3]; 3], n: [f64; 3]) -> [f64; 3] {
        m.map(|r| r[0] * n[0] + r[1] * n[1] + r[2] * n[2])
    }
    fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
        (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
            .clamp(-1.0, 1.0)
            .acos()
    }
    /// A random rotation (from a random unit quaternion) times diag(1/scale).
    fn random_matrix(r: &mut Rng, aniso: f64) -> [[f64; 3]; 3] {
        let (mut a, mut b, mut c, mut d);
        loop {
            (a, b, c, d) = (r.unit(), r.unit(), r.unit(), r.unit());
            let l = (a * a + b * b + c * c + d * d).sqrt();
            if l > 0.1 && l <= 1.0 {
                (a, b, c, d) = (a / l, b / l, c / l, d / l);
                break;
            }
        }
        let rot = [
            [
                a * a + b * b - c * c - d * d,
                2.0 * (b * c - a * d),
                2.0 * (b * d + a * c),
            ],
            [
                2.0 * (b * c + a * d),
                a * a - b * b + c * c - d * d,
                2.0 * (c * d - a * b),
            ],
            [
                2.0 * (b * d - a * c),
                2.0 * (c * d + a * b),
                a * a - b * b - c * c + d * d,
            ],
        ];
        let sc = [0, 1, 2].map(|_| aniso.powf(r.unit()));
        rot.map(|row| [row[0] / sc[0], row[1] / sc[1], row[2] / sc[2]])
    }

    /// Against the f64 oracle over random attribute codes and rotation·scale matrices
    /// (per-axis scales in [1/a, a], a = 1, 4, 100): every component within 1 code, except on the lower
    /// hemisphere's seam (x or y = 0 with z < 0, where ±u are the same direction, within 0.6°),
    /// and the decoded directions within two code bounds (1.92°) everywhere. Prints the counts docs/units/normal.md quotes.
    #[test]
    fn within_one_code_of_the_f64_path() {
        let seed = 0x9e37_79b9_7f4a_7c15u64;
        println!("seed {seed:#x}");
        let mut r = Rng(seed);
        let s = 127.0;
        let (mut n, mut differ, mut seam, mut worst_deg) = (0u64, 0u64, 0u64, 0.0f64);
        for i in 0..200_000 {
            let aniso = [1.0, 4.0, 100.0][i % 3];
            let m = random_matrix(&mut r, aniso);
            let oct = r.next() as u32;
            let want = oracle_encode(mat_vec(m, oracle_decode16(oct)), s);
            let got = normal_code(oct, &NormalMatrix::quantise(m), 8);
            n += 1;
            let d = (got[0] - want[0]).abs().max((got[1] - want[1]).abs());
            if d > 0 {
                differ += 1;
            }
            let deg = angle(oracle_dir(got, s), oracle_dir(want, s)).to_degrees();
            worst_deg = worst_deg.max(deg);
            if d > 1 {
                seam += 1;
                assert!(
                    deg < 0.6,
                    "seed {seed:#x} case {i}: oct {oct:#010x} got {got:?} want {want:?}, {deg}°"
                );
            }
        }
        println!(
            "{n} cases: {differ} differ by a code ({:.3} %), {seam} seam cases (>1 code, same direction), worst {worst_deg:.3}° between decoded codes",
            100.0 * differ as f64 / n as f64
        );
        // Two codes one step apart per component: at most twice the 8-bit code's own bound
        // (0.96°, hit_record::normal_error_bound_rad).
        assert!(worst_deg < 1.92, "worst {worst_deg}°");
        assert!(differ * 100 < n, "{differ} of {n} differ");
    }

    /// Identity: the attribute's code reduced to 8 bits, and the axes exactly.
    #[test]
    fn extreme_cases() {
        let id = NormalMatrix::quantise([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let enc = |u: i16, v: i16| (u as u16 as u32) | ((v as u16 as u32) << 16);
        assert_eq!(normal_code(enc(0, 0), &id, 8), [0, 0]); // +z
        assert_eq!(normal_code(enc(32767, 0), &id, 8), [127, 0]); // +x
        assert_eq!(normal_code(enc(-32767, 0), &id, 8), [-127, 0]); // −x
        assert_eq!(normal_code(enc(-32768, 0), &id, 8), [-127, 0]); // −32768 reads as −1
        assert_eq!(normal_code(enc(0, -32767), &id, 8), [0, -127]); // −y
                                                                    // −z: the fold's corner; u = v = 0 count as positive.
        assert_eq!(normal_code(enc(32767, 32767), &id, 8), [127, 127]);
        // A half-way upper-hemisphere code rounds ties away from zero: 16384/32767·127.
        assert_eq!(normal_code(enc(16384, -16384), &id, 8), [64, -64]);
        // Swap x and z: +x → +z, −z (folded) → −x.
        let swap = NormalMatrix::quantise([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]);
        assert_eq!(normal_code(enc(32767, 0), &swap, 8), [0, 0]);
        assert_eq!(normal_code(enc(32767, 32767), &swap, 8), [-127, 0]);
        // Large anisotropic scale (1e6:1): the thin axis dominates, exactly.
        let thin = NormalMatrix::quantise([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1e6]]);
        assert_eq!(thin.m_q2_16[2][2], 65536);
        assert_eq!(thin.m_q2_16[0][0], 0); // 1e-6 · 2^16 rounds to 0
        assert_eq!(normal_code(enc(100, 100), &thin, 8), [0, 0]);
        // Degenerate: zero or non-finite matrices give the zero vector's code.
        let zero = NormalMatrix::quantise([[0.0; 3]; 3]);
        assert_eq!(zero, NormalMatrix::default());
        assert_eq!(normal_code(enc(1234, -999), &zero, 8), [0, 0]);
        let nan = NormalMatrix::quantise([[f64::NAN, 0.0, 0.0], [0.0; 3], [0.0; 3]]);
        assert_eq!(nan, NormalMatrix::default());
        // 16-bit output: the identity returns the attribute code itself on the upper half.
        assert_eq!(normal_code(enc(1000, -2000), &id, 16), [1000, -2000]);
    }

    /// The widths the RTL relies on: |p|₁ = 32767 and |w_i| < 2^33 for every code and any
    /// matrix of elements within ±1.
    #[test]
    fn widths_hold() {
        let seed = 7u64;
        println!("seed {seed}");
        let mut r = Rng(seed);
        let full = NormalMatrix {
            m_q2_16: [[65536, -65536, 65536]; 3],
        };
        for _ in 0..100_000 {
            let oct = r.next() as u32;
            let p = unfold_int16(oct);
            assert_eq!(p.iter().map(|c| c.abs()).sum::<i64>(), 32767, "{oct:#x}");
            for w in product(&full, p) {
                assert!(w.abs() < 1 << 33);
            }
        }
    }
}
