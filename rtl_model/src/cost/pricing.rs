//! What a datapath configuration costs, as `sim sweep` prices it: unit latencies, the widest
//! multiplier of each unit, DSP48E2 slices, walker-stack bits and the bits of the on-chip
//! per-pixel tables.
//!
//! Pipeline position: beside the measurement of `sim sweep`, one per configuration. Every
//! figure comes from the functions the cycle model and `sim hardware` use — the hardware is
//! `HwConfig::for_datapath(dp)`, the default hardware with each unit's latency set to the
//! stage count of `dp`'s formats (`UnitTimings::for_datapath`), its resource estimate
//! (`HwConfig::resources`) and each unit's products (`units::*::products`) — so a sweep's cost
//! column is what `sim hardware --datapath` prints.

use crate::cycle::hw_config::HwConfig;
use crate::datapath::DatapathConfig;
use crate::fixed::Products;
use crate::units::{reciprocal, sphere, transform, walker};
use serde::Serialize;

/// Latency in cycles of each datapath unit whose stage count depends on the formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct UnitLatencies {
    /// Sphere lane without its square root.
    pub sphere: u32,
    /// Square root of the sphere lane (one stage per root digit).
    pub sqrt: u32,
    /// Transform into the instance frame.
    pub transform: u32,
    /// One reciprocal 1/d.
    pub reciprocal: u32,
    /// Walker root (slab products).
    pub walker_root: u32,
}

/// The widest product of each unit as "A×B" operand widths in bits (sign included for signed
/// operands; the reciprocal's are unsigned mantissas; `-` for a unit without a multiply).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct MultiplierWidths {
    /// Sphere lane: the widest of l·d, l·l and t_ca².
    pub sphere: String,
    /// Transform: the widest of R·(o − c) and R·d.
    pub transform: String,
    /// Reciprocal: the widest Newton–Raphson multiply.
    pub reciprocal: String,
    /// Walker root: (±e − o)·(1/|d|).
    pub walker_root: String,
}

/// The cost of one configuration.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Cost {
    /// Unit latencies.
    pub latency: UnitLatencies,
    /// Multiplier widths.
    pub multipliers: MultiplierWidths,
    /// DSP48E2 slices of the whole pipeline (all unit instances).
    pub dsp48e2: u64,
    /// Bits of all walker stacks: walkers × contexts × stack depth × frame bits.
    pub stack_bits: u64,
    /// Bits of on-chip RAM the datapath's formats size: the walker stacks, the hit buffer and
    /// the direction table (the hardware frame's pixels), wherever they are placed.
    pub bram_bits: u64,
    /// BRAM36 blocks of the whole design (`HwConfig::resources`).
    pub bram36: u64,
    /// URAM288 blocks of the whole design.
    pub uram288: u64,
}

/// The product with the most operand bits, as "A×B" (the first of equals, so a unit's list
/// order decides between A×B and B×A).
fn widest(products: impl IntoIterator<Item = (u32, u32)>) -> String {
    let mut best: Option<(u32, u32)> = None;
    for (a, b) in products {
        let key = |(a, b): (u32, u32)| (a * b, a.max(b));
        if best.is_none_or(|w| key((a, b)) > key(w)) {
            best = Some((a, b));
        }
    }
    best.map_or_else(|| "-".to_string(), |(a, b)| format!("{a}x{b}"))
}

fn widths<const N: usize>(p: [Products; N]) -> impl Iterator<Item = (u32, u32)> {
    p.into_iter().map(|p| p.operand_bits())
}

/// Multiplier widths of `dp`'s units.
pub fn multiplier_widths(dp: &DatapathConfig) -> MultiplierWidths {
    MultiplierWidths {
        sphere: widest(widths(sphere::products(&dp.sphere))),
        transform: widest(widths(transform::products(&dp.transform))),
        reciprocal: widest(reciprocal::multiplier_widths(&dp.reciprocal)),
        walker_root: widest(widths([walker::root_products(&dp.walker)])),
    }
}

/// The cost of `dp` on the hardware `hw` (normally `HwConfig::for_datapath(dp)`); an error
/// when either configuration is invalid.
pub fn cost(dp: &DatapathConfig, hw: &HwConfig) -> Result<Cost, String> {
    let r = hw.resources(dp)?;
    let u = &hw.units;
    let stack_bits = hw.stack_bits(dp, hw.walker_pool.stack_depth);
    let tables = hw.hit_buffer_bits(dp) + hw.direction_table_bits(dp);
    Ok(Cost {
        latency: UnitLatencies {
            sphere: u.sphere.latency_cycles,
            sqrt: u.sqrt.latency_cycles,
            transform: u.transform.latency_cycles,
            reciprocal: u.reciprocal.latency_cycles,
            walker_root: u.walker_root.latency_cycles,
        },
        multipliers: multiplier_widths(dp),
        dsp48e2: r.used.dsp48e2,
        stack_bits,
        bram_bits: stack_bits + tables,
        bram36: r.used.bram36,
        uram288: r.used.uram288,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widest_keeps_the_first_of_equals() {
        assert_eq!(widest([(29, 10), (10, 29)]), "29x10");
        assert_eq!(widest([(29, 10), (10, 29), (29, 29), (29, 29)]), "29x29");
        assert_eq!(widest([]), "-");
    }
}
