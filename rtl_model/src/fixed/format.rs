//! Number formats: signedness, width, fraction bits, quantisation and overflow modes.

use serde::{Deserialize, Serialize};

/// Quantisation (rounding) modes, named as in `ap_fixed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Quant {
    /// Truncate toward −∞ (drop the low bits of two's complement): `AP_TRN`, the default.
    Trn,
    /// Truncate toward zero: `AP_TRN_ZERO`.
    TrnZero,
    /// Round to nearest, ties toward +∞: `AP_RND`.
    Rnd,
    /// Round to nearest, ties toward zero: `AP_RND_ZERO`.
    RndZero,
    /// Round to nearest, ties toward −∞: `AP_RND_MIN_INF`.
    RndMinInf,
    /// Round to nearest, ties away from zero: `AP_RND_INF`.
    RndInf,
    /// Round to nearest, ties to even: `AP_RND_CONV`.
    RndConv,
}

/// Overflow modes, named as in `ap_fixed`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum OverflowMode {
    /// Clamp to the largest or smallest value: `AP_SAT`, the default.
    Sat,
    /// Clamp symmetrically: signed results never take the most negative code: `AP_SAT_SYM`.
    SatSym,
    /// Keep the low W bits (two's complement wrap): `AP_WRAP`.
    Wrap,
}

/// A fixed-point format: a W-bit two's-complement (or unsigned) integer scaled by 2^−F.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Format {
    /// Signed (two's complement) or unsigned.
    pub signed: bool,
    /// Total width W in bits, 1..=64 (2..=64 when signed).
    pub width: u8,
    /// Fraction bits F (may be negative or exceed W: the binary point may lie outside the word).
    pub frac: i8,
    /// How results are rounded into this format.
    #[serde(default = "default_quant")]
    pub quant: Quant,
    /// What happens to results outside the range.
    #[serde(default = "default_overflow")]
    pub overflow: OverflowMode,
}

fn default_quant() -> Quant {
    Quant::Trn
}

fn default_overflow() -> OverflowMode {
    OverflowMode::Sat
}

impl Format {
    /// A signed format with `int` integer bits (sign included) and `frac` fraction bits,
    /// truncating and saturating: the Q notation `Qint.frac` of the docs (`t_q16_16` is
    /// `Format::sq(16, 16)`, 32 bits).
    pub const fn sq(int: u8, frac: u8) -> Self {
        Self {
            signed: true,
            width: int + frac,
            frac: frac as i8,
            quant: Quant::Trn,
            overflow: OverflowMode::Sat,
        }
    }

    /// An unsigned format with `int` integer and `frac` fraction bits (`UQint.frac`).
    pub const fn uq(int: u8, frac: u8) -> Self {
        Self {
            signed: false,
            width: int + frac,
            frac: frac as i8,
            quant: Quant::Trn,
            overflow: OverflowMode::Sat,
        }
    }

    /// The same format with another quantisation mode.
    pub const fn with_quant(self, quant: Quant) -> Self {
        Self { quant, ..self }
    }

    /// The same format with another overflow mode.
    pub const fn with_overflow(self, overflow: OverflowMode) -> Self {
        Self { overflow, ..self }
    }

    /// Checks the limits that keep every exact intermediate within `i128`: width 1..=64
    /// (2..=64 signed), fraction bits F in −62..=62 and integer bits W − F in −62..=64. Then
    /// an operand aligned to any other valid format's fraction count stays below 2^126, and
    /// sums and products of two operands fit 127 bits.
    pub fn is_valid(&self) -> bool {
        let min = if self.signed { 2 } else { 1 };
        let int = i32::from(self.width) - i32::from(self.frac);
        (min..=64).contains(&self.width)
            && (-62..=62).contains(&self.frac)
            && (-62..=64).contains(&int)
    }

    /// Smallest raw value.
    #[inline]
    pub const fn min_raw(&self) -> i64 {
        if self.signed {
            if self.width == 64 {
                i64::MIN
            } else {
                -(1i64 << (self.width - 1))
            }
        } else {
            0
        }
    }

    /// Largest raw value. Unsigned 64-bit formats are limited to i64::MAX (63 value bits),
    /// since raw values are `i64`.
    #[inline]
    pub const fn max_raw(&self) -> i64 {
        if self.signed {
            if self.width == 64 {
                i64::MAX
            } else {
                (1i64 << (self.width - 1)) - 1
            }
        } else if self.width >= 63 {
            i64::MAX
        } else {
            (1i64 << self.width) - 1
        }
    }

    /// The format of the exact difference of two values of this one (c − o, ±e − o): one bit
    /// wider, same fraction bits. Every unit that subtracts before it multiplies (sphere,
    /// transform, walker root) sizes its product from this, so the DSP48E2 counts and latencies
    /// of `units` and `cost` agree on it. The width saturates at 255 (only an invalid format
    /// gets there).
    pub const fn exact_difference(self) -> Self {
        Self {
            width: self.width.saturating_add(1),
            ..self
        }
    }

    /// Value of one LSB: 2^−F.
    pub fn lsb(&self) -> f64 {
        2f64.powi(-i32::from(self.frac))
    }

    /// Largest representable value.
    pub fn max_value(&self) -> f64 {
        self.max_raw() as f64 * self.lsb()
    }

    /// Smallest representable value.
    pub fn min_value(&self) -> f64 {
        self.min_raw() as f64 * self.lsb()
    }

    /// Q-notation name, e.g. `sQ16.16` or `uQ1.23`.
    pub fn name(&self) -> String {
        let int = i32::from(self.width) - i32::from(self.frac);
        format!(
            "{}Q{}.{}",
            if self.signed { "s" } else { "u" },
            int,
            self.frac
        )
    }
}
