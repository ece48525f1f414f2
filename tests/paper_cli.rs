//! `sim paper` end to end at a tiny size: the four files are written, the table has the four
//! cases with a ratio of 1 for (a), the reference's walks grow from (c) to (b), a figure not
//! measured (`--repeats 0`) reads "–" (empty in the CSV, null in the JSON), `--hw` runs the
//! cycle model on the given hardware and names it, and bad options are refused naming the
//! option with nothing written.

use std::path::PathBuf;
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("svo_paper_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn sim(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(args)
        .output()
        .expect("run sim")
}

#[test]
fn paper_writes_table_csv_json_and_chart() {
    let out = scratch("ok");
    let o = sim(&[
        "paper",
        "--frames",
        "2",
        "--resolution",
        "48x32",
        "--repeats",
        "1",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    for f in ["paper.md", "paper.csv", "paper.json", "paper.png"] {
        assert!(out.join(f).is_file(), "{f} missing; stdout:\n{stdout}");
    }
    // Progress went to stderr, the table to stdout.
    assert!(stderr.contains("reference run 1/1"), "{stderr}");
    assert!(stdout.contains("### 48×32"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("paper.json")).expect("json"))
            .expect("parse");
    let rows = json.as_array().expect("rows");
    let ids: Vec<&str> = rows
        .iter()
        .map(|r| r["case"].as_str().unwrap_or(""))
        .collect();
    assert_eq!(ids, ["a", "a'", "b", "c"]);
    assert_eq!(rows[0]["reference_vs_a"].as_f64(), Some(1.0));
    assert_eq!(rows[0]["cycle_vs_a"].as_f64(), Some(1.0));
    let walks = |k: usize| rows[k]["walks"].as_u64().unwrap_or(0);
    assert!(walks(2) > walks(3), "(b) walks more than (c)");
    let cyc = |k: usize| rows[k]["cycles"].as_u64().unwrap_or(0);
    assert!(cyc(2) > cyc(3), "(b) takes more cycles than (c)");
    let csv = std::fs::read_to_string(out.join("paper.csv")).expect("csv");
    assert_eq!(csv.lines().count(), 5, "{csv}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn paper_refuses_bad_options_and_writes_nothing() {
    let out = scratch("bad");
    let hw_dir = scratch("bad_hw");
    std::fs::create_dir_all(&hw_dir).expect("scratch");
    let small_frame = hw_dir.join("frame_320x192.ron").display().to_string();
    std::fs::write(&small_frame, "(frame: (width: 320, height: 192))").expect("hw file");
    let o_str = out.to_str().expect("utf-8").to_string();
    for (args, msg) in [
        (
            vec!["--resolution", "2000x10"],
            "--resolution 2000x10: at most 1280x768",
        ),
        (
            vec!["--resolution", "640"],
            "--resolution 640: expected WxH",
        ),
        (vec!["--frames", "0"], "--frames 0: must be within 1 and 48"),
        (vec!["--repeats", "0", "--no-cycle"], "nothing to measure"),
        (
            vec!["--hw", "no/such/hardware.ron"],
            "cannot read hardware file no/such/hardware.ron",
        ),
        // The hardware's frame bounds the resolutions.
        (
            vec!["--hw", &small_frame, "--resolution", "640x384"],
            "--resolution 640x384: at most 320x192",
        ),
    ] {
        let mut a = vec!["paper", "--out", &o_str];
        a.extend(args.iter().copied());
        let o = sim(&a);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(stderr.contains(msg), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    let _ = std::fs::remove_dir_all(&hw_dir);
}

/// `tests/golden/small_hw.ron` (4 walkers × 4 contexts, a small cache).
fn small_hw() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden/small_hw.ron")
        .display()
        .to_string()
}

/// The cycle-model fps column of each case's row in `paper.md`.
fn cycle_fps(md: &str) -> Vec<String> {
    md.lines()
        .filter(|l| l.starts_with("| ("))
        .map(|l| {
            l.split('|')
                .map(str::trim)
                .nth(6)
                .expect("cells")
                .to_string()
        })
        .collect()
}

/// `--hw FILE` runs the cycle model on that hardware and the table says so: the small
/// machine's frame rates differ from the default's on the same frames.
#[test]
fn paper_runs_the_given_hardware() {
    let run = |name: &str, hw: Option<&str>| {
        let out = scratch(name);
        let o_str = out.to_str().expect("utf-8").to_string();
        let mut a = vec![
            "paper",
            "--frames",
            "2",
            "--resolution",
            "64x40",
            "--repeats",
            "0",
            "--out",
            &o_str,
        ];
        if let Some(hw) = hw {
            a.extend(["--hw", hw]);
        }
        let o = sim(&a);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let md = std::fs::read_to_string(out.join("paper.md")).expect("paper.md");
        let _ = std::fs::remove_dir_all(&out);
        md
    };
    let small_hw = small_hw();
    let default = run("hw_default", None);
    let small = run("hw_small", Some(&small_hw));
    assert!(
        default.contains("cycle model: default hardware at 300 MHz"),
        "{default}"
    );
    assert!(
        small.contains(&format!("cycle model: hardware {small_hw} at 300 MHz")),
        "{small}"
    );
    let (d, s) = (cycle_fps(&default), cycle_fps(&small));
    assert_eq!((d.len(), s.len()), (4, 4), "{default}\n{small}");
    assert!(d.iter().all(|f| f != "–") && s.iter().all(|f| f != "–"));
    assert_ne!(d, s, "the small machine's frame rates are the default's");
}

/// With `--repeats 0` the reference does not run, so its counters (walks, reused pixels) are
/// not measured: they read "–" in the table, are empty in the CSV and null in the JSON, like
/// its times, and never 0.
#[test]
fn paper_without_reference_leaves_its_counters_unmeasured() {
    let out = scratch("norepeat");
    let o = sim(&[
        "paper",
        "--frames",
        "1",
        "--resolution",
        "48x32",
        "--repeats",
        "0",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let md = std::fs::read_to_string(out.join("paper.md")).expect("paper.md");
    assert!(md.contains("reference: not run"), "{md}");
    let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| (")).collect();
    assert_eq!(rows.len(), 4, "{md}");
    for row in rows {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        // | case | scene | ref s | ref fps | ref ÷ (a) | cycle fps | cycle ÷ (a) | walks | reused |
        assert_eq!(cells[3..6], ["– / –", "–", "–"], "reference columns: {row}");
        assert_ne!(cells[6], "–", "the cycle model ran: {row}");
        assert_eq!(cells[8..10], ["–", "–"], "walks and reused px: {row}");
    }
    let csv = std::fs::read_to_string(out.join("paper.csv")).expect("csv");
    let mut lines = csv.lines();
    let header = csv_fields(lines.next().expect("header"));
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    for line in lines {
        let fields = csv_fields(line);
        assert_eq!(fields.len(), header.len(), "{line}");
        for name in ["reference_best_s", "walks", "reused"] {
            assert_eq!(fields[col(name)], "", "{name} in {line}");
        }
        assert_ne!(fields[col("cycles")], "", "cycles in {line}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("paper.json")).expect("json"))
            .expect("parse");
    for r in json.as_array().expect("rows") {
        for key in ["reference_best_s", "walks", "reused"] {
            assert!(r[key].is_null(), "{key} in {r}");
        }
        assert!(r["cycles"].as_u64().is_some_and(|n| n > 0), "cycles in {r}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// The fields of a CSV line whose quoted fields hold no quote (the label and flags may hold
/// commas).
fn csv_fields(line: &str) -> Vec<String> {
    let (mut fields, mut cur, mut quoted) = (Vec::new(), String::new(), false);
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(std::mem::take(&mut cur)),
            _ => cur.push(ch),
        }
    }
    fields.push(cur);
    fields
}
