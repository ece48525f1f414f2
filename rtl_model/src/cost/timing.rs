//! The clock rule: whether a register-to-register path of so many logic levels fits a clock
//! period on an UltraScale+ −2 part, the rule `sim hardware --synth` applies to the logic
//! levels it counts in each unit's synthesised netlist (docs/cycle-model.md §1.5).
//!
//! Pipeline position: beside the resource estimate, read once per configuration; it times
//! no transaction. The figures: DS923 (Virtex UltraScale+ data sheet, DC and AC switching
//! characteristics) gives the hard blocks' ceilings for the −2 speed grade at 0.85 V —
//! DSP48E2 775 MHz with all registers used, 544 MHz for a two-register multiply without
//! MREG, 410 MHz without pipeline registers — but does not tabulate CLB LUT, carry or routing
//! delays (those live in Vivado's timing models), so the per-level figures below are
//! assumptions, stated as such, typical of −2 timing reports: a LUT with its net, a CARRY8
//! segment, a MUXF, the flip-flop's clock-to-out plus setup, and a margin for clock skew and
//! jitter.

/// Assumed delays of the clock rule, in picoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClockRule {
    /// One LUT level with the net that leaves it (assumed: 100 ps cell + 350 ps route).
    pub lut_net_ps: u32,
    /// One CARRY8 segment on a carry chain, 8 bits (assumed; half of it per Yosys CARRY4).
    pub carry8_ps: u32,
    /// One MUXF7/F8/F9 (assumed; dedicated routing inside the slice).
    pub muxf_ps: u32,
    /// Flip-flop clock-to-out plus setup at the endpoint (assumed).
    pub clk_to_out_setup_ps: u32,
    /// Clock skew, jitter and routing margin reserved out of the period (assumed).
    pub margin_ps: u32,
}

/// The rule this project uses for an UltraScale+ −2 part (every number assumed, see the
/// module documentation).
pub const ULTRASCALE_PLUS_2: ClockRule = ClockRule {
    lut_net_ps: 450,
    carry8_ps: 100,
    muxf_ps: 100,
    clk_to_out_setup_ps: 150,
    margin_ps: 300,
};

/// DSP48E2 ceiling with every register used, −2 speed grade, 0.85 V (DS923, DSP48 slice
/// switching characteristics, F_MAX).
pub const DSP48E2_FMAX_MHZ_ALL_REGISTERS: u32 = 775;
/// DSP48E2 ceiling of a multiply without MREG (two registers), −2, 0.85 V (DS923).
pub const DSP48E2_FMAX_MHZ_NO_MREG: u32 = 544;

/// A combinational path between two registers as the clock rule sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PathLevels {
    /// LUTs (and LUT-RAM reads and inverters) on the path: the logic levels.
    pub luts: u32,
    /// Yosys CARRY4 cells on the path (two make one UltraScale+ CARRY8 segment).
    pub carry4: u32,
    /// MUXF7/F8/F9 on the path.
    pub muxf: u32,
}

impl PathLevels {
    /// Logic levels as Vivado counts them on UltraScale+: LUTs, CARRY8 segments (two
    /// CARRY4 of the Yosys netlist) and MUXFs.
    pub fn levels(&self) -> u32 {
        self.luts + self.carry4.div_ceil(2) + self.muxf
    }
}

impl ClockRule {
    /// Picoseconds of one Yosys CARRY4 (half a CARRY8 segment).
    pub fn carry4_ps(&self) -> u32 {
        self.carry8_ps / 2
    }

    /// Estimated delay of a register-to-register path: clock-to-out and setup, the margin,
    /// then per level its delay.
    pub fn path_ps(&self, p: &PathLevels) -> u32 {
        self.clk_to_out_setup_ps
            + self.margin_ps
            + p.luts * self.lut_net_ps
            + p.carry4 * self.carry4_ps()
            + p.muxf * self.muxf_ps
    }

    /// The highest clock (MHz, rounded down) the path allows.
    pub fn fmax_mhz(&self, p: &PathLevels) -> u32 {
        1_000_000 / self.path_ps(p).max(1)
    }

    /// Whether the path plausibly meets `mhz`.
    pub fn meets(&self, p: &PathLevels, mhz: u32) -> bool {
        u64::from(self.path_ps(p)) * u64::from(mhz) <= 1_000_000
    }

    /// LUT levels (no carry) that fit one period of `mhz`.
    pub fn lut_levels_at(&self, mhz: u32) -> u32 {
        let period = 1_000_000 / mhz.max(1);
        period.saturating_sub(self.clk_to_out_setup_ps + self.margin_ps) / self.lut_net_ps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_lut_levels_fit_300_mhz_and_seven_do_not() {
        let r = ULTRASCALE_PLUS_2;
        assert_eq!(r.lut_levels_at(300), 6);
        let six = PathLevels {
            luts: 6,
            ..PathLevels::default()
        };
        let seven = PathLevels { luts: 7, ..six };
        assert!(r.meets(&six, 300));
        assert!(!r.meets(&seven, 300));
        // A 64-bit adder: one LUT and 8 CARRY8 segments (16 CARRY4).
        let add64 = PathLevels {
            luts: 1,
            carry4: 16,
            muxf: 0,
        };
        assert_eq!(add64.levels(), 9);
        assert_eq!(r.path_ps(&add64), 150 + 300 + 450 + 800);
        assert!(r.meets(&add64, 300));
    }
}
