//! The human summary of an elaboration, printed by `sim` before the first frame.
//!
//! Pipeline position: output only. One line per unit (what happened, what it saves, why),
//! then the totals against the full pipeline's estimate.

use super::Elaboration;
use std::fmt;

/// Block RAM bits as Kib or Mib.
fn bits(b: u64) -> String {
    if b >= 1 << 20 {
        format!("{:.2} Mib", b as f64 / f64::from(1u32 << 20))
    } else if b > 0 {
        format!("{:.1} Kib", b as f64 / 1024.0)
    } else {
        "-".into()
    }
}

fn num(n: u64) -> String {
    if n == 0 {
        "-".into()
    } else {
        n.to_string()
    }
}

impl fmt::Display for Elaboration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Elaboration ({}):",
            if self.applied {
                "derived from the scene; --no-prune keeps everything"
            } else {
                "--no-prune: the full pipeline runs; what elaboration would do"
            }
        )?;
        writeln!(
            f,
            "  {:<18} {:<16} {:>7} {:>6} {:>7} {:>10} {:>5} {:>9}  why",
            "unit", "", "DSP48E2", "BRAM36", "URAM288", "RAM bits", "CEs", "cyc/ray"
        )?;
        for d in &self.decisions {
            let s = d.saved;
            let label = d.action.label();
            writeln!(
                f,
                "  {:<18} {:<16} {:>7} {:>6} {:>7} {:>10} {:>5} {:>9}  {}",
                d.unit,
                label,
                num(s.dsp48e2),
                num(s.bram36),
                num(s.uram288),
                bits(s.ram_bits),
                num(s.comparators),
                num(s.latency_cycles),
                d.reason
            )?;
        }
        let t = self.total_saved();
        // Applied, the arrow ends at the elaborated estimate: full − savings, plus what a kept
        // unit costs that the full pipeline does not have (the tile-list memory).
        let to = match self.applied {
            true => self.elaborated,
            false => self.full.saturating_sub(rtl_model::resources::Resources {
                dsp48e2: t.dsp48e2,
                bram36: t.bram36,
                uram288: t.uram288,
            }),
        };
        write!(
            f,
            "  saved{}: {} DSP48E2 ({} → {}), {} BRAM36 ({} → {}), {} URAM288 ({} → {}), {} of RAM, {} sorter comparators, {} cycles of latency per ray (estimate; measured cycles: docs/elaboration.md)",
            if self.applied { "" } else { " if applied" },
            t.dsp48e2,
            self.full.dsp48e2,
            to.dsp48e2,
            t.bram36,
            self.full.bram36,
            to.bram36,
            t.uram288,
            self.full.uram288,
            to.uram288,
            bits(t.ram_bits),
            t.comparators,
            t.latency_cycles
        )
    }
}
