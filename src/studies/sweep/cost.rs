//! What a datapath configuration costs in hardware: unit latencies, multiplier widths,
//! DSP48E2 slices, walker-stack bits and the bits of the on-chip per-pixel tables.
//!
//! Pipeline position: beside the measurement of `sim sweep`, one per configuration. Every
//! figure comes from the functions the cycle model and `sim hardware` use — the hardware is
//! `HwConfig::for_datapath(dp)`, the default hardware with each unit's latency set to the
//! stage count of `dp`'s formats (`UnitTimings::for_datapath`), and its resource estimate
//! (`HwConfig::resources`) — so a sweep's cost column is what `sim hardware --datapath` prints.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::Format;
use rtl_model::units::reciprocal;
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

/// A format one bit wider: the exact difference of two values of `f`.
fn wider(f: Format) -> Format {
    Format {
        width: f.width.saturating_add(1),
        ..f
    }
}

/// The product with the most operand bits, as "A×B".
fn widest(products: &[(u32, u32)]) -> String {
    products
        .iter()
        .max_by_key(|&&(a, b)| (a * b, a.max(b)))
        .map_or_else(|| "-".to_string(), |(a, b)| format!("{a}x{b}"))
}

fn bits(f: Format) -> u32 {
    u32::from(f.width)
}

/// Multiplier widths of `dp`'s units.
pub fn multiplier_widths(dp: &DatapathConfig) -> MultiplierWidths {
    let s = &dp.sphere;
    let l = bits(wider(s.pos));
    let t = &dp.transform;
    let r = &dp.reciprocal;
    // The mantissa is uQ1.G: G + 1 bits; the first iteration multiplies by the seed, t + 2 bits.
    let full = reciprocal::mantissa_frac_bits(r) + 1;
    let seed = (reciprocal::seed_frac_bits(r.table_bits)).min(full);
    let recip: Vec<(u32, u32)> = match r.iterations {
        0 => Vec::new(),
        1 => vec![(full, seed)],
        _ => vec![(full, full)],
    };
    MultiplierWidths {
        sphere: widest(&[(l, bits(s.dir)), (l, l), (bits(s.tca), bits(s.tca))]),
        transform: widest(&[
            (bits(t.mat), bits(wider(t.pos))),
            (bits(t.mat), bits(t.dir)),
        ]),
        reciprocal: widest(&recip),
        walker_root: widest(&[(bits(wider(dp.walker.pos)), bits(dp.walker.inv))]),
    }
}

/// The cost of `dp` on the hardware `hw` (normally `HwConfig::for_datapath(dp)`).
pub fn cost(dp: &DatapathConfig, hw: &HwConfig) -> Result<Cost, String> {
    let r = hw.resources(dp)?;
    let u = &hw.units;
    let w = &hw.walker_pool;
    let stack_bits = u64::from(w.walkers)
        * u64::from(w.contexts_per_walker)
        * u64::from(w.stack_depth)
        * u64::from(hw.stack_frame_bits(dp));
    let px = hw.frame.pixels();
    let tables =
        px * u64::from(dp.hit_record.word_bits()) + px * 3 * u64::from(bits(dp.raygen.dir));
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
    fn default_cost_matches_the_documented_figures() {
        let dp = DatapathConfig::default();
        let hw = HwConfig::for_datapath(&dp);
        assert_eq!(hw, HwConfig::default());
        let c = cost(&dp, &hw).unwrap();
        // docs/cycle-model.md: sphere 15 + sqrt 32, transform 8, reciprocal 23, root 8.
        assert_eq!(
            c.latency,
            UnitLatencies {
                sphere: 15,
                sqrt: 32,
                transform: 8,
                reciprocal: 23,
                walker_root: 8
            }
        );
        // `sim hardware` prints 432 DSP48E2 for the default.
        assert_eq!(c.dsp48e2, 432);
        assert_eq!(c.dsp48e2, hw.resources(&dp).unwrap().used.dsp48e2);
        assert_eq!(c.multipliers.transform, "32x41");
        // (±e − o) is sQ8.32 + 1 bit = 41 bits, 1/|d| sQ22.26 = 48.
        assert_eq!(c.multipliers.walker_root, "41x48");
        assert_eq!(c.multipliers.reciprocal, "29x29");
        // 32 walkers × 8 contexts × 21 frames × (6·62 + 68) bits.
        assert_eq!(c.stack_bits, 32 * 8 * 21 * (6 * 62 + 68));
    }

    #[test]
    fn narrower_positions_cost_what_the_tiles_say() {
        // Tiles of 26 × 17 magnitude bits, counted by hand for positions sQ8.16: l = c − o and
        // ±e − o are 25 bits (24 magnitude), directions and matrix entries 31, t_ca 41, 1/|d| 47.
        // Sphere lane: l·d 3 × 2, l·l 3 × 2, t_ca² 1 × 6 = 18, × 8 lanes = 144. Transform:
        // 9 × 2 (R·(o − c)) + 9 × 4 (R·d) = 54. Reciprocal 12 × 3 units = 36 (unchanged).
        // Walker root: 6 × 3 (24 × 47: 1 × 3 tiles) = 18. Total 252.
        let mut dp = DatapathConfig::default();
        crate::studies::sweep::configs::set_pos_frac(&mut dp, 16);
        let c = cost(&dp, &HwConfig::for_datapath(&dp)).unwrap();
        assert_eq!(c.dsp48e2, 144 + 54 + 36 + 18);
        assert_eq!(c.multipliers.walker_root, "25x48");
    }
}
