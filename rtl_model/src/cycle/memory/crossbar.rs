//! What the node memory's logic around its memory blocks costs in LUTs and flip-flops: the
//! walker-to-bank crossbars (requests in, data back), the per-bank request queues (with the
//! on-chip store's combining CAM), the miss queue and the MSHR search. The memory blocks
//! themselves are [`NodeMemoryConfig::resources`].
//!
//! Pipeline position: read once per configuration, like the resource estimate; the fabric
//! estimate (`cost::fabric`) adds these items to the units'. First-order formulas, not yet
//! calibrated against synthesis (no RTL of the node memory exists yet); each item carries its
//! formula so a report can show it. Widths: a request is a 32-bit word address, a 2-bit kind
//! and a `⌈log2 contexts⌉`-bit requester tag; a reply is 64 data bits (an attribute record is
//! two words) and the tag. A LUT6 is a 4:1 multiplexer, so an n:1 multiplexer takes
//! `⌈(n − 1)/3⌉` LUTs per bit; a 64-deep dual-port LUT-RAM takes 2 LUTs per bit (RAM64X1D);
//! an equality compare of b bits takes `⌈b/3⌉` LUTs (two bits per LUT and the AND tree).

use super::config::NodeMemoryConfig;
use serde::Serialize;

/// One item of logic: what it is, its LUTs and flip-flops, and the formula they come from.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct MemoryFabricItem {
    /// What it is.
    pub name: &'static str,
    /// CLB LUTs (logic and LUT-RAM).
    pub lut: u64,
    /// Flip-flops.
    pub ff: u64,
    /// How the figures follow from the configuration, with the values put in.
    pub formula: String,
}

fn clog2(n: u64) -> u64 {
    u64::from(n.max(1).next_power_of_two().trailing_zeros())
}

/// LUTs per bit of an n:1 multiplexer.
fn mux_luts(n: u64) -> u64 {
    n.saturating_sub(1).div_ceil(3)
}

/// A crossbar from `inputs` requesters to `outputs` bank ports and back: one request
/// multiplexer and round-robin arbiter per port, one reply multiplexer per requester, a
/// register on each side.
fn crossbar(name: &'static str, inputs: u64, outputs: u64, req: u64, rep: u64) -> MemoryFabricItem {
    let lut = outputs * (req * mux_luts(inputs) + 3 * inputs) + inputs * rep * mux_luts(outputs);
    let ff = outputs * req + inputs * rep;
    MemoryFabricItem {
        name,
        lut,
        ff,
        formula: format!(
            "{outputs} ports × ({req}-bit request × ⌈({inputs} − 1)/3⌉ + 3 × {inputs} arbiter) \
             + {inputs} requesters × {rep}-bit reply × ⌈({outputs} − 1)/3⌉ LUT; \
             {outputs} × {req} + {inputs} × {rep} FF"
        ),
    }
}

/// Per-bank request queues of `depth` entries of `width` bits in LUT-RAM, with read and write
/// pointers in FFs; with `cam`, the word addresses (32 bits) are in FFs with one compare per
/// entry and each entry keeps a mask of the `inputs` requesters it serves.
fn queues(
    name: &'static str,
    banks: u64,
    depth: u64,
    width: u64,
    cam: Option<u64>,
) -> MemoryFabricItem {
    let ram = banks * width * 2 * depth.div_ceil(64);
    let ptr = banks * 2 * (clog2(depth) + 1);
    match cam {
        None => MemoryFabricItem {
            name,
            lut: ram,
            ff: ptr,
            formula: format!(
                "{banks} banks × {width} bits × 2 × ⌈{depth}/64⌉ LUT-RAM; {banks} × 2 pointers of {} bits FF",
                clog2(depth) + 1
            ),
        },
        Some(inputs) => {
            let cmp = banks * depth * 32u64.div_ceil(3);
            MemoryFabricItem {
                name,
                lut: ram + cmp,
                ff: ptr + banks * depth * (32 + inputs),
                formula: format!(
                    "{banks} banks × ({width} bits × 2 × ⌈{depth}/64⌉ LUT-RAM + {depth} entries × \
                     ⌈32/3⌉ compare) LUT; {banks} × ({depth} × (32-bit address + {inputs}-requester \
                     mask) + 2 pointers of {} bits) FF",
                    clog2(depth) + 1
                ),
            }
        }
    }
}

impl NodeMemoryConfig {
    /// The logic this configuration needs around its memory blocks, for a pool of
    /// `requesters` walker request ports (`walker_pool.read_ports` per walker) with `contexts`
    /// contexts in all (module doc for the formulas). A
    /// bank queue is sized for its share of the contexts (each has at most one read out),
    /// at least 16 entries: `max(16, ⌈contexts / banks⌉)` rounded up to a power of two.
    pub fn fabric_items(&self, requesters: u32, contexts: u32) -> Vec<MemoryFabricItem> {
        let n = u64::from(requesters.max(1));
        let ctx = u64::from(contexts.max(1));
        let tag = clog2(ctx);
        let (req, rep) = (32 + 2 + tag, 64 + tag);
        let depth = |banks: u64| ctx.div_ceil(banks).max(16).next_power_of_two();
        let (o, c) = (&self.onchip, &self.cache);
        let ob = u64::from(o.banks.max(1));
        let cb = u64::from(c.banks.max(1));
        let mut items = vec![
            crossbar(
                "on-chip crossbar",
                n,
                ob * u64::from(o.ports_per_bank),
                req,
                rep,
            ),
            queues(
                "on-chip bank queues",
                ob,
                depth(ob),
                req,
                o.combine.then_some(n),
            ),
            crossbar("cache crossbar", n, cb * u64::from(c.ports), req, rep),
            queues("cache bank queues", cb, depth(cb), req, None),
        ];
        // The line address a miss or an MSHR holds: 34-bit byte addresses (node words and the
        // attribute region) less the line offset.
        let line_bits = 34 + 1 - clog2(u64::from(c.line_bytes));
        if c.miss_queue > 0 {
            let m = u64::from(c.miss_queue);
            items.push(queues("miss queue", 1, m, req + line_bits, None));
        }
        let mshrs = u64::from(self.dram.mshrs);
        items.push(MemoryFabricItem {
            name: "MSHR search",
            lut: mshrs * line_bits.div_ceil(3),
            ff: mshrs * (line_bits + 1),
            formula: format!(
                "{mshrs} MSHRs × ⌈{line_bits}-bit line compare / 3⌉ LUT; {mshrs} × ({line_bits} + valid) FF"
            ),
        });
        items
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn more_banks_cost_more_crossbar_and_combining_costs_a_cam() {
        // Four on-chip banks (the default before issue 28), so the hand count below is short.
        let mut base = NodeMemoryConfig::default();
        base.onchip.banks = 4;
        let total =
            |c: &NodeMemoryConfig| -> u64 { c.fabric_items(32, 256).iter().map(|i| i.lut).sum() };
        let mut wide = base.clone();
        wide.cache.banks = 8;
        assert!(total(&wide) > total(&base));
        let mut plain = base.clone();
        plain.onchip.combine = false;
        assert!(total(&plain) < total(&base));
        let mut blocking = base.clone();
        blocking.cache.miss_queue = 0;
        assert!(total(&blocking) < total(&base));
        // 32 requesters onto 4 × 2 on-chip ports: 8 × (42 × 11 + 96) + 32 × 72 × 3.
        let x = &base.fabric_items(32, 256)[0];
        assert_eq!(x.lut, 8 * (42 * 11 + 96) + 32 * 72 * 3);
        assert_eq!(x.ff, 8 * 42 + 32 * 72);
    }
}
