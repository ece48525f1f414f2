//! The order in which ray generation visits the pixels of a frame: scanline, square tiles, or
//! Morton (Z) order. The order changes only timing — which rays are in flight together and
//! so which node reads the walkers share in the cache, the on-chip banks' combining and the
//! MSHRs — never an image or a hit record: every pixel is traced once, its record written at
//! its own address.
//!
//! Pipeline position: part of the hardware configuration (`HwConfig::ray_order`); the ray
//! generation stage's pixel counter walks [`RayOrder::sequence`] instead of counting pixels.
//! In hardware the order is the counter's address logic: a tile order is two nested x/y
//! counters, Morton order a bit interleave of one counter (frames that are not a power of two
//! skip the codes outside the frame; the table here lists the pixels in the same order).

use serde::{Deserialize, Serialize};

/// Largest tile side accepted (the largest frame side the configuration accepts).
pub const MAX_TILE: u32 = 16384;

/// The pixel order of ray generation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum RayOrder {
    /// Row by row, left to right: the order before issue 28.
    #[default]
    Scanline,
    /// Square tiles of this side (pixels), tiles row by row, pixels within a tile row by row;
    /// the tiles at the right and bottom edges are clipped to the frame. `Tiles(1)` is the
    /// scanline order.
    Tiles(u32),
    /// Morton (Z) order of (x, y): each 2×2 block, then each 4×4 block of those, and so on.
    Morton,
}

impl RayOrder {
    /// Checks the tile side; the message names the field.
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            RayOrder::Tiles(n) if !(1..=MAX_TILE).contains(&n) => Err(format!(
                "ray_order = Tiles({n}): the tile side must be 1 to {MAX_TILE} pixels"
            )),
            _ => Ok(()),
        }
    }

    /// Whether every pixel is visited in raster order (no table needed).
    pub fn is_scanline(&self) -> bool {
        matches!(*self, RayOrder::Scanline | RayOrder::Tiles(1))
    }

    /// The raster index of the pixel visited `s`-th, for every `s` of a `width` × `height`
    /// frame: a permutation of `0 .. width·height`.
    pub fn sequence(&self, width: u32, height: u32) -> Vec<u32> {
        let (w, h) = (width, height);
        match *self {
            RayOrder::Scanline => (0..w * h).collect(),
            RayOrder::Tiles(n) => {
                let n = n.max(1);
                let mut out = Vec::with_capacity((w * h) as usize);
                for ty in (0..h).step_by(n as usize) {
                    for tx in (0..w).step_by(n as usize) {
                        for y in ty..(ty + n).min(h) {
                            for x in tx..(tx + n).min(w) {
                                out.push(y * w + x);
                            }
                        }
                    }
                }
                out
            }
            RayOrder::Morton => {
                let mut keyed: Vec<(u32, u32)> = (0..h)
                    .flat_map(|y| (0..w).map(move |x| (morton(x, y), y * w + x)))
                    .collect();
                keyed.sort_unstable();
                keyed.into_iter().map(|(_, p)| p).collect()
            }
        }
    }
}

/// The Morton code of (x, y), x in the even bits: coordinates below 2^16.
fn morton(x: u32, y: u32) -> u32 {
    fn spread(v: u32) -> u32 {
        let mut v = v & 0xffff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    }
    spread(x) | (spread(y) << 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_order_visits_every_pixel_once() {
        for order in [
            RayOrder::Scanline,
            RayOrder::Tiles(1),
            RayOrder::Tiles(3),
            RayOrder::Tiles(8),
            RayOrder::Tiles(100),
            RayOrder::Morton,
        ] {
            for (w, h) in [(1, 1), (7, 5), (16, 16), (20, 12)] {
                let mut s = order.sequence(w, h);
                s.sort_unstable();
                assert_eq!(s, (0..w * h).collect::<Vec<_>>(), "{order:?} {w}×{h}");
            }
        }
    }

    #[test]
    fn tiles_and_morton_by_hand() {
        // 4×3 in 2×2 tiles: tile (0,0) = 0 1 4 5, tile (1,0) = 2 3 6 7, then the clipped
        // bottom row of tiles 8 9, 10 11.
        assert_eq!(
            RayOrder::Tiles(2).sequence(4, 3),
            vec![0, 1, 4, 5, 2, 3, 6, 7, 8, 9, 10, 11]
        );
        // 4×4 Morton: the four 2×2 blocks in Z order, each in Z order.
        assert_eq!(
            RayOrder::Morton.sequence(4, 4),
            vec![0, 1, 4, 5, 2, 3, 6, 7, 8, 9, 12, 13, 10, 11, 14, 15]
        );
        assert_eq!(
            RayOrder::Tiles(1).sequence(3, 2),
            RayOrder::Scanline.sequence(3, 2)
        );
    }

    #[test]
    fn a_tile_of_side_zero_is_refused_with_the_field() {
        let e = RayOrder::Tiles(0).validate().unwrap_err();
        assert!(e.starts_with("ray_order = Tiles(0)"), "{e}");
        assert!(RayOrder::Tiles(MAX_TILE + 1).validate().is_err());
        assert!(RayOrder::Tiles(8).validate().is_ok() && RayOrder::Morton.validate().is_ok());
    }
}
