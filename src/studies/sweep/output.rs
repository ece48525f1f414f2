//! Files of `sim sweep`: `sweep.csv` (one row per scene and configuration), `sweep.json` (the
//! options, scenes, configurations with their full datapath, rows and the default's verdict)
//! and the two plots `sweep_cycles.png` and `sweep_dsp.png`, each written atomically.
//!
//! Pipeline position: the last step of `sim sweep`. Every figure but `wall_s` (the CSV's last
//! column and one field per JSON row) is a function of the inputs, so a rerun reproduces the
//! files byte for byte apart from that one figure.

use super::plot::{self, Axis};
use super::run::SweepResult;
use crate::output::figure::encode_png_best;
use crate::output::writer::write_files;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Header of `sweep.csv`.
pub const CSV_HEADER: &str = "config,scene,pixels,hit_mismatches,instance_mismatches,voxel_mismatches,t_err_max_m,t_err_rms_m,normal_mismatches,normal_err_max_deg,saturations,leaf_edge_m,error_score,cycles_per_frame,lat_sphere,lat_sqrt,lat_transform,lat_reciprocal,lat_walker_root,mul_sphere,mul_transform,mul_reciprocal,mul_walker_root,dsp48e2,stack_bits,bram_bits,bram36,uram288,front_cycles,dist_cycles_pct,excess_cycles_pct,front_dsp,dist_dsp_pct,excess_dsp_pct,wall_s";

/// The CSV text.
pub fn csv(result: &SweepResult) -> String {
    let mut s = String::with_capacity(256 * (result.rows.len() + 1));
    s.push_str(CSV_HEADER);
    s.push('\n');
    for r in &result.rows {
        let (e, c) = (&r.error, &r.cost);
        // `{:e}` and `{}` print Rust's shortest round-trip form: exact and deterministic.
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:e},{:e},{},{:e},{},{:e},{:e},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.4},{:.4},{},{:.4},{:.4},{:.3}",
            r.config,
            r.scene,
            e.pixels,
            e.hit_mismatches,
            e.instance_mismatches,
            e.voxel_mismatches,
            e.t_err_max,
            e.t_err_rms,
            e.normal_mismatches,
            e.normal_err_max_deg,
            e.saturations,
            e.leaf_edge,
            e.error_score,
            r.cycles_per_frame,
            c.latency.sphere,
            c.latency.sqrt,
            c.latency.transform,
            c.latency.reciprocal,
            c.latency.walker_root,
            c.multipliers.sphere,
            c.multipliers.transform,
            c.multipliers.reciprocal,
            c.multipliers.walker_root,
            c.dsp48e2,
            c.stack_bits,
            c.bram_bits,
            c.bram36,
            c.uram288,
            r.cycles_front.on_front,
            100.0 * r.cycles_front.distance,
            100.0 * r.cycles_front.excess,
            r.dsp_front.on_front,
            100.0 * r.dsp_front.distance,
            100.0 * r.dsp_front.excess,
            r.wall_s
        );
    }
    s
}

/// Writes the four files into `dir` (which must exist) and returns their paths. Everything is
/// encoded before the first file is written, so an error leaves no file behind.
pub fn write_outputs(result: &SweepResult, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let cycles = encode_png_best(&plot::render(result, Axis::Cycles)?, "sweep_cycles.png")?;
    let dsp = encode_png_best(&plot::render(result, Axis::Dsp)?, "sweep_dsp.png")?;
    let json = serde_json::to_string_pretty(result).map_err(|e| format!("sweep.json: {e}"))?;
    let files = [
        ("sweep.csv", csv(result).into_bytes()),
        ("sweep.json", json.into_bytes()),
        ("sweep_cycles.png", cycles),
        ("sweep_dsp.png", dsp),
    ];
    write_files(dir, &files)
}
