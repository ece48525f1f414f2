//! Sampled timing's warming (docs/cycle-model.md §3.5): how far the detailed warming around a
//! timed band reaches ([`Warming`], sized in rays that walk), and the functional warming of
//! the pixels between timed segments ([`warm_gap`]).
//!
//! Pipeline position: inside `model::CycleModel::run_frame`, between the sampled segments that
//! `pipeline::Pipeline` runs cycle by cycle.

use super::super::error::CycleError;
use super::super::machine::Machine;
use super::super::stages::{internal, FrameCounts, FrameInputs};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::svo::FetchKind;

/// The cap of the detailed warming, in multiples of its minimum rows.
pub const WARM_CAP_FACTOR: u32 = 8;

/// How far the detailed warming around a timed band reaches ([`SampleConfig::warming_for`](super::SampleConfig::warming_for)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Warming {
    /// Rows at least.
    pub min_rows: u32,
    /// Rays that walk it must hold (unless `max_rows` is reached first).
    pub walking: u64,
    /// Rows at most.
    pub max_rows: u32,
}

/// Every ray the pipeline can hold at once: its FIFOs, the walkers' ray slots and the unit
/// pipes' latencies (one ray per cycle in each).
pub fn pipeline_capacity(hw: &HwConfig) -> u64 {
    let f = &hw.fifos;
    let fifos = [
        f.raygen_to_sphere,
        f.sphere_to_sorter,
        f.sorter_to_check,
        f.check_to_transform,
        f.transform_to_reciprocal,
        f.reciprocal_to_root,
        f.root_to_dispatch,
        f.walker_to_record,
        f.record_to_write,
    ]
    .iter()
    .map(|&d| u64::from(d))
    .sum::<u64>();
    let slots = u64::from(hw.walker_pool.walkers * hw.walker_pool.contexts_per_walker);
    let u = &hw.units;
    let pipes = [
        u.raygen.latency_cycles,
        u.sphere.latency_cycles + u.sqrt.latency_cycles,
        u.sorter.latency_cycles,
        hw.hit_buffer_read_cycles() + u.hit_unpack.latency_cycles,
    ]
    .iter()
    .map(|&l| u64::from(l))
    .sum::<u64>();
    fifos + slots + pipes
}

/// Pixels of a row of the functional model's trace that walk (not reused from the hit
/// buffer, at least one candidate): what the walkers' queue holds.
pub fn walking_in_row(row: &crate::models::fixed::trace::RowTrace) -> u64 {
    row.pixels
        .iter()
        .filter(|pw| !pw.reused && pw.cand_len > 0)
        .count() as u64
}

/// Applies pixels `from..to` functionally (no cycle): each pixel's hit-buffer word is written
/// into the BRAM, each node and attribute read of its walks (relocated to its asset) goes
/// through the cache's tags, and the frame's counts take the pixel as written.
pub fn warm_gap(
    frame: &mut FrameInputs<'_>,
    machine: &mut Machine,
    counts: &mut FrameCounts,
    (from, to): (u64, u64),
) -> Result<(), CycleError> {
    let width = u64::from(frame.setup.width.max(1));
    for p in from..to {
        frame.need_row((p / width) as usize)?;
        let pixel = u32::try_from(p).map_err(internal)?;
        let (row, pw, i) = frame.trace_at(pixel)?;
        let word = row
            .words
            .get(i)
            .copied()
            .ok_or_else(|| internal(format!("row of pixel {p} has no word {i}")))?;
        machine.bram.poke(p as usize, word).map_err(internal)?;
        counts.written += 1;
        if pw.reused {
            counts.reused += 1;
            continue;
        }
        let cands = row.candidates_of(pw);
        if cands.is_empty() {
            continue;
        }
        counts.walks_entered += 1;
        if usize::from(pw.walk_len) < cands.len() {
            counts.early += 1;
        }
        for (c, tw) in row.walks_of(pw).iter().enumerate() {
            let k = cands.get(c).map_or(0, |&(_, k)| usize::from(k));
            let asset = frame.instance_asset.get(k).copied().unwrap_or(0);
            let nb = frame.layout.node_base.get(asset).copied().unwrap_or(0);
            let ab = frame.layout.attr_base.get(asset).copied().unwrap_or(0);
            for &o in row.ops_of(tw) {
                let a = o as u32;
                match o >> 32 {
                    0 => {}
                    1 => machine.mem.warm(FetchKind::Node, a.wrapping_add(nb)),
                    2 => machine.mem.warm(FetchKind::Far, a.wrapping_add(nb)),
                    _ => machine.mem.warm(FetchKind::Attr, a.wrapping_add(ab)),
                }
            }
        }
    }
    Ok(())
}
