//! Ray generation: the per-pixel direction table.
//!
//! Pipeline position: the first stage; one entry per pixel feeds the sphere tests and the
//! transform. Design choice (docs/number-formats.md §3.1): the host computes each pixel's unit
//! direction in f64 (the exact camera formula of `docs/reference.md` §2) and writes it into a
//! table in `raygen.dir`, rewriting it only when the camera changes. The hardware then needs
//! no reciprocal square root; a moving camera costs one table write per frame. The camera
//! position is one `raygen.pos` value per frame.

use crate::fixed::{from_f64, Format, Overflows, Quant, SignalId};
use serde::{Deserialize, Serialize};

/// Ray generation: a per-pixel direction table (the host writes it while the camera is
/// still, and again after each camera move) and the camera position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RaygenConfig {
    /// Direction table entries (unit-vector components) with a sign bit each.
    pub dir: Format,
    /// Camera position and instance centres in world space.
    pub pos: Format,
    /// Rotation matrix entries the host writes per instance.
    pub mat: Format,
}

impl Default for RaygenConfig {
    fn default() -> Self {
        Self {
            dir: Format::sq(2, 30).with_quant(Quant::RndConv),
            pos: Format::sq(8, 32).with_quant(Quant::RndConv),
            mat: Format::sq(2, 30).with_quant(Quant::RndConv),
        }
    }
}

/// The table entry of one unit direction (each component converted by `cfg.dir`'s mode).
#[inline]
pub fn direction_entry(
    dir: [f64; 3],
    cfg: &RaygenConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> [i64; 3] {
    dir.map(|x| from_f64(x, cfg.dir, ov, sig))
}

/// Bound on each component's error: one LSB of `dir` when truncating, half when rounding.
/// The entry's length then differs from 1 by at most √3 times this (plus its square).
pub fn error_bound(cfg: &RaygenConfig) -> f64 {
    match cfg.dir.quant {
        Quant::Trn | Quant::TrnZero => cfg.dir.lsb(),
        _ => 0.5 * cfg.dir.lsb(),
    }
}

/// Bits of one direction-table entry: three components of `dir`.
pub fn entry_bits(cfg: &RaygenConfig) -> u32 {
    3 * u32::from(cfg.dir.width)
}

/// Bits of the direction table for a `width`×`height` image (three components per pixel).
pub fn table_bits(cfg: &RaygenConfig, width: u32, height: u32) -> u64 {
    u64::from(entry_bits(cfg)) * u64::from(width) * u64::from(height)
}

/// Latency of ray generation in cycles: one direction-table entry and the camera position per
/// ray. 4: the table's URAM read, as the hit buffer's (`HitBuffer::read_latency_cycles`).
pub const LATENCY_CYCLES: u32 = 4;
