//! The RTL of the leaf units (`testbench/rtl/`) against the model's vectors in Icarus
//! Verilog, through `testbench/run.sh`: square root, reciprocal, transform and sphere test
//! each pass every row of a ≥ 10,000-transaction set generated here from a fixed seed
//! (adversarial rows included) with the model's latency; the committed golden set passes
//! too; and corrupting one expected value of one row makes each testbench report exactly one
//! failure.
//!
//! Without `iverilog` the tests print why and skip; with `CI=true` a missing `iverilog` fails
//! (`.ci/run` installs it).

mod common;
mod vector_files;

use common::process::run_sim;
use rtl_model::cycle::hw_config::UnitTimings;
use rtl_model::datapath::DatapathConfig;
use std::path::Path;
use std::process::Command;
use std::time::Duration;
use vector_files::{field, flip, manifest, repo, rows, Tmp};

/// The units with RTL, and the seed and size of the big set.
const UNITS: [&str; 4] = ["sqrt", "reciprocal", "transform", "sphere"];
const SEED: &str = "20190605";
const COUNT: &str = "10000";

/// Whether Icarus Verilog can run; prints the reason when not (and fails under CI=true).
fn icarus() -> bool {
    let ok = ["iverilog", "vvp"].iter().all(|tool| {
        Command::new(tool)
            .arg("-V")
            .output()
            .is_ok_and(|o| !o.stdout.is_empty() || !o.stderr.is_empty())
    });
    if ok {
        return true;
    }
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!("iverilog/vvp not found but CI=true: the testbenches must run (.ci/run installs the Debian package iverilog)");
    }
    eprintln!(
        "skipping: iverilog/vvp not found (install Icarus Verilog, e.g. apt-get install iverilog)"
    );
    false
}

/// What one testbench run printed.
struct Outcome {
    passed: u64,
    failed: u64,
    latency: Option<u64>,
    text: String,
}

/// `testbench/run.sh DIR UNIT`, parsed: the closing "N passed, N failed" line and the
/// measured latency the testbench reports.
fn run_testbench(dir: &Path, unit: &str) -> Outcome {
    let out = Command::new("bash")
        .arg(repo().join("testbench/run.sh"))
        .arg(dir)
        .arg(unit)
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
        last.ends_with(" failed") && last.contains(" passed, ") && nums.len() == 2,
        "{unit}: the testbench did not close with \"N passed, N failed\":\n{text}"
    );
    let latency = text
        .lines()
        .find_map(|l| l.split("latency ").nth(1))
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok());
    Outcome {
        passed: nums[0],
        failed: nums[1],
        latency,
        text,
    }
}

fn model_latency(unit: &str) -> u64 {
    let t = UnitTimings::for_datapath(&DatapathConfig::default());
    u64::from(match unit {
        "sqrt" => t.sqrt.latency_cycles,
        "reciprocal" => t.reciprocal.latency_cycles,
        "transform" => t.transform.latency_cycles,
        _ => t.sphere.latency_cycles + t.sqrt.latency_cycles,
    })
}

#[test]
fn rtl_units_pass_ten_thousand_vectors_each_at_the_models_latency() {
    if !icarus() {
        return;
    }
    let t = Tmp::new("icarus_big");
    let args = [
        "vectors",
        "--out",
        &t.p("v"),
        "--count",
        COUNT,
        "--seed",
        SEED,
        "--width",
        "24",
        "--height",
        "16",
        "--depth",
        "5",
    ];
    let r = run_sim(&args, None, Duration::from_secs(300));
    assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
    let dir = t.dir.join("v");
    // Two cores: two units at a time.
    let results: Vec<(&str, Outcome)> = std::thread::scope(|s| {
        let handles: Vec<_> = UNITS
            .chunks(2)
            .map(|pair| {
                let dir = &dir;
                s.spawn(move || {
                    pair.iter()
                        .map(|&u| (u, run_testbench(dir, u)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("testbench thread"))
            .collect()
    });
    for (unit, o) in &results {
        let m = manifest(&dir, unit);
        let depth = m["depth"].as_u64().expect("depth");
        let adversarial = m["rows"][0]["count"].as_u64().unwrap_or(0);
        println!(
            "{unit:<10} {} passed, {} failed of {depth} rows ({adversarial} adversarial), latency {:?} (model {})",
            o.passed,
            o.failed,
            o.latency,
            model_latency(unit)
        );
        assert_eq!(o.failed, 0, "{unit}:\n{}", o.text);
        assert_eq!(
            o.passed, depth,
            "{unit}: not every row was checked:\n{}",
            o.text
        );
        assert!(o.passed >= 10_000, "{unit}: only {} rows", o.passed);
        assert!(adversarial > 0 && m["rows"][0]["origin"] == "adversarial");
        assert_eq!(o.latency, Some(model_latency(unit)), "{unit}:\n{}", o.text);
    }
}

#[test]
fn golden_set_passes() {
    if !icarus() {
        return;
    }
    let dir = repo().join("vectors");
    for unit in UNITS {
        let o = run_testbench(&dir, unit);
        assert_eq!(o.failed, 0, "{unit}:\n{}", o.text);
        assert_eq!(
            Some(o.passed),
            manifest(&dir, unit)["depth"].as_u64(),
            "{unit}"
        );
    }
}

#[test]
fn one_corrupted_expected_value_is_exactly_one_failure() {
    if !icarus() {
        return;
    }
    let golden = repo().join("vectors");
    // Per unit: an output field and a row (one adversarial, one later) to corrupt.
    for (unit, out_field, row) in [
        ("sqrt", "root", 7usize),
        ("reciprocal", "inv", 200),
        ("transform", "local_d_y", 40),
        ("sphere", "t_enter", 70),
    ] {
        let t = Tmp::new(&format!("corrupt_{unit}"));
        for name in [
            format!("{unit}.hex"),
            format!("{unit}.json"),
            format!("{unit}_pkg.sv"),
            "reciprocal_seed.hex".into(),
        ] {
            std::fs::copy(golden.join(&name), t.dir.join(&name)).expect("copy a golden file");
        }
        let m = manifest(&t.dir, unit);
        let (off, w, _) = field(&m, out_field);
        let mut r = rows(&t.dir, unit);
        let depth = r.len() as u64;
        let row = row.min(r.len() - 1);
        r[row] = flip(&r[row], off + w / 2);
        let text = std::fs::read_to_string(t.dir.join(format!("{unit}.hex"))).expect("hex");
        let header: Vec<&str> = text.lines().take_while(|l| l.starts_with("//")).collect();
        let body = [header.join("\n"), r.join("\n")].join("\n") + "\n";
        std::fs::write(t.dir.join(format!("{unit}.hex")), body).expect("write the corrupted rows");
        let o = run_testbench(&t.dir, unit);
        println!(
            "{unit}: one bit of {out_field} in row {row} flipped: {} passed, {} failed",
            o.passed, o.failed
        );
        assert_eq!((o.passed, o.failed), (depth - 1, 1), "{unit}:\n{}", o.text);
        assert!(
            o.text.contains(&format!("row {row}: {out_field}")),
            "{unit}: the failure does not name row {row} and {out_field}:\n{}",
            o.text
        );
    }
}
