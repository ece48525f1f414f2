//! Every hardware field is real (issue 28 item 4): for each field of the hardware schema
//! (`HwConfig`, every leaf, found by walking its serialised default), changing it from the
//! default either changes the cycle model's timing (cycles per frame or frame rate) or the
//! cost estimate (`sim hardware`'s resource and fabric tables) on a small scene, or is refused
//! by validation with a message naming the field. No field is accepted and ignored.
//!
//! The list below is the test's input: one line per field. A field of the schema that is not
//! in it fails the test by name, and so does a line for a field the schema no longer has, so a
//! new field cannot slip through (the branches that add fields add their line).

mod common;

use ron::Value;
use rtl_model::cycle::hw_config::{HwConfig, Placement, StackStorage};
use rtl_model::cycle::memory::DramBackend;
use rtl_model::cycle::ray_order::RayOrder;
use rtl_model::datapath::DatapathConfig;
use std::collections::BTreeSet;
use svo_sim::models::reference::RenderOptions;
use svo_sim::output::config_text::hardware_text;
use svo_sim::run::elaborate::elaborate;
use svo_sim::run::{run, Model, RunConfig};
use svo_sim::world::assets::Materialise;
use svo_sim::world::scene::Scene;

/// What a field's change must do.
#[derive(Clone, Copy)]
enum Expect {
    /// Change the timing or the cost estimate.
    Changes,
    /// Be refused by validation, the message containing this text.
    Refused(&'static str),
}
use Expect::{Changes, Refused};

type Mutate = fn(&mut HwConfig);

/// One line per leaf field of the schema: its path, a change from the default, and what the
/// change must do.
const FIELDS: &[(&str, Mutate, Expect)] = &[
    ("part.name", |h| h.part.name = "xczu9eg".into(), Changes),
    ("part.dsp48e2", |h| h.part.dsp48e2 = 100, Changes),
    ("part.bram36", |h| h.part.bram36 = 100, Changes),
    ("part.uram288", |h| h.part.uram288 = 100, Changes),
    ("part.luts", |h| h.part.luts = 100_000, Changes),
    ("clock_mhz", |h| h.clock_mhz = 250, Changes),
    ("frame.width", |h| h.frame.width = 640, Changes),
    ("frame.height", |h| h.frame.height = 384, Changes),
    (
        "units.raygen.latency_cycles",
        |h| h.units.raygen.latency_cycles += 40,
        Changes,
    ),
    ("units.raygen.ii", |h| h.units.raygen.ii = 2, Changes),
    (
        "units.sphere.latency_cycles",
        |h| h.units.sphere.latency_cycles += 40,
        Changes,
    ),
    ("units.sphere.ii", |h| h.units.sphere.ii = 2, Changes),
    (
        "units.sqrt.latency_cycles",
        |h| h.units.sqrt.latency_cycles += 40,
        Changes,
    ),
    ("units.sqrt.ii", |h| h.units.sqrt.ii = 2, Changes),
    (
        "units.sorter.latency_cycles",
        |h| h.units.sorter.latency_cycles += 40,
        Changes,
    ),
    ("units.sorter.ii", |h| h.units.sorter.ii = 2, Changes),
    (
        "units.transform.latency_cycles",
        |h| h.units.transform.latency_cycles += 40,
        Changes,
    ),
    ("units.transform.ii", |h| h.units.transform.ii = 2, Changes),
    (
        "units.reciprocal.latency_cycles",
        |h| h.units.reciprocal.latency_cycles += 40,
        Changes,
    ),
    (
        "units.reciprocal.ii",
        |h| h.units.reciprocal.ii = 2,
        Changes,
    ),
    (
        "units.walker_root.latency_cycles",
        |h| h.units.walker_root.latency_cycles += 40,
        Changes,
    ),
    (
        "units.walker_root.ii",
        |h| h.units.walker_root.ii = 2,
        Changes,
    ),
    (
        "units.hit_pack.latency_cycles",
        |h| h.units.hit_pack.latency_cycles += 40,
        Changes,
    ),
    ("units.hit_pack.ii", |h| h.units.hit_pack.ii = 2, Changes),
    (
        "units.hit_unpack.latency_cycles",
        |h| h.units.hit_unpack.latency_cycles += 40,
        Changes,
    ),
    (
        "units.hit_unpack.ii",
        |h| h.units.hit_unpack.ii = 2,
        Changes,
    ),
    ("sphere_units", |h| h.sphere_units = 2, Changes),
    (
        "sorter_lanes",
        |h| h.sorter_lanes = 4,
        Refused("sorter_lanes = 4 must equal"),
    ),
    // The default has two walk-issue lanes (issue 28): each kind's units back to one lane.
    ("transform_units", |h| h.transform_units = 1, Changes),
    (
        "transform_products",
        |h| h.transform_products = false,
        Changes,
    ),
    ("reciprocal_units", |h| h.reciprocal_units = 3, Changes),
    ("walker_root_units", |h| h.walker_root_units = 1, Changes),
    (
        "walker_pool.walkers",
        |h| h.walker_pool.walkers = 2,
        Changes,
    ),
    (
        "walker_pool.contexts_per_walker",
        |h| h.walker_pool.contexts_per_walker = 1,
        Changes,
    ),
    (
        "walker_pool.step_cycles",
        |h| h.walker_pool.step_cycles = 3,
        Changes,
    ),
    (
        "walker_pool.step_latency_cycles",
        |h| h.walker_pool.step_latency_cycles = 9,
        Changes,
    ),
    // Unlimited request ports (the model before issue 29): no read waits for the port.
    (
        "walker_pool.read_ports",
        |h| h.walker_pool.read_ports = 0,
        Changes,
    ),
    // The pool's registers (issue 29): a completion seen, a read sent, one cycle later.
    (
        "walker_pool.response_register_cycles",
        |h| h.walker_pool.response_register_cycles = 1,
        Changes,
    ),
    (
        "walker_pool.request_register_cycles",
        |h| h.walker_pool.request_register_cycles = 1,
        Changes,
    ),
    (
        "walker_pool.stack_depth",
        |h| h.walker_pool.stack_depth = 40,
        Changes,
    ),
    (
        "walker_pool.stack",
        |h| h.walker_pool.stack = StackStorage::ExactPop,
        Changes,
    ),
    (
        "fifos.raygen_to_sphere",
        |h| h.fifos.raygen_to_sphere = 1,
        Changes,
    ),
    (
        "fifos.sphere_to_sorter",
        |h| h.fifos.sphere_to_sorter = 1,
        Changes,
    ),
    (
        "fifos.sorter_to_check",
        |h| h.fifos.sorter_to_check = 1,
        Changes,
    ),
    (
        "fifos.check_to_transform",
        |h| h.fifos.check_to_transform = 1,
        Changes,
    ),
    (
        "fifos.transform_to_reciprocal",
        |h| h.fifos.transform_to_reciprocal = 1,
        Changes,
    ),
    (
        "fifos.reciprocal_to_root",
        |h| h.fifos.reciprocal_to_root = 1,
        Changes,
    ),
    (
        "fifos.root_to_dispatch",
        |h| h.fifos.root_to_dispatch = 1,
        Changes,
    ),
    (
        "fifos.walker_to_record",
        |h| h.fifos.walker_to_record = 1,
        Changes,
    ),
    (
        "fifos.record_to_write",
        |h| h.fifos.record_to_write = 1,
        Changes,
    ),
    (
        "node_memory.onchip.levels",
        |h| h.node_memory.onchip.levels = 0,
        Changes,
    ),
    (
        "node_memory.onchip.max_bytes",
        |h| h.node_memory.onchip.max_bytes *= 4,
        Changes,
    ),
    (
        "node_memory.onchip.latency",
        |h| h.node_memory.onchip.latency = 20,
        Changes,
    ),
    (
        "node_memory.onchip.banks",
        |h| h.node_memory.onchip.banks = 4,
        Changes,
    ),
    (
        "node_memory.onchip.ports_per_bank",
        |h| h.node_memory.onchip.ports_per_bank = 1,
        Changes,
    ),
    (
        "node_memory.onchip.combine",
        |h| h.node_memory.onchip.combine = false,
        Changes,
    ),
    (
        "node_memory.cache.size_bytes",
        |h| h.node_memory.cache.size_bytes *= 4,
        Changes,
    ),
    (
        "node_memory.cache.ways",
        |h| h.node_memory.cache.ways = 1,
        Changes,
    ),
    (
        "node_memory.cache.line_bytes",
        |h| h.node_memory.cache.line_bytes = 16,
        Changes,
    ),
    (
        "node_memory.cache.hit_latency",
        |h| h.node_memory.cache.hit_latency = 20,
        Changes,
    ),
    (
        "node_memory.cache.ports",
        |h| h.node_memory.cache.ports = 1,
        Changes,
    ),
    (
        "node_memory.cache.attr_cached",
        |h| h.node_memory.cache.attr_cached = false,
        Changes,
    ),
    (
        "node_memory.cache.banks",
        |h| h.node_memory.cache.banks = 1,
        Changes,
    ),
    (
        "node_memory.cache.miss_queue",
        |h| h.node_memory.cache.miss_queue = 0,
        Changes,
    ),
    (
        "node_memory.dram.latency",
        |h| h.node_memory.dram.latency = 300,
        Changes,
    ),
    (
        "node_memory.dram.bytes_per_cycle",
        |h| h.node_memory.dram.bytes_per_cycle = 1,
        Changes,
    ),
    (
        "node_memory.dram.mshrs",
        |h| h.node_memory.dram.mshrs = 1,
        Changes,
    ),
    (
        "node_memory.dram.backend",
        |h| {
            h.node_memory.dram.backend = DramBackend::DramSim3 {
                config: "DDR4_8Gb_x16_2400".into(),
                channels: 2,
                controller_latency: 30,
            }
        },
        Changes,
    ),
    (
        "hit_buffer.present",
        |h| h.hit_buffer.present = false,
        Changes,
    ),
    (
        "hit_buffer.placement",
        |h| h.hit_buffer.placement = Placement::Bram,
        Changes,
    ),
    (
        "hit_buffer.read_ports",
        |h| h.hit_buffer.read_ports = 2,
        Refused("hit_buffer.read_ports = 2"),
    ),
    (
        // One write path: alone it is refused with the default's two record writes (they
        // need the two banks, next row), so the record writes go to one as well.
        "hit_buffer.write_ports",
        |h| {
            h.hit_buffer.write_ports = 1;
            h.hit_buffer.record_writes = 1;
        },
        Changes,
    ),
    (
        "hit_buffer.record_writes",
        |h| h.hit_buffer.record_writes = 1,
        Changes,
    ),
    (
        "hit_buffer.read_latency_cycles",
        |h| h.hit_buffer.read_latency_cycles = 40,
        Changes,
    ),
    (
        "direction_table",
        |h| h.direction_table = Placement::External,
        Changes,
    ),
    ("ray_order", |h| h.ray_order = RayOrder::Morton, Changes),
];

/// Every leaf path of a RON value.
fn paths(v: &Value, prefix: &str, out: &mut BTreeSet<String>) {
    if let Value::Map(m) = v {
        for (k, v) in m.iter() {
            let Value::String(k) = k else { continue };
            let p = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            paths(v, &p, out);
        }
    } else {
        out.insert(prefix.to_string());
    }
}

fn schema_paths() -> BTreeSet<String> {
    let text = ron::ser::to_string(&HwConfig::default()).expect("serialise");
    let v: Value = ron::from_str(&text).expect("RON");
    let mut out = BTreeSet::new();
    paths(&v, "", &mut out);
    out
}

/// Fields of the schema the list leaves out, and lines of the list the schema does not have.
fn coverage(listed: &[&str]) -> (Vec<String>, Vec<String>) {
    let schema = schema_paths();
    let listed: BTreeSet<String> = listed.iter().map(|s| s.to_string()).collect();
    (
        schema.difference(&listed).cloned().collect(),
        listed.difference(&schema).cloned().collect(),
    )
}

#[test]
fn every_field_of_the_schema_is_in_the_list() {
    let names: Vec<&str> = FIELDS.iter().map(|f| f.0).collect();
    let (unknown, stale) = coverage(&names);
    assert!(
        unknown.is_empty(),
        "hardware fields this test does not know: {unknown:?}; add a line to FIELDS in \
         tests/hw_fields_real.rs showing what each changes (or that it is refused)"
    );
    assert!(
        stale.is_empty(),
        "FIELDS lists fields the schema does not have: {stale:?}"
    );
    // Shown failing once: a list without one field names it.
    let cut: Vec<&str> = names
        .iter()
        .copied()
        .filter(|&n| n != "clock_mhz")
        .collect();
    assert_eq!(coverage(&cut).0, vec!["clock_mhz".to_string()]);
}

/// The timing of a small run: cycles of each frame and the frame rate.
fn timing(hw: &HwConfig) -> Result<(Vec<u64>, String), String> {
    let mut scene = Scene::default_car().map_err(|e| e.to_string())?;
    scene.set_resolution(48, 32).map_err(|e| e.to_string())?;
    scene.set_frames(2).map_err(|e| e.to_string())?;
    let dp = DatapathConfig::default();
    let cfg = RunConfig {
        scene,
        depth: Some(6),
        materialise: Materialise::Auto,
        image_layout: Default::default(),
        options: RenderOptions::default(),
        out_dir: None,
        report_json: None,
        dump_hits: None,
        progress_every: None,
        model: Model::Cycle,
        datapath: dp.clone(),
        hardware: hw.clone(),
        cross_check: false,
        sample: None,
        vcd: None,
        transaction_log: None,
        elaboration: None,
    };
    // Every unit kept (no scene-driven elaboration), so that no field is pruned away.
    let e = elaborate(&cfg.scene, cfg.depth, &cfg.hardware, &dp, true)
        .map_err(|e| e.to_string())?
        .not_applied();
    let cfg = cfg.elaborated(e);
    let out = run(&cfg, |_, _| {}).map_err(|e| format!("{e:#}"))?;
    let cycles = out
        .report
        .frames
        .iter()
        .filter_map(|f| f.cycle.as_ref().map(|c| c.cycles))
        .collect();
    let fps = out
        .report
        .summary
        .cycle
        .as_ref()
        .map(|c| format!("{:.6}", c.fps_at_clock))
        .unwrap_or_default();
    Ok((cycles, fps))
}

/// The cost estimate's text (`sim hardware`'s resource and fabric tables).
fn cost(hw: &HwConfig) -> Result<String, String> {
    hardware_text(hw, &DatapathConfig::default())
        .1
        .map_err(|e| e.to_string())
}

/// Timing and cost of `hw`: what each change is compared with.
fn base_of(hw: &HwConfig) -> (Vec<u64>, String, String) {
    let (cycles, fps) = timing(hw).expect("baseline run");
    (cycles, fps, cost(hw).expect("baseline cost"))
}

/// What changing one field did: `Ok(what)` or the failure.
fn judge(
    name: &str,
    mutate: Mutate,
    expect: Expect,
    base: &(Vec<u64>, String, String),
) -> Result<String, String> {
    let mut hw = HwConfig::default();
    mutate(&mut hw);
    if hw == HwConfig::default() {
        return Err(format!("{name}: the change leaves the default as it was"));
    }
    let dp = DatapathConfig::default();
    match expect {
        Refused(msg) => match hw.validate_for(&dp) {
            Err(e) if e.contains(msg) => Ok(format!("refused: {e}")),
            Err(e) => Err(format!("{name}: refused with '{e}', expected '{msg}'")),
            Ok(()) => Err(format!("{name}: accepted, expected refusal '{msg}'")),
        },
        Changes => {
            hw.validate_for(&dp)
                .map_err(|e| format!("{name}: the changed value is refused: {e}"))?;
            let c = cost(&hw).map_err(|e| format!("{name}: {e}"))?;
            let (cycles, fps) = timing(&hw).map_err(|e| format!("{name}: {e}"))?;
            let mut what = Vec::new();
            if cycles != base.0 {
                what.push(format!("cycles {:?} → {cycles:?}", base.0));
            }
            if fps != base.1 {
                what.push(format!("fps {} → {fps}", base.1));
            }
            if c != base.2 {
                what.push("cost estimate".to_string());
            }
            if what.is_empty() {
                Err(format!(
                    "{name}: accepted and ignored: neither timing nor cost changed"
                ))
            } else {
                Ok(what.join(", "))
            }
        }
    }
}

#[test]
fn every_field_changes_timing_or_cost_or_is_refused() {
    let base = base_of(&HwConfig::default());
    let mut failures = Vec::new();
    for &(name, mutate, expect) in FIELDS {
        match judge(name, mutate, expect, &base) {
            Ok(what) => println!("{name}: {what}"),
            Err(e) => failures.push(e),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // Shown failing once: with the baseline taken on the changed hardware itself (as if the
    // model ignored the field), the change is caught as ignored.
    let slow = HwConfig {
        clock_mhz: 250,
        ..HwConfig::default()
    };
    let e = judge("clock_mhz", |h| h.clock_mhz = 250, Changes, &base_of(&slow));
    assert!(
        e.as_ref()
            .is_err_and(|e| e.contains("accepted and ignored")),
        "{e:?}"
    );
}
