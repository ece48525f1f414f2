//! `sim` with the cycle model (the default): the JSON report's cycle fields, the waveform file
//! read back with the `vcd` crate's parser, the transaction log, and bad hardware input.

mod common;

use common::process::{run_sim, Scratch};
use std::time::Duration;

const LIMIT: Duration = Duration::from_secs(300);

#[test]
fn report_vcd_and_transaction_log() {
    let t = Scratch::new("cycle_cli", "report");
    let (json, vcd, log) = (t.p("r.json"), t.p("w.vcd"), t.p("log.jsonl"));
    let r = run_sim(
        &[
            "--width",
            "64",
            "--height",
            "48",
            "--frames",
            "3",
            "--depth",
            "7",
            "--no-png",
            "--report-json",
            &json,
            "--vcd",
            &vcd,
            "--vcd-cycles",
            "100:900",
            "--transaction-log",
            &log,
            "--log-count",
            "50",
            "--cross-check",
        ],
        None,
        LIMIT,
    );
    assert!(r.status.success(), "{}\n{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("bound:"), "{}", r.stdout);
    let rep: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(rep["options"]["model"], "cycle");
    for f in rep["frames"].as_array().unwrap() {
        let cycles = f["cycles"].as_u64().unwrap();
        assert!(cycles >= 64 * 48);
        let fps = f["fps_at_clock"].as_f64().unwrap();
        assert!((fps - 300e6 / cycles as f64).abs() < 1e-6 * fps);
        assert!(f["rays_per_cycle"].as_f64().unwrap() <= 1.0);
        let stages = f["stages"].as_array().unwrap();
        assert!(stages.len() >= 8);
        for s in stages {
            let sum: u64 = ["busy", "starved", "backpressured", "idle"]
                .iter()
                .map(|k| s[k].as_u64().unwrap())
                .sum();
            assert_eq!(sum, cycles, "{s}");
            assert!(s["name"].is_string());
        }
        let m = &f["memory"];
        for k in [
            "node_fetches",
            "bytes",
            "cache_hit_rate",
            "dram_bandwidth_pct",
        ] {
            assert!(m[k].is_number(), "memory.{k}");
        }
        assert!(f["bound"]["limit"].is_string());
        assert!(f["ops_per_pixel"]["multiplies"].is_number());
    }
    let s = &rep["summary"];
    for k in ["fps_at_clock", "sim_rays_per_s", "sim_cycles_per_s"] {
        assert!(s[k].as_f64().unwrap() > 0.0, "summary.{k}");
    }
    assert!(s["resources"]["used"]["dsp48e2"].as_u64().unwrap() > 0);
    assert!(rep["hardware"]["clock_mhz"].as_u64() == Some(300));

    // The waveform: parse it back and check the signals and the window.
    let file = std::io::BufReader::new(std::fs::File::open(&vcd).unwrap());
    let mut parser = vcd::Parser::new(file);
    let header = parser.parse_header().unwrap();
    let occ = header
        .find_var(&["top", "pipeline", "raygen_to_sphere", "occupancy"])
        .expect("raygen_to_sphere.occupancy");
    let ready = header
        .find_var(&["top", "pipeline", "raygen_to_sphere", "ready"])
        .expect("ready");
    assert!(header
        .find_var(&["top", "pipeline", "walkers", "w0", "busy_contexts"])
        .is_some());
    assert!(header
        .find_var(&["top", "pipeline", "walkers", "w15", "issue"])
        .is_some());
    assert!(header
        .find_var(&["top", "pipeline", "node_memory", "outstanding_reads"])
        .is_some());
    let (occ_code, ready_code) = (occ.code, ready.code);
    let (mut t_max, mut changes, mut occ_values) = (0u64, 0u64, Vec::new());
    for cmd in parser {
        match cmd.unwrap() {
            vcd::Command::Timestamp(t) => t_max = t_max.max(t),
            vcd::Command::ChangeVector(c, v) if c == occ_code => {
                changes += 1;
                let x = v
                    .iter()
                    .fold(0u64, |a, b| (a << 1) | u64::from(b == vcd::Value::V1));
                occ_values.push(x);
            }
            vcd::Command::ChangeScalar(c, _) if c == ready_code => changes += 1,
            _ => {}
        }
    }
    let period_ps = 3334; // 300 MHz, rounded to an even number of picoseconds
    assert!(t_max <= 900 * period_ps + period_ps, "window end: {t_max}");
    assert!(t_max >= 100 * period_ps, "window start: {t_max}");
    assert!(changes > 0, "no FIFO activity in the window");
    assert!(
        occ_values.iter().all(|&v| v <= 4),
        "occupancy above the depth: {occ_values:?}"
    );

    // The transaction log: one JSON object per record, stages in order, times consistent.
    let text = std::fs::read_to_string(&log).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 50);
    for l in lines {
        let v: serde_json::Value = serde_json::from_str(l).unwrap();
        let st = v["stages"].as_array().unwrap();
        assert_eq!(st[0]["stage"], "raygen");
        assert_eq!(st.last().unwrap()["stage"], "write");
        let mut prev = 0;
        for s in st {
            let e = s["entered"].as_u64().unwrap();
            let l = s["left"].as_u64().unwrap();
            assert!(e >= prev && l >= e, "{v}");
            prev = l;
        }
    }
}

#[test]
fn bad_hardware_files_are_errors_naming_the_problem() {
    let t = Scratch::new("cycle_cli", "badhw");
    let cases = [
        ("(walker_pool: (walkers: 0))", "walkers"),
        ("(clock_mhz: 300, walker_pool: (walker: 3))", "walker"),
        ("(clock_mhz: ", "malformed"),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let f = t.p(&format!("hw{i}.ron"));
        std::fs::write(&f, text).unwrap();
        let r = run_sim(
            &[
                "--width", "16", "--height", "16", "--frames", "1", "--no-png", "--hw", &f,
            ],
            None,
            LIMIT,
        );
        assert!(!r.status.success());
        assert!(r.stderr.contains(want), "{text}: {}", r.stderr);
        assert!(r.stderr.contains(&format!("hw{i}.ron")), "{}", r.stderr);
    }
    let r = run_sim(
        &[
            "--width", "2000", "--height", "16", "--frames", "1", "--no-png",
        ],
        None,
        LIMIT,
    );
    assert!(!r.status.success());
    assert!(r.stderr.contains("larger than"), "{}", r.stderr);
    // Implicit (depth 16) assets: the cycle model refuses them, naming the way out, and
    // leaves nothing behind.
    let out = t.p("out16");
    let r = run_sim(
        &[
            "--width", "16", "--height", "16", "--frames", "1", "--depth", "16", "--out", &out,
        ],
        None,
        LIMIT,
    );
    assert!(!r.status.success());
    assert!(r.stderr.contains("--model reference"), "{}", r.stderr);
    assert!(
        !std::path::Path::new(&out).exists(),
        "output folder left behind"
    );
    let r = run_sim(
        &[
            "--frames",
            "1",
            "--no-png",
            "--vcd",
            &t.p("x.vcd"),
            "--vcd-cycles",
            "9:3",
        ],
        None,
        LIMIT,
    );
    assert!(!r.status.success());
    assert!(r.stderr.contains("FROM is after TO"), "{}", r.stderr);
}

#[test]
fn lift_bound_at_the_clock_has_nothing_to_lift_and_succeeds() {
    // A single static SVO under a still camera at 48×32 runs at the clock's limit (the bound
    // line reads `clock`): `--lift bound` must say so and exit 0, not refuse after the run.
    let r = run_sim(
        &[
            "--scene",
            "scenes/static_single.ron",
            "--width",
            "48",
            "--height",
            "32",
            "--frames",
            "3",
            "--threads",
            "1",
            "--no-png",
            "-q",
            "--lift",
            "bound",
        ],
        Some(std::path::Path::new(env!("CARGO_MANIFEST_DIR"))),
        LIMIT,
    );
    assert!(r.status.success(), "{}\n{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("bound: clock"), "{}", r.stdout);
    assert!(
        r.stdout
            .contains("lift bound: the bound is clock: the frame is already at the clock's limit"),
        "{}",
        r.stdout
    );
    // A limit no hardware field lifts, asked for by name, is still refused before the run.
    let r = run_sim(&["--lift", "clock", "--frames", "1"], None, LIMIT);
    assert!(!r.status.success());
    assert!(
        r.stderr.contains("no hardware field lifts it"),
        "{}",
        r.stderr
    );
}
