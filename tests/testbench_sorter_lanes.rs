//! The RTL sorter (`testbench/rtl/svo_sorter.v`) at the network widths a datapath may set
//! (`sorter.n` 8, the old default, and 16, issue 28's): for each, the sorter's vectors are built
//! from the model at that width (`rtl_model::vectors::stage::sorter`, whose package carries the
//! model's network as NET_LANES, NET_DEPTH, NET_SLOTS and NET_PAIRS) into a temporary folder,
//! and `testbench/run.sh` runs the sorter bench on them: every row passes, bit- and
//! cycle-exact, at the model's network latency; one flipped bit of one 16-lane row is exactly
//! one failure. Without iverilog the test skips visibly (fails under CI=true,
//! tests/common/skip.rs); Verilator runs too when it is there.

mod common;
mod vector_files;

use rtl_model::datapath::DatapathConfig;
use rtl_model::units::sorter::network_latency;
use rtl_model::vectors::files::table_files;
use rtl_model::vectors::stage::build;
use rtl_model::vectors::stage::sorter::SorterStage;
use std::path::Path;
use std::process::Command;
use vector_files::{corrupt_field, repo, Tmp};

/// Seed of the random rows (printed).
const SEED: u64 = 28;

/// Writes the sorter's table for `lanes` lanes into `dir`: every adversarial row and 400 random.
fn write_sorter_vectors(dir: &Path, lanes: u8) {
    let mut dp = DatapathConfig::default();
    dp.sorter.n = lanes;
    let table = build(&SorterStage::new(&dp), &[], 400, SEED);
    for f in table_files(&table).expect("sorter table files") {
        std::fs::write(dir.join(&f.name), &f.bytes).expect("write a vector file");
    }
}

/// `testbench/run.sh --sim SIM DIR sorter`: (passed, failed, its output).
fn run_sorter(sim: &str, dir: &Path) -> (u64, u64, String) {
    let out = Command::new("bash")
        .arg(repo().join("testbench/run.sh"))
        .args(["--sim", sim, dir.to_str().expect("UTF-8 path"), "sorter"])
        .output()
        .expect("run testbench/run.sh");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let last = String::from_utf8_lossy(&out.stdout)
        .lines()
        .last()
        .unwrap_or("")
        .to_string();
    let nums: Vec<u64> = last
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect();
    assert!(
        last.ends_with(" failed") && nums.len() == 2,
        "sorter ({sim}): no \"N passed, N failed\" line:\n{text}"
    );
    (nums[0], nums[1], text)
}

/// The simulators here: Icarus is required (skip or CI failure), Verilator optional.
fn simulators() -> Vec<&'static str> {
    let mut v = Vec::new();
    if common::skip::tools(&["iverilog", "vvp"], "iverilog") {
        v.push("icarus");
    } else {
        return v;
    }
    if common::skip::tools_for(
        "the Verilator runs",
        &["verilator", "make", "g++"],
        "verilator",
    ) {
        v.push("verilator");
    }
    v
}

#[test]
fn sorter_rtl_passes_at_eight_and_sixteen_lanes() {
    let sims = simulators();
    if sims.is_empty() {
        return;
    }
    println!("seed {SEED}");
    for lanes in [8u8, 16] {
        let t = Tmp::new(&format!("sorter_lanes_{lanes}"));
        write_sorter_vectors(&t.dir, lanes);
        let pkg = std::fs::read_to_string(t.dir.join("sorter_pkg.sv")).expect("package");
        assert!(
            pkg.contains(&format!("localparam int NET_LANES = {lanes};")),
            "{lanes} lanes: the package does not carry the network width:\n{pkg}"
        );
        let depth = vector_files::manifest(&t.dir, "sorter")["depth"]
            .as_u64()
            .expect("depth");
        for sim in &sims {
            let (passed, failed, text) = run_sorter(sim, &t.dir);
            println!("{lanes} lanes, {sim}: {passed} passed, {failed} failed of {depth}");
            assert_eq!(
                (passed, failed),
                (depth, 0),
                "{lanes} lanes ({sim}):\n{text}"
            );
            let want = format!("rtl LATENCY svo_sorter {}", network_latency(lanes));
            assert!(
                text.contains(&want),
                "{lanes} lanes ({sim}): no \"{want}\":\n{text}"
            );
        }
        if lanes == 16 {
            // Row 40: a ray of 40 keys (three chunks, two passes); out_t33 is a merged key.
            let (row, depth) = corrupt_field(&t.dir, "sorter", "out_t33", 40, |w| w / 2);
            let (passed, failed, text) = run_sorter("icarus", &t.dir);
            println!("16 lanes: one bit of out_t33 in row {row} flipped: {passed} passed, {failed} failed");
            assert_eq!((passed, failed), (depth - 1, 1), "{text}");
            assert!(
                text.contains(&format!("row {row}: out_t33")),
                "the failure does not name row {row} and out_t33:\n{text}"
            );
        }
    }
}
