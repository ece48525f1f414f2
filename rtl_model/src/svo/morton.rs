//! 3-D Morton (Z-order) codes for leaf coordinates up to depth 20 (60 bits).
//!
//! Bit 3k+2 of a code is bit k of x, 3k+1 of y, 3k of z, so the three lowest bits of a code
//! are exactly the child label of the leaf inside its parent (x = 4, y = 2, z = 1), the label
//! convention of Revelles et al. (2000) that the walker uses.

/// Spreads the low 21 bits of `v` so that bit k moves to bit 3k.
#[inline]
fn spread3(v: u32) -> u64 {
    let mut x = u64::from(v) & 0x1f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// Inverse of [`spread3`]: gathers bits 0, 3, 6, … into a compact integer.
#[inline]
fn compact3(v: u64) -> u32 {
    let mut x = v & 0x1249_2492_4924_9249;
    x = (x | (x >> 2)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x >> 4)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x >> 8)) & 0x001f_0000_ff00_00ff;
    x = (x | (x >> 16)) & 0x001f_0000_0000_ffff;
    x = (x | (x >> 32)) & 0x1f_ffff;
    x as u32
}

/// Morton code of integer voxel coordinates (each below 2^21).
///
/// The lowest three bits are the child label inside the parent (x = 4, y = 2, z = 1):
/// ```
/// use rtl_model::svo::morton::{decode, encode};
/// assert_eq!(encode(1, 0, 1), 0b101);
/// assert_eq!(encode(2, 3, 1), 0b110_011);
/// assert_eq!(decode(encode(700, 5, 123_456)), [700, 5, 123_456]);
/// ```
#[inline]
pub fn encode(x: u32, y: u32, z: u32) -> u64 {
    (spread3(x) << 2) | (spread3(y) << 1) | spread3(z)
}

/// Integer voxel coordinates of a Morton code.
#[inline]
pub fn decode(code: u64) -> [u32; 3] {
    [compact3(code >> 2), compact3(code >> 1), compact3(code)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_bit_order() {
        assert_eq!(encode(1, 0, 0), 4);
        assert_eq!(encode(0, 1, 0), 2);
        assert_eq!(encode(0, 0, 1), 1);
        assert_eq!(encode(2, 0, 0), 32);
        for &(x, y, z) in &[
            (0, 0, 0),
            (1, 2, 3),
            (1_048_575, 7, 524_288),
            (12345, 67890, 99),
        ] {
            assert_eq!(decode(encode(x, y, z)), [x, y, z]);
        }
    }

    #[test]
    fn matches_bit_by_bit_definition() {
        // Oracle: interleave one bit at a time.
        let slow = |x: u32, y: u32, z: u32| {
            let mut c = 0u64;
            for k in 0..20 {
                c |= u64::from((x >> k) & 1) << (3 * k + 2);
                c |= u64::from((y >> k) & 1) << (3 * k + 1);
                c |= u64::from((z >> k) & 1) << (3 * k);
            }
            c
        };
        let mut s = 0x9e37_79b9_7f4a_7c15u64; // fixed seed, xorshift
        for _ in 0..10_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let (x, y, z) = (
                s as u32 & 0xf_ffff,
                (s >> 20) as u32 & 0xf_ffff,
                (s >> 40) as u32 & 0xf_ffff,
            );
            assert_eq!(encode(x, y, z), slow(x, y, z), "seed-state {s:#x}");
        }
    }
}
