//! The cycle model end to end with the DRAMsim3 DRAM backend (docs/cycle-model.md, DRAM):
//! bit-exact with the functional model under cross-check, the same cycles and reports on two
//! runs, the same reports with idle cycles skipped or stepped one by one (the fills in
//! DRAMsim3 bound the skip), and the device's counters in the frame report.

mod common;

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::memory::DramBackend;
use rtl_model::datapath::DatapathConfig;
use svo_sim::models::cycle::runner::CycleRun;
use svo_sim::models::cycle::CycleOptions;
use svo_sim::models::reference::FrameInput;
use svo_sim::world::assets::{build_assets, effective_depths, Materialise};
use svo_sim::world::scene::Scene;

/// The default car, small: 160×96, depth 8, three frames.
fn car() -> Scene {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(160, 96).unwrap();
    scene.set_frames(3).unwrap();
    scene
}

fn dramsim3_hw(channels: u32) -> HwConfig {
    let mut hw = HwConfig::default();
    hw.node_memory.dram.backend = DramBackend::DramSim3 {
        config: "DDR4_8Gb_x16_2400".into(),
        channels,
        controller_latency: 30,
    };
    hw
}

/// Every frame's report as JSON without its wall time.
fn reports(scene: &Scene, hw: &HwConfig, opts: CycleOptions) -> Vec<serde_json::Value> {
    let depths = effective_depths(scene, Some(8)).unwrap();
    let assets = build_assets(scene, &depths, Materialise::Auto).unwrap();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let dp = DatapathConfig::default();
    let (w, h) = scene.file.resolution;
    let mut run = CycleRun::new(hw, &dp, &assets, &scene.instance_asset, (w, h), opts).unwrap();
    let mut out = Vec::new();
    for f in 0..scene.file.frames {
        let state = scene.frame_state(f, &half).unwrap();
        let input = FrameInput {
            scene,
            assets: &assets,
            state: &state,
        };
        let r = run
            .frame(&input, &dp, true)
            .unwrap_or_else(|e| panic!("frame {f}: {e}"));
        let mut v = serde_json::to_value(&r.cycles).unwrap();
        v.as_object_mut().unwrap().remove("sim_wall_s");
        out.push(v);
    }
    out
}

#[test]
fn dramsim3_runs_are_bit_exact_and_give_the_same_reports() {
    let scene = car();
    let hw = dramsim3_hw(2);
    let crossed = reports(
        &scene,
        &hw,
        CycleOptions {
            cross_check: true,
            ..CycleOptions::default()
        },
    );
    let a = reports(&scene, &hw, CycleOptions::default());
    let b = reports(&scene, &hw, CycleOptions::default());
    assert_eq!(a, b, "two runs differ");
    for (f, (x, y)) in crossed.iter().zip(&a).enumerate() {
        assert_eq!(
            x["cycles"], y["cycles"],
            "frame {f}: cross-check changed timing"
        );
    }
    for (f, r) in a.iter().enumerate() {
        let d = &r["memory"]["dram_device"];
        assert_eq!(d["device"], "DDR4_8Gb_x16_2400", "frame {f}: {r}");
        let fills = d["fills"].as_u64().unwrap();
        assert!(fills > 0, "frame {f}: no fill");
        assert_eq!(
            d["transactions"].as_u64(),
            Some(fills),
            "one burst per 64-byte line"
        );
        println!(
            "frame {f}: {} cycles, {} fills, row-buffer hit rate {}, {} B/cycle",
            r["cycles"], fills, d["row_hit_rate"], d["bytes_per_cycle"]
        );
    }
    // The built-in model has no device counters.
    let builtin = reports(&scene, &HwConfig::default(), CycleOptions::default());
    assert!(builtin[0]["memory"].get("dram_device").is_none());
}

#[test]
fn dramsim3_reports_the_same_with_idle_cycles_skipped_or_stepped() {
    let scene = car();
    let mut hw = dramsim3_hw(1);
    // Few walkers: whole stretches wait on DRAM, so idle skipping has cycles to skip.
    hw.walker_pool.walkers = 2;
    let skipping = reports(&scene, &hw, CycleOptions::default());
    let stepping = reports(
        &scene,
        &hw,
        CycleOptions {
            step_every_cycle: true,
            ..CycleOptions::default()
        },
    );
    for (f, (x, y)) in skipping.iter().zip(&stepping).enumerate() {
        assert_eq!(x, y, "frame {f}: skipping changed the report");
    }
}

#[test]
fn the_hardware_file_refuses_a_bad_dramsim3_backend_naming_the_field() {
    let mut hw = dramsim3_hw(3);
    let e = hw.validate().unwrap_err();
    assert!(
        e.starts_with("node_memory.dram.backend.channels = 3 must be 1, 2, 4 or 8"),
        "{e}"
    );
    hw = dramsim3_hw(2);
    hw.node_memory.dram.backend = DramBackend::DramSim3 {
        config: "HBM2_4Gb_x128".into(),
        channels: 2,
        controller_latency: 30,
    };
    let e = hw.validate().unwrap_err();
    assert!(
        e.starts_with("node_memory.dram.backend.config = \"HBM2_4Gb_x128\" is not a bundled"),
        "{e}"
    );
    assert!(dramsim3_hw(2).validate().is_ok());
}
