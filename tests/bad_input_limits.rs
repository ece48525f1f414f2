//! Inputs past the model's limits, through the `sim` binary (issue 26, findings 3–5):
//!
//! * endless inputs (`/dev/zero` as scene, hardware, datapath, `sim render` model, and as a
//!   scene's `.vox` asset) stop at their cap with a message naming the file and the cap;
//! * hardware whose *derived* sizes break a limit (4096 walkers × 1024 contexts, every FIFO at
//!   its maximum) is refused by validation, naming the fields, before `--out` exists; the FIFOs
//!   at their maximum with the walk queue lowered to fit run;
//! * `sorter_lanes: 300` is refused with its range, not as a parse error;
//! * a datapath format with more fraction bits than width is refused as invalid, named;
//! * a run whose memory estimate exceeds the available memory is refused with both figures,
//!   before any output exists (`SVO_SIM_MEM_AVAILABLE_MIB` fixes the available figure).
//!
//! What a failure must look like otherwise (exit code, no panic, nothing half-written) is
//! checked by `tests/common/bad_input.rs`. No assertion on time: an endless read would be
//! killed by the guard below and fail the test.

use std::path::Path;
use std::time::Duration;

mod common;
use common::bad_input::{args, expect_failure, small_default, Tmp};
use common::process::{run_sim, run_sim_env};

/// Kill guard for the endless inputs: reading 16 MiB (or 256 MiB) of `/dev/zero` takes well
/// under a second; the old code read until memory ran out (about 46 s at 4 GB).
const GUARD: Duration = Duration::from_secs(60);

/// Runs `a` with `--out` in a folder that does not exist, expects a failure whose stderr holds
/// every string of `expect`, and that the folder still does not exist.
fn refused_before_out(t: &Tmp, a: &[String], expect: &[&str]) -> String {
    let out = t.dir.join("never_created");
    let mut full = a.to_vec();
    full.extend(args(&["--out", &out.display().to_string()]));
    let r = run_sim(&full, None, GUARD);
    let ctx = format!("sim {full:?}\nstdout:\n{}\nstderr:\n{}", r.stdout, r.stderr);
    assert!(
        r.status.code().is_some_and(|c| c != 0),
        "not refused\n{ctx}"
    );
    assert!(!r.stderr.contains("panicked"), "panicked\n{ctx}");
    for e in expect {
        assert!(r.stderr.contains(e), "the message lacks {e:?}\n{ctx}");
    }
    assert!(!out.exists(), "--out {} was created\n{ctx}", out.display());
    r.stderr
}

#[cfg(unix)]
#[test]
fn scene_dev_zero_stops_at_16_mib() {
    let t = Tmp::new("scene_dev_zero_stops_at_16_mib");
    refused_before_out(
        &t,
        &args(&["--scene", "/dev/zero"]),
        &["scene file /dev/zero is larger than 16 MiB"],
    );
}

#[cfg(unix)]
#[test]
fn hardware_dev_zero_stops_at_16_mib() {
    let t = Tmp::new("hardware_dev_zero_stops_at_16_mib");
    refused_before_out(
        &t,
        &small_default(&["--hw", "/dev/zero"]),
        &["hardware file /dev/zero is larger than 16 MiB"],
    );
}

#[cfg(unix)]
#[test]
fn datapath_dev_zero_stops_at_16_mib() {
    let t = Tmp::new("datapath_dev_zero_stops_at_16_mib");
    refused_before_out(
        &t,
        &small_default(&["--datapath", "/dev/zero"]),
        &["datapath file /dev/zero is larger than 16 MiB"],
    );
}

#[cfg(unix)]
#[test]
fn render_dev_zero_stops_at_the_vox_cap() {
    let t = Tmp::new("render_dev_zero_stops_at_the_vox_cap");
    let png = t.p("model.png");
    let a = args(&[
        "render",
        "/dev/zero",
        "--eye",
        "0,0,0",
        "--look",
        "1,1,1",
        "--max-vox-mib",
        "4",
        "--out",
        &png,
    ]);
    let r = run_sim(&a, None, GUARD);
    assert!(
        r.status.code().is_some_and(|c| c != 0),
        "not refused: {}",
        r.stderr
    );
    assert!(
        r.stderr.contains(
            "MagicaVoxel file /dev/zero is larger than 4 MiB (the limit for MagicaVoxel files)"
        ) && r.stderr.contains("--max-vox-mib"),
        "{}",
        r.stderr
    );
    assert!(!Path::new(&png).exists());
}

#[cfg(unix)]
#[test]
fn asset_dev_zero_stops_at_256_mib() {
    let t = Tmp::new("asset_dev_zero_stops_at_256_mib");
    let scene = t.write(
        "zero_asset.ron",
        r#"(
    resolution: (32, 24),
    frames: 1,
    camera: [(frame: 0, position: (0, 1, -6), look_at: (0, 0, 0), vfov_deg: 40)],
    assets: [(name: "endless", depth: 6, source: Vox(path: "/dev/zero", voxel_size: 0.05))],
    instances: [(name: "e", asset: "endless", keys: [(frame: 0)])],
)
"#,
    );
    expect_failure(
        &t,
        &args(&["--scene", &scene]),
        &[
            "asset \"endless\"",
            "MagicaVoxel file /dev/zero is larger than 256 MiB",
        ],
    );
}

#[test]
fn walker_pool_4096_by_1024_is_refused_before_out_exists() {
    let t = Tmp::new("walker_pool_4096_by_1024_is_refused_before_out_exists");
    let hw = t.write(
        "pool.ron",
        "(walker_pool: (walkers: 4096, contexts_per_walker: 1024))",
    );
    let err = refused_before_out(
        &t,
        &small_default(&["--hw", &hw]),
        &[
            &hw,
            "invalid hardware configuration",
            "walker_pool.walkers × walker_pool.contexts_per_walker + fifos.root_to_dispatch",
            "4194368 ray slots exceeds the limit 65536",
        ],
    );
    // Refused at validation: the elaboration table is never printed.
    assert!(!err.contains("above the maximum"), "{err}");
}

fn every_fifo(depth: u32, root_to_dispatch: u32) -> String {
    let names = [
        "raygen_to_sphere",
        "sphere_to_sorter",
        "sorter_to_check",
        "check_to_transform",
        "transform_to_reciprocal",
        "reciprocal_to_root",
        "walker_to_record",
        "record_to_write",
    ];
    let mut fields: Vec<String> = names.iter().map(|n| format!("{n}: {depth}")).collect();
    fields.push(format!("root_to_dispatch: {root_to_dispatch}"));
    format!("(fifos: ({}))", fields.join(", "))
}

#[test]
fn every_fifo_at_its_maximum_is_refused_naming_the_walk_queue() {
    let t = Tmp::new("every_fifo_at_its_maximum_is_refused_naming_the_walk_queue");
    let hw = t.write("fifos.ron", every_fifo(65536, 65536));
    refused_before_out(
        &t,
        &small_default(&["--hw", &hw]),
        &[
            "fifos.root_to_dispatch",
            "32 × 8 + 65536 = 65792 ray slots exceeds the limit 65536",
        ],
    );
}

#[test]
fn every_fifo_at_its_maximum_runs_when_the_ray_slots_fit() {
    let t = Tmp::new("every_fifo_at_its_maximum_runs_when_the_ray_slots_fit");
    // 32 walkers × 8 contexts = 256 slots: the walk queue may take the rest.
    let hw = t.write("fifos.ron", every_fifo(65536, 65536 - 256));
    let out = t.p("out");
    let a = small_default(&["--hw", &hw, "-q", "--out", &out]);
    let r = run_sim(&a, None, common::bad_input::TIMEOUT);
    assert!(r.status.success(), "{}\n{}", r.stdout, r.stderr);
    assert!(Path::new(&out).join("frame_0000.png").is_file());
}

#[test]
fn sorter_lanes_300_is_refused_with_its_range() {
    let t = Tmp::new("sorter_lanes_300_is_refused_with_its_range");
    let hw = t.write("lanes.ron", "(sorter_lanes: 300)");
    refused_before_out(
        &t,
        &small_default(&["--hw", &hw]),
        &[&hw, "sorter_lanes = 300 exceeds the limit 255"],
    );
}

#[test]
fn datapath_fraction_beyond_width_is_invalid() {
    let t = Tmp::new("datapath_fraction_beyond_width_is_invalid");
    // The default datapath as `sim datapath` prints it, with raygen.pos's 32 fraction bits
    // raised to 60 (its width is 40).
    let r = run_sim(&["datapath"], None, GUARD);
    assert!(r.status.success(), "{}", r.stderr);
    let at = r.stdout.find("pos:").expect("raygen.pos in the datapath");
    let frac = at + r.stdout[at..].find("frac: 32").expect("raygen.pos.frac");
    let text = format!("{}frac: 60{}", &r.stdout[..frac], &r.stdout[frac + 8..]);
    let dp = t.write("dp.ron", text);
    let err = refused_before_out(
        &t,
        &small_default(&["--datapath", &dp]),
        &[
            &dp,
            "invalid datapath configuration",
            "raygen.pos.frac = 60 exceeds raygen.pos.width = 40",
        ],
    );
    assert!(!err.contains("≠"), "reported as a mismatch: {err}");
}

#[test]
fn a_run_above_the_available_memory_is_refused_before_any_output() {
    let t = Tmp::new("a_run_above_the_available_memory_is_refused_before_any_output");
    let out = t.dir.join("never_created");
    let report = t.p("report.json");
    let a = args(&[
        "--model",
        "reference",
        "--width",
        "16384",
        "--height",
        "4096",
        "--frames",
        "1",
        "--out",
        &out.display().to_string(),
        "--report-json",
        &report,
    ]);
    let r = run_sim_env(&a, None, &[("SVO_SIM_MEM_AVAILABLE_MIB", "3500")], GUARD);
    assert!(
        r.status.code().is_some_and(|c| c != 0),
        "not refused: {}",
        r.stderr
    );
    assert!(
        r.stderr.contains(
            "a 16384×4096 run of the reference model needs about 7296 MiB (estimate: 128 MiB \
             fixed, plus 112 bytes per pixel) but only 3500 MiB is available \
             (SVO_SIM_MEM_AVAILABLE_MIB=3500)"
        ),
        "{}",
        r.stderr
    );
    assert!(!out.exists() && !Path::new(&report).exists());
    // The same run at a size that fits the same figure starts (and finishes).
    let small = args(&[
        "--model",
        "reference",
        "--width",
        "64",
        "--height",
        "32",
        "--frames",
        "1",
        "-q",
        "--out",
        &out.display().to_string(),
    ]);
    let r = run_sim_env(
        &small,
        None,
        &[("SVO_SIM_MEM_AVAILABLE_MIB", "3500")],
        GUARD,
    );
    assert!(r.status.success(), "{}", r.stderr);
}

/// The issue's own case: a 16384×4096 reference run under a 4 GB address-space limit
/// (`ulimit -v`, as on a machine or job with that limit) is refused with both figures, naming
/// the limit, instead of aborting in an allocation. On 1f329ce it aborted with "memory
/// allocation of … bytes failed" at 3.7 GB; before the limit was read, `MemAvailable` alone
/// (24 GiB here) let it start.
#[cfg(target_os = "linux")]
#[test]
fn a_run_above_the_address_space_limit_is_refused_naming_the_limit() {
    let t = Tmp::new("a_run_above_the_address_space_limit_is_refused_naming_the_limit");
    let out = t.dir.join("never_created");
    let script = format!(
        "ulimit -v 4000000 && exec '{}' --model reference --width 16384 --height 4096 --frames 1 --out '{}'",
        env!("CARGO_BIN_EXE_sim"),
        out.display()
    );
    let r = std::process::Command::new("sh")
        .args(["-c", &script])
        .env_remove(memory_env())
        .output()
        .expect("sh runs");
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "not refused cleanly: {stderr}");
    assert!(
        stderr.contains("a 16384×4096 run of the reference model needs about 7296 MiB")
            && stderr.contains("the address-space limit (ulimit -v) less this process's VmSize"),
        "{stderr}"
    );
    assert!(!stderr.contains("memory allocation"), "{stderr}");
    assert!(!out.exists());
}

/// The variable that would replace the machine's figures (kept out of the child above).
fn memory_env() -> &'static str {
    "SVO_SIM_MEM_AVAILABLE_MIB"
}
