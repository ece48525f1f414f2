//! Tile-list reader vectors (the two-level instance scheme, `units::tile_list`): per row a
//! pixel and its tile's offset-table entry in, the tile index, first word, lane cycles and the
//! last word's lane mask out (`units::tile_list::read_plan`), for 16-pixel tiles on a
//! 1280-pixel-wide frame (80 tiles a row) and 8 lanes.
//!
//! Adversarial cases: the frame's corners and tile edges, empty lists, lists of exactly one,
//! seven, eight and nine ids, the longest list (65,535) and the last word of the memory.

use super::{dedup, Stage};
use crate::units::tile_list::{read_plan, TileListConfig, LATENCY_CYCLES};
use crate::vectors::layout::{u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// Frame width the vectors assume (the hardware frame).
const WIDTH: u32 = 1280;
/// Frame height.
const HEIGHT: u32 = 768;
/// Lanes (the default `sphere_units`).
const LANES: u32 = 8;

/// One reader transaction: pixel and offset-table entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileListTxn {
    /// Column.
    pub i: u32,
    /// Row.
    pub j: u32,
    /// Start word of the tile's list.
    pub start: u32,
    /// Ids in the list.
    pub len: u32,
}

/// The stage (default list memory).
pub struct TileListStage {
    cfg: TileListConfig,
}

impl TileListStage {
    /// The default list memory.
    pub fn new() -> Self {
        Self {
            cfg: TileListConfig::default(),
        }
    }

    fn tiles_x(&self) -> u32 {
        WIDTH.div_ceil(self.cfg.tile)
    }

    fn start_bits(&self) -> u32 {
        self.cfg.offset_word_bits() - 16
    }
}

impl Default for TileListStage {
    fn default() -> Self {
        Self::new()
    }
}

impl Stage for TileListStage {
    type Txn = TileListTxn;

    fn name(&self) -> &'static str {
        "tile_list"
    }

    fn description(&self) -> &'static str {
        "one ray per row: pixel and its tile's offset-table entry in; tile, first word, lane cycles and last-word lane mask out"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.uint("i", Input, 11, "pixel column");
        l.uint("j", Input, 10, "pixel row");
        l.uint(
            "start",
            Input,
            self.start_bits(),
            "first list word of the tile",
        );
        l.uint("len", Input, 16, "ids in the tile's list");
        l.uint(
            "tile",
            Output,
            12,
            "tile index, raster order (80 tiles a row)",
        );
        l.uint("first_word", Output, self.start_bits(), "first word read");
        l.uint(
            "cycles",
            Output,
            14,
            "cycles on the lanes: max(1, ceil(len / 8))",
        );
        l.uint("last_mask", Output, LANES, "valid lanes of the last word");
        l
    }

    fn adversarial(&self) -> Vec<TileListTxn> {
        let last = self.cfg.capacity_words - 1;
        let mut v = Vec::new();
        for (i, j) in [
            (0, 0),
            (WIDTH - 1, 0),
            (0, HEIGHT - 1),
            (WIDTH - 1, HEIGHT - 1),
            (15, 15),
            (16, 16),
            (17, 31),
            (1279, 32),
        ] {
            for len in [0, 1, 7, 8, 9, 15, 16, 17, 65_535] {
                v.push(TileListTxn {
                    i,
                    j,
                    start: 0,
                    len,
                });
                v.push(TileListTxn {
                    i,
                    j,
                    start: last,
                    len,
                });
            }
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> TileListTxn {
        TileListTxn {
            i: rng.below(u64::from(WIDTH)) as u32,
            j: rng.below(u64::from(HEIGHT)) as u32,
            start: rng.below(u64::from(self.cfg.capacity_words)) as u32,
            len: match rng.below(4) {
                0 => rng.below(9) as u32,
                1 => rng.below(65) as u32,
                _ => rng.bits_up_to(16) as u32,
            },
        }
    }

    fn encode(&self, t: &TileListTxn) -> Vec<u128> {
        let r = read_plan(t.i, t.j, (t.start, t.len), self.tiles_x(), LANES, &self.cfg);
        [
            t.i,
            t.j,
            t.start,
            t.len,
            r.tile,
            r.first_word,
            r.cycles,
            r.last_mask,
        ]
        .map(|x| u(u64::from(x)))
        .to_vec()
    }

    fn timing(&self) -> Option<Timing> {
        Some(Timing {
            latency_cycles: LATENCY_CYCLES,
            ii: 1,
        })
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", self.cfg);
        t.param("lanes", LANES);
        t.param("tiles_x", self.tiles_x());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An independent oracle: the tile by division, the cycles by counting words.
    #[test]
    fn rows_match_a_counting_oracle() {
        let st = TileListStage::new();
        let mut rng = Rng::for_stage(7, "tile_list test");
        let mut txns = st.adversarial();
        txns.extend((0..2000).map(|_| st.random(&mut rng)));
        for t in txns {
            let v = st.encode(&t);
            let tile = (t.j / 16) * 80 + t.i / 16;
            let mut words = 0u32;
            let mut left = t.len;
            let mut mask = 0u32;
            while left > 0 {
                let k = left.min(8);
                mask = (1 << k) - 1;
                left -= k;
                words += 1;
            }
            assert_eq!(v[4], u128::from(tile), "{t:?}");
            assert_eq!(v[5], u128::from(t.start), "{t:?}");
            assert_eq!(v[6], u128::from(words.max(1)), "{t:?}");
            assert_eq!(v[7], u128::from(mask), "{t:?}");
        }
    }
}
