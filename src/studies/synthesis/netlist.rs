//! Logic levels of a mapped netlist: the longest combinational path into every register of a
//! unit, read from the JSON netlist Yosys writes after `synth_xilinx -family xcup`
//! (`testbench/synth/synth.sh`) or `synth_ecp5` (`testbench/synth/pnr_ecp5.sh`), timed by
//! the clock rule of that part (`rtl_model::cost::timing`).
//!
//! Pipeline position: `sim hardware --synth` and `tests/synthesis_yosys.rs`, after the
//! synthesis of a unit. The method: every register-like cell cuts paths — flip-flops, shift
//! registers, DSP48E2 and block/Ultra RAM (as the DSP's own A/B, M and P registers would when
//! Vivado packs the RTL's product register chain into it; Yosys 0.23 leaves them outside, so a
//! DSP48E2 here is taken as registered on both sides), the write side of LUT-RAM and the I/O
//! buffers (a unit's inputs come from registers of the unit before it). The combinational cells
//! between them carry delay: a LUT (or inverter, or a LUT-RAM read from its address) one
//! level with its net, a CARRY4 half an UltraScale+ CARRY8 segment, a MUXF7/8/9 its own. The
//! path into each register is the slowest by the rule's delays; registers are grouped into
//! stages by the RTL name of the net they drive. ECP5's cells map the same way: LUT4 a LUT,
//! CCU2C a carry cell (entered through its own LUT4 from any input but the carry in, which
//! costs a LUT level there), PFUMX and L6MUX21 a MUXF, TRELLIS_DPR16X4 a LUT-RAM read from
//! RAD; TRELLIS_FF, DP16KD and MULT18X18D cut paths (the multiplier as a DSP48E2 does: the
//! rule's reading, which nextpnr does not share when the product's registers stay outside).

use rtl_model::cost::timing::{ClockRule, PathLevels};
use serde::Deserialize;
use std::collections::HashMap;

/// A net bit, or a constant.
#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(untagged)]
enum Bit {
    Net(u64),
    // Constants ("0", "1", "x", "z") start no path.
    #[allow(dead_code)]
    Const(char),
}

#[derive(Deserialize)]
struct Cell {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    port_directions: HashMap<String, String>,
    #[serde(default)]
    connections: HashMap<String, Vec<Bit>>,
}

#[derive(Deserialize)]
struct NetName {
    hide_name: u8,
    bits: Vec<Bit>,
}

#[derive(Deserialize)]
struct Module {
    #[serde(default)]
    cells: HashMap<String, Cell>,
    #[serde(default)]
    netnames: HashMap<String, NetName>,
}

#[derive(Deserialize)]
struct Netlist {
    modules: HashMap<String, Module>,
}

/// The slowest path into one stage's registers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StagePath {
    /// The registers' RTL name (the net their output drives), or the cell kind.
    pub stage: String,
    /// The path's levels.
    pub path: PathLevels,
    /// Its delay by the clock rule, picoseconds (clock-to-out, setup and margin included).
    pub ps: u32,
    /// The path itself, from the register (or input) it starts at to the stage's register:
    /// per net bit on the way, the kind of the cell driving it (empty for the start) and the
    /// bit's RTL name when it has one.
    pub through: Vec<PathCell>,
}

/// One net bit on a stage's slowest path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathCell {
    /// The kind of the combinational cell that drives the bit (`LUT6`, `CARRY4`, …); empty
    /// for the path's start, a register's or an input's output.
    pub kind: String,
    /// The bit's RTL name (its net's stem), if the netlist keeps one.
    pub net: Option<String>,
}

/// How a cell takes part in the timing graph.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Lut,
    Carry,
    Muxf,
    LutRam,
    Register,
    Ignore,
}

fn role(kind: &str) -> Role {
    let k = kind.trim_start_matches('\\');
    if k.starts_with("LUT") || k == "INV" {
        Role::Lut
    } else if k.starts_with("CARRY") || k.starts_with("CCU2") {
        Role::Carry
    } else if k.starts_with("MUXF") || k == "PFUMX" || k == "L6MUX21" {
        Role::Muxf
    } else if k.starts_with("RAM32")
        || k.starts_with("RAM64")
        || k.starts_with("RAM128")
        || k.starts_with("TRELLIS_DPR16X4")
    {
        Role::LutRam
    } else if k == "BUFG" {
        Role::Ignore
    } else {
        // FD*, SRL*, DSP48E2, RAMB*, URAM*, IBUF, OBUF and anything unknown cut paths.
        Role::Register
    }
}

fn is_clock_pin(pin: &str) -> bool {
    // CLK, CLKARDCLK, CLKBWRCLK (UltraScale+); CLK, CLKA, CLKB, CLK0–3 (ECP5).
    pin.starts_with("CLK") || matches!(pin, "C" | "WCLK" | "WCK")
}

/// A carry cell's pin that continues its chain.
fn is_carry_in_pin(pin: &str) -> bool {
    matches!(pin, "CI" | "CIN")
}

/// Arrival at a net bit: (delay in ps, the levels on the way).
type Arrival = (u32, PathLevels);

struct Graph<'a> {
    rule: ClockRule,
    cells: Vec<&'a Cell>,
    roles: Vec<Role>,
    /// Net bit → the combinational cell that drives it.
    driver: HashMap<u64, usize>,
    memo: HashMap<u64, Arrival>,
    /// Net bit → the input bit its slowest arrival came through (bits with a driver only).
    pred: HashMap<u64, u64>,
}

impl Graph<'_> {
    /// The cell's delay and levels.
    fn weight(&self, r: Role) -> Arrival {
        let mut p = PathLevels::default();
        let ps = match r {
            Role::Lut | Role::LutRam => {
                p.luts = 1;
                self.rule.lut_net_ps
            }
            Role::Carry => {
                p.carry = 1;
                self.rule.carry_cell_ps
            }
            Role::Muxf => {
                p.muxf = 1;
                self.rule.muxf_ps
            }
            Role::Register | Role::Ignore => 0,
        };
        (ps, p)
    }

    /// The slowest arrival at net bit `b` (iterative depth-first, memoised).
    fn arrival(&mut self, b: u64) -> Arrival {
        if let Some(a) = self.memo.get(&b) {
            return *a;
        }
        // Explicit stack: (bit, inputs expanded). A bit whose inputs are being expanded is in
        // `open` until it resolves: met again below itself, it is a combinational loop's
        // back edge and is not expanded again (without this, a loop grew the stack without
        // end: 22 GB on svo_core's netlist before the kernel killed the run).
        let mut stack = vec![(b, false)];
        let mut open = std::collections::HashSet::new();
        while let Some((bit, expanded)) = stack.pop() {
            if self.memo.contains_key(&bit) || (!expanded && open.contains(&bit)) {
                continue;
            }
            let Some(&ci) = self.driver.get(&bit) else {
                self.memo.insert(bit, (0, PathLevels::default()));
                continue;
            };
            let inputs = self.comb_inputs(ci);
            if !expanded {
                open.insert(bit);
                stack.push((bit, true));
                for (_, i) in inputs {
                    if !self.memo.contains_key(&i) && !open.contains(&i) {
                        stack.push((i, false));
                    }
                }
                continue;
            }
            open.remove(&bit);
            let (w, p) = self.weight(self.roles[ci]);
            // A carry cell holding its own LUTs (ECP5's CCU2C) is entered through one of them
            // from any input but the chain's: a LUT level with its net before the carry.
            let entry = if self.roles[ci] == Role::Carry && self.rule.carry_holds_luts {
                self.weight(Role::Lut)
            } else {
                (0, PathLevels::default())
            };
            let mut best: Arrival = (0, PathLevels::default());
            let mut best_input = None;
            for (chain, i) in inputs {
                // An input still unresolved here is on a combinational loop: it starts none.
                let mut a = self.memo.get(&i).copied().unwrap_or_default();
                if !chain {
                    a.0 += entry.0;
                    a.1.luts += entry.1.luts;
                }
                if a.0 > best.0 || best_input.is_none() {
                    best = a;
                    best_input = Some(i);
                }
            }
            if let Some(i) = best_input {
                self.pred.insert(bit, i);
            }
            let lv = PathLevels {
                luts: best.1.luts + p.luts,
                carry: best.1.carry + p.carry,
                muxf: best.1.muxf + p.muxf,
            };
            self.memo.insert(bit, (best.0 + w, lv));
        }
        self.memo.get(&b).copied().unwrap_or_default()
    }

    /// The slowest path into net bit `end` (resolved by [`Graph::arrival`]), from its start:
    /// each bit with its driving cell's kind and its RTL name.
    fn path_to(&self, end: u64, names: &HashMap<u64, String>) -> Vec<PathCell> {
        let mut bits = vec![end];
        let mut b = end;
        // Each step goes to an earlier bit of an acyclic walk (a loop's bits start none).
        while let Some(&p) = self.pred.get(&b) {
            if bits.len() > self.cells.len() {
                break;
            }
            bits.push(p);
            b = p;
        }
        bits.iter()
            .rev()
            .map(|b| PathCell {
                kind: self
                    .driver
                    .get(b)
                    .map(|&ci| self.cells[ci].kind.trim_start_matches('\\').to_string())
                    .unwrap_or_default(),
                net: names.get(b).cloned(),
            })
            .collect()
    }

    /// Input bits of a combinational cell that its outputs depend on (a LUT-RAM's read
    /// address only), each with whether it is a carry cell's chain input.
    fn comb_inputs(&self, ci: usize) -> Vec<(bool, u64)> {
        let c = self.cells[ci];
        let ram = self.roles[ci] == Role::LutRam;
        let carry = self.roles[ci] == Role::Carry;
        let mut v = Vec::new();
        // Pins in name order: among inputs of equal delay the first wins, the same each run.
        let mut pins: Vec<(&String, &Vec<Bit>)> = c.connections.iter().collect();
        pins.sort_by(|a, b| a.0.cmp(b.0));
        for (pin, bits) in pins {
            if c.port_directions.get(pin).map(String::as_str) != Some("input") {
                continue;
            }
            // ADDRA–H (UltraScale+ RAM32M/RAM64M), RAD0–3 (ECP5 TRELLIS_DPR16X4).
            if ram && !(pin.starts_with("ADDR") || pin.starts_with("RAD")) {
                continue;
            }
            let chain = carry && is_carry_in_pin(pin);
            v.extend(bits.iter().filter_map(|b| match b {
                Bit::Net(n) => Some((chain, *n)),
                Bit::Const(_) => None,
            }));
        }
        v
    }
}

/// Strips a Yosys net name to its RTL stem: no leading `\`, no bit index, no hierarchy of
/// generate blocks beyond the last name.
fn stem(name: &str) -> String {
    let n = name.trim_start_matches('\\');
    let n = n.split('[').next().unwrap_or(n);
    n.to_string()
}

/// The slowest path into each stage of module `top` in the JSON netlist `json`, slowest
/// first, by `rule`.
pub fn stage_paths(json: &str, top: &str, rule: ClockRule) -> Result<Vec<StagePath>, String> {
    let nl: Netlist = serde_json::from_str(json).map_err(|e| format!("netlist JSON: {e}"))?;
    let m = nl
        .modules
        .get(top)
        .ok_or_else(|| format!("netlist has no module `{top}`"))?;
    // Public names of net bits, for naming stages.
    // A bit with several names takes the shortest (then the first in order), so that the
    // stage names do not depend on the hash map's order.
    let mut names: HashMap<u64, String> = HashMap::new();
    let mut nets: Vec<(&String, &NetName)> = m.netnames.iter().collect();
    nets.sort_by(|a, b| a.0.len().cmp(&b.0.len()).then_with(|| a.0.cmp(b.0)));
    for (n, net) in nets {
        if net.hide_name != 0 {
            continue;
        }
        for b in &net.bits {
            if let Bit::Net(x) = b {
                names.entry(*x).or_insert_with(|| stem(n));
            }
        }
    }
    let mut keys: Vec<&String> = m.cells.keys().collect();
    keys.sort();
    let cells: Vec<&Cell> = keys.iter().map(|k| &m.cells[*k]).collect();
    let roles: Vec<Role> = cells.iter().map(|c| role(&c.kind)).collect();
    let mut driver = HashMap::new();
    for (i, c) in cells.iter().enumerate() {
        if matches!(roles[i], Role::Register | Role::Ignore) {
            continue;
        }
        for (pin, bits) in &c.connections {
            if c.port_directions.get(pin).map(String::as_str) == Some("output") {
                for b in bits {
                    if let Bit::Net(x) = b {
                        driver.insert(*x, i);
                    }
                }
            }
        }
    }
    let mut g = Graph {
        rule,
        cells: cells.clone(),
        roles: roles.clone(),
        driver,
        memo: HashMap::new(),
        pred: HashMap::new(),
    };
    // Per stage: its slowest arrival and the endpoint bit it arrives at.
    let mut stages: HashMap<String, (Arrival, Option<u64>)> = HashMap::new();
    for (i, c) in cells.iter().enumerate() {
        // Every input of a register-like cell ends paths, and so does a LUT-RAM's write side
        // (data, write enable, write address), in pin-name order.
        if !matches!(roles[i], Role::Register | Role::LutRam) {
            continue;
        }
        let mut endpoint: Vec<(&String, &Vec<Bit>)> = c
            .connections
            .iter()
            .filter(|(p, _)| {
                c.port_directions.get(*p).map(String::as_str) == Some("input") && !is_clock_pin(p)
            })
            .collect();
        endpoint.sort_by(|a, b| a.0.cmp(b.0));
        let endpoint_pins: Vec<&Vec<Bit>> = endpoint.into_iter().map(|(_, b)| b).collect();
        let kind = c.kind.trim_start_matches('\\');
        // The stage: the RTL name of the first named net the cell drives.
        let mut outs: Vec<(&String, &Vec<Bit>)> = c
            .connections
            .iter()
            .filter(|(p, _)| c.port_directions.get(*p).map(String::as_str) == Some("output"))
            .collect();
        outs.sort_by(|a, b| a.0.cmp(b.0));
        let out_name = outs
            .into_iter()
            .flat_map(|(_, b)| b.iter())
            .find_map(|b| match b {
                Bit::Net(x) => names.get(x).cloned(),
                Bit::Const(_) => None,
            });
        let stage = match (kind, out_name) {
            ("OBUF", _) => "(outputs)".to_string(),
            ("IBUF", _) => continue,
            (_, Some(n)) => n,
            (k, None) => format!("({k})"),
        };
        for bits in endpoint_pins {
            for b in bits {
                if let Bit::Net(x) = b {
                    let a = g.arrival(*x);
                    let e = stages.entry(stage.clone()).or_default();
                    if a.0 > e.0 .0 || e.1.is_none() {
                        *e = (a, Some(*x));
                    }
                }
            }
        }
    }
    let fixed = rule.clk_to_out_setup_ps + rule.margin_ps;
    let mut out: Vec<StagePath> = stages
        .into_iter()
        .map(|(stage, ((ps, path), end))| StagePath {
            stage,
            path,
            ps: ps + fixed,
            through: end.map(|b| g.path_to(b, &names)).unwrap_or_default(),
        })
        .collect();
    out.sort_by(|a, b| b.ps.cmp(&a.ps).then_with(|| a.stage.cmp(&b.stage)));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rtl_model::cost::timing::ULTRASCALE_PLUS_2;

    /// FD → LUT → CARRY4 → CARRY4 → FD, and FD → FD.
    const NET: &str = r#"{"modules": {"t": {
      "cells": {
        "r0": {"type": "FDRE", "port_directions": {"C": "input", "D": "input", "Q": "output"},
               "connections": {"C": [1], "D": [2], "Q": [3]}},
        "l":  {"type": "LUT2", "port_directions": {"I0": "input", "I1": "input", "O": "output"},
               "connections": {"I0": [3], "I1": ["0"], "O": [4]}},
        "c0": {"type": "CARRY4", "port_directions": {"S": "input", "CO": "output"},
               "connections": {"S": [4], "CO": [5]}},
        "c1": {"type": "CARRY4", "port_directions": {"CI": "input", "O": "output"},
               "connections": {"CI": [5], "O": [6]}},
        "r1": {"type": "FDRE", "port_directions": {"C": "input", "D": "input", "Q": "output"},
               "connections": {"C": [1], "D": [6], "Q": [7]}},
        "r2": {"type": "FDRE", "port_directions": {"C": "input", "D": "input", "Q": "output"},
               "connections": {"C": [1], "D": [3], "Q": [8]}}
      },
      "netnames": {"\\sum_q": {"hide_name": 0, "bits": [7]},
                   "\\copy_q": {"hide_name": 0, "bits": [8]}}
    }}}"#;

    #[test]
    fn the_slowest_path_per_stage_counts_luts_and_carry_segments() {
        let r = ULTRASCALE_PLUS_2;
        let s = stage_paths(NET, "t", r).unwrap();
        assert_eq!(s[0].stage, "sum_q");
        assert_eq!(
            s[0].path,
            PathLevels {
                luts: 1,
                carry: 2,
                muxf: 0
            }
        );
        assert_eq!(r.levels(&s[0].path), 2);
        assert_eq!(s[0].ps, 150 + 300 + 450 + 2 * 50);
        // The path: r0's output, then the LUT and the two carry cells (no net names kept).
        let kinds: Vec<&str> = s[0].through.iter().map(|c| c.kind.as_str()).collect();
        assert_eq!(kinds, ["", "LUT2", "CARRY4", "CARRY4"]);
        let copy = s.iter().find(|p| p.stage == "copy_q").unwrap();
        assert_eq!(copy.path, PathLevels::default());
        assert!(stage_paths(NET, "nope", r).is_err());
    }

    /// FD → LUT a → LUT b → FD, with b feeding a back (a combinational loop, as a netlist
    /// can hold one through a latch-like path the mapper leaves): the walk ends, and the loop's
    /// back edge starts no path.
    const LOOP_NET: &str = r#"{"modules": {"t": {
      "cells": {
        "r0": {"type": "FDRE", "port_directions": {"C": "input", "D": "input", "Q": "output"},
               "connections": {"C": [1], "D": [2], "Q": [3]}},
        "a":  {"type": "LUT2", "port_directions": {"I0": "input", "I1": "input", "O": "output"},
               "connections": {"I0": [3], "I1": [5], "O": [4]}},
        "b":  {"type": "LUT2", "port_directions": {"I0": "input", "I1": "input", "O": "output"},
               "connections": {"I0": [4], "I1": ["0"], "O": [5]}},
        "r1": {"type": "FDRE", "port_directions": {"C": "input", "D": "input", "Q": "output"},
               "connections": {"C": [1], "D": [5], "Q": [6]}}
      },
      "netnames": {"\\loop_q": {"hide_name": 0, "bits": [6]}}
    }}}"#;

    #[test]
    fn a_combinational_loop_ends_the_walk() {
        let s = stage_paths(LOOP_NET, "t", ULTRASCALE_PLUS_2).unwrap();
        let q = s.iter().find(|p| p.stage == "loop_q").unwrap();
        // r0 → a → b: two LUT levels; b's edge back into a adds none.
        assert_eq!(q.path.luts, 2);
        let kinds: Vec<&str> = q.through.iter().map(|c| c.kind.as_str()).collect();
        assert_eq!(kinds, ["", "LUT2", "LUT2"]);
    }

    /// ECP5: TRELLIS_FF → LUT4 → CCU2C (through its LUT input) → CCU2C (carry in) →
    /// TRELLIS_FF; TRELLIS_FF → TRELLIS_DPR16X4 read (RAD0) → TRELLIS_FF; a MULT18X18D cuts.
    const ECP5_NET: &str = r#"{"modules": {"t": {
      "cells": {
        "r0": {"type": "TRELLIS_FF", "port_directions": {"CLK": "input", "DI": "input", "Q": "output"},
               "connections": {"CLK": [1], "DI": [2], "Q": [3]}},
        "l":  {"type": "LUT4", "port_directions": {"A": "input", "B": "input", "C": "input", "D": "input", "Z": "output"},
               "connections": {"A": [3], "B": ["0"], "C": ["0"], "D": ["0"], "Z": [4]}},
        "c0": {"type": "CCU2C", "port_directions": {"A0": "input", "CIN": "input", "COUT": "output", "S0": "output"},
               "connections": {"A0": [4], "CIN": ["0"], "COUT": [5], "S0": [9]}},
        "c1": {"type": "CCU2C", "port_directions": {"A0": "input", "CIN": "input", "S0": "output"},
               "connections": {"A0": ["0"], "CIN": [5], "S0": [6]}},
        "r1": {"type": "TRELLIS_FF", "port_directions": {"CLK": "input", "DI": "input", "Q": "output"},
               "connections": {"CLK": [1], "DI": [6], "Q": [7]}},
        "m":  {"type": "TRELLIS_DPR16X4", "port_directions": {"RAD": "input", "WAD": "input", "DI": "input", "WRE": "input", "WCK": "input", "DO": "output"},
               "connections": {"RAD": [3], "WAD": [3], "DI": [3], "WRE": [3], "WCK": [1], "DO": [10]}},
        "r2": {"type": "TRELLIS_FF", "port_directions": {"CLK": "input", "DI": "input", "Q": "output"},
               "connections": {"CLK": [1], "DI": [10], "Q": [11]}},
        "x":  {"type": "MULT18X18D", "port_directions": {"A0": "input", "CLK0": "input", "P0": "output"},
               "connections": {"A0": [6], "CLK0": [1], "P0": [12]}},
        "r3": {"type": "TRELLIS_FF", "port_directions": {"CLK": "input", "DI": "input", "Q": "output"},
               "connections": {"CLK": [1], "DI": [12], "Q": [13]}}
      },
      "netnames": {"\\sum_q": {"hide_name": 0, "bits": [7]},
                   "\\ram_q": {"hide_name": 0, "bits": [11]},
                   "\\prod": {"hide_name": 0, "bits": [12]},
                   "\\prod_q": {"hide_name": 0, "bits": [13]}}
    }}}"#;

    #[test]
    fn ecp5_cells_time_as_the_part_has_them() {
        use rtl_model::cost::timing::ECP5_6;
        let r = ECP5_6;
        let s = stage_paths(ECP5_NET, "t", r).unwrap();
        let get = |n: &str| s.iter().find(|p| p.stage == n).unwrap().clone();
        // The LUT4, then the first CCU2C entered through its own LUT: two LUT levels and two
        // carry cells; the second cell from the chain adds only its carry.
        let sum = get("sum_q");
        assert_eq!(
            sum.path,
            PathLevels {
                luts: 2,
                carry: 2,
                muxf: 0
            }
        );
        assert_eq!(sum.ps, 150 + 300 + 2 * 729 + 2 * 43);
        assert_eq!(s[0].ps, sum.ps);
        // The LUT-RAM read from its address: one level; its write side ends paths (the
        // `m` stage), and its write clock is no data input.
        assert_eq!(get("ram_q").path.luts, 1);
        // The multiplier cuts: its input is a path end (from the carry chain), its output a
        // path start (nothing between it and prod_q).
        assert_eq!(get("prod").path, sum.path);
        assert_eq!(get("prod_q").path, PathLevels::default());
        // The same netlist by the UltraScale+ rule: a carry cell holds no LUT there.
        let u = stage_paths(ECP5_NET, "t", ULTRASCALE_PLUS_2).unwrap();
        assert_eq!(u[0].path.luts, 1);
    }
}
