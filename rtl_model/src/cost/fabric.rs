//! The fabric estimate: LUTs and flip-flops per unit, a first-order model calibrated on the
//! Yosys synthesis of the RTL (`testbench/synth/`, `sim hardware --synth`) so that it follows
//! a change of the datapath's formats.
//!
//! Pipeline position: beside the resource estimate of hard blocks ([`super::estimate`]), read
//! once per configuration by `sim hardware`. Each unit with RTL has a width measure `W(dp)`
//! — a sum of the bit widths its registers and adders carry, one formula per unit (below and
//! in docs/cycle-model.md §1.5) — and its LUT and FF counts scale with it from the synthesis
//! of the default datapath: `LUT(dp) = LUT₀ · W(dp) / W(default)`, the same for FFs. At the
//! default the estimate therefore equals synthesis by construction; elsewhere it is linear in
//! the widths, which is first order (a multiplier's partial-product adders grow with the
//! product of its operand widths). LUTs here are what Vivado reports as CLB LUTs: logic
//! LUTs, shift registers (SRL16E/SRLC32E) and LUT-RAM.

use crate::cycle::hw_config::HwConfig;
use crate::datapath::DatapathConfig;
use crate::units::{reciprocal, sorter, sphere};

/// LUTs and FFs of one instance of a unit with RTL, from Yosys 0.23 `synth_xilinx -family
/// xcup -flatten` of the default datapath (testbench/README.md, synthesis): LUT1..6 + SRLs
/// + 8 per RAM32M16.
pub mod calibration {
    /// `svo_sqrt` N = 64: 2020 LUT + 58 SRL, 1531 FF.
    pub const SQRT: (u64, u64) = (2078, 1531);
    /// `svo_sphere` (16 stages and the root's 32) without its square root: (4325 + 1025
    /// SRL) − sqrt's 2078 LUT, 2216 − 1531 FF.
    pub const SPHERE: (u64, u64) = (3272, 685);
    /// `svo_transform` (9 stages): 3518 LUT + 1233 SRL, 1820 FF.
    pub const TRANSFORM: (u64, u64) = (4751, 1820);
    /// `svo_reciprocal` (26 stages): 894 LUT + 216 SRL, 442 FF.
    pub const RECIPROCAL: (u64, u64) = (1110, 442);
    /// `svo_walker_root` (each product as six 27 × 18 tiles and their adder tree): 3079
    /// LUT, 6228 FF.
    pub const WALKER_ROOT: (u64, u64) = (3079, 6228);
    /// `svo_walker` (one context, its 21-frame stack in 50 RAM32M16; the step in two
    /// register stages, zero-axis centres kept incrementally, no product): 4781 + 400 LUT,
    /// 2503 FF.
    pub const WALKER: (u64, u64) = (5181, 2503);
    /// `svo_walker_barrel`, the walker of R > 1 contexts (issue 29's whole-core synthesis at the
    /// default): CLB LUTs (LUT1–6 + LUT-RAM + SRL) and FFs at R = 2, 4, 8, 16 contexts, with one
    /// take and result port (`BARREL_K1`) and two (`BARREL_K2`, the default's two walk-issue
    /// lanes). Yosys 0.23 `synth_xilinx -family xcup -flatten` of svo_walker_barrel.v alone with
    /// `chparam -set CONTEXTS R -set K K -set TAG_W 10 -set STEP_LATENCY 4` (the default's slot
    /// tag and step; 38–71 s of CPU each). From R = 4 the stacks (R × 20 frames of 700 bits) are
    /// 10 RAMB36 and the contexts' words LUT-RAM (210–285 RAM32M16); at R = 2 the 40 frames are
    /// LUT-RAM (700 RAM64X1S) and the FFs rise. Each row: (R, CLB LUT, FF).
    pub const BARREL_K1: [(u64, u64, u64); 4] = [
        (2, 8560, 6585),
        (4, 8795, 4304),
        (8, 10582, 5075),
        (16, 13175, 6614),
    ];
    /// As [`BARREL_K1`] with K = 2: the second take port's `wram` bank and the second result
    /// port's read of the context RAMs.
    pub const BARREL_K2: [(u64, u64, u64); 4] = [
        (2, 9292, 8239),
        (4, 11663, 4308),
        (8, 14256, 5083),
        (16, 18463, 6630),
    ];
    /// `svo_raygen` (three direction and three position converters, svo_f64_to_fixed, the
    /// align in two stages, the shift decided in the decode stage's register block): 1954
    /// LUT + 50 SRL, 1168 FF.
    pub const RAYGEN: (u64, u64) = (2004, 1168);
    /// `svo_sorter` (8-lane network, MAX_KEYS = 32: its input copy, merge and two run
    /// buffers in flip-flops with their read multiplexers; placed for 300 MHz, the merge's
    /// heads and successors in registers): 13460 LUT + 95 SRL, 5897 FF.
    pub const SORTER: (u64, u64) = (13555, 5897);
    /// The network width `SORTER` was synthesised at (`svo_sorter`'s N).
    pub const SORTER_LANES: u8 = 8;
    /// `svo_sorter` at N = 16 (Green's 60-comparator, depth-10 network from the model's
    /// NET_PAIRS, MAX_KEYS = 64 as the 16-lane vectors' rows; same structure as `SORTER`):
    /// 31405 LUT + 260 SRL, 13134 FF. 2.34× the LUTs and 2.23× the flip-flops of the 8-lane
    /// sorter, where its network's comparator and register bits grow 3.2× and 3.3×: most of
    /// the unit is the ray copy, run buffers and their read multiplexers, which grow with
    /// MAX_KEYS = 4N, not with the network.
    pub const SORTER_16: (u64, u64) = (31665, 13134);
    /// The network width `SORTER_16` was synthesised at.
    pub const SORTER_16_LANES: u8 = 16;
    /// `svo_sorter` at N = 8 with MAX_KEYS = 16 = 2N, as svo_top builds it (`SO_MAX_KEYS` =
    /// `KEYN` = 2 × sorter lanes): 8839 LUT + 93 SRL, 3905 FF (Yosys 0.23 `synth_xilinx
    /// -family xcup -flatten` of svo_sorter.v with `chparam -set MAX_KEYS 16`, 39 s CPU;
    /// docs/cycle-model.md §1.5, "The whole svo_core"). 0.66× the LUTs and FFs of `SORTER`:
    /// the run buffers and their read multiplexers are half as deep.
    pub const SORTER_2N: (u64, u64) = (8932, 3905);
    /// `svo_sorter` at N = 16 with MAX_KEYS = 32 = 2N, as svo_top builds it: the whole core's
    /// `synth_core.sh --per-module testbench/hw/frame_hw_pkg.sv`, svo_sorter alone: 19546 CLB
    /// LUT (258 SRL), 9178 FF (0.62× and 0.70× of `SORTER_16`).
    pub const SORTER_16_2N: (u64, u64) = (19546, 9178);
    /// `svo_normal` (8-bit codes, an 18-bit divisor: 9 DSP48E2 products, the sums, the
    /// normalising shift and two 7-step restoring dividers, 13 stages each within 300 MHz by
    /// the clock rule): 1543 LUT (SRL included), 1508 FF.
    pub const NORMAL: (u64, u64) = (1543, 1508);
    /// `svo_hit_pack` (72-bit word): 105 LUT, 74 FF.
    pub const HIT_PACK: (u64, u64) = (105, 74);
    /// `svo_hit_check` (72-bit word; the unpacked fields are wires into the output
    /// register): 12 LUT, 145 FF.
    pub const HIT_CHECK: (u64, u64) = (12, 145);
}

/// LUTs and flip-flops.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fabric {
    /// CLB LUTs (logic, shift registers, LUT-RAM).
    pub lut: u64,
    /// Flip-flops.
    pub ff: u64,
}

/// One unit's line of the fabric estimate.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FabricItem {
    /// Component name, as in the resource estimate (`sphere`, `walker`, …).
    pub name: &'static str,
    /// Instances the hardware has.
    pub instances: u64,
    /// One instance.
    pub per_instance: Fabric,
    /// Whether the figure is calibrated on the unit's synthesis (every unit with RTL is; the
    /// structures of `cost::structures` are not).
    pub calibrated: bool,
    /// The formula, as printed.
    pub formula: String,
}

impl FabricItem {
    /// All instances together.
    pub fn total(&self) -> Fabric {
        Fabric {
            lut: self.per_instance.lut.saturating_mul(self.instances),
            ff: self.per_instance.ff.saturating_mul(self.instances),
        }
    }
}

/// The fabric estimate's totals against the part (`HwConfig::fabric`, docs/cycle-model.md
/// §1.5): the hard blocks' table says whether DSP48E2 and RAM fit, this whether the logic does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct FabricTotals {
    /// CLB LUTs of every row.
    pub lut: u64,
    /// Flip-flops of every row.
    pub ff: u64,
    /// The part's LUTs.
    pub lut_available: u64,
    /// The part's flip-flops (two per LUT on UltraScale+).
    pub ff_available: u64,
}

impl FabricTotals {
    /// The totals of `items` against a part of `part_luts` LUTs.
    pub fn of(items: &[FabricItem], part_luts: u64) -> Self {
        let (lut, ff) = items.iter().fold((0u64, 0u64), |(l, f), it| {
            let t = it.total();
            (l.saturating_add(t.lut), f.saturating_add(t.ff))
        });
        Self {
            lut,
            ff,
            lut_available: part_luts,
            ff_available: part_luts.saturating_mul(2),
        }
    }

    /// Whether the LUTs and flip-flops fit the part.
    pub fn fits(&self) -> bool {
        self.lut <= self.lut_available && self.ff <= self.ff_available
    }
}

impl std::fmt::Display for FabricTotals {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let pct = |u: u64, a: u64| 100.0 * u as f64 / a.max(1) as f64;
        write!(
            f,
            "fabric (estimate, docs/cycle-model.md §1.5): LUT {} of {} ({:.1}%), FF {} of {} ({:.1}%): {}",
            self.lut,
            self.lut_available,
            pct(self.lut, self.lut_available),
            self.ff,
            self.ff_available,
            pct(self.ff, self.ff_available),
            if self.fits() {
                "fits"
            } else if self.lut > self.lut_available {
                "DOES NOT FIT: more LUTs than the part has (`sim hardware` lists the rows)"
            } else {
                "DOES NOT FIT: more flip-flops than the part has (`sim hardware` lists the rows)"
            }
        )
    }
}

/// The width measures `W(dp)` (LUT, FF) of each unit with RTL.
fn widths(name: &str, dp: &DatapathConfig) -> Option<(u64, u64)> {
    let w = |f: crate::fixed::Format| u64::from(f.width);
    Some(match name {
        "sqrt" => {
            let c = sphere::sqrt_config(&dp.sphere);
            let r = w(c.output);
            (r * r, r * w(c.input))
        }
        "sphere" => {
            let s = &dp.sphere;
            let b = 3 * (w(s.pos) + 1) + 3 * w(s.dir) + 2 * w(s.tca) + 3 * w(s.sq) + w(s.t_enter);
            (b, b)
        }
        "transform" => {
            let t = &dp.transform;
            let b = 9 * (w(t.pos) + 1 + w(t.mat))
                + 9 * (w(t.dir) + w(t.mat))
                + 3 * w(t.local_pos)
                + 3 * w(t.local_dir);
            (b, b)
        }
        "reciprocal" => {
            let r = &dp.reciprocal;
            let g = u64::from(reciprocal::mantissa_frac_bits(r));
            let b = 2 * u64::from(r.iterations) * (2 * g + 2) + w(r.output) + w(r.input);
            (b, b)
        }
        "walker_root" => {
            let k = &dp.walker;
            let b = 6 * (w(k.pos) + 2 + w(k.inv)) + 6 * (w(k.t) + 1) + 3 * w(k.pos);
            (b, b)
        }
        "walker" => {
            let k = &dp.walker;
            let b = 9 * (w(k.t) + 1) + 3 * (w(k.pos) + 1);
            (b, b)
        }
        "raygen" => {
            // Each converter decodes a 64-bit float into its code: the float's part is fixed.
            let r = &dp.raygen;
            let b = 3 * (64 + w(r.dir)) + 3 * (64 + w(r.pos));
            (b, b)
        }
        "sorter" => {
            let s = sorter::resources(&dp.sorter, dp.hit_record.instance_bits);
            (s.comparator_bits, s.register_bits)
        }
        "hit_pack" | "hit_check" => {
            let b = u64::from(dp.hit_record.word_bits());
            (b, b)
        }
        "normal" => {
            // Two dividers of n − 1 steps on DIV_BITS + n + 1 bits, and the 37-bit sums.
            let n = u64::from(dp.hit_record.normal_bits);
            let d = u64::from(crate::units::normal::DIV_BITS);
            let b = 2 * (n - 1) * (d + n + 1) + 6 * 37;
            (b, b)
        }
        _ => return None,
    })
}

/// The formula of a unit's width measure, as printed.
fn formula(name: &str) -> &'static str {
    match name {
        "sqrt" => "W = R² (LUT), R·N (FF); R root bits, N radicand bits",
        "sphere" => "W = 3(pos+1) + 3 dir + 2 tca + 3 sq + t_enter (bits)",
        "transform" => "W = 9(pos+1+mat) + 9(dir+mat) + 3 local_pos + 3 local_dir",
        "reciprocal" => "W = 2·iterations·(2G+2) + output + input; G mantissa bits",
        "walker_root" => "W = 6(pos+2+inv) + 6(t+1) + 3 pos",
        "walker" => "W = 9(t+1) + 3(pos+1); per walker as the one-context RTL walker",
        "raygen" => "W = 3(64+dir) + 3(64+pos)",
        "sorter" => "W = comparators × compare bits (LUT), network register bits (FF), from the synthesis at N = 8 or 16 with MAX_KEYS = 2N as svo_top builds it",
        "hit_pack" | "hit_check" => "W = record word bits",
        "normal" => "W = 2(n−1)(div+n+1) + 6·37; n normal bits, div = 18",
        _ => "",
    }
}

/// The sorter synthesis a sorter of `lanes` lanes scales from, and its width: the 16-lane one
/// from 12 lanes up, else the 8-lane one (exact at 8 and 16; between and beyond, scaled by the
/// network's comparator and register bits from the nearer synthesised width).
fn sorter_calibration(lanes: u8) -> ((u64, u64), u8) {
    if lanes >= 12 {
        (calibration::SORTER_16, calibration::SORTER_16_LANES)
    } else {
        (calibration::SORTER, calibration::SORTER_LANES)
    }
}

/// The sorter as svo_top builds it, with `MAX_KEYS` = 2N keys (its `KEYN`): the 2N
/// synthesis of the nearer width ([`calibration::SORTER_2N`], [`calibration::SORTER_16_2N`]),
/// scaled between and beyond by the network's comparator and register bits as
/// [`unit_fabric`] scales the unit's. [`unit_fabric`]`("sorter")` stays the unit at its RTL
/// default (MAX_KEYS = 4N), the width `sim hardware --synth` synthesises it at.
pub fn sorter_as_built(dp: &DatapathConfig) -> Fabric {
    let (cal, n) = if dp.sorter.n >= 12 {
        (calibration::SORTER_16_2N, calibration::SORTER_16_LANES)
    } else {
        (calibration::SORTER_2N, calibration::SORTER_LANES)
    };
    let mut reference = DatapathConfig::default();
    reference.sorter.n = n;
    match (widths("sorter", dp), widths("sorter", &reference)) {
        (Some((wl, wf)), Some((wl0, wf0))) => Fabric {
            lut: scale(cal.0, wl, wl0),
            ff: scale(cal.1, wf, wf0),
        },
        _ => Fabric::default(),
    }
}

/// One walker of `r` > 1 contexts with `k` take and result ports, as `svo_walker_barrel`
/// builds it at the default datapath: the measured points of [`calibration::BARREL_K1`] and
/// [`calibration::BARREL_K2`] joined by straight lines in R, the last segment (8 → 16)
/// continued beyond 16 and the first (2 → 4) below 4 (R = 3, whose stack of 60 frames would
/// be LUT-RAM as R = 2's, is priced between them); K > 2, which the RTL refuses, continues
/// K = 1 → 2 (each more port another `wram` bank and result read). `None` for R ≤ 1 (the
/// one-context `svo_walker`, [`calibration::WALKER`]) or K = 0.
pub fn barrel_fabric(r: u64, k: u64) -> Option<Fabric> {
    if r <= 1 || k == 0 {
        return None;
    }
    let at = |table: &[(u64, u64, u64); 4]| -> (i128, i128) {
        let seg = table
            .windows(2)
            .position(|w| r <= w[1].0)
            .unwrap_or(table.len() - 2);
        let (a, b) = (table[seg], table[seg + 1]);
        let lin = |ya: u64, yb: u64| -> i128 {
            let (xa, xb, x) = (i128::from(a.0), i128::from(b.0), i128::from(r));
            let (ya, yb) = (i128::from(ya), i128::from(yb));
            // Rounded to nearest: ya + (yb − ya)(x − xa) / (xb − xa).
            let num = (yb - ya) * (x - xa);
            let den = xb - xa;
            ya + (2 * num + den * num.signum()) / (2 * den)
        };
        (lin(a.1, b.1), lin(a.2, b.2))
    };
    let one = at(&calibration::BARREL_K1);
    let two = at(&calibration::BARREL_K2);
    let kk = i128::from(k);
    let v = |o: i128, t: i128| -> u64 {
        u64::try_from((o + (t - o) * (kk - 1)).max(0)).unwrap_or(u64::MAX)
    };
    Some(Fabric {
        lut: v(one.0, two.0),
        ff: v(one.1, two.1),
    })
}

/// `c · w / w0`, rounded to nearest (0 for w0 = 0).
pub(crate) fn scale(c: u64, w: u64, w0: u64) -> u64 {
    (u128::from(c) * u128::from(w) + u128::from(w0) / 2)
        .checked_div(u128::from(w0))
        .map_or(0, |v| u64::try_from(v).unwrap_or(u64::MAX))
}

/// One instance of a unit with RTL (`sqrt`, `sphere` without its square root, `sorter`,
/// `transform`, `reciprocal`, `walker_root`, `walker` with one context, `raygen`, `hit_check`,
/// `hit_pack`) with datapath `dp`; `None` for a name without RTL.
pub fn unit_fabric(name: &str, dp: &DatapathConfig) -> Option<Fabric> {
    let cal = match name {
        "sqrt" => calibration::SQRT,
        "sphere" => calibration::SPHERE,
        "transform" => calibration::TRANSFORM,
        "reciprocal" => calibration::RECIPROCAL,
        "walker_root" => calibration::WALKER_ROOT,
        "walker" => calibration::WALKER,
        "raygen" => calibration::RAYGEN,
        "sorter" => sorter_calibration(dp.sorter.n).0,
        "hit_pack" => calibration::HIT_PACK,
        "hit_check" => calibration::HIT_CHECK,
        "normal" => calibration::NORMAL,
        _ => return None,
    };
    let (wl, wf) = widths(name, dp)?;
    // The widths the calibration was synthesised at: the default datapath's, with the RTL
    // sorter's own network width.
    let mut reference = DatapathConfig::default();
    reference.sorter.n = sorter_calibration(dp.sorter.n).1;
    let (wl0, wf0) = widths(name, &reference)?;
    Some(Fabric {
        lut: scale(cal.0, wl, wl0),
        ff: scale(cal.1, wf, wf0),
    })
}

/// The estimate of one instance of a unit with RTL, as `sim hardware --synth` sets it
/// beside the unit's synthesis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UnitEstimate {
    /// LUTs and flip-flops ([`unit_fabric`]).
    pub fabric: Fabric,
    /// DSP48E2 (the unit's own count).
    pub dsp48e2: u64,
    /// BRAM36.
    pub bram36: u64,
    /// URAM288.
    pub uram288: u64,
}

impl HwConfig {
    /// One instance of the RTL unit `name` as the estimate prices it: `sphere` with its
    /// square root (the RTL instantiates it), `walker` as one context with its stack of
    /// `walker_pool.stack_depth` frames (the RTL walker is one context), the others as their
    /// component of [`HwConfig::resources`]; `sorter`, `raygen`, `hit_check` and `hit_pack`
    /// with no DSP48E2 or RAM (the resource estimate gives them none). `None` for a name
    /// without RTL.
    pub fn unit_estimate(&self, name: &str, dp: &DatapathConfig) -> Option<UnitEstimate> {
        use crate::units::{sqrt, transform, walker};
        let sq_dsp = u64::from(sqrt::dsp48e2_count(&sphere::sqrt_config(&dp.sphere)));
        let (fabric, dsp48e2, bram36) = match name {
            "sphere" => {
                let (a, b) = (unit_fabric("sphere", dp)?, unit_fabric("sqrt", dp)?);
                let f = Fabric {
                    lut: a.lut + b.lut,
                    ff: a.ff + b.ff,
                };
                (f, u64::from(sphere::dsp48e2_count(&dp.sphere)) + sq_dsp, 0)
            }
            "sqrt" => (unit_fabric("sqrt", dp)?, sq_dsp, 0),
            "transform" => {
                let d = match self.transform_products {
                    true => transform::dsp48e2_count(&dp.transform),
                    false => 0,
                };
                (unit_fabric(name, dp)?, u64::from(d), 0)
            }
            "reciprocal" => (
                unit_fabric(name, dp)?,
                u64::from(reciprocal::dsp48e2_count(&dp.reciprocal)),
                0,
            ),
            "walker_root" => (
                unit_fabric(name, dp)?,
                u64::from(walker::root_dsp48e2_count(&dp.walker)),
                0,
            ),
            "raygen" | "sorter" | "hit_pack" | "hit_check" => (unit_fabric(name, dp)?, 0, 0),
            "normal" => (
                unit_fabric(name, dp)?,
                u64::from(crate::units::normal::DSP48E2_COUNT),
                0,
            ),
            "walker" => {
                // One context, as svo_walker: its stack of stack_depth − 1 frames.
                (unit_fabric(name, dp)?, 0, self.stack_bram36(dp, 1))
            }
            _ => return None,
        };
        Some(UnitEstimate {
            fabric,
            dsp48e2,
            bram36,
            uram288: 0,
        })
    }

    /// LUTs and flip-flops per unit of this configuration with datapath `dp` (the model of
    /// this module), with the part's LUTs; an error when either configuration is invalid.
    /// Counted, calibrated on synthesis: sphere lanes, their square roots, the sorter (as
    /// svo_top builds it, [`sorter_as_built`]), transform, reciprocal and walker-root units,
    /// each walker as the RTL walker (its step logic and one context), and the hit-buffer
    /// check and pack; the logic svo_core builds around them, calibrated on the whole core's
    /// synthesis (`cost::core_logic`: svo_front's candidate gathering, the ray-slot table,
    /// the units' elastic pipes, the hit buffer's check pipe); then, by the first-order
    /// formulas of `cost::structures` (uncalibrated): the walkers' other contexts, every FIFO
    /// between stages, the MSHR CAM and the cache control.
    /// Not counted: ray generation (the host writes the direction table; `svo_raygen`
    /// is priced by [`HwConfig::unit_estimate`] only, for a design that fills it on chip),
    /// the walkers' path to the memory ports, the memory controller and host interface.
    pub fn fabric(&self, dp: &DatapathConfig) -> Result<Vec<FabricItem>, String> {
        self.validate()?;
        dp.validate().map_err(|m| format!("datapath: {m}"))?;
        let unit = |name: &'static str, n: u32, per: Option<Fabric>| {
            per.map(|per| FabricItem {
                name,
                instances: u64::from(n),
                per_instance: per,
                calibrated: true,
                formula: formula(name).to_string(),
            })
        };
        let at = |name: &'static str, n: u32| unit(name, n, unit_fabric(name, dp));
        let mut items: Vec<FabricItem> = [
            at("sphere", self.sphere_units),
            at("sqrt", self.sphere_units),
            unit("sorter", 1, Some(sorter_as_built(dp))),
            at("transform", self.transform_units),
            at("reciprocal", self.reciprocal_units),
            at("walker_root", self.walker_root_units),
            at("walker", self.walker_pool.walkers),
            at("hit_check", 1),
            at("normal", 1),
            at("hit_pack", 1),
        ]
        .into_iter()
        .flatten()
        .collect();
        items.extend(super::core_logic::core_logic_items(self, dp));
        items.extend(super::structures::structure_items(self, dp));
        Ok(items)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_equals_its_calibration_and_wider_formats_cost_more() {
        let dp = DatapathConfig::default();
        let f = unit_fabric("transform", &dp).unwrap();
        assert_eq!((f.lut, f.ff), calibration::TRANSFORM);
        let mut wide = dp.clone();
        wide.transform.pos.width += 8;
        let g = unit_fabric("transform", &wide).unwrap();
        assert!(g.lut > f.lut && g.ff > f.ff);
        assert!(unit_fabric("node_memory", &dp).is_none());
        let at = |n: u8| {
            let mut d = dp.clone();
            d.sorter.n = n;
            let f = unit_fabric("sorter", &d).unwrap();
            (f.lut, f.ff)
        };
        // Both synthesised widths are their synthesis, whatever the default's n.
        assert_eq!(at(8), calibration::SORTER);
        assert_eq!(at(16), calibration::SORTER_16);
        // Between and beyond, scaled from the nearer one: monotonic in the width.
        assert!(at(4) < at(8) && at(8) < at(12) && at(12) < at(16) && at(16) < at(32));
        // As svo_top builds it (MAX_KEYS = 2N): its own synthesis at both widths.
        let built = |n: u8| {
            let mut d = dp.clone();
            d.sorter.n = n;
            let f = sorter_as_built(&d);
            (f.lut, f.ff)
        };
        assert_eq!(built(8), calibration::SORTER_2N);
        assert_eq!(built(16), calibration::SORTER_16_2N);
        assert!(built(16) < at(16) && built(8) < at(8));
    }
}
