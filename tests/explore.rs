//! `sim explore` (docs/explore.md): the same bytes on one thread and two, fields set by path
//! for any field of the schema, and every refusal of a space naming the field and its place in
//! the file — each shown on a corrupted space.

use rtl_model::cycle::hw_config::{HwConfig, Placement};
use rtl_model::datapath::DatapathConfig;
use std::path::Path;
use svo_sim::studies::explore::output::encode;
use svo_sim::studies::explore::run::{run_explore, usage};
use svo_sim::studies::explore::space::Space;
use svo_sim::studies::explore::SpaceError;

/// A small space on the embedded car: 2 × 2 points, one of them the default.
const SMALL: &str = r#"(
    scenes: [(path: "car", width: 48, height: 32, frames: 2, depth: 8)],
    fields: {
        "walker_pool.walkers": [8, 32],
        "node_memory.dram.mshrs": [8, 256],
    },
)"#;

fn space(text: &str) -> Result<(Space, Vec<svo_sim::studies::explore::Point>), SpaceError> {
    Space::from_text(text, Path::new("space.ron"), &DatapathConfig::default())
}

fn refusal(text: &str) -> String {
    match space(text) {
        Ok(_) => panic!("the space was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_files_are_the_same_bytes_on_one_thread_and_two() {
    let (sp, points) = space(SMALL).unwrap();
    assert_eq!(points.len(), 4);
    assert_eq!(points.iter().filter(|p| p.default).count(), 1);
    let dp = DatapathConfig::default();
    let files = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut seen = Vec::new();
        let r = pool
            .install(|| {
                run_explore(&sp, &points, &dp, u64::MAX, |row, _, _| {
                    seen.push(row.point)
                })
            })
            .unwrap();
        assert_eq!(seen, [1, 2, 3, 4], "progress in the points' order");
        encode(&r).unwrap()
    };
    let (one, two) = (files(1), files(2));
    assert_eq!(one.len(), 7);
    for ((name, a), (_, b)) in one.iter().zip(&two) {
        assert!(a == b, "{name} differs between 1 and 2 threads");
    }
    let csv = String::from_utf8(one[0].1.clone()).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with("point,scene,walker_pool.walkers,node_memory.dram.mshrs,default,"));
    // The default (32 walkers, 256 MSHRs) is point 4; exactly one best fitting row.
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert!(rows[3].starts_with("4,car,32,256,true,"), "{}", rows[3]);
    assert_eq!(rows.iter().filter(|r| r.ends_with(",true")).count(), 1);
}

#[test]
fn any_field_of_the_schema_is_set_by_its_path_and_the_default_is_added() {
    let text = r#"(
        scenes: [(path: "car", width: 48, height: 32, frames: 1)],
        fields: {
            "fifos.check_to_transform": (from: 64, to: 192, step: 64),
            "hit_buffer.placement": ["Bram", "External"],
            "units.sqrt.latency_cycles": [40],
        },
    )"#;
    let (_, points) = space(text).unwrap();
    // 3 × 2 × 1 points and the default, which none of them is, first as point 0.
    assert_eq!(points.len(), 7);
    assert_eq!((points[0].id, points[0].default), (0, true));
    assert_eq!(points[0].values, ["1024", "Uram", "32"]);
    assert_eq!(points[0].hw, HwConfig::default());
    let last = &points[6].hw;
    assert_eq!(last.fifos.check_to_transform, 192);
    assert_eq!(last.hit_buffer.placement, Placement::External);
    assert_eq!(last.units.sqrt.latency_cycles, 40);
    assert_eq!(points[6].values, ["192", "External", "40"]);
}

#[test]
fn a_bad_space_is_refused_naming_the_field_and_its_position() {
    // A field that does not exist: the segment, where, and what exists there.
    let m = refusal(&SMALL.replace("walker_pool.walkers", "walker_pool.walkrs"));
    assert!(m.starts_with("space.ron:4:9: field \"walker_pool.walkrs\": no field \"walkrs\" in walker_pool (its fields: "), "{m}");
    // A value of the wrong type, read by the schema.
    let m = refusal(&SMALL.replace("[8, 32]", "[8, \"many\"]"));
    assert!(m.starts_with("space.ron:4:9: field \"walker_pool.walkers\": value many: invalid type: string \"many\", expected u32"), "{m}");
    // A value the model's rules refuse, on the point that has it.
    let m = refusal(&SMALL.replace("[8, 32],\n        \"node", "[0, 32],\n        \"node"));
    assert!(m.starts_with("space.ron:4:9: field \"walker_pool.walkers\": point 1 (walker_pool.walkers = 0, node_memory.dram.mshrs = 8): walker_pool.walkers must be at least 1 (got 0)"), "{m}");
    // The second field, by its own line.
    let m = refusal(&SMALL.replace("[8, 256],\n    }", "[8, 99999],\n    }"));
    assert!(
        m.starts_with("space.ron:5:9: field \"node_memory.dram.mshrs\": point 2 "),
        "{m}"
    );
    assert!(
        m.contains("node_memory.dram.mshrs = 99999 is out of range (1 to 4096)"),
        "{m}"
    );
    // A path into a value.
    let m = refusal(&SMALL.replace("walker_pool.walkers", "walker_pool.walkers.x"));
    assert!(
        m.starts_with(
            "space.ron:4:9: field \"walker_pool.walkers.x\": walker_pool.walkers has no fields"
        ),
        "{m}"
    );
    // A bare enum name (write it as a string).
    let m = refusal(&SMALL.replace(
        "\"node_memory.dram.mshrs\": [8, 256]",
        "\"hit_buffer.placement\": [Bram]",
    ));
    assert!(
        m.starts_with("space.ron:5:9: field \"hit_buffer.placement\": a value is a bare name"),
        "{m}"
    );
    // A bad range.
    let m = refusal(&SMALL.replace(
        "[8, 32],\n        \"node",
        "(from: 8, to: 4, step: 1),\n        \"node",
    ));
    assert!(
        m.starts_with("space.ron:4:9: field \"walker_pool.walkers\": range to 4 is below from 8"),
        "{m}"
    );
    // A field named twice.
    let m = refusal(&SMALL.replace("node_memory.dram.mshrs", "walker_pool.walkers"));
    assert!(
        m.contains("field \"walker_pool.walkers\": named twice"),
        "{m}"
    );
    // Malformed RON, with the parser's position.
    let m = refusal(&SMALL.replace("fields:", "fields"));
    assert!(m.starts_with("space.ron:3:12: malformed space:"), "{m}");
}

#[test]
fn a_linked_field_sets_its_paths_together_and_refuses_a_wrong_tuple() {
    let text = r#"(
        scenes: [(path: "car", width: 48, height: 32, frames: 1)],
        fields: {
            "transform_units+reciprocal_units+walker_root_units": [(1, 3, 1), (2, 6, 2)],
            "walker_pool.walkers": [16, 32],
        },
    )"#;
    let (_, points) = space(text).unwrap();
    // 2 × 2 points; the default (2 transform units, two lanes of 3 reciprocal units, 2 roots,
    // 32 walkers) is the last.
    assert_eq!(points.len(), 4);
    assert_eq!(points[3].values, ["[2,6,2]", "32"]);
    assert!(points[3].default);
    assert_eq!(points[0].values, ["[1,3,1]", "16"]);
    assert_eq!(points[0].hw.walk_lanes(), 1);
    let p = &points[2];
    assert_eq!(p.values, ["[2,6,2]", "16"]);
    assert_eq!(
        (
            p.hw.transform_units,
            p.hw.reciprocal_units,
            p.hw.walker_root_units
        ),
        (2, 6, 2)
    );
    assert_eq!(p.hw.walk_lanes(), 2);
    // A tuple of the wrong length, and a bare value, name the field and what it needs.
    for bad in ["(2, 6)", "2"] {
        let m = refusal(&text.replace("(2, 6, 2)", bad));
        assert!(
            m.starts_with("space.ron:4:13: field \"transform_units+reciprocal_units+walker_root_units\": a value of a field linking 3 paths is a tuple of 3 values"),
            "{m}"
        );
    }
    // One path of the link that does not exist.
    let m = refusal(&text.replace("+walker_root_units", "+walker_roots"));
    assert!(m.contains("no field \"walker_roots\""), "{m}");
    // The model's rule on one path of the link blames the linked field.
    let m = refusal(&text.replace("(2, 6, 2)", "(2, 4, 2)"));
    assert!(
        m.starts_with("space.ron:4:13: field \"transform_units+reciprocal_units+walker_root_units\": point 3 "),
        "{m}"
    );
}

#[test]
fn the_cross_product_is_capped_with_a_clear_error() {
    let m = refusal(&SMALL.replace("scenes:", "max_points: 3,\n    scenes:"));
    assert_eq!(
        m,
        "space.ron: the space has 2 × 2 = 4 points, more than max_points = 3: narrow a field or raise max_points (at most 100000)"
    );
    assert!(space(&SMALL.replace("scenes:", "max_points: 4,\n    scenes:")).is_ok());
    let m = refusal(&SMALL.replace("scenes:", "max_points: 0,\n    scenes:"));
    assert!(m.contains("max_points = 0 is out of range"), "{m}");
}

#[test]
fn the_budget_is_70_percent_of_luts_and_90_percent_of_blocks() {
    let dp = DatapathConfig::default();
    // The default's 32 walkers of 8 contexts (issue 29) fit the budget, 67.2 % of the LUTs.
    let fitting = HwConfig::default();
    let u = usage(&fitting, &dp).unwrap();
    assert!(u.fits, "{}", u.why);
    // Issue 28's 48 walkers of 16 contexts, priced on the barrel walker's synthesis (issue
    // 29, docs/cycle-model.md §1.5), take more LUTs than the part has: over the budget.
    let mut hw = HwConfig::default();
    hw.walker_pool.walkers = 48;
    hw.walker_pool.contexts_per_walker = 16;
    let u = usage(&hw, &dp).unwrap();
    assert!(!u.fits);
    assert!(
        u.why.starts_with("LUT ") && u.why.contains("> 70 % of 1182240"),
        "{}",
        u.why
    );
    // The hit buffer in BRAM (1,920 BRAM36) takes the design over 90 % of 2,160.
    let mut hw = fitting.clone();
    hw.hit_buffer.placement = Placement::Bram;
    let u = usage(&hw, &dp).unwrap();
    assert!(!u.fits);
    assert_eq!(u.why, format!("BRAM36 {} > 90 % of 2160", u.used[3]));
    // 256 walkers pass 70 % of the LUTs.
    let mut hw = HwConfig::default();
    hw.walker_pool.walkers = 256;
    let u = usage(&hw, &dp).unwrap();
    assert!(u.why.starts_with("LUT "), "{}", u.why);
    assert!(u.why.contains("> 70 % of 1182240"), "{}", u.why);
}
