//! The two-level instance scheme (per-tile instance lists, docs/instances.md) against the flat
//! scheme on seeded random crowds of up to 2,000 instances: the same hit records, pixel for
//! pixel, every frame, in the f64 reference and the fixed-point model, and every instance whose
//! sphere a ray meets is in that ray's tile list (the conservativeness the equality rests on,
//! checked directly with the reference's own sphere test). The seed is printed;
//! `SVO_TEST_SEED` replays it, `SVO_PROPTEST_CASES` changes the number of cases.

mod common;

use common::SplitMix64;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::tile_list::TileListConfig;
use std::path::Path;
use std::sync::atomic::AtomicU64;
use svo_sim::models::fixed::cull::{install_lists, render_frame_fixed_two_level};
use svo_sim::models::fixed::{render_frame_fixed, FixedBuffer};
use svo_sim::models::reference::cull::{reference_keep_radius, BinSphere, TileLists};
use svo_sim::models::reference::ray::primary_ray;
use svo_sim::models::reference::sphere::sphere_entry;
use svo_sim::models::reference::{
    render_frame, render_frame_two_level, FrameInput, HitBuffer, RenderOptions,
};
use svo_sim::world::assets::{build_assets, effective_depths, Materialise};
use svo_sim::world::scene::Scene;

/// A random crowd scene: up to 2,000 instances of two SDF shapes, a camera outside or inside
/// the crowd (so spheres straddle the eye's plane and lie behind it), still or moving.
fn random_scene(rng: &mut SplitMix64, big: bool) -> String {
    let count = if big {
        1000 + rng.below(1001)
    } else {
        1 + rng.below(60)
    };
    let side = 4.0 + (count as f64).sqrt() * rng.range(0.8, 2.5);
    let inside = rng.chance(0.4);
    let (px, py, pz) = if inside {
        (
            rng.range(-2.0, 2.0),
            rng.range(0.2, 1.5),
            rng.range(-2.0, 2.0),
        )
    } else {
        (
            rng.range(-5.0, 5.0),
            rng.range(2.0, 15.0),
            side * rng.range(0.6, 1.5),
        )
    };
    let moving_cam = rng.chance(0.5);
    let cam2 = if moving_cam {
        format!(
            ", (frame: 2, position: ({}, {py}, {}), look_at: (0, 0, 0), vfov_deg: 50)",
            px + 0.7,
            pz - 0.5
        )
    } else {
        String::new()
    };
    let (w, h) = (40 + 8 * rng.below(5), 24 + 8 * rng.below(3));
    let speed = if rng.chance(0.3) {
        0.0
    } else {
        rng.range(0.05, 0.6)
    };
    format!(
        r#"(
    resolution: ({w}, {h}),
    frames: 3,
    camera: [(frame: 0, position: ({px}, {py}, {pz}), look_at: ({}, 0, 0), vfov_deg: 50){cam2}],
    assets: [
        (name: "ball", depth: 3, source: Sdf(shape: Sphere(radius: 0.4))),
        (name: "box", depth: 3, source: Sdf(shape: Box(half: (0.5, 0.25, 0.3)))),
    ],
    instances: [],
    crowds: [(count: {count}, seed: {}, area: ({side}, {side}), models: ["ball", "box"],
            speed: (0, {speed}), moving: {}, turn_deg: 10, scale: {})],
)"#,
        rng.range(-1.0, 1.0),
        rng.next_u64(),
        rng.range(0.0, 1.0),
        rng.range(0.3, 1.6),
    )
}

#[test]
fn two_level_equals_flat_on_random_crowds() {
    let seed = common::test_seed();
    println!("seed {seed:#x} (SVO_TEST_SEED reproduces it)");
    let mut rng = SplitMix64::derive(seed, "two_level");
    let cases = common::proptest_cases(8);
    let tl = TileListConfig {
        tile: 8,
        ..TileListConfig::default()
    };
    let dp = DatapathConfig {
        hit_record: rtl_model::units::hit_record::HitRecordConfig {
            instance_bits: 16,
            ..Default::default()
        },
        ..DatapathConfig::default()
    };
    let (mut tests_flat, mut tests_two) = (0u64, 0u64);
    for case in 0..cases {
        let big = case % 2 == 0;
        let ron = random_scene(&mut rng, big);
        let scene = Scene::from_ron(&ron, "random crowd", Path::new("."))
            .unwrap_or_else(|e| panic!("case {case}: {e}\n{ron}"));
        let depths = effective_depths(&scene, None).unwrap_or_else(|e| panic!("{e}"));
        let assets = build_assets(&scene, &depths, Materialise::Auto)
            .unwrap_or_else(|e| panic!("case {case}: {e}"));
        let halves: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
        let (w, h) = scene.file.resolution;
        let n = scene.file.instances.len();
        let mut rf = HitBuffer::new(w, h);
        let mut rt = HitBuffer::new(w, h);
        let mut ff = FixedBuffer::new(w, h);
        let mut ft = FixedBuffer::new(w, h);
        for f in 0..scene.file.frames {
            let state = scene
                .frame_state(f, &halves)
                .unwrap_or_else(|e| panic!("{e}"));
            let input = FrameInput {
                scene: &scene,
                assets: &assets,
                state: &state,
            };
            let opts = RenderOptions::default();
            let a = render_frame(&input, &mut rf, opts);
            let b = render_frame_two_level(&input, &mut rt, opts, tl.tile, &AtomicU64::new(0));
            let at = |p: usize| (p as u32 % w, p as u32 / w);
            for (p, (x, y)) in rf.records.iter().zip(&rt.records).enumerate() {
                assert_eq!(
                    x, y,
                    "seed {seed:#x} case {case} ({n} instances) frame {f} pixel {:?}: reference flat vs two-level",
                    at(p)
                );
            }
            assert_eq!(a.hit_buffer_reused, b.hit_buffer_reused);
            tests_flat += a.sphere_tests;
            tests_two += b.sphere_tests;
            // Conservative: every instance the reference's own test keeps is listed.
            let cam = state.camera;
            let spheres: Vec<BinSphere> = state
                .poses
                .iter()
                .map(|p| BinSphere {
                    centre: p.centre,
                    keep_radius: reference_keep_radius(
                        p.sphere_radius(),
                        (p.centre - cam.position).length(),
                    ),
                    behind_slack: 0.0,
                    everywhere: false,
                })
                .collect();
            let lists = TileLists::build(&cam, w, h, tl.tile, &spheres);
            for j in 0..h {
                for i in 0..w {
                    let ray = primary_ray(&cam, w, h, i, j);
                    let list = lists.list(j * w + i);
                    for (k, pose) in state.poses.iter().enumerate() {
                        if sphere_entry(ray.origin, ray.dir, pose.centre, pose.sphere_radius())
                            .is_some()
                        {
                            assert!(
                                list.binary_search(&(k as u16)).is_ok(),
                                "seed {seed:#x} case {case} frame {f}: instance {k} meets pixel ({i}, {j}) but is not listed"
                            );
                        }
                    }
                }
            }
            // The fixed-point model: flat and two-level words and records equal.
            let fa =
                render_frame_fixed(&input, &mut ff, &dp, true).unwrap_or_else(|e| panic!("{e}"));
            let (fb, used) = render_frame_fixed_two_level(&input, &mut ft, &dp, true, &tl, 8)
                .unwrap_or_else(|e| panic!("{e}"));
            for (p, (x, y)) in ff.records.iter().zip(&ft.records).enumerate() {
                assert_eq!(
                    x, y,
                    "seed {seed:#x} case {case} ({n} instances) frame {f} pixel {:?}: fixed flat vs two-level",
                    at(p)
                );
            }
            assert_eq!(fa.hit_buffer_reused, fb.hit_buffer_reused);
            assert_eq!(fa.walks, fb.walks);
            assert_eq!(used.flat_tiles, 0);
        }
        println!("case {case}: {n} instances, {w}×{h}, frames identical");
    }
    println!("sphere tests: flat {tests_flat}, two-level {tests_two}");
    assert!(tests_two < tests_flat);
}

/// A list memory too small for the frame: the tiles that do not fit test every instance,
/// are counted, and the records stay the flat scheme's.
#[test]
fn overflowing_list_memory_falls_back_to_flat_tiles() {
    let mut rng = SplitMix64::derive(common::test_seed(), "two_level overflow");
    let ron = random_scene(&mut rng, false);
    let scene = Scene::from_ron(&ron, "crowd", Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    let depths = effective_depths(&scene, None).unwrap_or_else(|e| panic!("{e}"));
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap_or_else(|e| panic!("{e}"));
    let halves: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let (w, h) = scene.file.resolution;
    let state = scene
        .frame_state(0, &halves)
        .unwrap_or_else(|e| panic!("{e}"));
    let input = FrameInput {
        scene: &scene,
        assets: &assets,
        state: &state,
    };
    let dp = DatapathConfig::default();
    let tl = TileListConfig {
        tile: 8,
        capacity_words: 3,
        ..TileListConfig::default()
    };
    let mut ff = FixedBuffer::new(w, h);
    let mut ft = FixedBuffer::new(w, h);
    render_frame_fixed(&input, &mut ff, &dp, false).unwrap_or_else(|e| panic!("{e}"));
    let mut ov = rtl_model::datapath::overflow_table();
    let mut plan =
        svo_sim::models::fixed::plan::FramePlan::new(&input, &mut ft, &dp, false, &mut ov)
            .unwrap_or_else(|e| panic!("{e}"));
    let used = install_lists(&mut plan, &input, &tl, 8);
    assert!(used.flat_tiles > 0, "{used:?}");
    assert!(used.words <= 3);
    let (_, used2) = render_frame_fixed_two_level(&input, &mut ft, &dp, false, &tl, 8)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(used, used2);
    assert_eq!(ff.records, ft.records);
}

/// The cycle model with the two-level scheme on a crowd of 300 (more ids than 8 bits hold):
/// elaboration keeps the lists and widens the ids; the cycle model checks its hit buffer
/// against the functional model word for word every frame (`CycleModel::run_frame`), the
/// records equal the flat functional model's, and the sphere lanes take fewer cycles.
#[test]
fn cycle_model_with_lists_matches_flat_and_elaboration_says_why() {
    use rtl_model::cycle::hw_config::HwConfig;
    use svo_sim::models::cycle::runner::CycleRun;
    use svo_sim::models::cycle::CycleOptions;
    use svo_sim::run::elaborate::elaborate;
    let ron = r#"(
    resolution: (48, 32),
    frames: 2,
    camera: [(frame: 0, position: (0, 12, 16), look_at: (0, 0, 0), vfov_deg: 50)],
    assets: [
        (name: "ball", depth: 3, source: Sdf(shape: Sphere(radius: 0.4))),
        (name: "box", depth: 3, source: Sdf(shape: Box(half: (0.5, 0.25, 0.3)))),
    ],
    crowds: [(count: 300, seed: 5, area: (16, 16), models: ["ball", "box"], speed: (0, 0.1), moving: 0.5)],
)"#;
    let scene = Scene::from_ron(ron, "crowd", Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    let dp = DatapathConfig::default();
    let hw = HwConfig::for_datapath(&dp);
    let e = elaborate(&scene, None, &hw, &dp, true).unwrap_or_else(|e| panic!("{e}"));
    let tl = e
        .two_level
        .expect("lists kept for 300 instances on 8 lanes");
    let units: Vec<(&str, String)> = e
        .decisions
        .iter()
        .map(|d| (d.unit.as_str(), d.action.label()))
        .collect();
    assert!(
        units.contains(&("instance_lists", "kept".into())),
        "{units:?}"
    );
    assert!(
        units.contains(&("instance_bits", "resized 8 → 9".into())),
        "{units:?}"
    );
    assert_eq!(e.datapath.hit_record.instance_bits, 9);
    // A 73-bit record takes two URAM columns: the direction table goes to DRAM, and the
    // printed totals (full − savings) equal the elaborated estimate.
    assert!(
        units.contains(&("direction_table", "left out".into())),
        "{units:?}"
    );
    assert_eq!(
        e.full.uram288 - e.total_saved().uram288,
        e.elaborated.uram288,
        "{:?} {:?}",
        e.full,
        e.elaborated
    );
    // The list memory is the scheme's price: the elaborated BRAM36 is the full pipeline's
    // less the savings, plus the lists' own count (units::tile_list::bram36_count, by hand:
    // two copies of 32,768 words of 8 × 16-bit ids and of the offset table).
    let f = &e.hardware.frame;
    let lists =
        rtl_model::units::tile_list::bram36_count(&tl, e.hardware.sphere_units, f.width, f.height);
    assert!(lists >= 2 * 116, "{lists} BRAM36 for the lists");
    // And the block-RAM candidate FIFO's growth with the wider instance ids
    // (check_to_transform carries 2 × sorter lanes of them, `cost::structures`): the
    // elaborated estimate's less the same hardware's with 8-bit ids, 1 BRAM36 here.
    let fifo_bram = |dp: &rtl_model::datapath::DatapathConfig| {
        e.hardware
            .resources(dp)
            .unwrap()
            .items
            .iter()
            .filter(|i| i.name == "fifo.check_to_transform")
            .map(|i| i.used.bram36)
            .sum::<u64>()
    };
    let mut eight = e.datapath.clone();
    eight.hit_record.instance_bits = 8;
    let fifo = fifo_bram(&e.datapath) - fifo_bram(&eight);
    assert_eq!(fifo, 1);
    assert_eq!(
        e.full.bram36 - e.total_saved().bram36 + lists + fifo,
        e.elaborated.bram36,
        "{:?} {:?}",
        e.full,
        e.elaborated
    );
    let depths = effective_depths(&scene, None).unwrap_or_else(|e| panic!("{e}"));
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap_or_else(|e| panic!("{e}"));
    let halves: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let (w, h) = scene.file.resolution;
    let mut runs: Vec<CycleRun> = [Some(tl), None]
        .into_iter()
        .map(|t| {
            let mut r = CycleRun::new(
                &e.hardware,
                &e.datapath,
                &assets,
                &scene.instance_asset,
                (w, h),
                CycleOptions::default(),
            )
            .unwrap_or_else(|e| panic!("{e}"));
            r.set_two_level(t);
            r
        })
        .collect();
    for f in 0..scene.file.frames {
        let state = scene
            .frame_state(f, &halves)
            .unwrap_or_else(|e| panic!("{e}"));
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &state,
        };
        let two = runs[0]
            .frame(&input, &e.datapath, e.use_hit_buffer)
            .unwrap_or_else(|e| panic!("{e}"));
        let flat = runs[1]
            .frame(&input, &e.datapath, e.use_hit_buffer)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            runs[0].buffer().records,
            runs[1].buffer().records,
            "frame {f}"
        );
        assert!(
            two.cycles.cycles * 2 < flat.cycles.cycles,
            "frame {f}: two-level {} cycles, flat {}",
            two.cycles.cycles,
            flat.cycles.cycles
        );
        assert!(
            two.fixed.sphere_tests * 3 < flat.fixed.sphere_tests,
            "frame {f}: two-level {} sphere tests, flat {}",
            two.fixed.sphere_tests,
            flat.fixed.sphere_tests
        );
    }
    // The default car (8 instances on 8 lanes) gets no line: it elaborates as before.
    let car = Scene::default_car().unwrap_or_else(|e| panic!("{e}"));
    let e = elaborate(&car, None, &hw, &dp, true).unwrap_or_else(|e| panic!("{e}"));
    assert!(e.two_level.is_none());
    assert!(e.decisions.iter().all(
        |d| !["instance_lists", "instance_bits", "direction_table"].contains(&d.unit.as_str())
    ));
}

/// The embedded crowd examples load with the right counts (they need the shared `.vox`
/// models: skipped with a reason when the folder is missing, a failure under `CI=true`).
#[test]
fn crowd_examples_load() {
    for (n, name) in [
        (100, "scenes/crowd_100.ron"),
        (1000, "scenes/crowd_1000.ron"),
        (10_000, "scenes/crowd_10000.ron"),
    ] {
        // The crowds' models are the shared .vox files.
        let Some(path) = common::skip::vox_scene_path(name) else {
            return;
        };
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(scene.file.instances.len(), n);
        // Every instance stays within the sphere unit's reach of the camera in every frame.
        let eye = glam::DVec3::from_array(scene.file.camera[0].position);
        for inst in &scene.file.instances {
            for k in &inst.keys {
                let p = glam::DVec3::from_array(k.translation);
                assert!((p - eye).length() < 125.0, "{name}: {} too far", inst.name);
            }
        }
    }
}

/// A bad crowd entry is an error naming the entry and the field.
#[test]
fn bad_crowds_are_named() {
    let base = |crowd: &str| {
        format!(
            r#"(resolution: (8, 8), frames: 2, camera: [(frame: 0, position: (0, 1, 9), look_at: (0, 0, 0), vfov_deg: 40)],
               assets: [(name: "b", depth: 3, source: Sdf(shape: Sphere(radius: 0.5)))], crowds: [{crowd}])"#
        )
    };
    for (crowd, expect) in [
        (
            r#"(count: 5, seed: 1, area: (4, 4), models: ["x"], speed: (0, 1))"#,
            "crowds[0]: crowd.models[0]: unknown asset \"x\"",
        ),
        (
            r#"(count: 0, seed: 1, area: (4, 4), models: ["b"], speed: (0, 1))"#,
            "crowds[0]: crowd.count",
        ),
        (
            r#"(count: 5, seed: 1, area: (4, -1), models: ["b"], speed: (0, 1))"#,
            "crowds[0]: crowd.area",
        ),
        (
            r#"(count: 5, seed: 1, area: (4, 4), models: ["b"], speed: (0, 1), moving: 2)"#,
            "crowds[0]: crowd.moving",
        ),
        (
            r#"(count: 5, seed: 1, area: (4, 4), models: ["b"], speed: (0, 1), colour: 3)"#,
            "colour",
        ),
    ] {
        let err = Scene::from_ron(&base(crowd), "t.ron", Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("{crowd} was accepted"))
            .to_string();
        assert!(err.contains(expect), "{crowd}: {err}");
    }
}
