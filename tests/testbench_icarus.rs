//! The RTL units (`testbench/rtl/`, every unit of `rtl_model::vectors::RTL_UNITS`) against the
//! model's vectors through `testbench/run.sh`, in Icarus Verilog and in Verilator: each passes
//! every row of a ≥ 10,000-transaction set generated here from a fixed seed (adversarial rows
//! included) at the model's timing in both simulators, and the committed golden set in both;
//! each RTL module's own `LATENCY` (read from its source, and printed by its testbench) equals
//! the model's `UnitTimings` latency of that module (hit_record: the packer's `hit_pack`, the
//! check's `hit_unpack`) and the latency measured; the frame's cycles are required and
//! checked; corrupting one expected value of one row makes each testbench report exactly one
//! failure; with `--walk-lanes 2` the transform, reciprocal and walker-root benches drive 2, 6
//! and 2 units side by side, every row passes and a corrupted row of a unit other than unit 0
//! is exactly one failure; and
//! `verilator --lint-only -Wall` finds nothing in `testbench/rtl/`.
//!
//! Without `iverilog` or `verilator` (with make and g++ for its builds) the tests skip that
//! simulator with a `SKIPPED` line, as does the large walker set without the shared `.vox`
//! models (tests/common/skip.rs); with `CI=true` a missing one fails (`.ci/run` installs them). Verilator builds are kept in
//! `CARGO_TARGET_TMPDIR/verilator_cache` (run.sh's `SIM_CACHE`, keyed by a hash of their
//! inputs), so the golden set and the large set of a unit share one build.
//!
//! This file holds what every bench run shares (the simulators found, `run.sh`, the seed);
//! the tests are in `testbench_icarus/`, one file a subject: `units` (the datapath units,
//! lint), `walker`, `frame` (the end-to-end frame) and `packages` (the hardware packages).
//!
//! Pipeline position: the RTL of `testbench/rtl/` against the model, unit by unit and frame
//! by frame.

mod common;
mod vector_files;

#[path = "testbench_icarus/frame.rs"]
mod frame;
#[path = "testbench_icarus/packages.rs"]
mod packages;
#[path = "testbench_icarus/units.rs"]
mod units;
#[path = "testbench_icarus/walker.rs"]
mod walker;

use std::path::PathBuf;
use std::process::Command;
use vector_files::repo;

/// The seed and size of the big set.
const SEED: &str = "20190605";
const COUNT: &str = "10000";

/// Icarus Verilog is on the PATH (else the test skips visibly, or fails under CI=true).
fn icarus() -> bool {
    common::skip::tools(&["iverilog", "vvp"], "iverilog")
}

/// Verilator can lint (else the test skips visibly, or fails under CI=true).
fn verilator_lint() -> bool {
    common::skip::tools(&["verilator"], "verilator")
}

/// The simulators that can run here (a missing one skips its part of the test visibly).
fn simulators() -> Vec<&'static str> {
    let mut v = Vec::new();
    if common::skip::tools_for("the Icarus Verilog runs", &["iverilog", "vvp"], "iverilog") {
        v.push("icarus");
    }
    if common::skip::tools_for(
        // `--binary` builds the simulation's C++ with make and g++.
        "the Verilator runs",
        &["verilator", "make", "g++"],
        "verilator make g++",
    ) {
        v.push("verilator");
    }
    v
}

/// Where run.sh keeps Verilator builds (content-addressed, so safe across runs).
fn sim_cache() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("verilator_cache")
}

/// What one testbench run printed.
struct Outcome {
    passed: u64,
    failed: u64,
    latency: Option<u64>,
    /// The RTL modules' own `LATENCY` localparams as the testbench printed them ("rtl
    /// LATENCY svo_sqrt 32"): (module, cycles).
    rtl_latency: Vec<(String, u64)>,
    text: String,
}

/// `bash testbench/run.sh ARGS` with `SIM_CACHE` and the given environment: (stdout, stdout
/// then stderr as one text).
fn run_sh(args: &[&str], env: &[(&str, &str)]) -> (String, String) {
    let out = Command::new("bash")
        .arg(repo().join("testbench/run.sh"))
        .args(args)
        .env("SIM_CACHE", sim_cache())
        .envs(env.iter().copied())
        .output()
        .expect("run testbench/run.sh");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let text = format!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    (stdout, text)
}

/// The numbers of a line, in order ("12 passed, 0 failed" → [12, 0]).
fn numbers(l: &str) -> Vec<u64> {
    l.split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect()
}
