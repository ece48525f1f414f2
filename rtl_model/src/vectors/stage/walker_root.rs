//! Walker-root vectors: the walker-root unit (`units::walker_root`) on the walks of the walker
//! table, one row per walk in the same order (row i of `walker_root.hex` is the root of row i
//! of `walker.hex`): origin, 1/|d|, zero and negative flags, half extents in; the mirrored
//! origin, the root's slab times per axis and the entry flag out.
//!
//! Pipeline position: the unit between the reciprocals and the walker's dispatcher. The
//! walker's bench (`tb_walker.sv`) runs a root in front of each walker and checks it only
//! through the walk; these rows check the unit's own outputs bit for bit at its fixed
//! latency, and with k walk-issue lanes (`vectors::lanes`) in k instances side by side
//! (`tb_walker_root.sv`).
//!
//! Output formats, as the RTL's ports: the mirrored origin is one bit wider than `pos` (−o of
//! the most negative code), a slab time one bit wider than `t`, so the ±∞ sentinels of zero
//! axes are the most negative and most positive codes of that width, outside every t code.

use super::walker::{walk_input_fields, WalkTxn};
use crate::datapath::DatapathConfig;
use crate::fixed::{Format, Overflows, SignalId};
use crate::units::walker::{root_latency_cycles, WalkerConfig, WalkerT};
use crate::units::walker_root::root_slabs;
use crate::vectors::layout::{b, s, Direction::*, Layout};
use crate::vectors::table::{Origin, Timing, VectorTable};

const AXES: [&str; 3] = ["x", "y", "z"];

/// The walker-root stage of a datapath.
pub struct WalkerRootStage {
    cfg: WalkerConfig,
    latency: u32,
}

impl WalkerRootStage {
    /// The root unit of `dp`'s walker.
    pub fn new(dp: &DatapathConfig) -> Self {
        Self {
            cfg: dp.walker,
            latency: root_latency_cycles(&dp.walker),
        }
    }

    /// `f` one bit wider (same fraction, quantisation and overflow).
    fn wider(f: Format) -> Format {
        Format {
            width: f.width + 1,
            ..f
        }
    }

    /// A slab time's code in the one-bit-wider output: the sentinels `i64::MIN` / `i64::MAX`
    /// become that width's extreme codes.
    fn t_code(&self, t: WalkerT) -> i64 {
        let top = 1i64 << self.cfg.t.width;
        match t {
            WalkerT::NEG_INF => -top,
            WalkerT::POS_INF => top - 1,
            t => t.raw,
        }
    }

    /// The row layout.
    pub fn layout(&self) -> Layout {
        let c = &self.cfg;
        let mut l = Layout::new();
        walk_input_fields(&mut l, c);
        l.flag(
            "enter",
            Output,
            "the walk enters the root: max(t0) < min(t1), min(t1) > 0, no zero axis outside its slab",
        );
        let t = Self::wider(c.t);
        for a in AXES {
            l.fixed(
                &format!("t0_{a}"),
                Output,
                t,
                "root slab entry time (-e - o')/|d|, m; the most negative code on a zero axis",
            );
        }
        for a in AXES {
            l.fixed(
                &format!("t1_{a}"),
                Output,
                t,
                "root slab exit time (e - o')/|d|, m; the most positive code on a zero axis",
            );
        }
        for a in AXES {
            l.fixed(
                &format!("om_{a}"),
                Output,
                Self::wider(c.pos),
                "mirrored origin o' (-o on a negative axis, exact), m",
            );
        }
        l
    }

    /// The table of the walks `blocks` (the walker table's, [`super::walker::WalkerStage::walk_blocks`]).
    pub fn build(&self, blocks: &[(Origin, Vec<WalkTxn>)]) -> VectorTable {
        let layout = self.layout();
        let mut table = VectorTable::new(
            "walker_root",
            "the walker-root unit on each walk of walker.hex (same rows, same order): local origin, 1/|d|, zero and negative flags, half extents in; entry flag, root slab times per axis (sentinels on zero axes) and the mirrored origin out",
            layout.clone(),
        );
        table.timing = Some(Timing {
            latency_cycles: self.latency,
            ii: 1,
        });
        let mut ov = Overflows::new(&["walker_root"]);
        for (origin, txns) in blocks {
            let rows = txns
                .iter()
                .map(|t| {
                    let inp = &t.input;
                    let r = root_slabs(inp, &self.cfg, &mut ov, SignalId(0));
                    let mut v = Vec::with_capacity(layout.fields().len());
                    v.extend(inp.origin.map(|p| s(p.raw)));
                    v.extend(inp.inv.map(|i| s(i.raw)));
                    v.extend(inp.zero.map(b));
                    v.extend(inp.negative.map(b));
                    v.extend(inp.half.map(|p| s(p.raw)));
                    v.push(b(r.enter));
                    v.extend(r.t0.map(|t| s(self.t_code(t))));
                    v.extend(r.t1.map(|t| s(self.t_code(t))));
                    v.extend(r.origin.map(|p| s(p.raw)));
                    layout.pack(&v)
                })
                .collect();
            table.push_block(*origin, rows);
        }
        table.param("config", self.cfg);
        table.param(
            "rows",
            "row i is the root of walker.hex row i (the same walk's inputs)",
        );
        table
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vectors::stage::walker::WalkerStage;

    #[test]
    fn one_row_per_walk_every_value_fits() {
        let dp = DatapathConfig::default();
        let walker = WalkerStage::new(&dp, Vec::new()).expect("synthetic images");
        let blocks = walker.walk_blocks(&[], 200, 3);
        let (walks, _) = walker.build(&[], 200, 3).expect("timed");
        let st = WalkerRootStage::new(&dp);
        let t = st.build(&blocks);
        assert_eq!(t.rows.len(), walks.rows.len());
        let (l, wl) = (st.layout(), walker.layout());
        let mut entered = 0;
        for (r, w) in t.rows.iter().zip(&walks.rows) {
            for f in ["o_x", "inv_y", "zero_z", "negative_x", "half_z"] {
                assert_eq!(l.read(r, f), wl.read(w, f), "{f}");
            }
            // A walk that does not enter its root misses.
            if l.read(r, "enter") == Some(0) {
                assert_eq!(wl.read(w, "outcome"), Some(0));
            } else {
                entered += 1;
            }
        }
        assert!(entered > 50, "{entered} walks enter their root");
    }
}
