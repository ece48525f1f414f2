//! Rotation-matrix arithmetic of the pose path: 3×3 products (composing a per-frame rotation
//! into an instance's matrix), Newton–Schulz re-orthonormalisation, and the exact
//! orthonormality metric.
//!
//! Pipeline position: once per instance and frame, before the sphere and transform units.
//! An animation can either rebuild each matrix from its keyframes (`units::keyframe`) or keep
//! it in a register and update it incrementally, R ← R·ΔR. Incremental updates accumulate
//! rounding: without correction RᵀR drifts away from I (the matrix scales and shears rays).
//! [`orthonormalise`] pulls it back each frame with one Newton–Schulz (Björck) step,
//!
//! ```text
//! C = (I − RᵀR)/2,   R' = R + R·C        (= R·(3I − RᵀR)/2)
//! ```
//!
//! which needs multipliers and adders only (no square root or division) and squares the
//! error: with RᵀR = I + E, R'ᵀR' = I − ¾E² + ¼E³. So one step per frame holds the error at
//! the rounding floor ([`steady_state_orthonormality_bound`]); derivation in `docs/drift.md`.
//!
//! Arithmetic, as the RTL does it: every dot product is formed from exact products, summed in
//! full width as (p0 + p1) + p2 and rounded once into the output format; C is rounded once
//! into the narrow `corr` format (it is tiny: a few LSBs of the matrix format), and R + R·C is
//! summed exactly and rounded once. Saturations are counted, never silent.
//!
//! Matrices are stored by columns, as the transform unit's `InstanceRaw::axes`: `m[c][r]` is
//! row r of column c.

use crate::fixed::{quantize, Format, Overflows, Quant, SignalId};
use serde::{Deserialize, Serialize};

/// A 3×3 matrix of raw codes, by columns (`m[c][r]`).
pub type MatRaw = [[i64; 3]; 3];

/// Formats of the rotation arithmetic.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationConfig {
    /// Per-frame rotation ΔR as the host writes it (the transform's matrix format).
    pub delta: Format,
    /// The incremental register R (its format is also the product's output).
    pub acc: Format,
    /// The correction C = (I − RᵀR)/2 of the Newton–Schulz step.
    pub corr: Format,
}

impl Default for RotationConfig {
    /// ΔR and R in sQ2.30 rounded to nearest even (the transform's `mat`), C in a 42-bit
    /// format with 60 fraction bits (|C| < 2^−19, 2^30 times the LSB of R; a larger C, i.e. a
    /// matrix already far from orthonormal, saturates and is counted).
    fn default() -> Self {
        let mat = Format::sq(2, 30).with_quant(Quant::RndConv);
        Self {
            delta: mat,
            acc: mat,
            corr: Format {
                signed: true,
                width: 42,
                frac: 60,
                quant: Quant::RndConv,
                overflow: crate::fixed::OverflowMode::Sat,
            },
        }
    }
}

impl RotationConfig {
    /// Checks that the formats are valid and signed and that every exact product and sum fits
    /// the 127-bit accumulator.
    pub fn validate(&self) -> Result<(), String> {
        for (name, f) in [
            ("delta", self.delta),
            ("acc", self.acc),
            ("corr", self.corr),
        ] {
            if !f.is_valid() || !f.signed {
                return Err(format!(
                    "rotation.{name}: format {} must be valid and signed",
                    f.name()
                ));
            }
        }
        let wa = u32::from(self.acc.width);
        if wa + u32::from(self.delta.width) + 2 > 126
            || 2 * wa + 3 > 126
            || wa + u32::from(self.corr.width) + 3 > 126
        {
            return Err("rotation: widths exceed the 127-bit accumulator".into());
        }
        if i32::from(self.corr.frac) < 2 * i32::from(self.acc.frac) - 62 {
            return Err("rotation.corr: too few fraction bits for acc".into());
        }
        Ok(())
    }
}

/// Overflow signals of the rotation arithmetic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RotationSignals {
    /// A matrix entry out of range.
    pub mat: SignalId,
    /// The correction C out of its format's range.
    pub corr: SignalId,
}

/// A·B, every entry an exact dot product (p0 + p1) + p2 rounded once into `out`.
pub fn mul(
    a: &MatRaw,
    fa: Format,
    b: &MatRaw,
    fb: Format,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> MatRaw {
    let frac = i32::from(fa.frac) + i32::from(fb.frac);
    // Column j of A·B is A times column j of B: row i is Σ_k A[k][i]·B[j][k].
    [0, 1, 2].map(|j| {
        [0, 1, 2].map(|i| {
            let p = [0, 1, 2].map(|k| i128::from(a[k][i]) * i128::from(b[j][k]));
            quantize((p[0] + p[1]) + p[2], frac, out, ov, sig)
        })
    })
}

/// RᵀR − I exactly, as i128 codes with 2·F fraction bits (F = `f.frac`): entry (i, j) is the
/// dot product of columns i and j, less 1 on the diagonal.
fn gram_minus_identity(r: &MatRaw, f: Format) -> [[i128; 3]; 3] {
    let one = 1i128 << (2 * i32::from(f.frac)).clamp(0, 124);
    [0, 1, 2].map(|i| {
        [0, 1, 2].map(|j| {
            let p = [0, 1, 2].map(|k| i128::from(r[i][k]) * i128::from(r[j][k]));
            (p[0] + p[1]) + p[2] - if i == j { one } else { 0 }
        })
    })
}

/// The orthonormality error max_ij |(RᵀR − I)_ij| of a matrix of codes in `f`, computed
/// exactly (then rounded once to f64).
pub fn orthonormality_error(r: &MatRaw, f: Format) -> f64 {
    let e = gram_minus_identity(r, f);
    let scale = 2f64.powi(-2 * i32::from(f.frac));
    e.iter()
        .flatten()
        .map(|&v| (v as f64 * scale).abs())
        .fold(0.0, f64::max)
}

/// One Newton–Schulz step R' = R + R·C, C = (I − RᵀR)/2, on a matrix of codes in `cfg.acc`;
/// the result is in `cfg.acc`.
pub fn orthonormalise(
    r: &MatRaw,
    cfg: &RotationConfig,
    ov: &mut Overflows,
    sig: RotationSignals,
) -> MatRaw {
    let fa = i32::from(cfg.acc.frac);
    let e = gram_minus_identity(r, cfg.acc);
    // C = −E/2: 2F + 1 fraction bits, exact, then rounded once into `corr`.
    let c = e.map(|col| col.map(|v| quantize(-v, 2 * fa + 1, cfg.corr, ov, sig.corr)));
    let fc = i32::from(cfg.corr.frac);
    // Column j of R' is column j of R plus Σ_k (column k of R)·C[k][j]; C is symmetric.
    [0, 1, 2].map(|j| {
        [0, 1, 2].map(|i| {
            let p = [0, 1, 2].map(|k| i128::from(r[k][i]) * i128::from(c[j][k]));
            let base = i128::from(r[j][i]) << fc;
            quantize(base + ((p[0] + p[1]) + p[2]), fa + fc, cfg.acc, ov, sig.mat)
        })
    })
}

/// Worst-case error of converting an exact value into `f` (by its quantisation mode).
fn conv(f: Format) -> f64 {
    match f.quant {
        Quant::Trn | Quant::TrnZero => f.lsb(),
        _ => 0.5 * f.lsb(),
    }
}

/// Orthonormality error of a matrix whose entries each lie within `e` of an orthonormal
/// matrix's: |(R + Δ)ᵀ(R + Δ) − I|_ij ≤ |RᵀΔ|_ij + |ΔᵀR|_ij + |ΔᵀΔ|_ij ≤ 2√3·e + 3e²
/// (a unit column's entries sum to at most √3 in magnitude).
pub fn rounding_orthonormality(e: f64) -> f64 {
    2.0 * 3f64.sqrt() * e + 3.0 * e * e
}

/// Orthonormality error after one Newton–Schulz step of a matrix with error at most `e_in`
/// (entry-wise): the exact step leaves ¾E² − ¼E³ with ‖E‖₂ ≤ 3·e_in; C's rounding moves
/// each entry of R·C by at most √3·e_corr·(1 + e_in); the output rounding adds
/// [`rounding_orthonormality`] of e_acc (plus the cross term with the C error).
pub fn reorthonormalised_bound(cfg: &RotationConfig, e_in: f64) -> f64 {
    let s = 3.0 * e_in;
    let quad = 0.75 * s * s + 0.25 * s * s * s;
    let ec = 3f64.sqrt() * conv(cfg.corr) * (1.0 + e_in);
    rounding_orthonormality(conv(cfg.acc) + ec) + quad + 2.0 * 3f64.sqrt() * ec
}

/// Orthonormality error of R·ΔR rounded into `acc`, for R with error `e_r` and ΔR quantised
/// from an exact rotation: ΔᵀΔ − I (≤ [`rounding_orthonormality`] of e_delta), plus
/// ΔᵀEΔ (≤ 3·e_r·(1 + η)), plus the product's rounding.
pub fn composed_bound(cfg: &RotationConfig, e_r: f64) -> f64 {
    let eta = rounding_orthonormality(conv(cfg.delta));
    eta + 3.0 * e_r * (1.0 + 3.0 * eta) + rounding_orthonormality(conv(cfg.acc)) * (1.0 + e_r)
}

/// The orthonormality error the incremental update R ← orthonormalise(R·ΔR) keeps for ever,
/// starting from a matrix quantised from a rotation: the fixed point of
/// e ↦ [`reorthonormalised_bound`]([`composed_bound`](e)), reached from above by iteration
/// (the map is a contraction near its small fixed point, since the step squares the error).
pub fn steady_state_orthonormality_bound(cfg: &RotationConfig) -> f64 {
    let mut e = rounding_orthonormality(conv(cfg.acc));
    for _ in 0..64 {
        let next = reorthonormalised_bound(cfg, composed_bound(cfg, e)).max(e);
        if next == e {
            break;
        }
        e = next;
    }
    e
}

/// Bound on the largest entry of R_n − R_exact(n) after n incremental updates with
/// re-orthonormalisation (the pose error; the orthonormality stays bounded, but a rotation
/// quantised once is turned by a slightly wrong angle every frame, so this grows linearly):
///
/// ```text
/// per frame (Frobenius): ΔR's quantisation 3·e_delta, the product's rounding 3·e_acc,
/// the correction R·C ≤ 1.5·3·e_comp, its rounding 3·e_acc; the error is carried by
/// ‖ΔR_q‖₂ ≤ 1 + η each frame:  ε_n ≤ (1 + η)^n·(ε_0 + n·δ).
/// ```
pub fn incremental_pose_error_bound(cfg: &RotationConfig, frames: u64) -> f64 {
    let e_comp = composed_bound(cfg, steady_state_orthonormality_bound(cfg));
    let delta = 3.0 * conv(cfg.delta) + 6.0 * conv(cfg.acc) + 4.5 * e_comp;
    let eta = rounding_orthonormality(conv(cfg.delta));
    let n = frames as f64;
    (1.0 + eta).powf(n) * (3.0 * conv(cfg.acc) + n * delta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{from_f64, Overflows};

    #[test]
    fn identity_stays_and_scaled_matrix_is_pulled_back() {
        let cfg = RotationConfig::default();
        cfg.validate().unwrap();
        let mut ov = Overflows::new(&["mat", "corr"]);
        let sig = RotationSignals {
            mat: SignalId(0),
            corr: SignalId(1),
        };
        let one = 1i64 << 30;
        let id = [[one, 0, 0], [0, one, 0], [0, 0, one]];
        assert_eq!(orthonormalise(&id, &cfg, &mut ov, sig), id);
        // 1 + 1000 LSB on the diagonal: one step brings it to the rounding floor.
        let s = from_f64(1.0 + 1000.0 / one as f64, cfg.acc, &mut ov, sig.mat);
        let big = [[s, 0, 0], [0, s, 0], [0, 0, s]];
        assert!(orthonormality_error(&big, cfg.acc) > 1.5e-6);
        let fixed = orthonormalise(&big, &cfg, &mut ov, sig);
        assert!(orthonormality_error(&fixed, cfg.acc) <= reorthonormalised_bound(&cfg, 2e-6));
        assert_eq!(ov.total(), 0);
        let b = steady_state_orthonormality_bound(&cfg);
        assert!(b > 1.5e-9 && b < 3e-9, "{b}");
    }
}
