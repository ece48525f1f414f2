//! Timing one hardware on the functional trace another hardware's run recorded
//! (`CycleRun::frame_recorded` / `frame_replayed`, what `sim explore` does for the points that
//! share a trace) gives, frame by frame, exactly the cycles of a run that renders the frame
//! itself; and a replay whose datapath differs from the recording's is refused.
//!
//! Oracle: `CycleRun::frame` on the second hardware, which renders its own trace; it shares
//! only the cycle model with the replay, which is what is being checked — that the recorded
//! trace and hit buffer stand in for a fresh rendering.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use svo_sim::models::cycle::runner::{CycleRun, CycleRunError, RecordedFrame};
use svo_sim::models::cycle::CycleOptions;
use svo_sim::models::reference::FrameInput;
use svo_sim::world::assets::{build_assets, effective_depths, Asset, Materialise};
use svo_sim::world::scene::Scene;

const W: u32 = 64;
const H: u32 = 40;
const FRAMES: u32 = 3;

fn car() -> (Scene, Vec<Asset>) {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(W, H).unwrap();
    scene.set_frames(FRAMES).unwrap();
    let depths = effective_depths(&scene, Some(7)).unwrap();
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap();
    (scene, assets)
}

/// A hardware far from the default in the walk section and the node memory.
fn other_hw() -> HwConfig {
    let mut hw = HwConfig::default();
    hw.walker_pool.walkers = 3;
    hw.walker_pool.contexts_per_walker = 2;
    hw.node_memory.cache.size_bytes /= 8;
    hw.node_memory.dram.mshrs = 4;
    hw
}

fn run_of(hw: &HwConfig, dp: &DatapathConfig, scene: &Scene, assets: &[Asset]) -> CycleRun {
    CycleRun::new(
        hw,
        dp,
        assets,
        &scene.instance_asset,
        (W, H),
        CycleOptions::default(),
    )
    .unwrap()
}

/// Every frame of the car recorded on the default hardware, with its cycles.
fn recorded(
    scene: &Scene,
    assets: &[Asset],
    dp: &DatapathConfig,
) -> (Vec<RecordedFrame>, Vec<u64>) {
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let mut run = run_of(&HwConfig::default(), dp, scene, assets);
    let (mut kept, mut cycles) = (Vec::new(), Vec::new());
    for f in 0..FRAMES {
        let state = scene.frame_state(f, &half).unwrap();
        let input = FrameInput {
            scene,
            assets,
            state: &state,
        };
        let (r, rec) = run.frame_recorded(&input, dp, true).unwrap();
        cycles.push(r.cycles.cycles);
        kept.push(rec);
    }
    (kept, cycles)
}

#[test]
fn a_replayed_frame_takes_the_cycles_of_a_rendered_one() {
    let (scene, assets) = car();
    let dp = DatapathConfig::default();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let (kept, recorded_cycles) = recorded(&scene, &assets, &dp);
    let hw = other_hw();
    let mut fresh = run_of(&hw, &dp, &scene, &assets);
    let mut replay = run_of(&hw, &dp, &scene, &assets);
    for f in 0..FRAMES {
        let state = scene.frame_state(f, &half).unwrap();
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &state,
        };
        let want = fresh.frame(&input, &dp, true).unwrap().cycles;
        let got = replay
            .frame_replayed(&input, &dp, true, &kept[f as usize])
            .unwrap();
        println!(
            "frame {f}: rendered {} cycles, replayed {} (recording hardware {})",
            want.cycles, got.cycles, recorded_cycles[f as usize]
        );
        assert_ne!(
            want.cycles, recorded_cycles[f as usize],
            "frame {f}: the two hardwares must differ in cycles for the check to mean anything"
        );
        assert_eq!(got.cycles, want.cycles, "frame {f}: cycles");
        assert_eq!(got.stalls, want.stalls, "frame {f}: stall counters");
    }
}

#[test]
fn a_replay_on_another_datapath_is_refused() {
    let (scene, assets) = car();
    let dp = DatapathConfig::default();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let (kept, _) = recorded(&scene, &assets, &dp);
    let mut other = dp.clone();
    other.sphere.reach /= 2.0;
    let mut replay = run_of(&HwConfig::default(), &other, &scene, &assets);
    let state = scene.frame_state(0, &half).unwrap();
    let input = FrameInput {
        scene: &scene,
        assets: &assets,
        state: &state,
    };
    match replay.frame_replayed(&input, &other, true, &kept[0]) {
        Err(CycleRunError::Config(m)) => {
            assert!(m.contains("another datapath"), "{m}")
        }
        Err(e) => panic!("refused for another reason: {e}"),
        Ok(c) => panic!("accepted: {} cycles", c.cycles),
    }
}

/// Frames replay in order: frame 1 replayed on a run that skipped frame 0 (it knows no
/// previous frame, so every pixel is traced afresh) disagrees with the trace, which reuses
/// pixels of frame 0, and the cycle model's check says so.
#[test]
fn a_replay_out_of_order_fails_its_check() {
    let (scene, assets) = car();
    let dp = DatapathConfig::default();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let (kept, _) = recorded(&scene, &assets, &dp);
    let mut replay = run_of(&HwConfig::default(), &dp, &scene, &assets);
    let state = scene.frame_state(1, &half).unwrap();
    let input = FrameInput {
        scene: &scene,
        assets: &assets,
        state: &state,
    };
    let r = replay.frame_replayed(&input, &dp, true, &kept[1]);
    match r {
        Ok(c) => panic!(
            "frame 1 replayed without frame 0 was accepted: {} cycles",
            c.cycles
        ),
        Err(e) => {
            let m = e.to_string();
            println!("{m}");
            assert!(m.contains("reuse"), "{m}");
        }
    }
}
