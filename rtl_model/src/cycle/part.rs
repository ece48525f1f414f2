//! The target FPGA part of the hardware configuration (`hw_config::HwConfig::part`): its name
//! and the hard-block and LUT budget the resource estimate is checked against.
//!
//! Pipeline position: none; read with the hardware configuration, and used by the estimate
//! (`cost::estimate`) and the report's fit line. Re-exported as `hw_config::Part`.

use serde::{Deserialize, Serialize};

/// A named FPGA part and its resource budget.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Part {
    /// AMD/Xilinx device name, e.g. `xcvu9p`.
    pub name: String,
    /// DSP48E2 slices (27×18 multipliers).
    pub dsp48e2: u32,
    /// 36 Kb block RAMs (RAMB36E2; a RAMB18 pair counts as one).
    pub bram36: u32,
    /// 288 Kb UltraRAMs (URAM288); 0 on parts without UltraRAM.
    pub uram288: u32,
    /// CLB LUTs: listed for the report; the estimate does not count LUTs.
    pub luts: u32,
}

impl Part {
    /// Virtex UltraScale+ XCVU9P: 6,840 DSP48E2, 2,160 BRAM36 (75.9 Mb), 960 URAM288 (270 Mb),
    /// 1,182,240 LUTs (AMD DS890, Virtex UltraScale+ feature summary; XMP103 selection guide).
    /// The default part: its UltraRAM holds the two per-pixel tables of a 1280×768 frame, the
    /// hit buffer (240 URAM288) and the direction table (480), which parts without UltraRAM
    /// cannot hold in block RAM.
    pub fn xcvu9p() -> Self {
        Self {
            name: "xcvu9p".into(),
            dsp48e2: 6840,
            bram36: 2160,
            uram288: 960,
            luts: 1_182_240,
        }
    }

    /// Zynq UltraScale+ XCZU9EG: 2,520 DSP48E2, 912 BRAM36 (32.1 Mb), no UltraRAM, 274,080
    /// LUTs (AMD DS891, Zynq UltraScale+ MPSoC feature summary). The alternative: the
    /// 1280×768 hit buffer (1,920 BRAM36) does not fit, so it must be external.
    pub fn xczu9eg() -> Self {
        Self {
            name: "xczu9eg".into(),
            dsp48e2: 2520,
            bram36: 912,
            uram288: 0,
            luts: 274_080,
        }
    }
}

impl Default for Part {
    fn default() -> Self {
        Self::xcvu9p()
    }
}
