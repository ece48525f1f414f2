//! Elaboration decisions: from the scene's facts, which units the pipeline keeps, leaves out
//! or resizes, and the hardware and datapath configuration that results.
//!
//! Pipeline position: between the scene facts ([`super::analyse`]) and the run. Every
//! decision here must leave every hit record bit for bit as the full pipeline computes it;
//! the reason each one does is in its doc comment and in `docs/elaboration.md`. Savings are
//! filled in afterwards by [`super::savings`].

use super::analyse::SceneFacts;
use super::savings::Saving;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::Format;
use rtl_model::units::{sorter, transform};

pub use crate::models::cycle::elaboration::{Action, Decision};

/// The elaborated configuration and the decisions that led to it (savings still zero).
#[derive(Clone, Debug)]
pub struct Plan {
    /// Hardware of the elaborated pipeline.
    pub hardware: HwConfig,
    /// Datapath of the elaborated pipeline.
    pub datapath: DatapathConfig,
    /// Whether the elaborated pipeline has a hit buffer to read.
    pub use_hit_buffer: bool,
    /// The decisions, in pipeline order.
    pub decisions: Vec<Decision>,
    /// The two-level instance scheme's list memory, when kept (`super::instances`).
    pub two_level: Option<rtl_model::units::tile_list::TileListConfig>,
}

/// A decision before its saving is priced; applied unless it keeps the unit as it is.
pub(super) fn decision(unit: &str, action: Action, reason: String) -> Decision {
    let applied = !matches!(action, Action::Kept | Action::CouldNarrow);
    Decision {
        unit: unit.into(),
        action,
        reason,
        applied,
        saved: Saving::default(),
    }
}

/// Names of up to three instances, and how many more.
fn some_names<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let all: Vec<&str> = names.collect();
    let mut s = all.iter().take(3).copied().collect::<Vec<_>>().join(", ");
    if all.len() > 3 {
        s.push_str(&format!(" and {} more", all.len() - 3));
    }
    s
}

/// Integer bits (sign included) a signed position format needs for |x| ≤ `range_m` with one
/// LSB of margin for rounding: the least i with range + LSB < 2^(i−1).
pub fn position_int_bits(range_m: f64, frac: i8) -> u8 {
    let lsb = (-f64::from(frac)).exp2();
    let mut i = 1u8;
    while i < 63 && range_m + lsb >= f64::from(i - 1).exp2() {
        i += 1;
    }
    i
}

/// The decisions for `facts` against the configured `hw`, `dp` and hit-buffer switch.
pub fn plan(facts: &SceneFacts, hw: &HwConfig, dp: &DatapathConfig, use_hit_buffer: bool) -> Plan {
    let mut out_hw = hw.clone();
    let mut out_dp = dp.clone();
    let mut ds = Vec::new();
    let n = facts.instances.len() as u64;

    // Sphere lanes: a ray tests every instance; lanes beyond the instance count never get an
    // instance, and with n ≤ lanes the tests take one pass either way (same timing).
    let lanes = u64::from(hw.sphere_units);
    ds.push(if n < lanes {
        out_hw.sphere_units = n as u32;
        decision(
            "sphere_lanes",
            Action::Resized { from: lanes, to: n },
            format!("{n} instance(s): one lane each tests them all in one pass"),
        )
    } else {
        decision(
            "sphere_lanes",
            Action::Kept,
            format!("{n} instances need every one of the {lanes} lanes"),
        )
    });

    // Sorter: with one instance a ray has at most one candidate, already in order. A one-lane
    // network has no comparator; its output register remains (a unit latency ≥ 1).
    ds.push(if n == 1 && dp.sorter.n > 1 {
        out_dp.sorter.n = 1;
        out_hw.sorter_lanes = 1;
        out_hw.units.sorter.latency_cycles = 1;
        out_hw.units.sorter.ii = 1;
        decision(
            "sorter",
            Action::LeftOut,
            "one instance: every ray has at most one candidate, nothing to order (a bypass register remains)".into(),
        )
    } else if n > 1 && n < u64::from(dp.sorter.n) {
        // A ray has at most n candidates: an n-lane network sorts every ray in one issue, as
        // the wider one did, with fewer comparators and layers. The configured latency keeps
        // any registers it had beyond the network's depth (timing closure).
        let (from, to) = (dp.sorter.n, n as u8); // n < dp.sorter.n ≤ 255
        let (d_from, d_to) = (sorter::depth(from) as u32, sorter::depth(to) as u32);
        out_dp.sorter.n = to;
        out_hw.sorter_lanes = u32::from(to);
        out_hw.units.sorter.latency_cycles = (hw.units.sorter.latency_cycles.saturating_sub(d_from)
            + d_to)
            .max(1);
        decision(
            "sorter",
            Action::Resized {
                from: u64::from(from),
                to: n,
            },
            format!(
                "{n} instances: a ray has at most {n} candidates, one issue of a {to}-lane network ({} comparators, depth {d_to}) instead of {from} lanes",
                sorter::comparator_count(to)
            ),
        )
    } else {
        decision(
            "sorter",
            Action::Kept,
            format!("{n} instances: rays can have several candidates to order"),
        )
    });

    // Transform products: R = I in every frame (as quantised) makes Rᵀ(o − c) = o − c and
    // Rᵀd = d exactly, so the unit is its subtractor and the output rounding.
    let rotating: Vec<&str> = facts.rotating().map(|i| i.name.as_str()).collect();
    ds.push(if rotating.is_empty() {
        out_hw.transform_products = false;
        out_hw.units.transform.latency_cycles = out_hw
            .units
            .transform
            .latency_cycles
            .min(transform::LATENCY_WITHOUT_PRODUCTS);
        decision(
            "transform_products",
            Action::LeftOut,
            "no instance rotates in any frame: every transform is o − c and d unchanged (exact), no multipliers".into(),
        )
    } else {
        decision(
            "transform_products",
            Action::Kept,
            format!(
                "{} rotate(s): Rᵀ(o − c) and Rᵀd need the 18 products",
                some_names(rotating.iter().copied())
            ),
        )
    });

    // Scale: not a unit of this pipeline (it lives in the octree box's half extents, which the
    // walker root reads per instance); reported so the question is answered.
    let scaled: Vec<&str> = facts
        .instances
        .iter()
        .filter(|i| i.scaled)
        .map(|i| i.name.as_str())
        .collect();
    ds.push(decision(
        "scale_path",
        Action::Kept,
        if scaled.is_empty() {
            "no instance is scaled, but scale is no separate unit here: it is the box half extent the walker root reads, nothing to leave out".into()
        } else {
            format!(
                "{} scaled; scale is the box half extent the walker root reads (no separate unit)",
                some_names(scaled.iter().copied())
            )
        },
    ));

    // Hit buffer: a pixel is reused only when the camera did not change since the previous
    // frame, so if it changes between every two frames no word is ever read for reuse.
    let hb_unused = facts.camera_moves_every_frame || !use_hit_buffer;
    ds.push(if hb_unused {
        // The check stage keeps its unpack register and reads nothing.
        out_hw.hit_buffer.present = false;
        decision(
            "hit_buffer",
            Action::LeftOut,
            if !use_hit_buffer {
                "--no-hit-buffer: no pixel is ever reused".into()
            } else if facts.frames == 1 {
                "one frame: no earlier frame to reuse a pixel from".into()
            } else {
                format!(
                    "the camera moves between every two of the {} frames: no pixel can be reused",
                    facts.frames
                )
            },
        )
    } else {
        decision(
            "hit_buffer",
            Action::Kept,
            "the camera is still between some frames: unchanged pixels are reused".into(),
        )
    });

    // Walker stacks: a walk of a depth-d octree pushes the root and one frame per level
    // below it, d + 1 frames at most (`units::walker`).
    let need = facts.deepest_asset.saturating_add(1);
    let have = hw.walker_pool.stack_depth;
    ds.push(if need < have {
        out_hw.walker_pool.stack_depth = need;
        decision(
            "walker_stacks",
            Action::Resized {
                from: u64::from(have),
                to: u64::from(need),
            },
            format!(
                "deepest asset has depth {}: a walk pushes at most {need} frames",
                facts.deepest_asset
            ),
        )
    } else {
        decision(
            "walker_stacks",
            Action::Kept,
            format!(
                "deepest asset has depth {}: walks may push {need} frames",
                facts.deepest_asset
            ),
        )
    });

    // Position format: reported, not applied (see docs/elaboration.md): the positions fit
    // fewer integer bits, but the same format holds local origins and ±e − o in the walker,
    // whose range the scene facts do not bound, so identical images are not guaranteed.
    let pos = dp.raygen.pos;
    let int_bits = position_int_bits(facts.coordinate_range_m, pos.frac);
    let have_int = i16::from(pos.width) - i16::from(pos.frac);
    ds.push(if i16::from(int_bits) < have_int {
        decision(
            "position_format",
            Action::CouldNarrow,
            format!(
                "positions within ±{:.2} m fit {} (now {}); not applied: the walker's local origins and ±e − o share the format and are not bounded by the scene facts",
                facts.coordinate_range_m,
                narrow_width(pos, int_bits).name(),
                pos.name()
            ),
        )
    } else {
        decision(
            "position_format",
            Action::Kept,
            format!(
                "positions reach ±{:.2} m: {} is needed",
                facts.coordinate_range_m,
                pos.name()
            ),
        )
    });

    // The two-level instance scheme (and the id width many instances need).
    let (more, two_level) = super::instances::decide(facts, &mut out_hw, &mut out_dp);
    ds.extend(more);
    Plan {
        hardware: out_hw,
        datapath: out_dp,
        use_hit_buffer: use_hit_buffer && !hb_unused,
        decisions: ds,
        two_level,
    }
}

/// `f` with `int_bits` integer bits (sign included) and its fraction bits unchanged.
fn narrow_width(f: Format, int_bits: u8) -> Format {
    let w = (i16::from(int_bits) + i16::from(f.frac)).clamp(1, i16::from(u8::MAX));
    Format {
        width: w as u8,
        ..f
    }
}

/// The datapath with every position format narrowed to `int_bits` integer bits (what the
/// `position_format` decision would apply), for its DSP estimate.
pub fn narrowed_positions(dp: &DatapathConfig, int_bits: u8) -> DatapathConfig {
    let narrow = |f: Format| narrow_width(f, int_bits);
    let mut d = dp.clone();
    d.raygen.pos = narrow(d.raygen.pos);
    d.sphere.pos = narrow(d.sphere.pos);
    d.transform.pos = narrow(d.transform.pos);
    d.transform.local_pos = narrow(d.transform.local_pos);
    d.walker.pos = narrow(d.walker.pos);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_bits_cover_the_range_with_a_margin() {
        assert_eq!(position_int_bits(0.0, 32), 1);
        assert_eq!(position_int_bits(0.9, 32), 1);
        assert_eq!(position_int_bits(1.0, 32), 2);
        assert_eq!(position_int_bits(6.5, 32), 4);
        assert_eq!(position_int_bits(127.0, 32), 8);
        assert_eq!(position_int_bits(128.0, 32), 9);
    }
}
