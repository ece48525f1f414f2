//! A packed transaction word of any width: little-endian 64-bit limbs, bit 0 = bit 0 of the
//! first field. What one line of a `$readmemh` file holds.
//!
//! Pipeline position: the encoding layer under every stage's vectors; nothing here knows a
//! unit. Field values enter as `u128` two's-complement bit patterns and are masked to the
//! field's width, so a negative code of a 40-bit field is stored as its low 40 bits.

/// A word of `bits` bits.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Word {
    bits: u32,
    limbs: Vec<u64>,
}

/// The low `w` bits of `v` (w ≤ 128).
fn low_bits(v: u128, w: u32) -> u128 {
    if w >= 128 {
        v
    } else {
        v & ((1u128 << w) - 1)
    }
}

impl Word {
    /// An all-zero word of `bits` bits.
    pub fn zero(bits: u32) -> Self {
        Self {
            bits,
            limbs: vec![0; bits.div_ceil(64) as usize],
        }
    }

    /// Width in bits.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// Writes the low `width` bits of `v` at bit `offset` (bits outside the word are dropped;
    /// the layout never places a field there).
    pub fn put(&mut self, offset: u32, width: u32, v: u128) {
        let v = low_bits(v, width);
        for i in 0..width.min(128) {
            if (v >> i) & 1 == 1 {
                self.set_bit(offset + i);
            }
        }
    }

    fn set_bit(&mut self, bit: u32) {
        if bit < self.bits {
            self.limbs[(bit / 64) as usize] |= 1u64 << (bit % 64);
        }
    }

    /// Bit `bit` (false outside the word).
    pub fn bit(&self, bit: u32) -> bool {
        bit < self.bits && (self.limbs[(bit / 64) as usize] >> (bit % 64)) & 1 == 1
    }

    /// The `width` bits at `offset` (width ≤ 128), unsigned.
    pub fn get(&self, offset: u32, width: u32) -> u128 {
        (0..width.min(128)).fold(0u128, |acc, i| {
            acc | (u128::from(self.bit(offset + i)) << i)
        })
    }

    /// The `width` bits at `offset` sign-extended (1 ≤ width ≤ 128).
    pub fn get_signed(&self, offset: u32, width: u32) -> i128 {
        let raw = self.get(offset, width);
        let s = 128 - width.clamp(1, 128);
        ((raw << s) as i128) >> s
    }

    /// Flips one bit (tests corrupt an expected value with it).
    pub fn flip(&mut self, bit: u32) {
        if bit < self.bits {
            self.limbs[(bit / 64) as usize] ^= 1u64 << (bit % 64);
        }
    }

    /// The word as ⌈bits/4⌉ lower-case hex digits, most significant first: one `$readmemh`
    /// line.
    pub fn to_hex(&self) -> String {
        let digits = self.bits.div_ceil(4).max(1);
        let mut s = String::with_capacity(digits as usize);
        for d in (0..digits).rev() {
            let nibble = self.get(4 * d, 4) as u32;
            s.push(char::from_digit(nibble, 16).unwrap_or('0'));
        }
        s
    }

    /// Parses a hex line of this width (the inverse of [`Word::to_hex`]); `None` if a digit is
    /// not hex or a bit beyond the width is set.
    pub fn from_hex(text: &str, bits: u32) -> Option<Self> {
        let mut w = Self::zero(bits);
        for (i, c) in text.trim().chars().rev().enumerate() {
            let nibble = u128::from(c.to_digit(16)?);
            let off = 4 * i as u32;
            if off >= bits {
                if nibble != 0 {
                    return None;
                }
                continue;
            }
            if off + 4 > bits && nibble >> (bits - off) != 0 {
                return None;
            }
            w.put(off, 4, nibble);
        }
        Some(w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_round_trip_across_limbs() {
        let mut w = Word::zero(130);
        w.put(60, 40, (-5i128) as u128);
        w.put(100, 30, 0x2abc_def1);
        assert_eq!(w.get_signed(60, 40), -5);
        assert_eq!(w.get(100, 30), 0x2abc_def1);
        assert_eq!(w.get(0, 60), 0);
        let hex = w.to_hex();
        assert_eq!(hex.len(), 33);
        assert_eq!(Word::from_hex(&hex, 130), Some(w.clone()));
        assert_eq!(Word::from_hex("g", 8), None);
        assert_eq!(
            Word::from_hex("1ff", 8),
            None,
            "bit 8 is outside an 8-bit word"
        );
    }

    #[test]
    fn hex_is_msb_first_and_padded() {
        let mut w = Word::zero(9);
        w.put(0, 9, 0x1a5);
        assert_eq!(w.to_hex(), "1a5");
        w.flip(8);
        assert_eq!(w.to_hex(), "0a5");
    }
}
