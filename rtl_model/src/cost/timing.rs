//! The clock rule: whether a register-to-register path of so many logic levels fits a clock
//! period, the rule `sim hardware --synth` applies to the logic levels it counts in each
//! unit's synthesised netlist (docs/cycle-model.md §1.5), for an UltraScale+ −2 part (the
//! model's target) and for a Lattice ECP5 speed grade 6 (the part the open place-and-route
//! flow of `testbench/synth/pnr_ecp5.sh` reaches, to set the rule beside a real router).
//!
//! Pipeline position: beside the resource estimate, read once per configuration; it times
//! no transaction.
//!
//! UltraScale+ −2: DS923 (Virtex UltraScale+ data sheet, DC and AC switching
//! characteristics) gives the hard blocks' ceilings for the −2 speed grade at 0.85 V —
//! DSP48E2 775 MHz with all registers used, 544 MHz for a two-register multiply without
//! MREG, 410 MHz without pipeline registers — but does not tabulate CLB LUT, carry or routing
//! delays (those live in Vivado's timing models), so the per-level figures below are
//! assumptions, stated as such, typical of −2 timing reports: a LUT with its net, a CARRY8
//! segment, a MUXF, the flip-flop's clock-to-out plus setup, and a margin for clock skew and
//! jitter.
//!
//! ECP5 speed 6: the cells' delays are the ones Yosys's ECP5 library gives its timing-driven
//! mapper (`techlibs/ecp5/cells_sim.v` and `ccu2c_sim.vh`: LUT4 141–379 ps by input, CCU2C
//! 516 ps from a LUT input to its carry out and 43 ps carry in to carry out, L6MUX21/PFUMX
//! 148 ps); the net per level, clock-to-out plus setup and the margin are the UltraScale+
//! rule's assumptions carried over unchanged, so that the comparison with nextpnr measures
//! the rule's method (a fixed net per level) rather than a fit to the router.

/// Assumed delays of the clock rule, in picoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClockRule {
    /// The rule's name on the command line.
    pub name: &'static str,
    /// One LUT level with the net that leaves it (assumed: 100 ps cell + 350 ps route).
    pub lut_net_ps: u32,
    /// One carry cell of the mapped netlist along its chain, carry in to carry out: a Yosys
    /// CARRY4 on UltraScale+ (half an assumed 100 ps CARRY8 segment), a CCU2C (2 bits) on ECP5.
    pub carry_cell_ps: u32,
    /// Carry cells that make one logic level as the vendor's tools count them: 2 on
    /// UltraScale+ (two Yosys CARRY4 are one CARRY8 segment), 1 on ECP5.
    pub carry_cells_per_level: u32,
    /// Whether a carry cell holds the LUTs that feed its chain (ECP5's CCU2C holds two LUT4):
    /// a path entering the chain through a LUT input then pays a LUT level with its net there.
    /// On UltraScale+ the LUT before a CARRY4 is a cell of its own and already counted.
    pub carry_holds_luts: bool,
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
    name: "xcup-2",
    lut_net_ps: 450,
    carry_cell_ps: 50,
    carry_cells_per_level: 2,
    carry_holds_luts: false,
    muxf_ps: 100,
    clk_to_out_setup_ps: 150,
    margin_ps: 300,
};

/// The same rule for a Lattice ECP5 of speed grade 6: the cells' delays from Yosys's ECP5
/// library, the net, clock-to-out, setup and margin the UltraScale+ rule's (module
/// documentation).
pub const ECP5_6: ClockRule = ClockRule {
    name: "ecp5-6",
    // LUT4's slowest input (C or D, 379 ps) with the UltraScale+ rule's 350 ps net.
    lut_net_ps: 379 + 350,
    // CCU2C carry in to carry out.
    carry_cell_ps: 43,
    carry_cells_per_level: 1,
    carry_holds_luts: true,
    // L6MUX21 and PFUMX, select to output.
    muxf_ps: 148,
    clk_to_out_setup_ps: 150,
    margin_ps: 300,
};

/// The rules by name, for the command line (`sim hardware --levels … --rule NAME`).
pub const RULES: [ClockRule; 2] = [ULTRASCALE_PLUS_2, ECP5_6];

/// The rule named `name`, if there is one.
pub fn rule_named(name: &str) -> Option<ClockRule> {
    RULES.iter().copied().find(|r| r.name == name)
}

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
    /// Carry cells on the path: Yosys CARRY4 (two make one UltraScale+ CARRY8 segment) or
    /// ECP5 CCU2C.
    pub carry: u32,
    /// MUXF7/F8/F9 on the path.
    pub muxf: u32,
}

impl ClockRule {
    /// Logic levels of `p` as the vendor's tools count them: LUTs, carry segments (on
    /// UltraScale+ a CARRY8, two CARRY4 of the Yosys netlist) and MUXFs.
    pub fn levels(&self, p: &PathLevels) -> u32 {
        p.luts + self.carry_levels(p) + p.muxf
    }

    /// The carry segments of `p` as logic levels.
    pub fn carry_levels(&self, p: &PathLevels) -> u32 {
        p.carry.div_ceil(self.carry_cells_per_level.max(1))
    }

    /// Estimated delay of a register-to-register path: clock-to-out and setup, the margin,
    /// then per level its delay.
    pub fn path_ps(&self, p: &PathLevels) -> u32 {
        self.clk_to_out_setup_ps
            + self.margin_ps
            + p.luts * self.lut_net_ps
            + p.carry * self.carry_cell_ps
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
            carry: 16,
            muxf: 0,
        };
        assert_eq!(r.levels(&add64), 9);
        assert_eq!(r.path_ps(&add64), 150 + 300 + 450 + 800);
        assert!(r.meets(&add64, 300));
    }

    #[test]
    fn the_ecp5_rule_takes_yosys_cell_delays_and_counts_every_ccu2c_as_a_level() {
        let r = ECP5_6;
        // 150 + 300 + 4 × 729 = 3,366 ps: four LUT4 levels fit 250 MHz (4 ns), five do not.
        assert_eq!(r.lut_levels_at(250), 4);
        // A 32-bit adder on ECP5: 16 CCU2C, each a level (the vendor's count).
        let add32 = PathLevels {
            luts: 1,
            carry: 15,
            muxf: 0,
        };
        assert_eq!(r.levels(&add32), 16);
        assert_eq!(r.path_ps(&add32), 150 + 300 + 729 + 15 * 43);
        assert_eq!(r.fmax_mhz(&add32), 1_000_000 / 1_824);
    }

    #[test]
    fn rules_are_found_by_their_names_and_only_those() {
        assert_eq!(rule_named("xcup-2"), Some(ULTRASCALE_PLUS_2));
        assert_eq!(rule_named("ecp5-6"), Some(ECP5_6));
        assert_eq!(rule_named("ecp5"), None);
    }
}
