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

    // Walk-issue lanes: a ray walks each of its candidates at most once and has at most one
    // candidate per instance, so it needs at most n walks; rays leave the check stage at most
    // one per cycle, so on average at most n walks per cycle reach the transform (the loop
    // back carries a ray's later walks, n in all). A unit kind needs no more units than n
    // walks per cycle keep busy: n × its II (three reciprocal units per walk). With one
    // instance that is one walk-issue chain. Timing only (images cannot change); the glue
    // that `walk_lanes()` sizes (the walk FIFOs' ports, dispatcher, retire port, record
    // packing) narrows with the units, so bursts of finished walks leave one a cycle: a
    // measured cost on the frames that walk (docs/elaboration.md §4).
    ds.push(walk_lanes(n, hw, &mut out_hw));

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

/// Units of one walk-issue kind that `walks` walks per cycle can keep busy when each unit
/// takes a walk every `ii` cycles, at most the `configured` count.
fn units_for(configured: u32, walks: u64, ii: u32) -> u32 {
    let need = walks.saturating_mul(u64::from(ii.max(1)));
    u32::try_from(need).map_or(configured, |n| configured.min(n.max(1)))
}

/// The walk-issue lanes decision for a scene of `n` instances (at most `n` walks per ray):
/// shrinks `transform_units`, `reciprocal_units` (in lanes of three; fewer than three units
/// already take one walk in several passes and stay) and `walker_root_units` of `out` to what
/// `n` walks per cycle keep busy.
fn walk_lanes(n: u64, hw: &HwConfig, out: &mut HwConfig) -> Decision {
    let walks = n.max(1);
    let u = &hw.units;
    out.transform_units = units_for(hw.transform_units, walks, u.transform.ii);
    if hw.reciprocal_units >= 3 {
        out.reciprocal_units = 3 * units_for(hw.reciprocal_units / 3, walks, u.reciprocal.ii);
    }
    out.walker_root_units = units_for(hw.walker_root_units, walks, u.walker_root.ii);
    let (from, to) = (hw.walk_lanes(), out.walk_lanes());
    let units = |h: &HwConfig| (h.transform_units, h.reciprocal_units, h.walker_root_units);
    if units(hw) == units(out) {
        return decision(
            "walk_lanes",
            Action::Kept,
            format!(
                "{n} instance(s): a ray may need up to {n} walks, which the {from} walk-issue lane(s) (transform {}, reciprocal {}, root {}) can use",
                hw.transform_units, hw.reciprocal_units, hw.walker_root_units
            ),
        );
    }
    decision(
        "walk_lanes",
        Action::Resized {
            from: u64::from(from),
            to: u64::from(to),
        },
        format!(
            "{n} instance(s): a ray needs at most {walks} walk(s) and rays come one per cycle, so at most {walks} walk(s) per cycle on average: transform {} → {}, reciprocal {} → {}, root {} → {} (the walk glue narrows with them: bursts of finished walks retire one a cycle, a cycle cost on frames that walk, docs/elaboration.md §4)",
            hw.transform_units,
            out.transform_units,
            hw.reciprocal_units,
            out.reciprocal_units,
            hw.walker_root_units,
            out.walker_root_units
        ),
    )
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
    fn units_follow_the_walks_a_cycle_and_never_grow() {
        assert_eq!(units_for(2, 1, 1), 1);
        assert_eq!(
            units_for(2, 1, 2),
            2,
            "a unit of II 2 takes a walk every other cycle"
        );
        assert_eq!(units_for(1, 8, 1), 1, "never more than configured");
        assert_eq!(units_for(8, 3, 1), 3);
        assert_eq!(units_for(4, 0, 1), 1, "at least one unit");
    }

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
