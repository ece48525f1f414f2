//! The stress table: Markdown (for `docs/stability.md` and stdout), CSV and JSON, each
//! deterministic (no timing).

use super::measure::CaseResult;
use std::fmt::Write as _;

fn sci(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.2e}")
    }
}

fn signals(r: &CaseResult) -> String {
    if r.saturated_signals.is_empty() {
        "0".into()
    } else {
        r.saturated_signals
            .iter()
            .map(|(n, c)| format!("{n} {c}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The Markdown table, one row per case.
pub fn markdown(results: &[CaseResult]) -> String {
    let mut s = String::new();
    s.push_str("| case | rays exercise: +0 / −0 / tiny comps, grazing, cand. max, camera in spheres/boxes | ε (m): flushable / not | hits ref / fixed | mismatches hit / inst / voxel (beyond bound) | t err max (÷ bound) | saturations | step limit | zero flushes | sorter extra chunks | max stack | verdict (expected) |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in results {
        let c = &r.census;
        let _ = writeln!(
            s,
            "| `{}` | {} / {} / {}, {}, {}, {}/{} | {} / {} | {} / {} | {} / {} / {} ({}) | {} ({:.3}) | {} | {} | {} | {} | {} | **{}** ({}) |",
            r.name,
            c.zero_components,
            c.negative_zero_components,
            c.tiny_components,
            c.grazing,
            c.candidates_max,
            c.camera_in_spheres,
            c.camera_in_boxes,
            sci(r.eps),
            sci(r.eps_unflushed),
            r.reference_hits,
            r.fixed_hits,
            r.hit_mismatches,
            r.instance_mismatches,
            r.voxel_mismatches,
            r.beyond_bound,
            sci(r.t_err_max),
            r.t_err_over_bound,
            signals(r),
            r.step_limit_hits,
            r.zero_flushes,
            r.sorter_overflow_batches,
            r.max_stack,
            r.verdict.word(),
            r.expected.word()
        );
    }
    s
}

/// Header of the CSV.
pub const CSV_HEADER: &str = "case,width,height,depth_max,eps,eps_unflushed,zero_components,negative_zero_components,tiny_components,grazing,candidates_max,camera_in_spheres,camera_in_boxes,reference_hits,fixed_hits,hit_mismatches,instance_mismatches,voxel_mismatches,beyond_bound,t_err_max,t_err_over_bound,saturations,step_limit_hits,zero_flushes,sorter_overflow_batches,max_stack,verdict,expected";

/// The CSV, one row per case.
pub fn csv(results: &[CaseResult]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in results {
        let c = &r.census;
        let _ = writeln!(
            s,
            "{},{},{},{},{:e},{:e},{},{},{},{},{},{},{},{},{},{},{},{},{},{:e},{:e},{},{},{},{},{},{},{}",
            r.name,
            r.width,
            r.height,
            r.depth_max,
            r.eps,
            r.eps_unflushed,
            c.zero_components,
            c.negative_zero_components,
            c.tiny_components,
            c.grazing,
            c.candidates_max,
            c.camera_in_spheres,
            c.camera_in_boxes,
            r.reference_hits,
            r.fixed_hits,
            r.hit_mismatches,
            r.instance_mismatches,
            r.voxel_mismatches,
            r.beyond_bound,
            r.t_err_max,
            r.t_err_over_bound,
            r.saturations,
            r.step_limit_hits,
            r.zero_flushes,
            r.sorter_overflow_batches,
            r.max_stack,
            r.verdict.word(),
            r.expected.word()
        );
    }
    s
}
