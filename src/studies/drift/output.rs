//! Files of `sim drift`: `drift.csv` (every frame of every pose path), `drift.json` (bounds,
//! per-path summaries and the claims) and `drift.png` (the plot), each written atomically.
//! Nothing in them depends on timing or thread count, so a rerun reproduces them byte for
//! byte.

use super::plot;
use super::run::DriftResult;
use crate::output::figure::encode_png_best;
use crate::output::writer::write_files;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Header of `drift.csv`.
pub const CSV_HEADER: &str = "frame,mode,orthonormality,matrix_error,matrix_bound,t_err_max,t_err_rms,t_err_over_bound,hit_mismatches,instance_mismatches,voxel_mismatches,beyond_bound,beyond_keyframe_bound,t_err_over_keyframe_bound,saturations";

/// The CSV text.
pub fn csv(result: &DriftResult) -> String {
    let mut s = String::with_capacity(result.rows.len() * 96);
    s.push_str(CSV_HEADER);
    s.push('\n');
    for r in &result.rows {
        // `{:e}` is Rust's shortest round-trip form: exact and deterministic.
        let _ = writeln!(
            s,
            "{},{},{:e},{:e},{:e},{:e},{:e},{:e},{},{},{},{},{},{:e},{}",
            r.frame,
            r.mode.name(),
            r.orthonormality,
            r.matrix_error,
            r.matrix_bound,
            r.t_err_max,
            r.t_err_rms,
            r.t_err_over_bound,
            r.hit_mismatches,
            r.instance_mismatches,
            r.voxel_mismatches,
            r.beyond_bound,
            r.beyond_keyframe_bound,
            r.t_err_over_keyframe_bound,
            r.saturations
        );
    }
    s
}

/// Writes the three files into `dir` (which must exist) and returns their paths. The plot is
/// rendered before anything is written, so a drawing error leaves no file behind.
pub fn write_outputs(result: &DriftResult, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let png = encode_png_best(&plot::render(result)?, "drift.png")?;
    let json = serde_json::to_string_pretty(result).map_err(|e| format!("drift.json: {e}"))?;
    let files = [
        ("drift.csv", csv(result).into_bytes()),
        ("drift.json", json.into_bytes()),
        ("drift.png", png),
    ];
    write_files(dir, &files)
}
