//! The units of fixed or per-ray timing (every unit of `RTL_UNITS` but the walker) against
//! their vectors: the large seeded set and the golden set in both simulators, at the model's
//! latency (the testbench's measured latency, and each RTL module's `LATENCY` localparam, both
//! as printed and as read from the source); one corrupted expected value is exactly one
//! failure; `--walk-lanes 2` drives units side by side; `verilator --lint-only -Wall` is clean.
//!
//! Pipeline position: the RTL datapath units, one bench each (`testbench/tb_*.sv`), run through
//! `testbench/run.sh` by the helpers of `tests/testbench_icarus.rs`.

use super::common::process::run_sim;
use super::vector_files::{corrupt_field, manifest, repo, Tmp};
use super::{icarus, numbers, run_sh, simulators, verilator_lint, Outcome, COUNT, SEED};
use rtl_model::cycle::hw_config::UnitTimings;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::normal;
use rtl_model::vectors::RTL_UNITS;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// The units of fixed or per-ray timing, which `run_testbench` and the shared tests handle; the
/// walker (per-row cycles at three memory latencies, its own memory images) has its own
/// tests (`walker.rs`).
fn pipe_units() -> impl Iterator<Item = &'static str> {
    RTL_UNITS.iter().copied().filter(|&u| u != "walker")
}

/// `testbench/run.sh --sim SIM DIR UNIT`, parsed: the closing "N passed, N failed" line and
/// the measured latency the testbench reports.
fn run_testbench(sim: &str, dir: &Path, unit: &str) -> Outcome {
    let d = dir.to_string_lossy();
    let (stdout, text) = run_sh(&["--sim", sim, &d, unit], &[]);
    let last = stdout.lines().last().unwrap_or("");
    let nums = numbers(last);
    assert!(
        last.ends_with(" failed") && last.contains(" passed, ") && nums.len() == 2,
        "{unit} ({sim}): the testbench did not close with \"N passed, N failed\":\n{text}"
    );
    let latency = text
        .lines()
        .find_map(|l| l.split("latency ").nth(1))
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok());
    let rtl_latency = text
        .lines()
        .filter_map(|l| l.split("rtl LATENCY ").nth(1))
        .filter_map(|l| {
            let (m, n) = l.split_once(' ')?;
            Some((m.to_string(), n.trim().parse().ok()?))
        })
        .collect();
    Outcome {
        passed: nums[0],
        failed: nums[1],
        latency,
        rtl_latency,
        text,
    }
}

/// The latency the vector package states for `unit` (the model's, `UnitTimings`): what the
/// testbench requires every row to take. For hit_record it is the packer's, `units.hit_pack`;
/// the check (`units.hit_unpack`) must leave with it ("valid together").
fn model_latency(unit: &str) -> u64 {
    let t = UnitTimings::for_datapath(&DatapathConfig::default());
    u64::from(match unit {
        "sqrt" => t.sqrt.latency_cycles,
        "reciprocal" => t.reciprocal.latency_cycles,
        "transform" => t.transform.latency_cycles,
        "sphere" => t.sphere.latency_cycles + t.sqrt.latency_cycles,
        "raygen" => t.raygen.latency_cycles,
        // The first row is a ray without candidates: one network pass.
        "sorter" => t.sorter.latency_cycles,
        // units.hit_pack is svo_normal then svo_hit_pack (svo_walk_wide's packing lane).
        "hit_record" => t.hit_pack.latency_cycles - normal::LATENCY_CYCLES,
        "normal" => normal::LATENCY_CYCLES,
        "walker_root" => t.walker_root.latency_cycles,
        other => panic!("no model latency for unit {other}"),
    })
}

/// The model's latency of each RTL module a unit's testbench instantiates, taken from
/// `UnitTimings` module by module (the sphere module holds its square root).
fn model_module_latencies(unit: &str) -> Vec<(&'static str, u64)> {
    let t = UnitTimings::for_datapath(&DatapathConfig::default());
    let l = |x: u32| u64::from(x);
    match unit {
        "sqrt" => vec![("svo_sqrt", l(t.sqrt.latency_cycles))],
        "reciprocal" => vec![("svo_reciprocal", l(t.reciprocal.latency_cycles))],
        "transform" => vec![("svo_transform", l(t.transform.latency_cycles))],
        "sphere" => vec![(
            "svo_sphere",
            l(t.sphere.latency_cycles + t.sqrt.latency_cycles),
        )],
        "raygen" => vec![("svo_raygen", l(t.raygen.latency_cycles))],
        "sorter" => vec![("svo_sorter", l(t.sorter.latency_cycles))],
        "hit_record" => vec![
            (
                "svo_hit_pack",
                l(t.hit_pack.latency_cycles - normal::LATENCY_CYCLES),
            ),
            ("svo_hit_check", l(t.hit_unpack.latency_cycles)),
        ],
        "normal" => vec![("svo_normal", l(normal::LATENCY_CYCLES))],
        "walker_root" => vec![("svo_walker_root", l(t.walker_root.latency_cycles))],
        other => panic!("no model latency for unit {other}"),
    }
}

/// The RTL's latencies (its `LATENCY` localparams, printed by the testbench) against the
/// model's, module by module, and the latency measured on the first row against the RTL's.
fn assert_rtl_latencies(sim: &str, unit: &str, o: &Outcome) {
    let want = model_module_latencies(unit);
    let mut got = o.rtl_latency.clone();
    got.sort();
    got.dedup();
    assert_eq!(
        got.len(),
        want.len(),
        "{unit} ({sim}): the testbench printed the RTL latencies {got:?}, expected one per module of {want:?}:\n{}",
        o.text
    );
    let mut lead = None;
    for (module, model) in want {
        let rtl = got
            .iter()
            .find(|(m, _)| m == module)
            .map(|&(_, n)| n)
            .unwrap_or_else(|| panic!("{unit} ({sim}): no RTL latency for {module}:\n{}", o.text));
        println!("{unit:<10} {sim:<9} {module}: RTL LATENCY {rtl}, model {model}");
        assert_eq!(
            rtl, model,
            "{unit} ({sim}): {module}'s LATENCY against the model's"
        );
        lead = lead.or(Some(rtl));
    }
    // The first row left after the first module's latency (for hit_record the packer's).
    assert_eq!(
        o.latency, lead,
        "{unit} ({sim}): measured latency against the RTL's"
    );
}

/// Checks one unit's outcome on the table in `dir`: every row passed, at the model's latency.
fn assert_all_passed(sim: &str, dir: &Path, unit: &str, o: &Outcome, min_rows: u64) {
    let m = manifest(dir, unit);
    let depth = m["depth"].as_u64().expect("depth");
    let adversarial = m["rows"][0]["count"].as_u64().unwrap_or(0);
    println!(
        "{unit:<10} {sim:<9} {} passed, {} failed of {depth} rows ({adversarial} adversarial), latency {:?} (model {})",
        o.passed,
        o.failed,
        o.latency,
        model_latency(unit)
    );
    assert_eq!(o.failed, 0, "{unit} ({sim}):\n{}", o.text);
    assert_eq!(
        o.passed, depth,
        "{unit} ({sim}): not every row was checked:\n{}",
        o.text
    );
    assert!(o.passed >= min_rows, "{unit}: only {} rows", o.passed);
    assert!(adversarial > 0 && m["rows"][0]["origin"] == "adversarial");
    assert_eq!(
        o.latency,
        Some(model_latency(unit)),
        "{unit} ({sim}):\n{}",
        o.text
    );
    assert_rtl_latencies(sim, unit, o);
}

/// The large set, and the golden set in Verilator (whose build the large set then reuses).
#[test]
fn rtl_units_pass_ten_thousand_vectors_each_in_both_simulators() {
    let sims = simulators();
    if sims.is_empty() {
        return;
    }
    let t = Tmp::new("rtl_big");
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
    let golden = repo().join("vectors");
    // Per unit, in order: every simulator on the large set, and Verilator on the golden set
    // first (it builds; the large set's run reuses the build). Two cores: two units at a time.
    let mut jobs: Vec<Vec<(&str, &Path, &str)>> = vec![Vec::new(), Vec::new()];
    for (i, unit) in pipe_units().enumerate() {
        for &sim in &sims {
            if sim == "verilator" {
                jobs[i % 2].push((sim, golden.as_path(), unit));
            }
            jobs[i % 2].push((sim, dir.as_path(), unit));
        }
    }
    let results: Vec<(&str, &Path, &str, Outcome, f64)> = std::thread::scope(|s| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|list| {
                s.spawn(move || {
                    list.iter()
                        .map(|&(sim, d, u)| {
                            let start = std::time::Instant::now();
                            let o = run_testbench(sim, d, u);
                            (sim, d, u, o, start.elapsed().as_secs_f64())
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("testbench thread"))
            .collect()
    });
    for (sim, d, unit, o, secs) in &results {
        let big = *d == dir.as_path();
        println!(
            "{} set, {secs:.1} s (build included)",
            if big { "large" } else { "golden" }
        );
        assert_all_passed(sim, d, unit, o, if big { 10_000 } else { 1 });
    }
}

#[test]
fn golden_set_passes() {
    if !icarus() {
        return;
    }
    let dir = repo().join("vectors");
    for unit in pipe_units() {
        let o = run_testbench("icarus", &dir, unit);
        assert_all_passed("icarus", &dir, unit, &o, 1);
    }
}

/// Every file of testbench/rtl/ lints clean with `verilator --lint-only -Wall` (waivers are
/// comments in the files, each with its reason).
#[test]
fn verilator_lint_is_clean() {
    if !verilator_lint() {
        return;
    }
    let out = Command::new("bash")
        .arg(repo().join("testbench/run.sh"))
        .arg("--lint")
        .output()
        .expect("run testbench/run.sh --lint");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let counts: Vec<(String, u64)> = text
        .lines()
        .filter_map(|l| l.strip_prefix("lint "))
        .filter_map(|l| {
            let (m, rest) = l.split_once(": ")?;
            Some((m.to_string(), rest.split(' ').next()?.parse().ok()?))
        })
        .collect();
    println!("{text}");
    assert!(
        counts.len() >= RTL_UNITS.len(),
        "run.sh --lint linted too few files:\n{text}"
    );
    for (module, n) in &counts {
        if LINT_PENDING.contains(&module.as_str()) {
            println!("{module}: {n} warnings, pending its owner's lint fixes (LINT_PENDING)");
            continue;
        }
        assert_eq!(*n, 0, "{module} has lint warnings:\n{text}");
    }
}

/// Files whose lint fixes land with another branch of issue 15 (the reciprocal and sphere
/// change formats there); empty this list when it is merged.
const LINT_PENDING: &[&str] = &[];

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
        ("raygen", "dir_y", 30),
        ("sorter", "out_t9", 290),
        ("sorter", "out_id3", 5),
        ("hit_record", "reused_word", 40),
        ("hit_record", "word", 60),
        ("normal", "u", 20),
        ("normal", "v", 130),
        ("walker_root", "t1_y", 120),
    ] {
        let t = Tmp::new(&format!("corrupt_{unit}_{out_field}"));
        for name in [
            format!("{unit}.hex"),
            format!("{unit}.json"),
            format!("{unit}_pkg.sv"),
            "reciprocal_seed.hex".into(),
        ] {
            std::fs::copy(golden.join(&name), t.dir.join(&name)).expect("copy a golden file");
        }
        let (row, depth) = corrupt_field(&t.dir, unit, out_field, row, |w| w / 2);
        let o = run_testbench("icarus", &t.dir, unit);
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

#[test]
fn walk_issue_units_side_by_side_each_pass_and_each_is_checked() {
    // `--walk-lanes 2`: the transform bench drives 2 transforms, the reciprocal bench 6
    // reciprocals and the walker-root bench 2 roots, each in the same cycles; a corrupted row
    // of a unit other than unit 0 is exactly one failure, so every unit's outputs are checked
    // against its own rows.
    let sims = simulators();
    let t = Tmp::new("lanes_2");
    let r = run_sim(
        &[
            "vectors",
            "--out",
            t.dir.to_str().expect("UTF-8 path"),
            "--walk-lanes",
            "2",
            "--count",
            "500",
            "--seed",
            "7",
            "--width",
            "12",
            "--height",
            "8",
            "--depth",
            "4",
        ],
        None,
        Duration::from_secs(600),
    );
    assert!(r.status.success(), "sim vectors failed:\n{}", r.stderr);
    for (unit, units, out_field, row) in [
        ("transform", 2, "local_o_z", 41usize),
        ("reciprocal", 6, "zero", 203),
        ("walker_root", 2, "t0_z", 117),
    ] {
        for sim in &sims {
            let o = run_testbench(sim, &t.dir, unit);
            let rows = manifest(&t.dir, unit)["depth"].as_u64().unwrap();
            println!(
                "{unit} × {units} ({sim}): {} passed, {} failed",
                o.passed, o.failed
            );
            assert_eq!(
                (o.passed, o.failed),
                (rows, 0),
                "{unit} ({sim}):\n{}",
                o.text
            );
            assert!(
                o.text
                    .contains(&format!("{unit}: {units} units side by side")),
                "{unit} ({sim}):\n{}",
                o.text
            );
        }
        if !sims.contains(&"icarus") {
            continue;
        }
        let c = Tmp::new(&format!("lanes_2_corrupt_{unit}"));
        for name in [
            format!("{unit}.hex"),
            format!("{unit}.json"),
            format!("{unit}_pkg.sv"),
            "reciprocal_seed.hex".into(),
        ] {
            std::fs::copy(t.dir.join(&name), c.dir.join(&name)).expect("copy a vector file");
        }
        let (row, depth) = corrupt_field(&c.dir, unit, out_field, row, |w| w / 2);
        assert_ne!(
            row % units,
            0,
            "{unit}: corrupt a row of a unit other than unit 0"
        );
        let o = run_testbench("icarus", &c.dir, unit);
        println!(
            "{unit} × {units}: one bit of {out_field} in row {row} (unit {}) flipped: {} passed, {} failed",
            row % units,
            o.passed,
            o.failed
        );
        assert_eq!((o.passed, o.failed), (depth - 1, 1), "{unit}:\n{}", o.text);
        assert!(
            o.text.contains(&format!("row {row}: {out_field}")),
            "{unit}: the failure does not name row {row} and {out_field}:\n{}",
            o.text
        );
    }
}

/// The RTL's latencies read from its source, with no simulator: each module's `LATENCY`
/// localparam, evaluated from the file's own `parameter`/`localparam` defaults (integers,
/// names, `+ - * /`, left to right with `*` and `/` first), against the model's `UnitTimings`
/// module by module. The testbenches print the elaborated values too (`assert_rtl_latencies`).
#[test]
fn rtl_latency_localparams_match_the_model() {
    let units = [
        "sqrt",
        "reciprocal",
        "transform",
        "sphere",
        "raygen",
        "sorter",
        "hit_record",
        "normal",
    ];
    for unit in units {
        for (module, model) in model_module_latencies(unit) {
            let path = repo().join(format!("testbench/rtl/{module}.v"));
            let text = std::fs::read_to_string(&path).expect("read an RTL file");
            let params = verilog_params(&text);
            let rtl = eval_param("LATENCY", &params, 0)
                .unwrap_or_else(|e| panic!("{}: LATENCY: {e}", path.display()));
            // The sorter's source defaults are the 8-lane network (its width comes in as
            // parameters from the vectors' package, 16 lanes at the default datapath): its
            // default LATENCY is compared with the model's for the source's default N.
            let model = if module == "svo_sorter" {
                let n = eval_param("N", &params, 0)
                    .unwrap_or_else(|e| panic!("{}: N: {e}", path.display()));
                let mut dp = DatapathConfig::default();
                dp.sorter.n = u8::try_from(n).expect("N fits a lane count");
                u64::from(UnitTimings::for_datapath(&dp).sorter.latency_cycles)
            } else {
                model
            };
            println!("{module}: LATENCY {rtl} in the source, model {model}");
            assert_eq!(
                rtl, model,
                "{module}: the RTL's LATENCY against the model's"
            );
        }
    }
}

/// `NAME = EXPR` of every `parameter` and `localparam` of a Verilog file (comments removed).
fn verilog_params(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("").trim();
        let Some(rest) = code
            .strip_prefix("localparam ")
            .or_else(|| code.strip_prefix("parameter "))
        else {
            continue;
        };
        for decl in rest.trim_end_matches([';', ',']).split(',') {
            if let Some((name, expr)) = decl.split_once('=') {
                let name = name.split_whitespace().last().unwrap_or("").to_string();
                out.push((name, expr.trim().to_string()));
            }
        }
    }
    out
}

/// The value of parameter `name`: its expression's integers and names (recursively), with
/// `*` and `/` before `+` and `-`.
fn eval_param(name: &str, params: &[(String, String)], depth: u32) -> Result<u64, String> {
    if depth > 16 {
        return Err(format!("{name}: definitions nest too deep"));
    }
    let expr = params
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, e)| e.as_str())
        .ok_or_else(|| format!("no parameter {name}"))?;
    let value = |tok: &str| -> Result<i64, String> {
        match tok.parse::<i64>() {
            Ok(v) => Ok(v),
            Err(_) => eval_param(tok, params, depth + 1).map(|v| v as i64),
        }
    };
    let spaced: String = expr
        .chars()
        .flat_map(|c| match c {
            '+' | '-' | '*' | '/' => vec![' ', c, ' '],
            _ => vec![c],
        })
        .collect();
    let tokens: Vec<&str> = spaced.split_whitespace().collect();
    // Split on + and − into terms, each a product of * and / factors.
    let (mut sum, mut term, mut sign, mut op) = (0i64, 1i64, 1i64, '*');
    let mut expect_value = true;
    for &tok in &tokens {
        match tok {
            "+" | "-" if !expect_value => {
                sum += sign * term;
                (term, op, sign) = (1, '*', if tok == "+" { 1 } else { -1 });
                expect_value = true;
            }
            "*" | "/" if !expect_value => {
                op = tok.chars().next().unwrap_or('*');
                expect_value = true;
            }
            t if expect_value => {
                let v = value(t)?;
                term = if op == '*' { term * v } else { term / v };
                expect_value = false;
            }
            t => return Err(format!("{name} = {expr}: unexpected {t}")),
        }
    }
    let v = sum + sign * term;
    u64::try_from(v).map_err(|_| format!("{name} = {expr} is negative"))
}
