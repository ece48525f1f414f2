//! The fabric of the structures between and around the units: the walker contexts beyond the
//! one the RTL walker holds, the FIFOs between stages, the miss-status (MSHR) CAM and the
//! cache's control. The walker contexts are calibrated on the barrel walker's synthesis; the
//! others are first-order formulas from their bit widths, not calibrations;
//! `docs/cycle-model.md` §1.5 ("Structures") gives every formula and why.
//!
//! Pipeline position: the second half of [`HwConfig::fabric`](crate::cycle::hw_config::HwConfig::fabric)
//! (`cost::fabric` adds the calibrated units, this file the rest), read once per
//! configuration by `sim hardware` and `sim explore`.
//!
//! Adding a structure (a crossbar, request queues per bank, …) is one function here that
//! returns its [`FabricItem`] from the hardware fields that size it, listed in
//! [`structure_items`], and one row in the docs table; a structure the model does not have
//! is not priced.

use super::fabric::{barrel_fabric, calibration, scale, unit_fabric, Fabric, FabricItem};
use crate::cycle::hw_config::HwConfig;
use crate::datapath::DatapathConfig;

/// LUTs of one RAM32M16 (UltraScale+ LUT-RAM: 32 deep × 14 bits with one write and one read
/// port, in one CLB's eight LUTs).
const RAM32M16_LUTS: u64 = 8;
/// Bits a RAM32M16 holds per entry in simple dual-port use (7 ports of 2 bits).
const RAM32M16_BITS: u64 = 14;
/// RAM64M8: 64 deep × 7 bits (simple dual port) in eight LUTs.
const RAM64M8_BITS: u64 = 7;
/// Bits of a node-memory byte address: 32-bit word indices of 4-byte words.
const BYTE_ADDRESS_BITS: u64 = 34;
/// Bits of the word a cache lookup returns (a node word in the low half, or an attribute
/// record whole, as the walker's 64-bit read port).
const READ_WORD_BITS: u64 = 64;

/// ⌈log₂ n⌉, at least 1 (a counter or index of `n` values).
pub fn clog2(n: u64) -> u64 {
    u64::from(64 - n.saturating_sub(1).leading_zeros()).max(1)
}

/// LUTs of a LUT-RAM of `depth` entries × `bits` bits with one write and one read port:
/// RAM32M16 (8 LUTs per 14 bits) up to 32 entries, else RAM64M8 (8 LUTs per 7 bits) per 64
/// entries.
pub fn lutram_luts(depth: u64, bits: u64) -> u64 {
    if depth == 0 || bits == 0 {
        0
    } else if depth <= 32 {
        RAM32M16_LUTS * bits.div_ceil(RAM32M16_BITS)
    } else {
        RAM32M16_LUTS * bits.div_ceil(RAM64M8_BITS) * depth.div_ceil(64)
    }
}

/// LUTs of an equality compare of `bits` bits: LUT6s of three bit pairs each, then the AND
/// of their outputs six at a time.
pub fn compare_luts(bits: u64) -> u64 {
    let pairs = bits.div_ceil(3);
    pairs + if pairs > 1 { pairs.div_ceil(6) } else { 0 }
}

/// LUTs per bit of an `n`:1 multiplexer: a LUT6 selects one of 4 (MUXF7/F8 join them), so
/// ⌈(n − 1)/3⌉.
pub fn mux_luts_per_bit(n: u64) -> u64 {
    n.saturating_sub(1).div_ceil(3)
}

/// Bits of a ray-slot tag: which in-flight ray a walk, a read or a result belongs to.
pub fn slot_bits(hw: &HwConfig) -> u64 {
    clog2(u64::from(hw.ray_slots()))
}

/// Bits of a pixel index in the hardware frame.
pub fn pixel_bits(hw: &HwConfig) -> u64 {
    clog2(hw.frame.pixels())
}

/// Candidates a ray carries from the sphere lanes to the record stage: svo_top's `KEYN` =
/// 2 × sorter lanes (the sorter's `MAX_KEYS`), the width of every key list in the RTL.
pub fn candidate_keys(hw: &HwConfig) -> u64 {
    2 * u64::from(hw.sorter_lanes)
}

/// Bits of one candidate: its key (t_enter) and instance.
pub fn candidate_bits(dp: &DatapathConfig) -> u64 {
    u64::from(dp.sorter.key.width) + u64::from(dp.hit_record.instance_bits)
}

/// Bits of a ray as the RTL's FIFOs carry it: its pixel and direction (the origin is the
/// camera's, one register for the frame, not carried per ray).
pub fn ray_bits(hw: &HwConfig, dp: &DatapathConfig) -> u64 {
    pixel_bits(hw) + 3 * u64::from(dp.raygen.dir.width)
}

/// Bits of a ray's candidate list as the RTL carries it (svo_walk_wide's `RAY` less the ray): a
/// count of 0..=[`candidate_keys`] and that many candidates ([`candidate_bits`]).
pub fn candidate_list_bits(hw: &HwConfig, dp: &DatapathConfig) -> u64 {
    let k = candidate_keys(hw);
    clog2(k + 1) + k * candidate_bits(dp)
}

/// The walker contexts beyond the first, calibrated on the barrel walker's synthesis (issue
/// 29): a walker of R > 1 contexts is `svo_walker_barrel`, one step datapath whose contexts'
/// words are in LUT-RAM, with per-context sequencer, chaining bases and age order around it
/// ([`barrel_fabric`], measured at R = 2…16 and K = 1, 2 take and result ports, K =
/// [`HwConfig::walk_lanes`]). The walker's own row prices the one-context `svo_walker`, so
/// this row is the barrel less that walker, both scaled by the walker's width measure
/// (`unit_fabric("walker")` against its calibration). R = 1 adds nothing.
fn walker_contexts(hw: &HwConfig, dp: &DatapathConfig) -> FabricItem {
    let r = u64::from(hw.walker_pool.contexts_per_walker);
    let k = u64::from(hw.walk_lanes());
    let walker = unit_fabric("walker", dp).unwrap_or_default();
    let (cal_lut, cal_ff) = calibration::WALKER;
    let (per, barrel) = match barrel_fabric(r, k) {
        Some(b) => {
            let scaled = Fabric {
                lut: scale(b.lut, walker.lut, cal_lut),
                ff: scale(b.ff, walker.ff, cal_ff),
            };
            (
                Fabric {
                    lut: scaled.lut.saturating_sub(walker.lut),
                    ff: scaled.ff.saturating_sub(walker.ff),
                },
                b,
            )
        }
        None => (Fabric::default(), Fabric::default()),
    };
    FabricItem {
        name: "walker_contexts",
        instances: u64::from(hw.walker_pool.walkers),
        per_instance: per,
        calibrated: r > 1,
        formula: if r > 1 {
            format!(
                "per walker: svo_walker_barrel of {r} contexts, {k} take ports ({} LUT, {} FF at the default widths) less the walker's row (none at R = 1)",
                barrel.lut, barrel.ff
            )
        } else {
            "one context: the walker's row (none at R = 1)".to_string()
        },
    }
}

/// Bits of one entry of each FIFO of the model, in pipeline order, with its depth. A ray is
/// its pixel and direction ([`ray_bits`]); from the sphere lanes on it carries its candidate
/// list ([`candidate_list_bits`]: `KEYN` candidates as svo_walk_wide's `RAY` entry, 1,414 bits in
/// the RTL at 16 sorter lanes); a walk carries its ray-slot tag and the operands of the next
/// unit (the transform's outputs, the reciprocals, the walker's inputs); a result is the
/// walker's outputs without its counters; a record is the hit word and its pixel. The
/// loop-back is not here: it is the ray-slot table (`cost::core_logic`).
pub fn fifo_entries(hw: &HwConfig, dp: &DatapathConfig) -> Vec<(&'static str, u64, u64)> {
    let w = |f: crate::fixed::Format| u64::from(f.width);
    let (p, s) = (pixel_bits(hw), slot_bits(hw));
    let ray = ray_bits(hw, dp);
    let candidates = candidate_list_bits(hw, dp);
    let inst = u64::from(dp.hit_record.instance_bits);
    let t = &dp.transform;
    let k = &dp.walker;
    let to_reciprocal = s + inst + 3 * w(t.local_pos) + 3 * w(t.local_dir);
    let to_root = s + inst + 3 * w(k.pos) + 3 * w(k.inv) + 3;
    let to_walker = s + 1 + 6 * (w(k.t) + 1) + 3 * (w(k.pos) + 1) + 3 * w(k.pos) + 6 + 64;
    let result = s + 2 + w(k.t) + 60 + 5 + 32 + 2;
    let record = u64::from(dp.hit_record.word_bits()) + p;
    let f = &hw.fifos;
    let d = |x: u32| u64::from(x);
    vec![
        ("fifo.raygen_to_sphere", d(f.raygen_to_sphere), ray),
        (
            "fifo.sphere_to_sorter",
            d(f.sphere_to_sorter),
            ray + candidates,
        ),
        (
            "fifo.sorter_to_check",
            d(f.sorter_to_check),
            ray + candidates,
        ),
        (
            "fifo.check_to_transform",
            d(f.check_to_transform),
            ray + candidates,
        ),
        (
            "fifo.transform_to_reciprocal",
            d(f.transform_to_reciprocal),
            to_reciprocal,
        ),
        ("fifo.reciprocal_to_root", d(f.reciprocal_to_root), to_root),
        ("fifo.root_to_dispatch", d(f.root_to_dispatch), to_walker),
        ("fifo.walker_to_record", d(f.walker_to_record), result),
        ("fifo.record_to_write", d(f.record_to_write), record),
    ]
}

/// The deepest FIFO kept in LUT-RAM. Yosys 0.23 `synth_xilinx -family xcup` maps `svo_fifo`
/// (testbench/rtl) of 64 entries to RAM64M8 and of 128 entries and more to RAMB36E2, at 72
/// and 546 bits alike (docs/cycle-model.md §1.5, "Structures"); so does the whole core's
/// check_to_transform (1,024 × 546 bits: 15 RAMB36E2).
pub const FIFO_LUTRAM_MAX_DEPTH: u64 = 64;

/// Whether a FIFO of `depth` entries is built in block RAM rather than LUT-RAM.
pub fn fifo_in_bram(depth: u64) -> bool {
    depth > FIFO_LUTRAM_MAX_DEPTH
}

/// BRAM36 blocks of a FIFO of `depth` entries of `bits` bits ([`fifo_in_bram`]), the
/// cheapest mix of block shapes (`units::hit_record::bram36_count`); 0 in LUT-RAM.
pub fn fifo_bram36(depth: u64, bits: u64) -> u64 {
    if fifo_in_bram(depth) {
        crate::units::hit_record::bram36_count(u32::try_from(bits).unwrap_or(u32::MAX), depth)
    } else {
        0
    }
}

/// The fabric of one FIFO of `depth` entries of `bits` bits, as Yosys builds `svo_fifo`
/// (docs/cycle-model.md §1.5, "Structures"): read and write pointers and a count of
/// ⌈log₂ D⌉ + 1 bits each (3 of them in FFs, their increments and the full/empty compares in
/// as many LUTs), and
/// - in LUT-RAM ([`lutram_luts`]): the storage, read as it is addressed (no output
///   register: 64 × 546 bits gave 78 RAM64M8, 35 LUTs and 25 FFs; 624 + 21 LUTs and 21 FFs by
///   this formula);
/// - in block RAM ([`fifo_in_bram`]; the blocks are [`fifo_bram36`]): the output register the
///   synchronous read needs, with a LUT per bit selecting its next value (128 and 256 × 546
///   bits: 603 and 634 LUTs, 569 and 572 FFs; 570 and 573 of each by this formula).
pub fn fifo_fabric(depth: u64, bits: u64) -> Fabric {
    let ptr = clog2(depth) + 1;
    let (storage, output) = if fifo_in_bram(depth) {
        (bits, bits)
    } else {
        (lutram_luts(depth, bits), 0)
    };
    Fabric {
        lut: storage + 3 * ptr,
        ff: output + 3 * ptr,
    }
}

fn fifos(hw: &HwConfig, dp: &DatapathConfig) -> Vec<FabricItem> {
    fifo_entries(hw, dp)
        .into_iter()
        .map(|(name, depth, bits)| FabricItem {
            name,
            instances: 1,
            per_instance: fifo_fabric(depth, bits),
            calibrated: false,
            formula: if fifo_in_bram(depth) {
                format!(
                    "{depth} × {bits} bits in {} BRAM36, output register and its select, pointers",
                    fifo_bram36(depth, bits)
                )
            } else {
                format!("{depth} × {bits} bits in LUT-RAM, pointers")
            },
        })
        .collect()
}

/// The miss-status registers: M entries of a valid bit, the line address (34 − log₂ line
/// bytes) and the first requester's slot tag in FFs; every lookup port compares every
/// entry's line address ([`compare_luts`]) and picks a free entry (M LUTs). The list of
/// merged requesters behind an entry is not counted.
fn mshr_cam(hw: &HwConfig) -> FabricItem {
    let nm = &hw.node_memory;
    let m = u64::from(nm.dram.mshrs);
    let line = u64::from(nm.cache.line_bytes.max(1));
    // `line_bytes` is a validated power of two from 8 to 4096.
    let a = BYTE_ADDRESS_BITS.saturating_sub(clog2(line));
    let s = slot_bits(hw);
    let ports = u64::from(nm.cache.ports.max(1));
    FabricItem {
        name: "mshr_cam",
        instances: 1,
        per_instance: Fabric {
            lut: ports * m * compare_luts(a) + m,
            ff: m * (1 + a + s),
        },
        calibrated: false,
        formula: format!(
            "{m} entries × (1 + {a}-bit line + {s}-bit tag) FF; {ports} ports × {m} × compare({a}) + {m} LUT"
        ),
    }
}

/// The cache's control per lookup port (none when the cache is disabled): the tag compare
/// of every way (tag T = 34 − log₂ line − log₂ sets, plus its valid bit), the way select of
/// the 64-bit word, and the LRU state of every set (W·⌈log₂ W⌉ bits) in a LUT-RAM copy per
/// port with its update (as many LUTs as state bits); FFs: the address and word through
/// the hit latency's stages and the W tags read.
fn cache_control(hw: &HwConfig) -> Option<FabricItem> {
    let nm = &hw.node_memory;
    let c = &nm.cache;
    let sets = nm.cache_sets();
    if c.size_bytes == 0 || sets == 0 {
        return None;
    }
    let ways = u64::from(c.ways);
    let line = u64::from(c.line_bytes);
    let index = if sets > 1 { clog2(sets) } else { 0 };
    let tag = BYTE_ADDRESS_BITS.saturating_sub(clog2(line) + index);
    let lru = ways * clog2(ways);
    let lut = ways * compare_luts(tag + 1)
        + READ_WORD_BITS * mux_luts_per_bit(ways)
        + lutram_luts(sets, lru)
        + lru;
    let ff = u64::from(c.hit_latency) * (BYTE_ADDRESS_BITS + READ_WORD_BITS) + ways * (tag + 1);
    Some(FabricItem {
        name: "cache_control",
        instances: u64::from(c.ports),
        per_instance: Fabric { lut, ff },
        calibrated: false,
        formula: format!(
            "per port: {ways} × compare({}) + 64 × mux({ways}) + LUT-RAM {sets} × {lru} LRU + {lru} LUT; {} × (34 + 64) + {ways} × {} FF",
            tag + 1,
            c.hit_latency,
            tag + 1
        ),
    })
}

/// The node memory's logic around its blocks, as the memory model lists it
/// (`NodeMemoryConfig::fabric_items`, `cycle/memory/crossbar.rs`): the walker-to-bank
/// crossbars, the bank queues (with the on-chip combining CAM) and the miss queue. Its "MSHR
/// search" item is left out: [`mshr_cam`] counts the same comparators with the ports' copies.
/// The crossbars' requesters are the walkers' request ports (`walker_pool.read_ports` each;
/// one for 0, as `WalkerPool::priced_read_ports` says why).
fn memory_logic(hw: &HwConfig) -> impl Iterator<Item = FabricItem> {
    let pool = &hw.walker_pool;
    let contexts = pool.walkers.saturating_mul(pool.contexts_per_walker);
    let requesters = pool.walkers.saturating_mul(pool.priced_read_ports());
    hw.node_memory
        .fabric_items(requesters, contexts)
        .into_iter()
        .filter(|i| i.name != "MSHR search")
        .map(|i| FabricItem {
            name: i.name,
            instances: 1,
            per_instance: Fabric {
                lut: i.lut,
                ff: i.ff,
            },
            calibrated: false,
            formula: i.formula,
        })
}

/// The second record write (`hit_buffer.record_writes: 2`, none otherwise): a second read
/// port of `record_to_write` (a copy of its LUT-RAM, the usual way to read two entries a
/// cycle) and, in front of each of the two banks' write ports, a 3:1 multiplexer (the check's
/// word, the record FIFO's head or the entry behind it) of word and pixel-address bits.
fn record_write_path(hw: &HwConfig, dp: &DatapathConfig) -> Option<FabricItem> {
    if hw.hit_buffer.record_writes < 2 {
        return None;
    }
    let bits = u64::from(dp.hit_record.word_bits()) + pixel_bits(hw);
    let depth = u64::from(hw.fifos.record_to_write);
    let banks = u64::from(hw.hit_buffer.write_ports);
    Some(FabricItem {
        name: "record_write_path",
        instances: 1,
        per_instance: Fabric {
            lut: lutram_luts(depth, bits) + banks * bits * mux_luts_per_bit(3),
            ff: bits,
        },
        calibrated: false,
        formula: format!(
            "LUT-RAM {depth} × {bits} bits (second read port) + {banks} × {bits} × mux(3) LUT; {bits} FF (second output register)"
        ),
    })
}

/// Every structure of this configuration, in pipeline order: walker contexts, the FIFOs,
/// the second record write path, the node memory's crossbars and queues, the MSHR CAM and
/// the cache control.
pub fn structure_items(hw: &HwConfig, dp: &DatapathConfig) -> Vec<FabricItem> {
    let mut items = vec![walker_contexts(hw, dp)];
    items.extend(fifos(hw, dp));
    items.extend(record_write_path(hw, dp));
    items.extend(memory_logic(hw));
    items.push(mshr_cam(hw));
    items.extend(cache_control(hw));
    items
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_building_blocks_count_as_documented() {
        assert_eq!(
            (clog2(1), clog2(2), clog2(8), clog2(9), clog2(320)),
            (1, 1, 3, 4, 9)
        );
        assert_eq!(lutram_luts(8, 14), 8);
        assert_eq!(lutram_luts(32, 15), 16);
        assert_eq!(lutram_luts(33, 7), 8);
        assert_eq!(lutram_luts(1024, 8), 8 * 2 * 16);
        assert_eq!(
            (compare_luts(3), compare_luts(28), compare_luts(19)),
            (1, 12, 9)
        );
        assert_eq!(
            (
                mux_luts_per_bit(1),
                mux_luts_per_bit(4),
                mux_luts_per_bit(8)
            ),
            (0, 1, 3)
        );
    }
}
