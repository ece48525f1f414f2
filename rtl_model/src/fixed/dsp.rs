//! Multiplier cost on the target's DSP slices: how many DSP48E2 (27×18 signed multipliers)
//! a product of two formats needs when split into sub-words, the usual decomposition, and how
//! many cycles it takes.
//!
//! Pipeline position: below every unit's cost function (`units::*::dsp48e2_count`,
//! `*_latency_cycles`); `cost` adds the units up.

use super::Format;

/// Value bits a DSP48E2 input port takes from one operand: 27-bit port A holds 26 magnitude
/// bits plus sign, 18-bit port B holds 17 plus sign.
const A_BITS: u32 = 26;
const B_BITS: u32 = 17;

/// Cycles of one multiply in a DSP48E2 with its input, multiplier and product registers.
pub const DSP_PIPELINE_CYCLES: u32 = 3;

/// Magnitude bits of an operand: width − sign, at least 1, so that a format narrower than its
/// sign bit (no valid configuration has one) is counted as one magnitude bit instead of
/// underflowing.
fn magnitude_bits(f: Format) -> u32 {
    u32::from(f.width)
        .saturating_sub(u32::from(f.signed))
        .max(1)
}

/// DSP48E2 slices for one a×b product: the operands are split into ⌈m/26⌉ and ⌈m/17⌉
/// sub-words (m = magnitude bits), one slice per partial product, with the wider operand on
/// the 27-bit port (whichever assignment needs fewer slices).
pub fn dsp48e2_per_product(a: Format, b: Format) -> u32 {
    let (ma, mb) = (magnitude_bits(a), magnitude_bits(b));
    let one = ma.div_ceil(A_BITS) * mb.div_ceil(B_BITS);
    let other = mb.div_ceil(A_BITS) * ma.div_ceil(B_BITS);
    one.min(other).max(1)
}

/// Cycles of one a×b product: [`DSP_PIPELINE_CYCLES`], plus one to add the partial products
/// when it spans several slices. Every unit's latency counts its products by this rule.
pub fn product_latency_cycles(a: Format, b: Format) -> u32 {
    DSP_PIPELINE_CYCLES + u32::from(dsp48e2_per_product(a, b) > 1)
}

/// `count` products of `a` × `b` a unit computes side by side (in the same pipeline stage).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Products {
    /// How many.
    pub count: u32,
    /// First operand (on the wider port when it is the wider one).
    pub a: Format,
    /// Second operand.
    pub b: Format,
}

impl Products {
    /// `count` products of `a` × `b`.
    pub const fn new(count: u32, a: Format, b: Format) -> Self {
        Self { count, a, b }
    }

    /// DSP48E2 slices of all of them.
    pub fn dsp48e2(&self) -> u32 {
        self.count * dsp48e2_per_product(self.a, self.b)
    }

    /// Cycles of the stage (they run in parallel: one product's latency).
    pub fn latency_cycles(&self) -> u32 {
        product_latency_cycles(self.a, self.b)
    }

    /// Operand widths in bits (sign included), as `sim sweep` prints them.
    pub fn operand_bits(&self) -> (u32, u32) {
        (u32::from(self.a.width), u32::from(self.b.width))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn native_sizes_take_one_slice() {
        assert_eq!(dsp48e2_per_product(Format::sq(1, 26), Format::sq(1, 17)), 1);
        assert_eq!(dsp48e2_per_product(Format::sq(1, 17), Format::sq(1, 26)), 1);
        assert_eq!(dsp48e2_per_product(Format::sq(8, 32), Format::sq(2, 30)), 4);
        assert_eq!(dsp48e2_per_product(Format::uq(0, 26), Format::uq(0, 17)), 1);
    }

    #[test]
    fn a_product_spanning_slices_takes_one_more_cycle() {
        assert_eq!(
            product_latency_cycles(Format::sq(1, 26), Format::sq(1, 17)),
            3
        );
        assert_eq!(
            product_latency_cycles(Format::sq(8, 32), Format::sq(2, 30)),
            4
        );
    }

    #[test]
    fn a_format_narrower_than_its_sign_counts_one_magnitude_bit() {
        let bad = Format {
            width: 1,
            ..Format::sq(1, 0)
        };
        assert_eq!(dsp48e2_per_product(bad, Format::sq(1, 17)), 1);
        assert_eq!(Format::sq(8, 32).exact_difference().width, 41);
    }
}
