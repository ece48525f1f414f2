//! The text of `sim hardware --synth`: per unit the model's estimate beside Yosys's counts
//! (LUT, FF, DSP48E2, BRAM36, URAM288), the slowest stages' logic levels and the clock
//! verdict; and the DSP48E2 check the CI test applies.
//!
//! Pipeline position: after the synthesis study (`studies::synthesis`), the estimate from
//! `HwConfig::unit_estimate`; nothing is recomputed here.

use super::{SynthProgress, UnitSynthesis};
use rtl_model::cost::fabric::UnitEstimate;
use rtl_model::cost::timing::ClockRule;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::fmt::Write;

/// The progress line of one event: `synth 3/10 sorter: started`, `synth 3/10 sorter: done in
/// 41.2 s` (or `from the cache in 0.0 s`, or `FAILED after 3.1 s`).
pub fn progress_line(p: SynthProgress<'_>) -> String {
    match p {
        SynthProgress::Started { unit, index, of } => format!("synth {index}/{of} {unit}: started"),
        SynthProgress::Finished {
            unit,
            index,
            of,
            seconds,
            cached,
            failed,
        } => {
            let what = if failed {
                "FAILED after"
            } else if cached {
                "from the cache in"
            } else {
                "done in"
            };
            format!("synth {index}/{of} {unit}: {what} {seconds:.1} s")
        }
    }
}

/// Stages listed per unit below the table.
const STAGES_SHOWN: usize = 3;

/// The estimate of a synthesised unit (zero for a unit the estimate does not know), at the
/// width it was synthesised: the sorter's network is its `N` parameter in units.tsv (the
/// RTL's default, 8, without one), whatever the datapath's `sorter.n`, so that the RTL that
/// Yosys saw is compared with the estimate of the same network.
pub fn estimate(hw: &HwConfig, dp: &DatapathConfig, u: &UnitSynthesis) -> UnitEstimate {
    let mut at = dp.clone();
    if u.spec.name == "sorter" {
        at.sorter.n = u
            .spec
            .params
            .iter()
            .find_map(|p| p.strip_prefix("N=").and_then(|v| v.parse().ok()))
            .unwrap_or(RTL_SORTER_LANES);
    }
    hw.unit_estimate(&u.spec.name, &at).unwrap_or_default()
}

/// `testbench/rtl/svo_sorter.v`'s default `N`: the width synthesised when units.tsv sets none.
const RTL_SORTER_LANES: u8 = 8;

/// Units whose Yosys DSP48E2 count differs from the estimate by other than the difference
/// recorded in units.tsv, one message each.
pub fn dsp_mismatches(hw: &HwConfig, dp: &DatapathConfig, units: &[UnitSynthesis]) -> Vec<String> {
    units
        .iter()
        .filter_map(|u| {
            let e = estimate(hw, dp, u).dsp48e2;
            let got = u.cells.dsp48e2;
            let diff = i128::from(got) - i128::from(e);
            (diff != i128::from(u.spec.dsp_vs_model)).then(|| {
                format!(
                    "{}: Yosys {got} DSP48E2, estimate {e} (difference {diff:+}, recorded {:+}{})",
                    u.spec.name,
                    u.spec.dsp_vs_model,
                    if u.spec.reason.is_empty() {
                        String::new()
                    } else {
                        format!(": {}", u.spec.reason)
                    }
                )
            })
        })
        .collect()
}

/// The comparison table, the slowest stages and the verdict at `mhz`.
pub fn synthesis_text(
    hw: &HwConfig,
    dp: &DatapathConfig,
    units: &[UnitSynthesis],
    rule: &ClockRule,
    mhz: u32,
) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "synthesis (Yosys synth_xilinx -family xcup) against the estimate, per instance (est/yosys):"
    );
    let _ = writeln!(
        s,
        "  {:<12} {:>13} {:>13} {:>9} {:>7} {:>7} {:>6} {:>8} {:>6}  {mhz} MHz",
        "unit", "LUT", "FF", "DSP48E2", "BRAM36", "URAM", "levels", "path ns", "fmax"
    );
    for u in units {
        let e = estimate(hw, dp, u);
        let c = &u.cells;
        let worst = u.stages.first();
        let (levels, ns, fmax, ok) = match worst {
            Some(w) => (
                rule.levels(&w.path).to_string(),
                format!("{:.2}", f64::from(w.ps) / 1000.0),
                (1_000_000 / w.ps.max(1)).to_string(),
                if rule.meets(&w.path, mhz) {
                    "plausible"
                } else {
                    "NOT plausible"
                },
            ),
            None => ("-".into(), "-".into(), "-".into(), "plausible (no logic)"),
        };
        let _ = writeln!(
            s,
            "  {:<12} {:>13} {:>13} {:>9} {:>7} {:>7} {:>6} {:>8} {:>6}  {ok}",
            u.spec.name,
            format!("{}/{}", e.fabric.lut, c.clb_luts()),
            format!("{}/{}", e.fabric.ff, c.ff),
            format!("{}/{}", e.dsp48e2, c.dsp48e2),
            format!("{}/{}", e.bram36, c.bram36()),
            format!("{}/{}", e.uram288, c.uram288),
            levels,
            ns,
            fmax,
        );
    }
    let _ = writeln!(
        s,
        "  LUT counts logic + SRL + LUT-RAM; levels = LUTs + CARRY8 segments + MUXFs on the slowest \
         register-to-register path; path ns by the clock rule: {} ps per LUT level with its net, \
         {} ps per CARRY8, {} ps per MUXF, {} ps clock-to-out + setup, {} ps margin (assumed; \
         docs/cycle-model.md §1.5)",
        rule.lut_net_ps,
        rule.carry_cell_ps * rule.carry_cells_per_level,
        rule.muxf_ps, rule.clk_to_out_setup_ps, rule.margin_ps
    );
    let _ = writeln!(
        s,
        "slowest stages (register: LUT + CARRY8 + MUXF levels, ns):"
    );
    for u in units {
        let list: Vec<String> = u
            .stages
            .iter()
            .take(STAGES_SHOWN)
            .map(|p| {
                format!(
                    "{} {}+{}+{} {:.2}",
                    p.stage,
                    p.path.luts,
                    rule.carry_levels(&p.path),
                    p.path.muxf,
                    f64::from(p.ps) / 1000.0
                )
            })
            .collect();
        let over = u
            .stages
            .iter()
            .filter(|p| !rule.meets(&p.path, mhz))
            .count();
        let _ = writeln!(
            s,
            "  {:<12} {}; {over} of {} stages over {mhz} MHz",
            u.spec.name,
            list.join(", "),
            u.stages.len()
        );
    }
    let _ = writeln!(
        s,
        "recorded DSP48E2 differences (testbench/synth/units.tsv):"
    );
    for u in units.iter().filter(|u| u.spec.dsp_vs_model != 0) {
        let _ = writeln!(
            s,
            "  {:<12} {:+}: {}",
            u.spec.name, u.spec.dsp_vs_model, u.spec.reason
        );
    }
    let bad = dsp_mismatches(hw, dp, units);
    if bad.is_empty() {
        let _ = writeln!(
            s,
            "DSP48E2 check: every unit agrees with the estimate or differs by its recorded reason"
        );
    } else {
        for b in &bad {
            let _ = writeln!(s, "DSP48E2 MISMATCH {b}");
        }
    }
    let ran: f64 = units.iter().map(|u| u.seconds).sum();
    let cached = units.iter().filter(|u| u.cached).count();
    let _ = writeln!(
        s,
        "// {} units, {cached} from the cache, {ran:.1} s of Yosys",
        units.len()
    );
    s
}

/// The slowest stages of one netlist by `rule` (`sim hardware --levels`): per stage its
/// registers' name, LUT / carry / MUXF levels, the path's delay and the clock it allows,
/// slowest first, `shown` of them.
pub fn levels_text(
    netlist: &str,
    top: &str,
    stages: &[super::netlist::StagePath],
    rule: &ClockRule,
    shown: usize,
) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "logic levels of `{top}` in {netlist} by the clock rule {} ({} ps per LUT level with \
         its net, {} ps per carry cell, {} ps per MUXF, {} ps clock-to-out + setup, {} ps \
         margin; rtl_model::cost::timing):",
        rule.name,
        rule.lut_net_ps,
        rule.carry_cell_ps,
        rule.muxf_ps,
        rule.clk_to_out_setup_ps,
        rule.margin_ps
    );
    let _ = writeln!(
        s,
        "  {:<32} {:>5} {:>6} {:>5} {:>7} {:>8} {:>9}",
        "stage (registers)", "LUT", "carry", "MUXF", "levels", "path ns", "fmax MHz"
    );
    for p in stages.iter().take(shown) {
        let _ = writeln!(
            s,
            "  {:<32} {:>5} {:>6} {:>5} {:>7} {:>8.2} {:>9.1}",
            p.stage,
            p.path.luts,
            p.path.carry,
            p.path.muxf,
            rule.levels(&p.path),
            f64::from(p.ps) / 1000.0,
            1.0e6 / f64::from(p.ps.max(1))
        );
    }
    match stages.first() {
        Some(w) => {
            let _ = writeln!(
                s,
                "fmax by the rule: {:.1} MHz ({} of {} stages shown)",
                1.0e6 / f64::from(w.ps.max(1)),
                stages.len().min(shown),
                stages.len()
            );
        }
        None => {
            let _ = writeln!(
                s,
                "no register-to-register path: no logic between registers"
            );
        }
    }
    s
}

/// The slowest path of each of the first `shown` stages (`sim hardware --levels --path`): the
/// named nets it passes, from the register it starts at, with the cells between two names
/// counted by kind (a run without names is what synthesis did not keep a name for).
pub fn paths_text(stages: &[super::netlist::StagePath], shown: usize) -> String {
    let mut s = String::new();
    for p in stages.iter().take(shown) {
        let _ = writeln!(s, "path into {}:", p.stage);
        // Runs of unnamed cells, as (kind, count) in order, between the named bits.
        let mut run: Vec<(&str, usize)> = Vec::new();
        let mut parts: Vec<String> = Vec::new();
        let flush = |run: &mut Vec<(&str, usize)>, parts: &mut Vec<String>| {
            if !run.is_empty() {
                let cells: Vec<String> = run
                    .iter()
                    .map(|(k, n)| {
                        if *n > 1 {
                            format!("{k} ×{n}")
                        } else {
                            k.to_string()
                        }
                    })
                    .collect();
                parts.push(format!("[{}]", cells.join(", ")));
                run.clear();
            }
        };
        for (i, c) in p.through.iter().enumerate() {
            if !c.kind.is_empty() {
                match run.last_mut() {
                    Some((k, n)) if *k == c.kind => *n += 1,
                    _ => run.push((c.kind.as_str(), 1)),
                }
            }
            // A name ends the run before it; the same name again (a wide net's bits) once.
            if let Some(name) = &c.net {
                let repeat = i > 0 && p.through[i - 1].net.as_ref() == Some(name);
                if !repeat {
                    flush(&mut run, &mut parts);
                    parts.push(name.clone());
                }
            } else if i == 0 {
                parts.push("(unnamed register)".to_string());
            }
        }
        flush(&mut run, &mut parts);
        parts.push(p.stage.clone());
        let _ = writeln!(s, "  {}", parts.join(" → "));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::super::netlist::{PathCell, StagePath};
    use super::*;
    use rtl_model::cost::timing::PathLevels;

    /// Named bits stand on their own (a wide net's bits once), unnamed cells between them are
    /// counted by kind in order, and the stage ends the line.
    #[test]
    fn a_path_prints_its_named_nets_and_the_cells_between() {
        let cell = |kind: &str, net: Option<&str>| PathCell {
            kind: kind.to_string(),
            net: net.map(str::to_string),
        };
        let p = StagePath {
            stage: "q".to_string(),
            path: PathLevels::default(),
            ps: 0,
            through: vec![
                cell("", Some("a")),
                cell("LUT6", None),
                cell("LUT6", None),
                cell("CARRY4", None),
                cell("LUT2", Some("b")),
                cell("LUT2", Some("b")),
                cell("LUT3", None),
            ],
        };
        assert_eq!(
            paths_text(&[p], 1),
            "path into q:\n  a → [LUT6 ×2, CARRY4, LUT2] → b → [LUT2, LUT3] → q\n"
        );
    }
}
