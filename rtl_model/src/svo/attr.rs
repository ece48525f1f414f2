//! Leaf attributes: colour and normal of one solid voxel, two 32-bit words.
//!
//! Word 0: colour as R, G, B, A bytes, R in bits 7..0 (little-endian RGBA8).
//! Word 1: unit normal in octahedral encoding, two signed 16-bit components
//! (u in bits 15..0, v in bits 31..16, value = raw / 32767). Octahedral encoding keeps the
//! normal's error below 1e-4 rad-ish at 16 bits per component and decodes with adds only.

/// Colour and normal of one leaf voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct LeafAttr {
    /// RGBA8, R in the low byte.
    pub colour_rgba8: u32,
    /// Octahedral normal, u in the low half, v in the high half, both snorm16.
    pub normal_oct16: u32,
}

impl LeafAttr {
    /// Builds attributes from an sRGB colour and a (not necessarily unit) normal.
    /// A zero or non-finite normal is stored as +z.
    pub fn new(rgba: [u8; 4], normal: [f64; 3]) -> Self {
        Self {
            colour_rgba8: u32::from_le_bytes(rgba),
            normal_oct16: encode_octahedral(normal),
        }
    }

    /// Colour bytes R, G, B, A.
    pub fn rgba(self) -> [u8; 4] {
        self.colour_rgba8.to_le_bytes()
    }

    /// Unit normal decoded from the octahedral encoding.
    pub fn normal(self) -> [f64; 3] {
        decode_octahedral(self.normal_oct16)
    }

    /// The two memory words.
    pub fn words(self) -> [u32; 2] {
        [self.colour_rgba8, self.normal_oct16]
    }
}

fn snorm16(x: f64) -> u16 {
    ((x.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16
}

fn encode_octahedral(n: [f64; 3]) -> u32 {
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    let (mut u, mut v, z) = if l1 > 0.0 && l1.is_finite() {
        (n[0] / l1, n[1] / l1, n[2] / l1)
    } else {
        (0.0, 0.0, 1.0)
    };
    if z < 0.0 {
        let (pu, pv) = (u, v);
        u = (1.0 - pv.abs()) * if pu >= 0.0 { 1.0 } else { -1.0 };
        v = (1.0 - pu.abs()) * if pv >= 0.0 { 1.0 } else { -1.0 };
    }
    u32::from(snorm16(u)) | (u32::from(snorm16(v)) << 16)
}

fn decode_octahedral(w: u32) -> [f64; 3] {
    let u = f64::from(w as u16 as i16) / 32767.0;
    let v = f64::from((w >> 16) as u16 as i16) / 32767.0;
    octahedral_unfold(u, v)
}

/// The unit vector of octahedral coordinates (u, v) in [−1, 1]²: the upper half directly,
/// the lower half folded back over the diagonals, then normalised. Shared by the leaf
/// attribute's 16-bit code and the hit record's narrower one.
pub fn octahedral_unfold(u: f64, v: f64) -> [f64; 3] {
    let z = 1.0 - u.abs() - v.abs();
    let (x, y) = if z < 0.0 {
        (
            (1.0 - v.abs()) * if u >= 0.0 { 1.0 } else { -1.0 },
            (1.0 - u.abs()) * if v >= 0.0 { 1.0 } else { -1.0 },
        )
    } else {
        (u, v)
    };
    let len = (x * x + y * y + z * z).sqrt();
    [x / len, y / len, z / len]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_round_trip_within_tolerance() {
        let mut s = 0x2545_f491_4f6c_dd1du64; // fixed seed
        for _ in 0..20_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let a = (s & 0xffff) as f64 / 65535.0 * 2.0 - 1.0;
            let b = ((s >> 16) & 0xffff) as f64 / 65535.0 * 2.0 - 1.0;
            let c = ((s >> 32) & 0xffff) as f64 / 65535.0 * 2.0 - 1.0;
            let len = (a * a + b * b + c * c).sqrt();
            if len < 1e-3 {
                continue;
            }
            let n = [a / len, b / len, c / len];
            let m = LeafAttr::new([0, 0, 0, 255], n).normal();
            let dot = n[0] * m[0] + n[1] * m[1] + n[2] * m[2];
            assert!(
                dot > 1.0 - 1e-8,
                "normal {n:?} decoded as {m:?} (state {s:#x})"
            );
        }
        for n in [
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, -1.0],
            [0.0, 0.0, 1.0],
        ] {
            let m = LeafAttr::new([0; 4], n).normal();
            for k in 0..3 {
                assert!((m[k] - n[k]).abs() < 1e-9, "{n:?} -> {m:?}");
            }
        }
    }

    #[test]
    fn colour_bytes_round_trip() {
        let a = LeafAttr::new([1, 2, 3, 4], [0.0, 1.0, 0.0]);
        assert_eq!(a.rgba(), [1, 2, 3, 4]);
        assert_eq!(a.colour_rgba8 & 0xff, 1);
    }
}
