//! The `sim explore` command line: options, progress on stderr, the summary on stdout and the
//! files. Options are plain data: `src/bin/sim/explore.rs` parses them and calls
//! [`run_command`].

use super::output::write_outputs;
use super::run::{run_explore, ExploreResult, ExploreRow, RESOURCES};
use super::space::Space;
use anyhow::{bail, Context, Result};
use rtl_model::datapath::DatapathConfig;
use std::path::PathBuf;
use std::time::Instant;

/// Options of `sim explore`.
#[derive(Debug, Clone)]
pub struct ExploreCommand {
    /// The space file (RON; docs/explore.md).
    pub space: PathBuf,
    /// Folder for the CSV, JSON and PNG files (created if missing).
    pub out: PathBuf,
    /// Largest `.vox` asset file read, bytes.
    pub max_vox_bytes: u64,
}

/// One row as a progress line.
pub fn row_line(space: &Space, r: &ExploreRow) -> String {
    let u = &r.usage;
    let pct = |k: usize| {
        if u.available[k] == 0 {
            0.0
        } else {
            100.0 * u.used[k] as f64 / u.available[k] as f64
        }
    };
    format!(
        "{} point {:>4}{} ({}): {:>9.1} fps {:.3} rays/clk  LUT {:.1} % FF {:.1} % DSP {:.1} % BRAM {:.1} % URAM {:.1} %  {}",
        r.scene,
        r.point,
        if r.default { " default" } else { "" },
        space.describe_values(&r.values),
        r.fps,
        r.rays_per_clock,
        pct(0),
        pct(1),
        pct(2),
        pct(3),
        pct(4),
        if u.fits { "fits".to_string() } else { format!("does not fit: {}", u.why) }
    )
}

/// The summary: per scene the default and the best fitting point.
pub fn summary(space: &Space, result: &ExploreResult) -> String {
    let mut s = String::new();
    for sc in &result.scenes {
        let rows: Vec<&ExploreRow> = result.rows.iter().filter(|r| r.scene == sc.name).collect();
        let fitting = rows.iter().filter(|r| r.usage.fits).count();
        s.push_str(&format!(
            "scene {} ({}×{}, {} frames): {} points, {} fit the part\n",
            sc.name,
            sc.spec.width,
            sc.spec.height,
            sc.spec.frames,
            rows.len(),
            fitting
        ));
        for r in &rows {
            if r.default {
                let on: Vec<&str> = (0..5)
                    .filter(|&k| r.front[k])
                    .map(|k| RESOURCES[k])
                    .collect();
                s.push_str(&format!(
                    "  default:      {}\n                on the fronts of: {}\n",
                    row_line(space, r),
                    if on.is_empty() {
                        "none".to_string()
                    } else {
                        on.join(", ")
                    }
                ));
            }
        }
        match rows.iter().find(|r| r.best) {
            Some(r) => s.push_str(&format!("  best fitting: {}\n", row_line(space, r))),
            None => s.push_str("  best fitting: none (no point fits the part)\n"),
        }
    }
    s
}

/// Runs `sim explore` on the default datapath.
pub fn run_command(a: &ExploreCommand) -> Result<()> {
    let start = Instant::now();
    crate::output::writer::refuse_stdout_folder("--out", &a.out)?;
    if a.out.exists() && !a.out.is_dir() {
        bail!("--out {} exists and is not a folder", a.out.display());
    }
    let dp = DatapathConfig::default();
    let (space, points) = Space::load(&a.space, &dp)?;
    println!(
        "sim explore: {} points ({} fields) x {} scenes on {} threads{}",
        points.len(),
        space.fields.len(),
        space.scenes.len(),
        rayon::current_num_threads(),
        space.sample.map_or_else(String::new, |x| format!(
            ", sampled timing 1/{:.0}",
            1.0 / x.rate
        ))
    );
    let result = run_explore(&space, &points, &dp, a.max_vox_bytes, |r, done, total| {
        eprintln!("[{done}/{total}] {}", row_line(&space, r));
    })?;
    print!("{}", summary(&space, &result));
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    for p in write_outputs(&result, &a.out).map_err(anyhow::Error::msg)? {
        println!("wrote {}", p.display());
    }
    println!(
        "({} points x {} scenes in {:.1} s)",
        points.len(),
        space.scenes.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
