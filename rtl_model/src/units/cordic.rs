//! CORDIC sine and cosine of a binary angle (turns), for the pose path that rebuilds an
//! instance's rotation matrix from its keyframed Euler angles every frame.
//!
//! Pipeline position: host side of the frame, once per instance and angle (three per
//! instance), before `units::rotation` multiplies the three axis rotations into the matrix
//! the transform unit reads. No multiplier: shifts, adds and a small arctangent ROM.
//!
//! Datapath (bit for bit what [`Cordic::sin_cos`] computes):
//! 1. The angle θ is a binary angle: sQ0.32 turns, so its two's-complement wrap *is* the
//!    modulo-one-turn of an angle (`units::keyframe`).
//! 2. Quadrant: q = ⌊4θ + ½⌋ from the top bits, residual r = θ − q/4 ∈ [−⅛, ⅛] turn (exact).
//! 3. Rotation-mode CORDIC on r for `iterations` steps i = 0, 1, …: d = sign(z),
//!    x ← x − d·⌊y·2^−i⌋, y ← y + d·⌊x·2^−i⌋, z ← z − d·atan_i, with x, y in `work_frac`
//!    fraction bits, z and the ROM atan_i = atan(2^−i)/2π in `z_frac` fraction bits of a turn.
//!    x starts at 1/K (K = Π√(1 + 2^−2i), the CORDIC gain, a ROM constant), y at 0.
//! 4. The quadrant rotates (cos r, sin r) by q·90°: swaps and negations, exact.
//!
//! Error bound ([`error_bound`], derived in `docs/drift.md` §3): the micro-rotations turn the
//! vector by exactly Σ d_i·atan(2^−i), which differs from r by the final residual |z_n| ≤
//! atan(2^−(n−1)) plus the ROM's rounding n·e_z; each step's two floors add at most √2 LSB,
//! amplified by at most K by the later steps; 1/K is rounded once (times K).

use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Largest supported x/y fraction bits: the rotation matrix forms triple products of sines
/// and cosines exactly (3·(work_frac + 2) bits within the 127-bit accumulator), and 1/K is
/// computed in f64, exact to 2^−52.
pub const MAX_WORK_FRAC: u8 = 40;
/// Largest supported angle fraction bits inside the unit.
pub const MAX_Z_FRAC: u8 = 50;
/// Most iterations (beyond the fraction bits they stop adding accuracy).
pub const MAX_ITERATIONS: u8 = 52;

/// Parameters of the CORDIC unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CordicConfig {
    /// Fraction bits of x and y (sQ2.work_frac: the vector stays within ±1.65).
    pub work_frac: u8,
    /// Fraction bits of a turn for z and the arctangent ROM.
    pub z_frac: u8,
    /// Micro-rotations.
    pub iterations: u8,
}

impl Default for CordicConfig {
    /// 40 fraction bits for x and y, 44 for z, 36 iterations: 2^−35 rad from the residual
    /// angle and about 90 LSB of 2^−40 from the floors, together 1.3·10^−10, a seventh of
    /// the matrix format's LSB (2^−30), so the matrix entries are rounded once, nearly
    /// exactly.
    fn default() -> Self {
        Self {
            work_frac: 40,
            z_frac: 44,
            iterations: 36,
        }
    }
}

impl CordicConfig {
    /// Checks the parameters against the limits above (and z_frac ≥ 34 so the sQ0.32 angle
    /// and the quadrant split fit without rounding).
    pub fn validate(&self) -> Result<(), String> {
        if !(8..=MAX_WORK_FRAC).contains(&self.work_frac) {
            return Err(format!(
                "cordic.work_frac: {} outside 8..={MAX_WORK_FRAC}",
                self.work_frac
            ));
        }
        if !(34..=MAX_Z_FRAC).contains(&self.z_frac) {
            return Err(format!(
                "cordic.z_frac: {} outside 34..={MAX_Z_FRAC}",
                self.z_frac
            ));
        }
        if !(1..=MAX_ITERATIONS).contains(&self.iterations) {
            return Err(format!(
                "cordic.iterations: {} outside 1..={MAX_ITERATIONS}",
                self.iterations
            ));
        }
        Ok(())
    }
}

/// Fraction bits of the binary-angle input: sQ0.32 turns.
pub const ANGLE_FRAC: u32 = 32;

/// The arctangent ROM: atan(2^−i)/2π rounded to `z_frac` bits of a turn, i < `iterations`.
pub fn atan_table(cfg: &CordicConfig) -> Vec<i64> {
    let z = 2f64.powi(i32::from(cfg.z_frac.min(MAX_Z_FRAC)));
    (0..cfg.iterations.min(MAX_ITERATIONS))
        .map(|i| ((2f64.powi(-i32::from(i))).atan() / TAU * z).round() as i64)
        .collect()
}

/// The CORDIC gain K = Π √(1 + 2^−2i) over the iterations.
pub fn gain(iterations: u8) -> f64 {
    (0..iterations.min(MAX_ITERATIONS))
        .map(|i| (1.0 + 2f64.powi(-2 * i32::from(i))).sqrt())
        .product()
}

/// The unit with its ROM contents (built once, used for every angle).
#[derive(Clone, Debug)]
pub struct Cordic {
    cfg: CordicConfig,
    atan: Vec<i64>,
    x0: i64,
}

impl Cordic {
    /// Builds the ROMs. The configuration is clamped into the supported ranges
    /// ([`CordicConfig::validate`] says whether it needed to be).
    pub fn new(cfg: &CordicConfig) -> Self {
        let cfg = CordicConfig {
            work_frac: cfg.work_frac.clamp(8, MAX_WORK_FRAC),
            z_frac: cfg.z_frac.clamp(34, MAX_Z_FRAC),
            iterations: cfg.iterations.clamp(1, MAX_ITERATIONS),
        };
        let x0 = (2f64.powi(i32::from(cfg.work_frac)) / gain(cfg.iterations)).round() as i64;
        Self {
            atan: atan_table(&cfg),
            cfg,
            x0,
        }
    }

    /// (cos θ, sin θ) of the binary angle `theta` (sQ0.32 turns; any `i64` is taken modulo
    /// one turn, i.e. its low 32 bits), as raw codes with `work_frac` fraction bits.
    pub fn sin_cos(&self, theta: i64) -> (i64, i64) {
        // Low 32 bits, sign-extended: the angle modulo one turn in [−½, ½).
        let theta = i64::from(theta as i32);
        // q = ⌊4θ + ½⌋ ∈ {−2, …, 2}; r = θ − q/4 in [−⅛, ⅛] turn, exact.
        let quarter = 1i64 << (ANGLE_FRAC - 2);
        let q = (theta + (quarter >> 1)) >> (ANGLE_FRAC - 2);
        let r = theta - q * quarter;
        let mut z = r << (u32::from(self.cfg.z_frac) - ANGLE_FRAC);
        let (mut x, mut y) = (self.x0, 0i64);
        for (i, &a) in self.atan.iter().enumerate() {
            let (dx, dy) = (y >> i, x >> i);
            if z >= 0 {
                x -= dx;
                y += dy;
                z -= a;
            } else {
                x += dx;
                y -= dy;
                z += a;
            }
        }
        // Rotate (cos r, sin r) by q quarter turns.
        match q.rem_euclid(4) {
            0 => (x, y),
            1 => (-y, x),
            2 => (-x, -y),
            _ => (y, -x),
        }
    }

    /// The configuration in use (after clamping).
    pub fn config(&self) -> &CordicConfig {
        &self.cfg
    }
}

/// Bound on |cos_fixed − cos θ| and |sin_fixed − sin θ| (values, not LSBs) for any angle
/// code, with θ the code's exact value:
///
/// ```text
/// angle:    atan(2^−(n−1)) + 2π·n·½·2^−z_frac      (final residual, ROM rounding; radians)
/// floors:   n·√2·K·2^−work_frac                    (two floors per step, amplified by ≤ K)
/// start:    K·½·2^−work_frac                        (1/K rounded)
/// ```
pub fn error_bound(cfg: &CordicConfig) -> f64 {
    let c = Cordic::new(cfg).cfg;
    let n = f64::from(c.iterations);
    let k = gain(c.iterations);
    let lsb = 2f64.powi(-i32::from(c.work_frac));
    let ez = 0.5 * 2f64.powi(-i32::from(c.z_frac));
    let angle = (2f64.powi(1 - i32::from(c.iterations))).atan() + TAU * n * ez;
    angle + n * 2f64.sqrt() * k * lsb + k * 0.5 * lsb
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrants_are_exact_rotations() {
        let c = Cordic::new(&CordicConfig::default());
        let one = 1i64 << 40;
        let quarter = 1i64 << 30;
        let b = error_bound(&CordicConfig::default()) * one as f64;
        for (turns, want) in [
            (0, (1.0, 0.0)),
            (quarter, (0.0, 1.0)),
            (2 * quarter, (-1.0, 0.0)),
            (-quarter, (0.0, -1.0)),
            (-2 * quarter, (-1.0, 0.0)),
        ] {
            let (cs, sn) = c.sin_cos(turns);
            assert!(((cs as f64) - want.0 * one as f64).abs() <= b, "{turns}");
            assert!(((sn as f64) - want.1 * one as f64).abs() <= b, "{turns}");
        }
        assert!(error_bound(&CordicConfig::default()) < 2f64.powi(-32));
    }
}
