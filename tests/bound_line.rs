//! The bound line names the limit that binds (issue 28 item 5): on hand-built hardware where
//! one limit is made far worse than the rest, a small run of the default car must name it
//! (docs/cycle-model.md §2.2), and its stall counter must be the one that grew.

mod common;

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use svo_sim::models::cycle::lift::{lift, lift_datapath};
use svo_sim::models::reference::RenderOptions;
use svo_sim::run::elaborate::elaborate;
use svo_sim::run::{run, Model, RunConfig};
use svo_sim::world::assets::Materialise;
use svo_sim::world::scene::Scene;

/// Memory that is never the limit: every level on chip in many banks, many ports.
fn fast_memory(h: &mut HwConfig) {
    let nm = &mut h.node_memory;
    nm.onchip.levels = 21;
    nm.onchip.max_bytes = 1 << 26;
    nm.onchip.banks = 64;
    nm.onchip.latency = 1;
    nm.cache.ports = 64;
    nm.cache.hit_latency = 1;
    h.walker_pool.walkers = 64;
}

/// The bound of the last frame of a 64×40 run of the car (2 frames, depth 6) on `hw`, with
/// the JSON of its stall counters.
fn bound(hw: &HwConfig) -> (String, String) {
    bound_with(hw, &DatapathConfig::default())
}

/// [`bound`] with the datapath `dp` (the sorter's width is the datapath's too).
fn bound_with(hw: &HwConfig, dp: &DatapathConfig) -> (String, String) {
    let mut scene = Scene::default_car().expect("car");
    scene.set_resolution(64, 40).expect("resolution");
    scene.set_frames(2).expect("frames");
    let dp = dp.clone();
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
    let e = elaborate(&cfg.scene, cfg.depth, &cfg.hardware, &dp, true)
        .expect("elaborate")
        .not_applied();
    let out = run(&cfg.elaborated(e), |_, _| {}).expect("run");
    let c = out
        .report
        .frames
        .last()
        .and_then(|f| f.cycle.clone())
        .expect("a cycle frame");
    let stalls = serde_json::to_string(&c.stalls).expect("json");
    (c.bound.limit, format!("{} — {stalls}", c.bound.reason))
}

/// The default hardware with the walker pool of before issue 28 (32 walkers of 8 contexts),
/// to change field by field: the default's 768 ray slots never fill on the 64×40 image, so a
/// slow memory would show only as rays waiting, not as the full pool the memory causes split.
fn base() -> HwConfig {
    let mut h = HwConfig::default();
    h.walker_pool.walkers = 32;
    h.walker_pool.contexts_per_walker = 8;
    h
}

/// Hand-built cases: the limit, and the hardware where it binds.
fn cases() -> Vec<(&'static str, HwConfig)> {
    let mut v = Vec::new();
    let mut h = base();
    fast_memory(&mut h);
    h.units.transform.ii = 3;
    v.push(("walk_issue", h));
    let mut h = base();
    fast_memory(&mut h);
    h.transform_units = 4;
    h.reciprocal_units = 12;
    h.walker_root_units = 4;
    h.fifos.record_to_write = 1;
    v.push(("write_port", h));
    let mut h = base();
    fast_memory(&mut h);
    h.units.raygen.ii = 8;
    v.push(("ray_generation", h));
    let mut h = base();
    h.node_memory.onchip.max_bytes = 1 << 26;
    h.node_memory.onchip.levels = 21;
    h.node_memory.onchip.latency = 1;
    h.walker_pool.walkers = 1;
    h.walker_pool.contexts_per_walker = 1;
    v.push(("walkers", h));
    let mut h = base();
    h.node_memory.onchip.levels = 0;
    h.node_memory.cache.ports = 1;
    h.node_memory.cache.size_bytes = 1 << 24;
    h.node_memory.dram.mshrs = 4096;
    v.push(("memory_ports", h));
    let mut h = base();
    h.node_memory.onchip.levels = 0;
    h.node_memory.cache.size_bytes = 4096;
    h.node_memory.cache.ports = 8;
    h.node_memory.dram.mshrs = 1;
    v.push(("mshr_full", h));
    let mut h = base();
    h.node_memory.onchip.latency = 300;
    h.node_memory.cache.hit_latency = 300;
    h.node_memory.cache.size_bytes = 1 << 24;
    v.push(("hit_latency", h));
    let mut h = base();
    h.node_memory.onchip.levels = 0;
    h.node_memory.cache.size_bytes = 4096;
    h.node_memory.cache.ports = 8;
    h.node_memory.dram.mshrs = 4096;
    h.node_memory.dram.latency = 3000;
    v.push(("dram_latency", h));
    let mut h = base();
    h.node_memory.onchip.levels = 0;
    h.node_memory.cache.size_bytes = 4096;
    h.node_memory.cache.ports = 8;
    h.node_memory.dram.mshrs = 4096;
    h.node_memory.dram.bytes_per_cycle = 1;
    v.push(("dram_bandwidth", h));
    v
}

#[test]
fn each_limit_is_named_where_it_binds() {
    let mut wrong = Vec::new();
    for (want, hw) in cases() {
        let (got, why) = bound(&hw);
        println!("{want}: bound {got} ({why})");
        if got != want {
            wrong.push(format!("{want}: the bound line says {got} ({why})"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn lifting_the_named_limit_moves_the_bound_on() {
    // Shown on the walk-issue case: lifted, the walk issue no longer binds.
    let (want, hw) = cases().swap_remove(0);
    assert_eq!(bound(&hw).0, want);
    let lifted = lift(&hw, want).expect("lift");
    let (after, why) = bound(&lifted);
    assert_ne!(after, want, "lifted, {want} still binds ({why})");
}

/// A datapath and hardware whose sorter has `lanes` lanes (the hardware's width must equal the
/// datapath's), on fast memory.
fn sorter_of(lanes: u8) -> (HwConfig, DatapathConfig) {
    let mut dp = DatapathConfig::default();
    dp.sorter.n = lanes;
    let mut h = HwConfig::for_datapath(&dp);
    fast_memory(&mut h);
    (h, dp)
}

#[test]
fn the_sorter_is_named_where_its_merges_bind() {
    // One lane: every ray of two or more candidates is merged, and holds the sorter's input
    // for C + P·(count + 1) cycles (`units::sorter::pipe_cost`).
    let (hw, dp) = sorter_of(1);
    // A one-lane network has no layer: its output register is the unit's latency.
    assert_eq!(hw.units.sorter.latency_cycles, 1);
    let (got, why) = bound_with(&hw, &dp);
    println!("sorter: bound {got} ({why})");
    assert_eq!(got, "sorter", "{why}");
    // Lifted (a 255-lane network), the sorter no longer binds.
    let (after, why) = bound_with(
        &lift(&hw, "sorter").expect("lift"),
        &lift_datapath(&dp, "sorter"),
    );
    println!("sorter lifted: bound {after} ({why})");
    assert_ne!(after, "sorter", "lifted, the sorter still binds ({why})");
}

#[test]
fn the_sphere_lanes_are_named_where_their_passes_bind() {
    // One sphere lane for the car's 8 instances: 8 passes a ray, at most 0.125 rays a cycle.
    let mut hw = base();
    fast_memory(&mut hw);
    hw.sphere_units = 1;
    let (got, why) = bound(&hw);
    println!("sphere: bound {got} ({why})");
    assert_eq!(got, "sphere", "{why}");
    let (after, why) = bound(&lift(&hw, "sphere").expect("lift"));
    println!("sphere lifted: bound {after} ({why})");
    assert_ne!(
        after, "sphere",
        "lifted, the sphere lanes still bind ({why})"
    );
}

#[test]
fn the_record_write_path_is_named_where_it_binds() {
    // Four walk lanes pack up to four records a cycle into a one-entry write FIFO drained at
    // one a cycle. No hit buffer (no pixel reused: every ray with a candidate is a record) and
    // the check's words on their own path; the fast memory and 64 walkers leave the walkers
    // holding finished walks.
    let mut hw = base();
    fast_memory(&mut hw);
    hw.transform_units = 4;
    hw.reciprocal_units = 12;
    hw.walker_root_units = 4;
    hw.hit_buffer.present = false;
    hw.hit_buffer.write_ports = 2;
    hw.fifos.record_to_write = 1;
    let (got, why) = bound(&hw);
    println!("record_write: bound {got} ({why})");
    assert_eq!(got, "record_write", "{why}");
    let (after, why) = bound(&lift(&hw, "record_write").expect("lift"));
    println!("record_write lifted: bound {after} ({why})");
    assert_ne!(
        after, "record_write",
        "lifted, the record write path still binds ({why})"
    );
}

#[test]
fn at_the_clock_the_line_names_what_holds_the_rest() {
    // The default hardware runs the car's still frame at the clock (0.9 rays per cycle or
    // more); when 1 % or more of the clock's rate is lost the line names the cause with the
    // most stalled cycles, as counted (the rule itself, on hand-set counters:
    // `stats::tests::at_the_clock_the_reason_names_what_holds_the_rest`).
    let (got, why) = bound(&HwConfig::default());
    println!("default: bound {got} ({why})");
    assert_eq!(got, "clock", "{why}");
    let stalls: serde_json::Value =
        serde_json::from_str(why.rsplit(" — ").next().expect("stalls")).expect("stall json");
    let count = |k: &str| stalls[k].as_u64().expect(k);
    let causes = [
        ("walk_issue", "walk_issue"),
        ("write_port", "the hit-buffer write port"),
        ("sorter", "sorter"),
        ("sphere", "sphere"),
        ("walkers_full", "walkers"),
    ];
    let (n, top) = causes
        .iter()
        .map(|&(k, name)| (count(k), name))
        .max_by_key(|&(n, _)| n)
        .expect("causes");
    // Whatever the line names as holding the rest is the largest stalled cause.
    if why.contains("the rest is held by") {
        assert!(n > 0, "{why}");
        assert!(
            why.contains(&format!("the rest is held by {top}")),
            "expected {top} named: {why}"
        );
    }
}
