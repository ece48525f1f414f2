//! Files of `sim explore`: `explore.csv` (one row per point and scene), `explore.json` (the
//! fields, scenes and rows) and the five fronts `explore_lut.png`, `explore_ff.png`,
//! `explore_dsp.png`, `explore_bram.png`, `explore_uram.png`, written together through the
//! project's writer: everything is encoded first, so an error leaves no file behind.
//!
//! Pipeline position: the last step of `sim explore`. No wall time is written: every byte is
//! a function of the space, so one thread and two give the same files.

use super::plot;
use super::run::{ExploreResult, RESOURCES};
use crate::output::figure::encode_png_best;
use crate::output::writer::write_files;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The PNG of each resource, in the order of [`RESOURCES`].
pub const PLOTS: [&str; 5] = [
    "explore_lut.png",
    "explore_ff.png",
    "explore_dsp.png",
    "explore_bram.png",
    "explore_uram.png",
];

/// A CSV cell: quoted when it holds a comma or a quote.
fn cell(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The CSV text: `point,scene,<fields…>,default,cycles_per_frame,fps,rays_per_clock,lut,ff,
/// dsp48e2,bram36,uram288,fits,why,front_lut,…,front_uram,best`.
pub fn csv(result: &ExploreResult) -> String {
    let mut s = String::new();
    s.push_str("point,scene");
    for f in &result.fields {
        let _ = write!(s, ",{}", cell(f));
    }
    s.push_str(
        ",default,cycles_per_frame,fps,rays_per_clock,lut,ff,dsp48e2,bram36,uram288,fits,why",
    );
    for r in RESOURCES {
        let _ = write!(s, ",front_{}", r.to_lowercase());
    }
    s.push_str(",best\n");
    for r in &result.rows {
        let _ = write!(s, "{},{}", r.point, cell(&r.scene));
        for v in &r.values {
            let _ = write!(s, ",{}", cell(v));
        }
        let u = &r.usage;
        // `{}` prints Rust's shortest round-trip form: exact and deterministic.
        let _ = write!(
            s,
            ",{},{},{},{},{},{},{},{},{},{},{}",
            r.default,
            r.cycles_per_frame,
            r.fps,
            r.rays_per_clock,
            u.used[0],
            u.used[1],
            u.used[2],
            u.used[3],
            u.used[4],
            u.fits,
            cell(&u.why)
        );
        for f in r.front {
            let _ = write!(s, ",{f}");
        }
        let _ = writeln!(s, ",{}", r.best);
    }
    s
}

/// Every file's name and bytes.
pub fn encode(result: &ExploreResult) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
    let json = serde_json::to_string_pretty(result).map_err(|e| format!("explore.json: {e}"))?;
    let mut files = vec![
        ("explore.csv", csv(result).into_bytes()),
        ("explore.json", json.into_bytes()),
    ];
    for (k, name) in PLOTS.iter().enumerate() {
        files.push((*name, encode_png_best(&plot::render(result, k)?, name)?));
    }
    Ok(files)
}

/// Writes the files into `dir` (which must exist) and returns their paths.
pub fn write_outputs(result: &ExploreResult, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let files = encode(result)?;
    write_files(dir, &files)
}
