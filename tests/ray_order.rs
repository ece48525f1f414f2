//! Ray order (`HwConfig::ray_order`, `rtl_model::cycle::ray_order`) end to end: scanline,
//! tiles and Morton give the same hit buffer as the functional model (the cycle model's
//! cross-check compares every pixel's word each frame and stops at the first difference), the
//! same work, and different cycles; sampled timing refuses any order but scanline, naming the
//! field.

use rtl_model::cycle::hw_config::{HwConfig, RayOrder};
use rtl_model::datapath::DatapathConfig;
use svo_sim::models::cycle::runner::CycleRun;
use svo_sim::models::cycle::sample::SampleConfig;
use svo_sim::models::cycle::validate::compare;
use svo_sim::models::cycle::CycleOptions;
use svo_sim::models::reference::FrameInput;
use svo_sim::world::assets::{build_assets, effective_depths, Asset, Materialise};
use svo_sim::world::scene::Scene;

fn car(w: u32, h: u32, frames: u32) -> (Scene, Vec<Asset>) {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(w, h).unwrap();
    scene.set_frames(frames).unwrap();
    let depths = effective_depths(&scene, Some(8)).unwrap();
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap();
    (scene, assets)
}

/// Per frame: (cycles, walks, reused pixels, node reads), cross-checked.
fn run(order: RayOrder) -> Vec<(u64, u64, u64, u64)> {
    let (scene, assets) = car(160, 96, 2);
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let dp = DatapathConfig::default();
    let hw = HwConfig {
        ray_order: order,
        ..HwConfig::default()
    };
    let mut run = CycleRun::new(
        &hw,
        &dp,
        &assets,
        &scene.instance_asset,
        scene.file.resolution,
        CycleOptions {
            cross_check: true,
            ..CycleOptions::default()
        },
    )
    .unwrap();
    (0..scene.file.frames)
        .map(|f| {
            let state = scene.frame_state(f, &half).unwrap();
            let input = FrameInput {
                scene: &scene,
                assets: &assets,
                state: &state,
            };
            let r = run
                .frame(&input, &dp, true)
                .unwrap_or_else(|e| panic!("{order:?} frame {f}: {e}"));
            let c = r.cycles;
            println!("{order:?} frame {f}: {} cycles", c.cycles);
            (c.cycles, c.walkers.walks, c.reused, c.memory.node_fetches)
        })
        .collect()
}

#[test]
fn every_order_gives_the_same_hits_and_work_in_different_cycles() {
    let scan = run(RayOrder::Scanline);
    let work = |v: &[(u64, u64, u64, u64)]| -> Vec<(u64, u64, u64)> {
        v.iter().map(|&(_, w, r, n)| (w, r, n)).collect()
    };
    for order in [RayOrder::Tiles(8), RayOrder::Morton] {
        let other = run(order);
        assert_eq!(work(&other), work(&scan), "{order:?}: the work differs");
        assert_ne!(
            other.iter().map(|x| x.0).collect::<Vec<_>>(),
            scan.iter().map(|x| x.0).collect::<Vec<_>>(),
            "{order:?}: the order changed no cycle"
        );
    }
    // Tiles(1) is the scanline order, cycle for cycle.
    assert_eq!(run(RayOrder::Tiles(1)), scan);
}

#[test]
fn sampled_timing_refuses_an_order_other_than_scanline() {
    let (scene, assets) = car(160, 96, 1);
    let hw = HwConfig {
        ray_order: RayOrder::Tiles(8),
        ..HwConfig::default()
    };
    let cfg = SampleConfig {
        period: 4,
        band_rows: 2,
        warm_rows: Some(2),
        seed: 1,
    };
    let e = compare(&scene, &assets, &DatapathConfig::default(), &hw, true, cfg)
        .map(|_| ())
        .map_err(|e| format!("{e:#}"))
        .expect_err("sampled timing accepted Tiles(8)");
    assert!(
        e.contains("ray_order = Tiles(8) cannot be timed with --sample"),
        "{e}"
    );
}
