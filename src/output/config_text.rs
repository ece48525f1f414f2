//! The text of `sim datapath` and `sim hardware`: a configuration as the RON a user edits and
//! passes back (`--datapath`, `--hw`), followed by what it costs and how accurate it is, as
//! `//` comments so that the whole output is still a valid configuration file.
//!
//! Pipeline position: beside the run; the figures come from the units' own cost and bound
//! functions (`rtl_model::units`), the bounds that span units (`rtl_model::cost::bounds`) and
//! the hardware's resource estimate (`rtl_model::cost::estimate`); nothing is recomputed here.

use rtl_model::cost::direction_error_bound;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::{hit_record, reciprocal, sphere, sqrt, transform, walker};
use std::fmt::Write;

fn pretty() -> ron::ser::PrettyConfig {
    ron::ser::PrettyConfig::new().struct_names(false)
}

/// `sim datapath`: the configuration, each unit's DSP48E2 count and every named error bound.
pub fn datapath_text(cfg: &DatapathConfig) -> Result<String, ron::Error> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "// Datapath configuration (docs/number-formats.md). Edit and pass with --datapath."
    );
    let _ = writeln!(s, "{}", ron::ser::to_string_pretty(cfg, pretty())?);
    let sph = &cfg.sphere;
    let sphere_dsp = sphere::dsp48e2_count(sph);
    let walker_dsp = walker::root_dsp48e2_count(&cfg.walker);
    let _ = writeln!(
        s,
        "// DSP48E2 slices per unit (27x18 products, sub-word decomposition):"
    );
    let _ = writeln!(
        s,
        "//   sphere test  {sphere_dsp:>4}  (l.d: 3, l.l: 3, t_ca^2: 1 products)"
    );
    let _ = writeln!(
        s,
        "//   transform    {:>4}  (9 origin + 9 direction products)",
        transform::dsp48e2_count(&cfg.transform)
    );
    let _ = writeln!(
        s,
        "//   reciprocal   {:>4}  per axis (Newton-Raphson), x3 per walk",
        reciprocal::dsp48e2_count(&cfg.reciprocal)
    );
    let _ = writeln!(
        s,
        "//   walker root  {walker_dsp:>4}  (6 slab products per walk; midpoints are adders)"
    );
    let _ = writeln!(
        s,
        "//   square root     0  (digit recurrence: subtractors only); sorter 0; hit record 0"
    );
    let reach = cfg.sphere.reach;
    let rb = reciprocal::error_bound(&cfg.reciprocal);
    let _ = writeln!(
        s,
        "// Error bounds (metres unless noted), derivations in docs/number-formats.md:"
    );
    let _ = writeln!(
        s,
        "//   transform origin, |o - c| <= {reach} m : {:.3e}",
        transform::origin_error_bound(&cfg.transform, reach)
    );
    let _ = writeln!(
        s,
        "//   transform origin, |o - c| <= 20 m    : {:.3e}",
        transform::origin_error_bound(&cfg.transform, 20.0)
    );
    let _ = writeln!(
        s,
        "//   transform direction (per component) : {:.3e}",
        transform::dir_error_bound(&cfg.transform)
    );
    let _ = writeln!(
        s,
        "//   sphere p^2 widening W (m^2)         : {:.3e}",
        sph.widening()
    );
    let _ = writeln!(
        s,
        "//   sphere entry (earlier by at most)   : {:.3e}",
        sph.t_enter_error_bound(1.0)
    );
    let _ = writeln!(
        s,
        "//   reciprocal: relative {:.3e}, absolute {:.3e}, zero below |d| = {:.3e}",
        rb.rel,
        rb.abs,
        reciprocal::zero_threshold(&cfg.reciprocal)
    );
    let sq = sqrt::SqrtConfig::default();
    let _ = writeln!(
        s,
        "//   square root (default unit config)   : {:.3e}",
        sqrt::error_bound(&sq)
    );
    let spatial = walker::spatial_error_bound(
        &cfg.walker,
        transform::origin_error_bound(&cfg.transform, 20.0),
        direction_error_bound(cfg),
        25.0,
        11,
    );
    let _ = writeln!(
        s,
        "//   walker spatial, 20 m away, depth 11  : {spatial:.3e}"
    );
    let _ = writeln!(
        s,
        "//   hit record t                        : {:.3e}",
        hit_record::t_error_bound(&cfg.hit_record)
    );
    Ok(s)
}

/// Why `sim hardware` cannot print a configuration.
#[derive(Debug, thiserror::Error)]
pub enum HardwareTextError {
    /// The configuration could not be written as RON.
    #[error("hardware configuration: {0}")]
    Ron(#[from] ron::Error),
    /// The hardware does not fit its datapath, or its estimate failed.
    #[error("hardware configuration: {0}")]
    Invalid(String),
}

/// `sim hardware`: the configuration and its resource estimate against the part, checked
/// against the datapath `dp`. The RON is returned even when the check fails, so a user sees
/// what was read before the reason it is refused.
pub fn hardware_text(
    hw: &HwConfig,
    dp: &DatapathConfig,
) -> (String, Result<String, HardwareTextError>) {
    let mut s = String::from(
        "// Hardware configuration of the cycle model (docs/cycle-model.md). Edit and pass with --hw.\n",
    );
    match ron::ser::to_string_pretty(hw, pretty()) {
        Ok(r) => {
            s.push_str(&r);
            s.push('\n');
        }
        Err(e) => return (s, Err(e.into())),
    }
    let estimate = hw
        .validate_for(dp)
        .and_then(|()| Ok((hw.resources(dp)?, hw.fabric(dp)?)))
        .map_err(HardwareTextError::Invalid)
        .map(|(r, f)| {
            let mut t: String = r.to_string().lines().map(|l| format!("// {l}\n")).collect();
            t.push_str(&fabric_text(&f, u64::from(hw.part.luts)));
            t
        });
    (s, estimate)
}

/// The LUT/FF estimate (`HwConfig::fabric`) as `//` lines: per component instances, LUTs and
/// flip-flops in all, and the formula; the total against the part's LUTs (and its flip-flops,
/// two per LUT on UltraScale+).
fn fabric_text(items: &[rtl_model::cost::FabricItem], part_luts: u64) -> String {
    let mut s = String::from(
        "// fabric (estimate, calibrated on Yosys synthesis of the RTL; docs/cycle-model.md §1.5):\n",
    );
    let _ = writeln!(
        s,
        "//   {:<30} {:>5} {:>9} {:>9}  formula",
        "component", "n", "LUT", "FF"
    );
    let totals = rtl_model::cost::FabricTotals::of(items, part_luts);
    let (lut, ff) = (totals.lut, totals.ff);
    for it in items {
        let t = it.total();
        let _ = writeln!(
            s,
            "//   {:<30} {:>5} {:>9} {:>9}  {}{}",
            it.name,
            it.instances,
            t.lut,
            t.ff,
            it.formula,
            if it.calibrated { "" } else { " (uncalibrated)" }
        );
    }
    let pct = |u: u64, a: u64| {
        if a == 0 {
            "none".to_string()
        } else {
            format!("{:.1}%", 100.0 * u as f64 / a as f64)
        }
    };
    let _ = writeln!(s, "//   {:<30} {:>5} {lut:>9} {ff:>9}", "used", "");
    let _ = writeln!(
        s,
        "//   {:<30} {:>5} {part_luts:>9} {:>9}",
        "available",
        "",
        part_luts.saturating_mul(2)
    );
    let _ = writeln!(
        s,
        "//   {:<30} {:>5} {:>9} {:>9}  {}",
        "utilisation",
        "",
        pct(lut, part_luts),
        pct(ff, part_luts.saturating_mul(2)),
        if totals.fits() {
            "fits"
        } else {
            "DOES NOT FIT the part"
        }
    );
    s
}
