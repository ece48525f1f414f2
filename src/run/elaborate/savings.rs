//! What each elaboration decision saves: DSP48E2 (the walk-issue lanes' included), block RAM (BRAM36, URAM288 and the bits
//! they hold), sorter comparators and cycles of latency per ray.
//!
//! Pipeline position: after [`super::plan`], before the run. The counts come from the
//! hardware model's own estimate (`HwConfig::resources`, `rtl_model::cost::estimate`) of the
//! full and the elaborated configuration, and the RAM bits from the same module
//! (`HwConfig::stack_bits`, `HwConfig::hit_buffer_bits`), so a saving is exactly the
//! difference of two estimates `sim hardware` would print (a hit buffer left out or a
//! transform without products is a switch of the hardware configuration, `hit_buffer.present`
//! and `transform_products`, which the estimate prices itself).

use super::plan::{narrowed_positions, position_int_bits, Plan};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::resources::{ResourceReport, Resources};
use rtl_model::units::sorter;

pub use crate::models::cycle::elaboration::Saving;

/// The saving of an estimate `kept` against `full` (DSP48E2 and blocks; the bit, comparator
/// and latency fields are the caller's).
fn less(full: Resources, kept: Resources) -> Saving {
    let d = full.saturating_sub(kept);
    Saving {
        dsp48e2: d.dsp48e2,
        bram36: d.bram36,
        uram288: d.uram288,
        ..Saving::default()
    }
}

/// Fills in every decision's saving. `full` is the estimate of the configured pipeline,
/// `elaborated` that of the plan's (already adjusted); `range_m` the scene's coordinate range.
pub fn fill(
    plan: &mut Plan,
    range_m: f64,
    hw: &HwConfig,
    dp: &DatapathConfig,
    full: &ResourceReport,
    elaborated: &ResourceReport,
) {
    let (ehw, edp) = (plan.hardware.clone(), plan.datapath.clone());
    // The elaborated pipeline with the configured walk-issue units: the transform's products
    // are priced against it on the configured units, and the lanes against the elaborated
    // estimate, so the two decisions never count the same transform DSP twice.
    let mut lanes_kept = ehw.clone();
    lanes_kept.transform_units = hw.transform_units;
    lanes_kept.reciprocal_units = hw.reciprocal_units;
    lanes_kept.walker_root_units = hw.walker_root_units;
    let lanes_kept = lanes_kept
        .resources(&edp)
        .unwrap_or_else(|_| elaborated.clone());
    const WALK_ISSUE: [&str; 3] = ["transform", "reciprocal", "walker_root"];
    for d in &mut plan.decisions {
        let diff = |names: &[&str]| less(full.sum_of(names), elaborated.sum_of(names));
        d.saved = match d.unit.as_str() {
            // A lane's own DSP48E2 (svo_front's candidate gathering uses none).
            "sphere_lanes" => diff(&["sphere", "sqrt"]),
            "sorter" => Saving {
                comparators: (sorter::comparator_count(dp.sorter.n) as u64)
                    .saturating_sub(sorter::comparator_count(edp.sorter.n) as u64),
                latency_cycles: u64::from(
                    hw.units
                        .sorter
                        .latency_cycles
                        .saturating_sub(ehw.units.sorter.latency_cycles),
                ),
                ..Saving::default()
            },
            "transform_products" => Saving {
                latency_cycles: u64::from(
                    hw.units
                        .transform
                        .latency_cycles
                        .saturating_sub(ehw.units.transform.latency_cycles),
                ),
                ..less(
                    full.sum_of(&["transform"]),
                    lanes_kept.sum_of(&["transform"]),
                )
            },
            "walk_lanes" => less(
                lanes_kept.sum_of(&WALK_ISSUE),
                elaborated.sum_of(&WALK_ISSUE),
            ),
            "hit_buffer" if d.applied => Saving {
                ram_bits: hw.hit_buffer_bits(dp),
                latency_cycles: u64::from(
                    hw.hit_buffer_read_cycles()
                        .saturating_sub(ehw.hit_buffer_read_cycles()),
                ),
                ..diff(&["hit_buffer"])
            },
            "walker_stacks" => {
                let w = &hw.walker_pool;
                let frames = w.stack_depth.saturating_sub(ehw.walker_pool.stack_depth);
                Saving {
                    ram_bits: hw.stack_bits(dp, frames),
                    ..diff(&["walker_stacks"])
                }
            }
            "position_format" if !d.applied && d.action != super::plan::Action::Kept => {
                narrowing_saving(hw, dp, range_m)
            }
            // The instance scheme's decisions carry their own (`super::instances`).
            "instance_lists" | "instance_bits" | "direction_table" => d.saved,
            _ => Saving::default(),
        };
    }
}

/// DSP48E2 the narrowed position formats would save (zero if the narrowed datapath does not
/// validate).
fn narrowing_saving(hw: &HwConfig, dp: &DatapathConfig, range_m: f64) -> Saving {
    let int_bits = position_int_bits(range_m, dp.raygen.pos.frac);
    let ndp = narrowed_positions(dp, int_bits);
    match (hw.resources(dp), hw.resources(&ndp)) {
        (Ok(a), Ok(b)) => less(a.used, b.used),
        _ => Saving::default(),
    }
}
