//! What a datapath configuration costs in hardware, as `sim sweep` prices it: unit latencies,
//! multiplier widths, DSP48E2 slices, walker-stack bits and the bits of the on-chip per-pixel
//! tables.
//!
//! Pipeline position: beside the measurement of `sim sweep`, one per configuration. The
//! figures are `rtl_model::cost::pricing`'s, the one home of every cost the hardware model
//! states (`HwConfig::resources`, `UnitTimings::for_datapath`, each unit's products), so a
//! sweep's cost column is what `sim hardware --datapath` prints. This module is the sweep's
//! view of it, and checks it on the sweep's own configurations.

pub use rtl_model::cost::pricing::{cost, Cost};

#[cfg(test)]
mod tests {
    use super::*;
    use rtl_model::cost::pricing::UnitLatencies;
    use rtl_model::cycle::hw_config::HwConfig;
    use rtl_model::datapath::DatapathConfig;

    #[test]
    fn default_cost_matches_the_documented_figures() {
        let dp = DatapathConfig::default();
        let hw = HwConfig::for_datapath(&dp);
        assert_eq!(hw, HwConfig::default());
        let c = cost(&dp, &hw).unwrap();
        // docs/cycle-model.md: sphere 16 + sqrt 32, transform 9, reciprocal 26, root 8.
        assert_eq!(
            c.latency,
            UnitLatencies {
                sphere: 16,
                sqrt: 32,
                transform: 9,
                reciprocal: 26,
                walker_root: 8
            }
        );
        // `sim hardware` prints 569 DSP48E2 for the default (two walk-issue lanes, the normal
        // unit 9; svo_front's candidate gathering none since its decoder, issue 29).
        assert_eq!(c.dsp48e2, 569);
        assert_eq!(c.dsp48e2, hw.resources(&dp).unwrap().used.dsp48e2);
        assert_eq!(c.multipliers.transform, "32x41");
        // (±e − o) is sQ8.32 + 1 bit = 41 bits, 1/|d| sQ22.30 = 52.
        assert_eq!(c.multipliers.walker_root, "41x52");
        assert_eq!(c.multipliers.reciprocal, "33x33");
        // 32 walkers × 8 contexts × 21 frames × the RTL's frame: 9 × (62 + 1) t bits, node
        // address 32, descriptor 32, next child 4, level 5, coordinates 60 (700 bits).
        assert_eq!(c.stack_bits, 32 * 8 * 21 * (9 * 63 + 32 + 32 + 4 + 5 + 60));
    }

    #[test]
    fn narrower_positions_cost_what_the_tiles_say() {
        // Tiles of 26 × 17 magnitude bits, counted by hand for positions sQ8.16: l = c − o and
        // ±e − o are 25 bits (24 magnitude), directions and matrix entries 31, t_ca 33, 1/|d| 51.
        // Sphere lane: l·d 3 × 2, l·l 3 × 2, t_ca² 1 × 4 = 16, × 8 lanes = 128. Transform:
        // 9 × 2 (R·(o − c)) + 9 × 4 (R·d) = 54 a unit. Reciprocal 12 a unit (unchanged).
        // Walker root: 6 × 3 (24 × 51: 1 × 3 tiles) = 18 a unit. The default's two walk-issue
        // lanes: 128 + 2 × 54 + 6 × 12 + 2 × 18 = 344 and the normal unit's 9 (svo_front's
        // candidate gathering, a decoder per key slot, takes none).
        let mut dp = DatapathConfig::default();
        crate::studies::sweep::configs::set_pos_frac(&mut dp, 16);
        let c = cost(&dp, &HwConfig::for_datapath(&dp)).unwrap();
        assert_eq!(c.dsp48e2, 128 + 2 * 54 + 6 * 12 + 2 * 18 + 9);
        assert_eq!(c.multipliers.walker_root, "25x52");
    }
}
