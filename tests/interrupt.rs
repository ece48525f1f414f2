//! Clean interruption (docs/report.md §1.7): SIGINT or SIGTERM during a long
//! run removes every unfinished temporary, keeps the finished frames' PNGs, says so in one
//! line and exits 130 / 143.
//!
//! All three tests fail on the code before the interruption handling (1f329ce): the default
//! action of the signal ended the process with the dump's or the table's temporary on disk
//! and no line saying what was kept.

mod common;

use common::process::Scratch;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `sim args` in `cwd`, sends each signal (`INT`, `TERM`) after its pause, and returns the
/// exit code and stderr (killed and failed after 5 minutes).
fn interrupt_sim(args: &[&str], cwd: &Path, signals: &[(&str, Duration)]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start sim");
    let mut err = child.stderr.take().expect("stderr is piped");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    for (signal, after) in signals {
        std::thread::sleep(*after);
        assert!(
            child.try_wait().expect("poll sim").is_none(),
            "sim {args:?} ended before SIG{signal}: make the run longer"
        );
        let sent = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status();
        assert!(sent.is_ok_and(|s| s.success()), "kill -{signal} failed");
    }
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait for sim") {
            break s;
        }
        if start.elapsed() > Duration::from_secs(300) {
            let _ = child.kill();
            panic!("sim {args:?} did not stop within 5 minutes of {signals:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status.code(), reader.join().expect("stderr reader"))
}

/// Every file under `dir` whose name contains `.tmp`.
fn temporaries(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    for e in std::fs::read_dir(dir).expect("list").flatten() {
        let p = e.path();
        if p.is_dir() {
            found.extend(temporaries(&p));
        } else if e.file_name().to_string_lossy().contains(".tmp") {
            found.push(p.display().to_string());
        }
    }
    found
}

#[test]
fn sigint_during_a_long_run_leaves_no_temporaries_and_says_what_was_kept() {
    let t = Scratch::new("interrupt", "sigint");
    let (code, stderr) = interrupt_sim(
        &[
            "--model",
            "reference",
            "--width",
            "1280",
            "--height",
            "768",
            "--frames",
            "48",
            "--out",
            "out",
            "--dump-hits",
            "d.bin",
            "--report-json",
            "r.json",
        ],
        &t.0,
        &[("INT", Duration::from_secs(4))],
    );
    assert_eq!(
        code,
        Some(130),
        "exit status after SIGINT; stderr:\n{stderr}"
    );
    assert_eq!(temporaries(&t.0), Vec::<String>::new(), "stderr:\n{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("interrupted by SIGINT at frame "))
        .unwrap_or_else(|| panic!("no interruption line on stderr:\n{stderr}"));
    assert!(
        line.contains("kept ") && line.contains("unfinished file"),
        "{line}"
    );
    // The unfinished dump and the report are not there; the kept frames are, as named.
    assert!(!t.0.join("d.bin").exists(), "a partial hit dump was left");
    assert!(
        !t.0.join("r.json").exists(),
        "a report of an unfinished run was left"
    );
    let pngs = std::fs::read_dir(t.0.join("out")).map_or(0, |d| d.count());
    if pngs == 0 {
        assert!(line.contains("kept nothing"), "{line}");
    } else {
        assert!(line.contains("out/frame_0000.png"), "{line}");
        assert!(
            line.contains(&format!("({pngs} files)")) || pngs == 1,
            "{line}"
        );
    }
}

#[test]
fn sigterm_during_a_sweep_leaves_no_temporaries() {
    let t = Scratch::new("interrupt", "sigterm");
    let (code, stderr) = interrupt_sim(
        &[
            "sweep",
            "--scene",
            "car",
            "--width",
            "160",
            "--height",
            "96",
            "--frames",
            "16",
            "--out",
            "sweep_out",
        ],
        &t.0,
        &[("TERM", Duration::from_secs(3))],
    );
    assert_eq!(
        code,
        Some(143),
        "exit status after SIGTERM; stderr:\n{stderr}"
    );
    assert_eq!(temporaries(&t.0), Vec::<String>::new(), "stderr:\n{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("interrupted by SIGTERM at configuration "))
        .unwrap_or_else(|| panic!("no interruption line on stderr:\n{stderr}"));
    assert!(line.contains("kept nothing"), "{line}");
    assert!(!t.0.join("sweep_out").join("sweep.csv").exists());
}

#[test]
fn a_second_signal_stops_at_once_and_still_removes_the_temporaries() {
    let t = Scratch::new("interrupt", "second");
    // A cycle-model frame re-executed stage by stage (`--cross-check`) at 1280×768 takes
    // about 10 s, so both signals arrive inside the first frame, before any check.
    let (code, stderr) = interrupt_sim(
        &[
            "--width",
            "1280",
            "--height",
            "768",
            "--frames",
            "4",
            "--cross-check",
            "--out",
            "out",
            "--dump-hits",
            "d.bin",
        ],
        &t.0,
        &[
            ("INT", Duration::from_secs(3)),
            ("TERM", Duration::from_millis(500)),
        ],
    );
    assert_eq!(
        code,
        Some(143),
        "exit status of the second signal; stderr:\n{stderr}"
    );
    assert!(
        stderr.contains("interrupted again by SIGTERM: stopped at once; removed 1 unfinished file"),
        "stderr:\n{stderr}"
    );
    assert_eq!(temporaries(&t.0), Vec::<String>::new(), "stderr:\n{stderr}");
    assert!(!t.0.join("d.bin").exists(), "a partial hit dump was left");
}
