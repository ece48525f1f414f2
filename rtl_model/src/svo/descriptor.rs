//! The 32-bit child descriptor: one word per internal node, the unit of a node fetch.
//!
//! ```text
//!  31            17  16  15        8  7         0
//! +----------------+----+------------+-----------+
//! | child_ptr (15) |far | valid (8)  | leaf (8)  |
//! +----------------+----+------------+-----------+
//! ```
//! `valid` bit i: child i exists. `leaf` bit i: child i is a solid leaf voxel (only meaningful
//! where `valid` is set). Child labels are x = 4, y = 2, z = 1 (Revelles et al. 2000).
//! `child_ptr` is the distance in words from this descriptor to its children's group; with
//! `far` set it is instead the distance to a far word holding that 32-bit distance.

/// Largest `child_ptr` value that fits without the far escape.
pub const NEAR_PTR_MAX: u32 = (1 << 15) - 1;

/// A decoded child descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChildDescriptor {
    /// Bit i set: child i exists.
    pub valid: u8,
    /// Bit i set: child i is a leaf voxel.
    pub leaf: u8,
    /// `child_ptr` field: the children's distance, or with `far` the far word's distance.
    pub ptr: u16,
    /// The far-pointer escape.
    pub far: bool,
}

impl ChildDescriptor {
    /// Unpacks a descriptor word.
    #[inline]
    pub fn unpack(word: u32) -> Self {
        Self {
            valid: (word >> 8) as u8,
            leaf: word as u8,
            ptr: (word >> 17) as u16,
            far: (word >> 16) & 1 == 1,
        }
    }

    /// Packs to a descriptor word. `ptr` must fit 15 bits (checked in debug builds; the
    /// builder never produces a larger one).
    #[inline]
    pub fn pack(self) -> u32 {
        debug_assert!(u32::from(self.ptr) <= NEAR_PTR_MAX);
        (u32::from(self.ptr) << 17)
            | (u32::from(self.far) << 16)
            | (u32::from(self.valid) << 8)
            | u32::from(self.leaf)
    }

    /// Slot of child `label` within the children's group: the number of valid children with
    /// a lower label (the popcount of the lower mask bits).
    #[inline]
    pub fn slot(self, label: u8) -> u32 {
        (u32::from(self.valid) & ((1u32 << label) - 1)).count_ones()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_unpack_round_trip_exhaustive_masks() {
        for valid in 0..=255u8 {
            for &leaf in &[0u8, valid, valid & 0x55] {
                for &(ptr, far) in &[(0u16, false), (1, true), (32767, false), (12345, true)] {
                    let d = ChildDescriptor {
                        valid,
                        leaf,
                        ptr,
                        far,
                    };
                    assert_eq!(ChildDescriptor::unpack(d.pack()), d);
                }
            }
        }
    }

    #[test]
    fn bit_positions_are_as_documented() {
        let d = ChildDescriptor {
            valid: 0b1000_0001,
            leaf: 0b0000_0001,
            ptr: 3,
            far: true,
        };
        assert_eq!(d.pack(), (3 << 17) | (1 << 16) | (0x81 << 8) | 0x01);
    }

    #[test]
    fn slot_is_popcount_of_lower_valid_bits() {
        let d = ChildDescriptor {
            valid: 0b1010_0110,
            leaf: 0,
            ptr: 0,
            far: false,
        };
        assert_eq!(d.slot(1), 0);
        assert_eq!(d.slot(2), 1);
        assert_eq!(d.slot(5), 2);
        assert_eq!(d.slot(7), 3);
    }
}
