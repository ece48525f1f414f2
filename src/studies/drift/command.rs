//! The `sim drift` command line: options, progress and the closing summary. Options are plain
//! data: the command line (`src/bin/sim/drift.rs`) parses them and calls [`run_command`].

use super::output::write_outputs;
use super::run::{run_drift, DriftOptions, Mode};
use anyhow::{bail, Context, Result};
use std::path::PathBuf;
use std::time::Instant;

/// Options of `sim drift`.
#[derive(Debug, Clone)]
pub struct DriftCommand {
    /// Frames of the animation (at least 2).
    pub frames: u32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Octree depth of the spinning part (1-12).
    pub depth: u8,
    /// Folder for drift.csv, drift.json and drift.png (created if missing).
    pub out: PathBuf,
}

/// Runs `sim drift`.
pub fn run_command(a: &DriftCommand) -> Result<()> {
    if !(1..=12).contains(&a.depth) {
        bail!("--depth {} is out of range (1 to 12)", a.depth);
    }
    crate::output::writer::refuse_stdout_folder("--out", &a.out)?;
    if a.out.exists() && !a.out.is_dir() {
        bail!("--out {} exists and is not a folder", a.out.display());
    }
    let opts = DriftOptions::new(a.frames, a.width, a.height, a.depth);
    println!(
        "sim drift: {} frames at {}x{}, depth {}: (a) keyframes in fixed point, (b) incremental with and without re-orthonormalisation",
        a.frames, a.width, a.height, a.depth
    );
    let start = Instant::now();
    let step = (a.frames / 10).max(1);
    let result = run_drift(&opts, |n| {
        if (n + 1) % step == 0 {
            eprintln!(
                "  frame {}/{} after {:.1} s",
                n + 1,
                a.frames,
                start.elapsed().as_secs_f64()
            );
        }
    })
    .with_context(|| {
        format!(
            "sim drift --frames {} --width {} --height {} --depth {}",
            a.frames, a.width, a.height, a.depth
        )
    })?;
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let paths = write_outputs(&result, &a.out).map_err(anyhow::Error::msg)?;
    let b = &result.bounds;
    println!(
        "bounds: (a) matrix {:.3e}, orthonormality {:.3e}; (b) orthonormality {:.3e}, matrix at frame {} {:.3e}",
        b.keyframe_matrix,
        b.keyframe_orthonormality,
        b.incremental_orthonormality,
        a.frames - 1,
        b.incremental_matrix_at_end
    );
    println!(
        "{:<22} {:>11} {:>11} {:>11} {:>11} {:>8} {:>11} {:>11} {:>10} {:>8} {:>10} {:>6}",
        "path",
        "orth max",
        "orth last",
        "matrix max",
        "t err max",
        "t/bound",
        "t 1st 10%",
        "t last 10%",
        "mismatch",
        "beyond",
        "beyond(a)",
        "sat"
    );
    for s in &result.summary {
        // beyond: mismatches and t errors beyond the path's own bound; beyond(a): beyond the
        // bound a pose rebuilt from the keys guarantees.
        println!(
            "{:<22} {:>11.3e} {:>11.3e} {:>11.3e} {:>11.3e} {:>8.3} {:>11.3e} {:>11.3e} {:>10} {:>8} {:>10} {:>6}",
            s.mode.name(),
            s.orthonormality_max,
            s.orthonormality_last,
            s.matrix_error_max,
            s.t_err_max,
            s.t_err_over_bound_max,
            s.t_err_max_first_tenth,
            s.t_err_max_last_tenth,
            s.mismatches,
            s.beyond_bound,
            s.beyond_keyframe_bound,
            s.saturations
        );
    }
    let c = &result.claims;
    let yes = |b: bool| if b { "yes" } else { "NO" };
    println!(
        "claims: (a) bounded {}; (b) with re-orthonormalisation bounded {}; (b) without it drifts {}",
        yes(c.keyframe_bounded),
        yes(c.incremental_bounded),
        yes(c.no_reorth_drifts)
    );
    for p in paths {
        println!("wrote {}", p.display());
    }
    println!(
        "({} modes x {} frames in {:.1} s)",
        Mode::ALL.len(),
        a.frames,
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
