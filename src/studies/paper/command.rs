//! `sim paper` end to end: runs [`super::measure`], formats the table (Markdown text, CSV,
//! JSON) and draws the chart, then writes `paper.md`, `paper.csv`, `paper.json` and
//! `paper.png` into the output folder through `output::writer` (all or nothing: every file is
//! encoded before the first is written).
//!
//! Pipeline position: called by `src/bin/sim/paper.rs` with plain options.

use super::measure::{measure, PaperConfig, Row};
use crate::output::writer::write_files;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("–".into(), |x| format!("{x:.digits$}"))
}

/// A count, or "–" when it was not measured (the reference's counters with `--repeats 0`).
fn count(v: Option<u64>) -> String {
    v.map_or("–".into(), |n| n.to_string())
}

/// The table as Markdown, one block per resolution.
pub fn table(rows: &[Row], c: &PaperConfig, threads: usize, clock_mhz: u32) -> String {
    let mut s = String::new();
    let timing = match (&c.sample, c.cycle) {
        (_, false) => "not run".to_string(),
        (None, true) => "every cycle simulated".to_string(),
        (Some(sc), true) => format!(
            "sampled: one band of {} rows in {} timed",
            sc.band_rows, sc.period
        ),
    };
    let reference = if c.repeats == 0 {
        "not run".to_string()
    } else {
        format!(
            "f64, {threads} threads, best of {} runs (cases alternating), wall time of the whole \
             animation",
            c.repeats
        )
    };
    let _ = writeln!(
        s,
        "Espe et al. Fig. 7 on this model: {} frames; reference: {reference}; cycle model: \
         {} at {clock_mhz} MHz, {timing}.\n",
        c.frames, c.hw_name
    );
    let mut res: Vec<(u32, u32)> = Vec::new();
    for r in rows {
        if !res.contains(&(r.width, r.height)) {
            res.push((r.width, r.height));
        }
    }
    for (w, h) in res {
        let _ = writeln!(s, "### {w}×{h}\n");
        let _ = writeln!(
            s,
            "| case | scene and switches | reference s (best / median) | reference fps | ref ÷ (a) | cycle-model fps | cycle ÷ (a) | walks | reused px |"
        );
        let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|");
        for r in rows.iter().filter(|r| (r.width, r.height) == (w, h)) {
            let _ = writeln!(
                s,
                "| ({}) | {} `{}` | {} / {} | {} | {} | {} | {} | {} | {} |",
                r.case,
                r.label,
                r.flags,
                opt(r.reference_best_s, 3),
                opt(r.reference_median_s, 3),
                opt(r.reference_fps, 1),
                opt(r.reference_vs_a, 3),
                opt(r.cycle_fps, 1),
                opt(r.cycle_vs_a, 3),
                count(r.walks),
                count(r.reused)
            );
        }
        let _ = writeln!(s);
    }
    s
}

/// The rows as CSV (a header, one line per case and resolution; empty fields: not run).
pub fn csv(rows: &[Row]) -> String {
    let f = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
    let c = |v: Option<u64>| v.map_or(String::new(), |n| n.to_string());
    let mut s = String::from(
        "case,label,flags,width,height,frames,reference_best_s,reference_median_s,reference_fps,reference_vs_a,walks,reused,cycles,cycle_fps,cycle_vs_a,cycle_sampled\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},\"{}\",\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.case,
            r.label,
            r.flags,
            r.width,
            r.height,
            r.frames,
            f(r.reference_best_s),
            f(r.reference_median_s),
            f(r.reference_fps),
            f(r.reference_vs_a),
            c(r.walks),
            c(r.reused),
            c(r.cycles),
            f(r.cycle_fps),
            f(r.cycle_vs_a),
            r.cycle_sampled
        );
    }
    s
}

/// Runs the study and writes its four files into `out` (created if missing); returns the
/// table and the paths written. `progress` gets a line per finished step.
pub fn run_command(
    c: &PaperConfig,
    out: &Path,
    progress: &mut dyn FnMut(&str),
) -> Result<(String, Vec<PathBuf>), String> {
    if c.resolutions.is_empty() {
        return Err("no resolution to run".into());
    }
    if c.repeats == 0 && !c.cycle {
        return Err(
            "nothing to measure: no reference run (--repeats 0) and no cycle model (--no-cycle)"
                .into(),
        );
    }
    crate::output::writer::refuse_stdout_folder("--out", out).map_err(|e| e.to_string())?;
    let clock_mhz = c.hw.clock_mhz;
    let threads = rayon::current_num_threads();
    let rows = measure(c, progress)?;
    let md = table(&rows, c, threads, clock_mhz);
    let json = serde_json::to_vec_pretty(&rows).map_err(|e| format!("paper.json: {e}"))?;
    let png = super::plot::render(&rows, clock_mhz)?;
    let png = crate::output::figure::encode_png_best(&png, "paper.png")?;
    std::fs::create_dir_all(out).map_err(|e| format!("--out {}: {e}", out.display()))?;
    let paths = write_files(
        out,
        &[
            ("paper.md", md.clone().into_bytes()),
            ("paper.csv", csv(&rows).into_bytes()),
            ("paper.json", json),
            ("paper.png", png),
        ],
    )?;
    Ok((md, paths))
}
