//! Keyframe interpolation in fixed point: an instance's Euler angles and translation at a
//! frame, and its rotation matrix R = Rz(γ)·Ry(β)·Rx(α) from CORDIC sines and cosines.
//!
//! Pipeline position: the pose path, once per instance and frame, before the sphere and
//! transform units (the alternative to the incremental update of `units::rotation`). Every
//! frame is computed from the keys afresh, so errors never accumulate across frames.
//!
//! Arithmetic:
//! - Per key segment the host writes the value at the segment's first key (`base`) and the
//!   change per frame (`step`); the unit computes v = base + step·k, k = frames since that
//!   key (`frame` format), as an exact product and sum rounded once. Angles are binary angles
//!   (turns): their sum wraps modulo one turn in two's complement, which is the angle's own
//!   periodicity and not an overflow; they are rounded half up into sQ0.32 turns.
//! - Each matrix entry is a sum of at most two products of three sines/cosines, formed exactly
//!   (3·(G + 2) bits, G the CORDIC's fraction bits) and rounded once into `mat`.

use super::cordic::{error_bound as cordic_error_bound, Cordic, CordicConfig, ANGLE_FRAC};
use super::rotation::MatRaw;
use crate::fixed::{quantize, Format, Overflows, Quant, SignalId};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Formats of the keyframe path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeConfig {
    /// An angle at a key, in turns (wraps modulo one turn).
    pub angle_base: Format,
    /// Angle change per frame, turns.
    pub angle_step: Format,
    /// Frames since the segment's first key.
    pub frame: Format,
    /// Translation at a key (metres): the datapath's position format.
    pub pos: Format,
    /// Translation change per frame (metres).
    pub pos_step: Format,
    /// Matrix entries out (the transform's `mat`).
    pub mat: Format,
    /// Sine and cosine unit.
    pub cordic: CordicConfig,
}

impl Default for KeyframeConfig {
    /// Angles at keys in sQ0.48 turns and steps in sQ16.48 turns per frame (to 2^−49 turn:
    /// 10^6 frames of one segment add 2·10^−9 turn); frames since the key in uQ24.8 (keys
    /// on 1/256 frame are exact); translations sQ8.32 with steps sQ8.48; matrix sQ2.30 to
    /// nearest even; the default CORDIC.
    fn default() -> Self {
        Self {
            angle_base: Format::sq(0, 48).with_quant(Quant::RndConv),
            angle_step: Format::sq(16, 48).with_quant(Quant::RndConv),
            frame: Format::uq(24, 8).with_quant(Quant::RndConv),
            pos: Format::sq(8, 32).with_quant(Quant::RndConv),
            pos_step: Format::sq(8, 48).with_quant(Quant::RndConv),
            mat: Format::sq(2, 30).with_quant(Quant::RndConv),
            cordic: CordicConfig::default(),
        }
    }
}

impl KeyframeConfig {
    /// Checks the formats and the accumulator widths.
    pub fn validate(&self) -> Result<(), String> {
        self.cordic.validate()?;
        for (name, f) in [
            ("angle_base", self.angle_base),
            ("angle_step", self.angle_step),
            ("frame", self.frame),
            ("pos", self.pos),
            ("pos_step", self.pos_step),
            ("mat", self.mat),
        ] {
            if !f.is_valid() {
                return Err(format!("keyframe.{name}: format {} is not valid", f.name()));
            }
        }
        let prod = |a: Format, b: Format| u32::from(a.width) + u32::from(b.width);
        if prod(self.angle_step, self.frame) > 120 || prod(self.pos_step, self.frame) > 120 {
            return Err("keyframe: step × frame exceeds the accumulator".into());
        }
        if i32::from(self.angle_base.frac) < ANGLE_FRAC as i32
            || i32::from(self.angle_step.frac) + i32::from(self.frame.frac) > 100
        {
            return Err("keyframe: angle formats need at least 32 fraction bits".into());
        }
        Ok(())
    }
}

/// Overflow signals of the keyframe path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyframeSignals {
    /// Host values (bases, steps, frame counts) out of their formats.
    pub host: SignalId,
    /// Interpolated translation out of `pos`.
    pub pos: SignalId,
    /// A matrix entry out of `mat`.
    pub mat: SignalId,
}

/// One interpolated channel as the host writes it: value at the key and change per frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Segment {
    /// Value at the segment's first key (`angle_base` or `pos`).
    pub base: i64,
    /// Change per frame (`angle_step` or `pos_step`).
    pub step: i64,
}

/// base + step·k, exact, with the fraction count of the larger side.
fn affine(base: i64, fb: Format, s: &Segment, fs: Format, k: i64, fk: Format) -> (i128, i32) {
    let fp = i32::from(fs.frac) + i32::from(fk.frac);
    let f = fp.max(i32::from(fb.frac));
    let prod = (i128::from(s.step) * i128::from(k)) << (f - fp);
    ((i128::from(base) << (f - i32::from(fb.frac))) + prod, f)
}

/// The binary angle base + step·k (sQ0.32 turns, wrapped modulo one turn, rounded half up).
pub fn angle_at(s: &Segment, k: i64, cfg: &KeyframeConfig) -> i64 {
    let (sum, f) = affine(s.base, cfg.angle_base, s, cfg.angle_step, k, cfg.frame);
    let shift = f - ANGLE_FRAC as i32;
    let rounded = if shift > 0 {
        (sum + (1i128 << (shift - 1))) >> shift
    } else {
        sum << -shift
    };
    // Two's-complement wrap to 32 bits: modulo one turn.
    i64::from(rounded as i32)
}

/// The translation base + step·k in `pos` (saturating, counted).
pub fn position_at(
    s: &Segment,
    k: i64,
    cfg: &KeyframeConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    let (sum, f) = affine(s.base, cfg.pos, s, cfg.pos_step, k, cfg.frame);
    quantize(sum, f, cfg.pos, ov, sig)
}

/// R = Rz(γ)·Ry(β)·Rx(α) for binary angles [α, β, γ] (sQ0.32 turns), by columns in `mat`.
pub fn euler_matrix(
    angles: [i64; 3],
    cordic: &Cordic,
    cfg: &KeyframeConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> MatRaw {
    let g = i32::from(cordic.config().work_frac);
    let [(ca, sa), (cb, sb), (cg, sg)] = angles
        .map(|a| cordic.sin_cos(a))
        .map(|(c, s)| (i128::from(c), i128::from(s)));
    let one = 1i128 << g;
    // Every entry at 3G fraction bits; two-factor terms carry an exact factor 2^G.
    let entries = [
        [cg * cb * one, sg * cb * one, -sb * one * one],
        [
            cg * sb * sa - sg * ca * one,
            sg * sb * sa + cg * ca * one,
            cb * sa * one,
        ],
        [
            cg * sb * ca + sg * sa * one,
            sg * sb * ca - cg * sa * one,
            cb * ca * one,
        ],
    ];
    entries.map(|col| col.map(|v| quantize(v, 3 * g, cfg.mat, ov, sig)))
}

/// Worst-case error of converting an exact value into `f` (by its quantisation mode).
fn conv(f: Format) -> f64 {
    match f.quant {
        Quant::Trn | Quant::TrnZero => f.lsb(),
        _ => 0.5 * f.lsb(),
    }
}

/// Bound (radians) on an interpolated angle's error against the exact base + step·k, for
/// k ≤ `k_max` frames and |step| ≤ `step_max` turns per frame: the base's and the step's
/// quantisation (times k), k's quantisation (times |step|), and the output's half LSB.
/// `k_exact`: every key lies on a multiple of the `frame` format's LSB (integer keys do), so
/// k is exact and its term vanishes.
pub fn angle_error_bound(cfg: &KeyframeConfig, k_max: f64, step_max: f64, k_exact: bool) -> f64 {
    let out = 0.5 * 2f64.powi(-(ANGLE_FRAC as i32));
    let k_err = if k_exact { 0.0 } else { conv(cfg.frame) };
    TAU * (conv(cfg.angle_base) + k_max * conv(cfg.angle_step) + step_max * k_err + out)
}

/// Bound on each matrix entry's error against the exact Rz·Ry·Rx of the exact angles, given
/// the angles' error `angle_err` (radians): each entry is a sum of at most two products of
/// three sines/cosines with error e_c ≤ the CORDIC bound, so 6·e_c·(1 + e_c)²; each angle
/// moves an entry by at most its error (∂R/∂θ = K·R has entries ≤ 1), so 3·angle_err; then
/// the output rounding.
pub fn matrix_error_bound(cfg: &KeyframeConfig, angle_err: f64) -> f64 {
    let ec = cordic_error_bound(&cfg.cordic);
    6.0 * ec * (1.0 + ec) * (1.0 + ec) + 3.0 * angle_err + conv(cfg.mat)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_wrap_modulo_one_turn() {
        let cfg = KeyframeConfig::default();
        cfg.validate().unwrap();
        // 0.75 turn + 0.5 turn/frame × 1 frame = 1.25 ≡ 0.25 turn.
        let s = Segment {
            base: (0.75 * 2f64.powi(48)) as i64 - (1i64 << 48),
            step: 1i64 << 47,
        };
        assert_eq!(angle_at(&s, 1 << 8, &cfg), 1 << 30);
    }
}
