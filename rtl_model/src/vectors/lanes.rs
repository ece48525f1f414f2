//! The walk-issue width of a vector set: how many units of the transform, the reciprocal and
//! the walker root a k-wide walk issue instantiates (docs/cycle-model.md §2.1, "Walk issue of width k"), and
//! which of them each row is for.
//!
//! Pipeline position: beside the vector tables, after they are built ([`super::unit_tables`]).
//! The rows do not change with k (each unit computes exactly what one unit does); the table
//! gains the unit count, as the package's `UNITS` and the manifest's `units`, and the rule that
//! row `i` belongs to unit `i mod UNITS`, rows `g·UNITS ..` entering together in one cycle. A
//! testbench instantiates `UNITS` units and checks each against its own rows
//! (`testbench/tb/tb_common.svh`), so every instance an RTL build of width k has is driven and
//! checked, all of them in the same cycles.

use super::table::VectorTable;

/// Largest walk-issue width a vector set is made for: a testbench instantiates 3 × this many
/// reciprocal units, and `sim --lift walk_issue` goes to 8 lanes.
pub const MAX_WALK_LANES: u32 = 64;

/// Units of the table named `name` in a pipeline of `lanes` walk-issue lanes: a transform per
/// lane, three reciprocals per lane (one per axis), a walker root per lane; `None` for a table
/// of another unit.
pub fn units_of(name: &str, lanes: u32) -> Option<u32> {
    match name {
        "transform" => Some(lanes),
        "reciprocal" => Some(3 * lanes),
        "walker_root" => Some(lanes),
        _ => None,
    }
}

/// Records in each walk-issue table of `tables` its unit count for `lanes` lanes: the
/// package constant `UNITS` and the manifest parameters `units` and `unit_of_row`.
pub fn set_walk_lanes(tables: &mut [VectorTable], lanes: u32) {
    for t in tables {
        let Some(units) = units_of(&t.name, lanes) else {
            continue;
        };
        t.constants.push((
            "UNITS".into(),
            i64::from(units),
            "units side by side (walk-issue lanes); row i is unit i mod UNITS".into(),
        ));
        t.param("units", units);
        t.param(
            "unit_of_row",
            "row i is driven into unit i mod units; rows g·units .. g·units + units − 1 enter in the same cycle",
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lane_is_one_transform_three_reciprocals_and_one_root() {
        assert_eq!(units_of("transform", 2), Some(2));
        assert_eq!(units_of("reciprocal", 2), Some(6));
        assert_eq!(units_of("walker_root", 2), Some(2));
        assert_eq!(units_of("sphere", 2), None);
    }
}
