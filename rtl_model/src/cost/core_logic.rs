//! The logic svo_core's RTL builds around its units, calibrated on the whole core's synthesis
//! (issue 29): svo_front's candidate gathering, the walk section's ray-slot table with the record
//! decision and slot allocation around it, the walker pool's own logic around its walkers, the
//! fixed-latency units' elastic pipes, and the hit buffer's check pipe and write FIFOs.
//!
//! Pipeline position: the middle part of
//! [`HwConfig::fabric`](crate::cycle::hw_config::HwConfig::fabric), after the units of
//! `cost::fabric` and before the uncalibrated structures of `cost::structures`; read once per
//! configuration by `sim hardware` and `sim explore`. None of these items maps to DSP48E2
//! (svo_front's gathering did, one per sphere lane, before its decoder per key slot).
//!
//! Each item is a measured figure of Yosys 0.23 `synth_xilinx -family xcup` of svo_core on
//! `testbench/hw/frame_hw_pkg.sv` (docs/cycle-model.md §1.5, "The whole svo_core"; the
//! figures are in testbench/synth/svo_core_frame_hw.tsv) scaled by a structural measure of
//! what the RTL builds: `figure · M(hw, dp) / M(frame_hw)`. Each has one measured point, so
//! the estimate equals the synthesis at frame_hw by construction and elsewhere follows its
//! measure; that scaling is an argument from the RTL's structure, not a measurement. The
//! walker pool is the exception: it was synthesised alone at eight sizes (seven at two
//! walk-issue lanes, one at one) and its item is a fit over them
//! ([`calibration::POOL_MEASURED`]).

use super::fabric::{scale, Fabric, FabricItem};
use super::structures::{
    candidate_bits, candidate_keys, candidate_list_bits, clog2, lutram_luts, pixel_bits, ray_bits,
    slot_bits,
};
use crate::cycle::hw_config::HwConfig;
use crate::datapath::DatapathConfig;

/// The measured figures (CLB LUT = LUT1–6 + SRL + LUTs used as LUT-RAM; FF) and the measures
/// of frame_hw (1 walker × 1 context, 8 sphere lanes, 16 sorter lanes: 32 candidates of 40
/// bits, 65 ray slots, a 1280 × 768 frame: 20-bit pixels) they are taken at.
pub mod calibration {
    /// svo_front's own logic, synthesised alone (its submodules as black boxes, the
    /// `--per-module` block): 6,709 CLB LUT, 1,432 FF, no DSP48E2, since the candidate gathering
    /// is a decoder per key slot (issue 29; svo_front.v, "Compaction"): each hit lane's rank
    /// (a prefix count of the pass's hits on the ray's key count) is compared with each slot,
    /// and each key bit is an AND-OR over the lanes beside the slot's held bit. Its registers
    /// are the accumulated key list (1,280 bits) and the pass state. (Written as a running
    /// index `sp_keys[sp_n * 40 +: 40]` before, it took 36,056 LUT, 1,432 FF and 8 DSP48E2
    /// the same way, 35,906 LUT in `--per-module`.)
    pub const FRONT_GATHER: (u64, u64) = (6_709, 1_432);
    /// Its measures at frame_hw: lanes × keys × candidate bits (LUT: the AND-OR terms) =
    /// 8 × 32 × 40; keys × candidate bits (FF) = 32 × 40.
    pub const FRONT_GATHER_AT: (u64, u64) = (8 * 32 * 40, 32 * 40);
    /// svo_walk's own LUT-RAM, synthesised alone: 8,024 LUTs (the flat netlist's 7,728), the
    /// ray-slot tables read asynchronously (`s_keys` and t, origin, direction, attribute,
    /// voxel), at 65 slots: 2.08 × one LUT-RAM copy of them ([`super::lutram_luts`] of 65 ×
    /// 1,682 bits = 3,856), the copies per read port Yosys makes.
    pub const SLOT_RAM_LUTS: u64 = 8_024;
    /// svo_walk's own logic besides the LUT-RAM, alone: 15,422 − 8,024 = 7,398 CLB LUT (the
    /// record decision, the tables' read multiplexers, the lowest-free-slot chain), 1,594 FF.
    /// (svo_walk was the walk section at K = 1 until svo_walk_wide replaced it; its own block
    /// at K = 1 measures 16,187 CLB LUT of which 8,208 LUT-RAM, 1,562 FF — within 5 % of these,
    /// so the calibration stands: docs/cycle-model.md §1.5.)
    pub const SLOT_LOGIC: (u64, u64) = (15_422 - 8_024, 1_594);
    /// The slot table's bits per slot at frame_hw (32 × 40 keys + t 62 + origin 3 × 40 +
    /// direction 3 × 32 + attribute 64 + voxel 60) and its slots.
    pub const SLOT_BITS_AT: u64 = 1_682;
    /// Ray slots at frame_hw (1 × 1 + root_to_dispatch 64).
    pub const SLOTS_AT: u64 = 65;
    /// The units' elastic pipes and tag FIFOs (the flat netlist's `*_pipe`, `*_tags` rows):
    /// 4,912 CLB LUT (most of them LUT-RAM: the sphere's 48-deep pipe of a ray and its
    /// candidates alone 1,802), 185 FF.
    pub const ELASTIC: (u64, u64) = (4_912, 185);
    /// Their measure at frame_hw: Σ latency × width over the pipes ([`elastic_measure`]).
    pub const ELASTIC_AT: u64 = 97_292;
    /// svo_walker_pool's own logic, its walkers as black boxes (the barrels are
    /// `walker_contexts` and `walker`): the dispatcher, the retire order, per walker the R × R
    /// age order of its contexts' events, the send queue's pick and rank. Yosys 0.23
    /// `synth_xilinx -family xcup` (not flattened; dispatch and retire as their own modules,
    /// the design hierarchy's total) with `chparam -set WALKERS W -set CONTEXTS R -set K K
    /// -set TAG_W 10 -set CW ⌈log₂ N⌉ -set STEP_LATENCY 4 -set CTX_RESP 2 -set ATTR_MERGE 0`
    /// (svo_top behind its node cache: every response on its context's own port, no attribute
    /// merge in the pool), at (W, R, K, CLB LUT, FF): `testbench/synth/synth_pool.sh pool W R
    /// K`. 20 s (4 × 4) to 1,606 s (32 × 8) of CPU.
    pub const POOL_MEASURED: [(u64, u64, u64, u64, u64); 8] = [
        (2, 16, 2, 11_229, 2_111),
        (4, 16, 2, 22_719, 4_320),
        (8, 16, 2, 47_802, 8_865),
        (16, 16, 2, 100_721, 18_210),
        (4, 4, 2, 4_348, 686),
        (8, 8, 2, 17_348, 3_360),
        (32, 8, 2, 109_423, 14_370),
        (4, 16, 1, 17_759, 4_320),
    ];
    /// The LUT fit over the seven K = 2 points, LUT = N·(a + b·R) + d·W² with N = W·R
    /// contexts, least squares on the relative error, in thousandths: a logic per context, the
    /// walker's R × R age order (a row of R a context) and what grows with the walkers
    /// pairwise (the W × W rank compares of a cycle's sends, the retire's and the
    /// dispatcher's choices across walkers): a = 167.944, b = 11.013, d = 42.214. Within
    /// −6.5 … +10.0 % of the seven points (the K = 1 point by `k1`). Out of sample: fitted on
    /// the six pools before 32 × 8 this form gave 32 × 8 9.8 % under its synthesis, where the
    /// fit then in use, N(223.154 + 7.543 R + 0.171 N) (within −5.8 … +8.6 % of those six),
    /// gave it 23.4 % under: the pool grows with its walkers squared, not its contexts. The
    /// default's 32 × 8 is a measured point (108,775 LUTs against 109,423 synthesised; its W²
    /// term is 40 % of it); issue 28's 48 walkers are 1.5 × beyond the largest measured, so
    /// there it is an extrapolation (the W² term 27 % of that pool).
    pub const POOL_LUT_MILLI: PoolLutFit = PoolLutFit {
        a: 167_944,
        b_r: 11_013,
        c_n: 0,
        d_w2: 42_214,
        k1: 782,
    };
    /// The same pool with the attribute records on the walkers' response ports (`CTX_RESP 1`,
    /// svo_top with every node word on chip and no cache, `onchip.levels` 21, where the merge
    /// rule needs those ports): any context may be answered on any port, so every context
    /// decodes every port and selects its 64-bit word among all W (N × W compares, N 64-bit
    /// W-to-1 selects). Measured the same way with `CTX_RESP 1` (the pool svo_top built
    /// behind its cache too until issue 29 moved the records to the context ports): 2 × 16
    /// 13,511 LUT; 4 × 16 31,306; 8 × 16 88,415; 16 × 16 259,369 (2,439 s of CPU, 8.0 GB);
    /// 4 × 4 7,424; 8 × 8 33,437; the FFs the same as `POOL_MEASURED`'s; 4 × 16 at K = 1
    /// 26,427 LUT. Fit N·(368.178 + 2.487 N), within −12.1 … +7.8 % of the six K = 2 points
    /// (fitted on the first five it was N(379.9 + 2.266 N) and gave 16 × 16 5.2 % under its
    /// synthesis).
    pub const POOL_PORTS_LUT_MILLI: PoolLutFit = PoolLutFit {
        a: 368_178,
        b_r: 0,
        c_n: 2_487,
        d_w2: 0,
        k1: 844,
    };
    /// The LUT fit's coefficients in thousandths of a LUT: LUT = (N·(a + b_r·R + c_n·N) +
    /// d_w2·W²) / 1000.
    #[derive(Debug, Clone, Copy)]
    pub struct PoolLutFit {
        /// Per context.
        pub a: u64,
        /// Per context and context of its walker.
        pub b_r: u64,
        /// Per context and context of the pool.
        pub c_n: u64,
        /// Per pair of walkers.
        pub d_w2: u64,
        /// The factor at one walk-issue lane (one take and retire lane): K = 1 against K = 2
        /// at 4 × 16, whose flip-flops are the same (17,759 / 22,719 LUTs with the records on
        /// the context ports, 26,427 / 31,306 with them on the walker ports).
        pub k1: u64,
    }
    /// The FF fit, FF = N·(f₀ + f_r·R) + f_w2·W² (the age order's R bits a context, its
    /// state, the pairwise terms' registers): f₀ = 32.690, f_r = 2.187, f_w2 = 1.591, in
    /// thousandths; within 3 % of the seven K = 2 points (N·(34.986 + 2.096 R) before 32 × 8,
    /// which it missed by 7.8 %).
    pub const POOL_FF_MILLI: (u64, u64, u64) = (32_690, 2_187, 1_591);
    /// The hit buffer's check pipe (the ray and its candidates beside the read, 1,494 SRL),
    /// write FIFOs and bank selection, flat: 3,426 CLB LUT, 937 FF, less what the estimate
    /// prices there already (hit_check 12 + record_to_write 68 + record_write_path 240 LUT;
    /// 145 + 12 + 92 FF).
    pub const HIT_CHECK_PIPE: (u64, u64) = (3_426 - 320, 937 - 249);
    /// Its measure at frame_hw: the check pipe's entry, pixel 20 + 2 flags + word 72 +
    /// direction 96 + count 6 + 32 × 40 candidates.
    pub const HIT_CHECK_PIPE_AT: u64 = 1_476;
}

/// svo_front's candidate gathering, a decoder per key slot: each of the `KEYN` key slots
/// takes the hit lane whose rank is the slot's, so each key bit is an AND-OR over the `lanes`
/// sphere lanes (LUT ∝ lanes × keys × candidate bits; the lanes × keys rank compares are of
/// ⌈log₂(keys + lanes + 1)⌉ bits, small beside them); its registers hold the key list (FF ∝
/// keys × bits). No DSP48E2.
fn front_gather(hw: &HwConfig, dp: &DatapathConfig) -> FabricItem {
    let (lanes, k, b) = (
        u64::from(hw.sphere_units),
        candidate_keys(hw),
        candidate_bits(dp),
    );
    let (c, at) = (calibration::FRONT_GATHER, calibration::FRONT_GATHER_AT);
    FabricItem {
        name: "front_gather",
        instances: 1,
        per_instance: Fabric {
            lut: scale(c.0, lanes * k * b, at.0),
            ff: scale(c.1, k * b, at.1),
        },
        calibrated: true,
        formula: format!(
            "{} LUT · ({lanes} lanes × {k} keys × {b} bits) / (8 × 32 × 40); {} FF · ({k} × {b}) / (32 × 40)",
            c.0, c.1
        ),
    }
}

/// Bits of one ray slot's LUT-RAM tables: the candidate keys, the best t, the origin and
/// direction in the instance's frame, the best hit's attribute word and voxel.
pub fn slot_table_bits(hw: &HwConfig, dp: &DatapathConfig) -> u64 {
    let w = |f: crate::fixed::Format| u64::from(f.width);
    candidate_keys(hw) * candidate_bits(dp)
        + w(dp.walker.t)
        + 3 * w(dp.walker.pos)
        + 3 * w(dp.transform.local_dir)
        + 64
        + 60
}

/// The walk section's ray slots (`HwConfig::ray_slots`, svo_walk_wide's slot tables): the slot tables in LUT-RAM (read
/// asynchronously, so LUT-RAM at any depth; LUTs as [`lutram_luts`] of slots × bits, 64
/// slots a block), the logic around them (the tables' read multiplexers, the record decision
/// and the lowest-free-slot chain: LUT ∝ slots × bits, FF ∝ slots), and the loop-back FIFO,
/// which in the RTL carries slot tags only (slots × tag bits in LUT-RAM and its pointers).
fn ray_slots(hw: &HwConfig, dp: &DatapathConfig) -> FabricItem {
    let slots = u64::from(hw.ray_slots());
    let bits = slot_table_bits(hw, dp);
    let (at_s, at_b) = (calibration::SLOTS_AT, calibration::SLOT_BITS_AT);
    let ram = scale(
        calibration::SLOT_RAM_LUTS,
        lutram_luts(slots, bits),
        lutram_luts(at_s, at_b),
    );
    let (lc, fc) = calibration::SLOT_LOGIC;
    let logic = scale(lc, slots * bits, at_s * at_b);
    let tag = slot_bits(hw);
    let ptr = clog2(slots) + 1;
    FabricItem {
        name: "ray_slots",
        instances: 1,
        per_instance: Fabric {
            lut: ram + logic + lutram_luts(slots, tag) + 3 * ptr,
            ff: scale(fc, slots, at_s) + 3 * ptr,
        },
        calibrated: true,
        formula: format!(
            "{slots} slots × {bits} bits: LUT-RAM {} · lutram / lutram(65 × 1682) + {lc} · (slots × bits) / (65 × 1682) LUT, {fc} · slots / 65 FF; loop-back {slots} × {tag}-bit tags",
            calibration::SLOT_RAM_LUTS
        ),
    }
}

/// svo_walker_pool's own logic around its walkers ([`calibration::POOL_MEASURED`]): with N =
/// W·R contexts, LUT = N·(a + b_r·R + c_n·N) + d_w2·W² (× the fit's `k1` at one walk-issue
/// lane) and FF = N·(f₀ + f_r·R) + f_w2·W² ([`calibration::POOL_FF_MILLI`]). The LUT fit is
/// the pool svo_top builds for the node memory: behind a cache every response comes on its
/// context's port ([`calibration::POOL_LUT_MILLI`]); with every node word on chip and no
/// cache (`onchip.levels` 21, the deepest tree's: MAX_DEPTH + 1) the records come on the
/// walkers' ports ([`calibration::POOL_PORTS_LUT_MILLI`], whose response decode grows as
/// N·W). A pool of one context (one walker of one context) schedules nothing: none.
fn walker_pool(hw: &HwConfig) -> FabricItem {
    let w = &hw.walker_pool;
    let (walkers, r) = (u64::from(w.walkers), u64::from(w.contexts_per_walker));
    let (n, w2) = (walkers * r, walkers * walkers);
    let on_ports = hw.node_memory.onchip.levels > crate::svo::MAX_DEPTH;
    let fit = if on_ports {
        calibration::POOL_PORTS_LUT_MILLI
    } else {
        calibration::POOL_LUT_MILLI
    };
    let (f0, f_r, f_w2) = calibration::POOL_FF_MILLI;
    let k1 = hw.walk_lanes() < 2;
    let per = if n > 1 {
        let lut_milli = n
            .saturating_mul(
                fit.a
                    .saturating_add(fit.b_r.saturating_mul(r))
                    .saturating_add(fit.c_n.saturating_mul(n)),
            )
            .saturating_add(fit.d_w2.saturating_mul(w2));
        let lut_milli = if k1 {
            lut_milli.saturating_mul(fit.k1) / 1000
        } else {
            lut_milli
        };
        let ff_milli = n
            .saturating_mul(f0.saturating_add(f_r.saturating_mul(r)))
            .saturating_add(f_w2.saturating_mul(w2));
        Fabric {
            lut: lut_milli.saturating_add(500) / 1000,
            ff: ff_milli.saturating_add(500) / 1000,
        }
    } else {
        Fabric::default()
    };
    let milli = |v: u64| format!("{}.{:03}", v / 1000, v % 1000);
    let mut lut = format!("N · ({} + {} R", milli(fit.a), milli(fit.b_r));
    if fit.c_n > 0 {
        lut += &format!(" + {} N", milli(fit.c_n));
    }
    lut += ")";
    if fit.d_w2 > 0 {
        lut += &format!(" + {} W²", milli(fit.d_w2));
    }
    FabricItem {
        name: "walker_pool",
        instances: 1,
        per_instance: per,
        calibrated: n > 1,
        formula: format!(
            "N = {n} contexts of W = {walkers} walkers, records on {}: {lut} LUT{}, N · ({} + {} R) + {} W² FF; measured at 2–32 walkers of 4–16 contexts",
            if on_ports { "the walker ports" } else { "the context ports" },
            if k1 {
                format!(" × {} (one lane)", milli(fit.k1))
            } else {
                String::new()
            },
            milli(f0),
            milli(f_r),
            milli(f_w2),
        ),
    }
}

/// The measure of the units' elastic pipes: Σ latency × width, each fixed-latency unit's
/// `svo_elastic` queue (capacity = its latency) of what leaves it, and its tag FIFO (one
/// more than the latency) of what waits beside it. Front (once): raygen (the ray), the sphere lanes with their
/// square roots (the ray and its candidate list; the tags: pass count and ray), the sorter
/// (ray and list; the tags: the ray). Per walk-issue lane (`transform_units`): transform and
/// reciprocal (pipe and tags of slot tags), walker root (its bundle: enter, t0 and t1, origin,
/// half extents, axis flags, slot tag), and the record's pack (the word and pixel beside the
/// normal unit and in the pack pipe: twice the pack latency).
pub fn elastic_measure(hw: &HwConfig, dp: &DatapathConfig) -> u64 {
    let w = |f: crate::fixed::Format| u64::from(f.width);
    let u = &hw.units;
    let l = |t: &crate::cycle::hw_config::UnitTiming| u64::from(t.latency_cycles);
    let (ray, list, s) = (ray_bits(hw, dp), candidate_list_bits(hw, dp), slot_bits(hw));
    let sphere = l(&u.sphere) + l(&u.sqrt);
    let front = l(&u.raygen) * ray
        + sphere * (ray + list)
        + (sphere + 1) * (8 + ray)
        + l(&u.sorter) * (ray + list)
        + (l(&u.sorter) + 1) * ray;
    let k = &dp.walker;
    let bundle = 1 + 6 * (w(k.t) + 1) + 3 * (w(k.pos) + 1) + 3 * w(k.pos) + 6 + s;
    let record = pixel_bits(hw) + u64::from(dp.hit_record.word_bits());
    let lane = (2 * l(&u.transform) + 1) * s
        + (2 * l(&u.reciprocal) + 1) * s
        + l(&u.walker_root) * bundle
        + 2 * l(&u.hit_pack) * record;
    front + u64::from(hw.transform_units) * lane
}

fn elastic_pipes(hw: &HwConfig, dp: &DatapathConfig) -> FabricItem {
    let m = elastic_measure(hw, dp);
    let (c, at) = (calibration::ELASTIC, calibration::ELASTIC_AT);
    FabricItem {
        name: "elastic_pipes",
        instances: 1,
        per_instance: Fabric {
            lut: scale(c.0, m, at),
            ff: scale(c.1, m, at),
        },
        calibrated: true,
        formula: format!("({} LUT, {} FF) · Σ latency × width {m} / {at}", c.0, c.1),
    }
}

/// The measure of the hit buffer's check pipe: the bits of its entry (pixel, the direct and
/// reuse flags, the record word, the ray's direction and candidate list), which its delay
/// line (one SRL per bit while the read latency is at most 16) and its queue's LUT-RAM
/// (⌈bits / 14⌉ RAM32M16 while the capacity is at most 32) grow with.
pub fn hit_check_measure(hw: &HwConfig, dp: &DatapathConfig) -> u64 {
    pixel_bits(hw)
        + 2
        + u64::from(dp.hit_record.word_bits())
        + 3 * u64::from(dp.raygen.dir.width)
        + candidate_list_bits(hw, dp)
}

fn hit_check_pipe(hw: &HwConfig, dp: &DatapathConfig) -> Option<FabricItem> {
    if !hw.hit_buffer.present {
        return None;
    }
    let m = hit_check_measure(hw, dp);
    let (c, at) = (calibration::HIT_CHECK_PIPE, calibration::HIT_CHECK_PIPE_AT);
    Some(FabricItem {
        name: "hit_check_pipe",
        instances: 1,
        per_instance: Fabric {
            lut: scale(c.0, m, at),
            ff: scale(c.1, m, at),
        },
        calibrated: true,
        formula: format!("({} LUT, {} FF) · entry bits {m} / {at}", c.0, c.1),
    })
}

/// The items of this module, in pipeline order.
pub fn core_logic_items(hw: &HwConfig, dp: &DatapathConfig) -> Vec<FabricItem> {
    let mut items = vec![front_gather(hw, dp)];
    items.extend(hit_check_pipe(hw, dp));
    items.push(ray_slots(hw, dp));
    items.push(walker_pool(hw));
    items.push(elastic_pipes(hw, dp));
    items
}

#[cfg(test)]
mod tests {
    use super::*;

    /// frame_hw's fields that size these items: one walker of one context (65 ray slots),
    /// the rest the default's (8 sphere lanes, 16 sorter lanes, a 1280 × 768 frame).
    fn frame_hw() -> HwConfig {
        let mut hw = HwConfig::default();
        hw.walker_pool.walkers = 1;
        hw.walker_pool.contexts_per_walker = 1;
        hw.transform_units = 1;
        hw.reciprocal_units = 3;
        hw.walker_root_units = 1;
        hw
    }

    #[test]
    fn the_measures_at_frame_hw_are_the_calibration_points() {
        let (hw, dp) = (frame_hw(), DatapathConfig::default());
        assert_eq!(u64::from(hw.ray_slots()), calibration::SLOTS_AT);
        assert_eq!(slot_table_bits(&hw, &dp), calibration::SLOT_BITS_AT);
        assert_eq!(elastic_measure(&hw, &dp), calibration::ELASTIC_AT);
        assert_eq!(hit_check_measure(&hw, &dp), calibration::HIT_CHECK_PIPE_AT);
        let items = core_logic_items(&hw, &dp);
        let at = |n: &str| {
            let f = items.iter().find(|i| i.name == n).unwrap().per_instance;
            (f.lut, f.ff)
        };
        assert_eq!(at("front_gather"), calibration::FRONT_GATHER);
        assert_eq!(at("elastic_pipes"), calibration::ELASTIC);
        assert_eq!(at("hit_check_pipe"), calibration::HIT_CHECK_PIPE);
        // The slot table and its logic, and the loop-back's 65 × 7-bit tags (16 LUTs of
        // RAM64M8) with 3 pointers of 8 bits.
        assert_eq!(
            at("ray_slots"),
            (
                calibration::SLOT_RAM_LUTS + calibration::SLOT_LOGIC.0 + 16 + 24,
                calibration::SLOT_LOGIC.1 + 24
            )
        );
    }

    #[test]
    fn more_lanes_keys_and_slots_cost_more() {
        let dp = DatapathConfig::default();
        let lut = |hw: &HwConfig, n: &str| {
            let items = core_logic_items(hw, &dp);
            items.iter().find(|i| i.name == n).unwrap().per_instance.lut
        };
        let base = frame_hw();
        let mut lanes = base.clone();
        lanes.sphere_units = 16;
        assert_eq!(lut(&lanes, "front_gather"), 2 * lut(&base, "front_gather"));
        let mut slots = base.clone();
        slots.walker_pool.walkers = 8;
        assert!(lut(&slots, "ray_slots") > lut(&base, "ray_slots"));
        let mut sorter = base.clone();
        sorter.sorter_lanes = 8;
        assert!(lut(&sorter, "front_gather") < lut(&base, "front_gather"));
        assert!(lut(&sorter, "elastic_pipes") < lut(&base, "elastic_pipes"));
        let mut none = base;
        none.hit_buffer.present = false;
        assert!(core_logic_items(&none, &dp)
            .iter()
            .all(|i| i.name != "hit_check_pipe"));
    }
}
