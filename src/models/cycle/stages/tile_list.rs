//! The tile-list reader's timing (two-level instance scheme, docs/instances.md §6): how many
//! cycles each ray occupies the sphere lanes — one list word of `sphere_units` ids per cycle,
//! ⌈list length / lanes⌉ and at least one — and the reader's latency in front of them
//! (`rtl_model::units::tile_list::LATENCY_CYCLES`: the offset-table and list-word reads).
//!
//! Pipeline position: inside the sphere stage (`sphere.rs`), which takes a [`TilePasses`]
//! when the frame's plan carries tile lists; without them the stage keeps its flat
//! ⌈instances / lanes⌉ passes. Which instances are tested comes from the functional model's
//! trace as before; this part only times the lanes.

use crate::models::fixed::plan::FramePlan;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::units::tile_list::{passes, LATENCY_CYCLES};

/// Per-tile lane passes of a frame.
#[derive(Clone, Debug)]
pub struct TilePasses {
    tile: u32,
    width: u32,
    tiles_x: u32,
    passes: Vec<u64>,
    /// Cycles the reader adds before the lanes.
    pub latency: u64,
}

impl TilePasses {
    /// The passes of `plan`'s tile lists on `hw`'s lanes, or `None` without lists.
    pub fn of(plan: &FramePlan<'_>, hw: &HwConfig) -> Option<Self> {
        let l = plan.lists.as_ref()?;
        let lanes = hw.sphere_units.max(1);
        Some(Self {
            tile: l.tile.max(1),
            width: l.width.max(1),
            tiles_x: l.tiles_x,
            passes: (0..l.tiles())
                .map(|t| u64::from(passes(l.len_of_tile(t), lanes)))
                .collect(),
            latency: u64::from(LATENCY_CYCLES),
        })
    }

    /// Lane passes of the ray of pixel `p` (raster order).
    #[inline]
    pub fn passes(&self, p: u32) -> u64 {
        let (i, j) = (p % self.width, p / self.width);
        let t = ((j / self.tile) * self.tiles_x + i / self.tile) as usize;
        self.passes.get(t).copied().unwrap_or(1)
    }
}
