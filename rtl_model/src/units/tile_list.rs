//! The tile-list reader of the two-level instance scheme (docs/instances.md): per screen tile,
//! the list of instances whose bounding sphere can meet a ray of that tile, written by the host
//! once per frame; the reader hands a ray's sphere lanes the ids of its tile's list, `lanes`
//! ids per cycle, instead of every instance.
//!
//! Pipeline position: between ray generation and the sphere lanes. It computes nothing on
//! the ray: what it decides is *which* instances are tested, so the images cannot change as
//! long as every list is conservative (the host's binning, `svo_sim::models::reference::cull`).
//!
//! Memory format (declared here, priced by `resources`):
//! - list words of `lanes × id_bits` bits, each tile's list padded to whole words so one word
//!   feeds the lanes in one cycle; `capacity_words` words per copy, two copies (the host
//!   writes the next frame's lists while this frame reads the other);
//! - an offset table of one `offset_bits + len_bits` word per tile (start word and length).
//!
//! Overflow: when the frame's padded lists exceed `capacity_words`, the tiles that no longer fit
//! (in raster order) are marked *flat*: the reader then counts 0 … n−1 itself and the tile's
//! rays test every instance, as without the scheme. Never lossy; counted per frame
//! ([`ListBudget::flat_tiles`]) and reported.

use crate::resources::{ResourceItem, Resources};
use serde::{Deserialize, Serialize};

/// Configuration of the tile lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TileListConfig {
    /// Tile side in pixels (a power of two: the tile index is the pixel coordinates' top bits).
    pub tile: u32,
    /// Bits of an instance id in a list (14 hold 10,000 instances and more).
    pub id_bits: u8,
    /// List words per copy (each `lanes × id_bits` bits).
    pub capacity_words: u32,
}

impl Default for TileListConfig {
    /// 16-pixel tiles, 16-bit ids, 32,768 words per copy (docs/instances.md §4: a 10,000-
    /// instance crowd at 1280×768 needs about 21,000 words of 8 ids).
    fn default() -> Self {
        Self {
            tile: 16,
            id_bits: 16,
            capacity_words: 32_768,
        }
    }
}

impl TileListConfig {
    /// Checks the fields.
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=256).contains(&self.tile) || !self.tile.is_power_of_two() {
            return Err(format!(
                "tile_list.tile {} must be a power of two from 1 to 256",
                self.tile
            ));
        }
        if !(1..=16).contains(&self.id_bits) {
            return Err(format!(
                "tile_list.id_bits {} is outside 1..=16",
                self.id_bits
            ));
        }
        if !(1..=1 << 24).contains(&self.capacity_words) {
            return Err(format!(
                "tile_list.capacity_words {} is outside 1..=16777216",
                self.capacity_words
            ));
        }
        Ok(())
    }

    /// Tiles of a `w`×`h` frame.
    pub fn tiles(&self, w: u32, h: u32) -> u64 {
        u64::from(w.div_ceil(self.tile)) * u64::from(h.div_ceil(self.tile))
    }

    /// Bits of one offset-table word: start word (⌈log₂ capacity⌉) and length in ids (16).
    pub fn offset_word_bits(&self) -> u32 {
        (32 - (self.capacity_words.max(2) - 1).leading_zeros()) + 16
    }
}

/// Cycles a ray occupies `lanes` sphere lanes for a list of `len` instances: one word per
/// cycle, and at least one cycle (a ray with an empty list still passes through the lanes).
///
/// ```
/// use rtl_model::units::tile_list::passes;
/// assert_eq!(passes(0, 8), 1);
/// assert_eq!(passes(8, 8), 1);
/// assert_eq!(passes(9, 8), 2);
/// assert_eq!(passes(1000, 8), 125);
/// ```
pub fn passes(len: u32, lanes: u32) -> u32 {
    len.div_ceil(lanes.max(1)).max(1)
}

/// Latency the reader adds in front of the sphere lanes: the offset-table read (address and
/// output registers, 2) and the list-word read (2).
pub const LATENCY_CYCLES: u32 = 4;

/// What the reader does for one ray: which tile, which words, how many, and which lanes of
/// the last word hold ids (bit k set: lane k valid).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadPlan {
    /// Tile index (raster order).
    pub tile: u32,
    /// First list word.
    pub first_word: u32,
    /// Cycles the ray occupies the lanes ([`passes`]).
    pub cycles: u32,
    /// Valid lanes of the last word (all ones for a full word, 0 for an empty list).
    pub last_mask: u32,
}

/// The reader's transaction: pixel (`i`, `j`) of a frame `tiles_x` tiles wide, whose tile's
/// offset-table entry is (`start`, `len`), on `lanes` lanes with `cfg.tile`-pixel tiles.
///
/// ```
/// use rtl_model::units::tile_list::{read_plan, TileListConfig};
/// let cfg = TileListConfig::default();
/// let r = read_plan(35, 17, (100, 11), 80, 8, &cfg);
/// assert_eq!((r.tile, r.first_word, r.cycles, r.last_mask), (82, 100, 2, 0b111));
/// ```
pub fn read_plan(
    i: u32,
    j: u32,
    (start, len): (u32, u32),
    tiles_x: u32,
    lanes: u32,
    cfg: &TileListConfig,
) -> ReadPlan {
    let shift = cfg.tile.max(1).trailing_zeros();
    let lanes = lanes.clamp(1, 32);
    let rem = len % lanes;
    let full = if lanes == 32 {
        u32::MAX
    } else {
        (1u32 << lanes) - 1
    };
    ReadPlan {
        tile: (j >> shift) * tiles_x + (i >> shift),
        first_word: start,
        cycles: passes(len, lanes),
        last_mask: match (len, rem) {
            (0, _) => 0,
            (_, 0) => full,
            (_, r) => (1u32 << r) - 1,
        },
    }
}

/// How a frame's lists fit the memory.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ListBudget {
    /// Words each tile takes (0 for a flat tile).
    pub words: Vec<u32>,
    /// Whether each tile is flat (did not fit: its rays test every instance).
    pub flat: Vec<bool>,
    /// Flat tiles (the overflow count).
    pub flat_tiles: u32,
    /// Words used.
    pub used_words: u64,
}

/// Places the lists of lengths `lens` (tiles in raster order) into `cfg`'s capacity with
/// `lanes` ids per word: each list padded to whole words; a tile that no longer fits is flat.
pub fn budget(lens: &[u32], lanes: u32, cfg: &TileListConfig) -> ListBudget {
    let mut b = ListBudget {
        words: Vec::with_capacity(lens.len()),
        flat: Vec::with_capacity(lens.len()),
        ..ListBudget::default()
    };
    for &len in lens {
        let w = len.div_ceil(lanes.max(1));
        if b.used_words + u64::from(w) > u64::from(cfg.capacity_words) {
            b.words.push(0);
            b.flat.push(true);
            b.flat_tiles += 1;
        } else {
            b.used_words += u64::from(w);
            b.words.push(w);
            b.flat.push(false);
        }
    }
    b
}

/// BRAM36 of the unit for a `w`×`h` frame and `lanes` lanes: two copies of the list words and
/// of the offset table (`crate::units::hit_record::bram36_count` of each).
pub fn bram36_count(cfg: &TileListConfig, lanes: u32, w: u32, h: u32) -> u64 {
    let word_bits = lanes.max(1) * u32::from(cfg.id_bits);
    let lists = crate::units::hit_record::bram36_count(word_bits, u64::from(cfg.capacity_words));
    let offsets = crate::units::hit_record::bram36_count(cfg.offset_word_bits(), cfg.tiles(w, h));
    2 * (lists + offsets)
}

/// The unit's line of the resource estimate (`resources::ResourceReport::push`): its
/// [`bram36_count`] for a `w`×`h` frame on `lanes` sphere lanes.
pub fn resource_item(cfg: &TileListConfig, lanes: u32, w: u32, h: u32) -> ResourceItem {
    ResourceItem::new(
        "instance_lists",
        1,
        Resources::bram36(bram36_count(cfg, lanes, w, h)),
        format!(
            "per-tile instance lists, {} tiles of {} px, {} list words of {} ids, double-buffered",
            cfg.tiles(w, h),
            cfg.tile,
            cfg.capacity_words,
            lanes.max(1)
        ),
    )
}

/// Bytes the host writes per frame: the used list words and the offset table.
pub fn host_bytes(cfg: &TileListConfig, lanes: u32, used_words: u64, w: u32, h: u32) -> u64 {
    let word_bits = u64::from(lanes.max(1) * u32::from(cfg.id_bits));
    (used_words * word_bits).div_ceil(8)
        + (cfg.tiles(w, h) * u64::from(cfg.offset_word_bits())).div_ceil(8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budget_pads_and_overflows_in_raster_order() {
        let cfg = TileListConfig {
            capacity_words: 4,
            ..TileListConfig::default()
        };
        let b = budget(&[3, 9, 0, 8, 1], 8, &cfg);
        assert_eq!(b.words, vec![1, 2, 0, 1, 0]);
        assert_eq!(b.flat, vec![false, false, false, false, true]);
        assert_eq!((b.flat_tiles, b.used_words), (1, 4));
    }

    #[test]
    fn default_memory_is_small() {
        let cfg = TileListConfig::default();
        // 32,768 × 128-bit words = 4 Mib per copy: 2 × (116 + offsets).
        let n = bram36_count(&cfg, 8, 1280, 768);
        assert!(n > 200 && n < 260, "{n}");
        assert!(cfg.validate().is_ok());
        assert!(TileListConfig { tile: 12, ..cfg }.validate().is_err());
    }
}
