//! Multiplier cost on the target's DSP slices: how many DSP48E2 (27×18 signed multipliers)
//! a product of two formats needs when split into sub-words, the usual decomposition.

use super::Format;

/// Value bits a DSP48E2 input port takes from one operand: 27-bit port A holds 26 magnitude
/// bits plus sign, 18-bit port B holds 17 plus sign.
const A_BITS: u32 = 26;
const B_BITS: u32 = 17;

fn magnitude_bits(f: Format) -> u32 {
    u32::from(f.width) - u32::from(f.signed)
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
}
