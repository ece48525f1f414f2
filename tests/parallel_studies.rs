//! Parallel studies (`run::parallel::map_in_order`): `sim sweep` on one thread and on several
//! writes the same CSV, JSON, plots and progress lines, wall-time fields aside.

mod common;

use common::process::{run_sim, Scratch};
use std::time::Duration;

/// A sweep's printed lines (progress on stderr, then stdout) with the wall-time column and the closing timing line removed.
fn stdout_without_wall(s: &str) -> String {
    s.lines()
        .filter(|l| !l.contains(" s)") && !l.starts_with("wrote "))
        .map(|l| {
            // Rows end in `wall ms` and, in the progress table, ` [scene]`.
            let (body, scene) = match l.rfind(" [") {
                Some(k) if l.ends_with(']') => l.split_at(k),
                _ => (l, ""),
            };
            let body = body.trim_end();
            let cut = body
                .rfind(' ')
                .filter(|&k| body[k + 1..].chars().all(|c| c.is_ascii_digit()))
                .map_or(body, |k| &body[..k]);
            // The wall time is right-aligned: its padding depends on its own width.
            format!("{}{scene}", cut.trim_end())
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The CSV without its wall-time column (the last).
fn csv_without_wall(csv: &str) -> String {
    csv.lines()
        .map(|l| l.rsplit_once(',').map_or(l, |(a, _)| a))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The JSON without the rows' wall times.
fn json_without_wall(text: &str) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(text).expect("sweep.json");
    for r in v["rows"].as_array_mut().expect("rows") {
        r.as_object_mut().expect("row").remove("wall_s");
    }
    v
}

#[test]
fn sweep_on_several_threads_equals_one_thread() {
    let t = Scratch::new("parallel", "sweep");
    let mut outs = Vec::new();
    for threads in ["1", "3"] {
        let dir = t.p(&format!("t{threads}"));
        let r = run_sim(
            &[
                "sweep",
                "--only",
                "default,coarse,recip_iter1,lean,t_frac16",
                "--scene",
                "car",
                "--width",
                "48",
                "--height",
                "32",
                "--frames",
                "2",
                "--threads",
                threads,
                "--out",
                &dir,
            ],
            None,
            Duration::from_secs(300),
        );
        assert!(r.status.success(), "{}\n{}", r.stdout, r.stderr);
        outs.push((dir, format!("{}\n{}", r.stderr, r.stdout)));
    }
    let read = |d: &str, f: &str| std::fs::read(std::path::Path::new(d).join(f)).expect(f);
    let text = |d: &str, f: &str| String::from_utf8(read(d, f)).expect("UTF-8");
    let ((a, out_a), (b, out_b)) = (&outs[0], &outs[1]);
    assert_eq!(
        csv_without_wall(&text(a, "sweep.csv")),
        csv_without_wall(&text(b, "sweep.csv"))
    );
    assert_eq!(
        json_without_wall(&text(a, "sweep.json")),
        json_without_wall(&text(b, "sweep.json"))
    );
    for png in ["sweep_cycles.png", "sweep_dsp.png"] {
        assert!(read(a, png) == read(b, png), "{png} differs");
    }
    let (sa, sb) = (stdout_without_wall(out_a), stdout_without_wall(out_b));
    // Progress rows (stderr) and the scene's table (stdout), five configurations each.
    assert!(
        sa.lines().filter(|l| l.contains("recip_iter1")).count() == 2,
        "{sa}"
    );
    assert_eq!(sa, sb);
}

#[test]
fn sweep_refuses_a_zero_thread_count() {
    let t = Scratch::new("parallel", "zero");
    let r = run_sim(
        &["sweep", "--threads", "0", "--out", &t.p("o")],
        None,
        Duration::from_secs(60),
    );
    assert!(!r.status.success());
    assert!(r.stderr.contains("--threads 0"), "{}", r.stderr);
    assert!(!std::path::Path::new(&t.p("o")).exists());
}
