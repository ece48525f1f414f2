//! The hardware configuration of the cycle model: the target part and its resource budget, the
//! clock, the latency and initiation interval of every fixed unit, how many of each unit there
//! are, the walker pool, the FIFO depths between stages, the node memory (on-chip part, cache,
//! external DRAM) and the hit buffer: the schema (serde types and their defaults) and its
//! validation.
//!
//! Pipeline position: read once per run, like the datapath configuration; every stage, the
//! walker pool and the memory model take their part of it. The unit timings a datapath needs
//! are collected from the units by [`UnitTimings::for_datapath`] (`cycle::unit_latency`); what
//! a configuration costs lives in `cost`, the layer above: the estimate of the DSP48E2, BRAM36
//! and URAM288 it needs against the part's budget ([`HwConfig::resources`],
//! `cost::estimate`), which the report prints. This file imports nothing from `cost`. The
//! defaults, and the reason for each number, are documented field by field here and in
//! `docs/cycle-model.md` ("Hardware configuration").
//!
//! Conventions: latencies are cycles from a transaction entering a unit to its result leaving
//! it; an initiation interval (II) is the number of cycles between two transactions a unit
//! accepts (1 = fully pipelined). Every structure is serde (RON) with `deny_unknown_fields`,
//! and every field has a default, so a RON file need only name what it changes.
//!
//! This file holds the schema and what it derives (walk lanes, ray slots, the longest wait);
//! `hw_config/validate.rs` checks a configuration against its limits and its datapath.

mod validate;

use super::memory::NodeMemoryConfig;
pub use super::part::Part;
pub use super::ray_order::RayOrder;
use crate::datapath::DatapathConfig;
use crate::svo::MAX_DEPTH;
use serde::{Deserialize, Serialize};

/// The resource estimate's types, where the users of [`HwConfig::resources`] look for them.
/// They live in `crate::resources`, below this layer; the estimate itself is `cost::estimate`,
/// above it.
pub use crate::resources::{ResourceItem, ResourceReport, Resources};

/// Most sorter lanes: `sorter_lanes` must equal the datapath's `sorter.n`, an 8-bit field.
pub const MAX_SORTER_LANES: u32 = u8::MAX as u32;

/// Latency and initiation interval of a fixed-timing unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitTiming {
    /// Cycles from a transaction entering the unit to its result leaving it (≥ 1: every
    /// unit's output is registered, which the two-phase commit of the stages needs).
    pub latency_cycles: u32,
    /// Cycles between two transactions the unit accepts (1 = fully pipelined).
    pub ii: u32,
}

impl UnitTiming {
    /// A fully pipelined unit (II = 1) of the given latency.
    pub const fn pipelined(latency_cycles: u32) -> Self {
        Self {
            latency_cycles,
            ii: 1,
        }
    }
}

/// Timing of every fixed-latency unit, one instance each (how many instances there are is
/// set by [`HwConfig::sphere_units`] and its siblings).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct UnitTimings {
    /// Ray generation: one direction-table entry and the camera position per ray. Default 4
    /// (`units::raygen::LATENCY_CYCLES`): the table's URAM read as the hit buffer's
    /// (`HitBuffer::read_latency_cycles`).
    pub raygen: UnitTiming,
    /// Sphere test up to the square root's radicand, and the entry subtraction after it
    /// (`units::sphere::latency_cycles`, 16 by default); the square root itself is `sqrt`.
    pub sphere: UnitTiming,
    /// Square root of the sphere unit (digit recurrence, one stage per root digit):
    /// `units::sqrt::latency_cycles` of `units::sphere::sqrt_config` of the sphere formats, 32.
    pub sqrt: UnitTiming,
    /// Sorting network: `units::sorter::network_latency(n)` layers (6 for 8 lanes), II
    /// `network_ii` = 1. Rays with more candidates than lanes take the extra chunks and merge
    /// passes of `units::sorter::sort_timing` on top.
    pub sorter: UnitTiming,
    /// Transform into an instance's frame (`units::transform::latency_cycles`, 9 by default).
    pub transform: UnitTiming,
    /// One reciprocal 1/d: `units::reciprocal::latency_cycles`, 26 by default.
    pub reciprocal: UnitTiming,
    /// Root slabs of a walk, t = (±e − o)·(1/|d|) on three axes and the entry test
    /// (`units::walker::root_latency_cycles`, 8 by default).
    pub walker_root: UnitTiming,
    /// Packing a hit record into its word: one register (concatenation, t saturation;
    /// `units::hit_record::PACK_LATENCY_CYCLES`).
    pub hit_pack: UnitTiming,
    /// Unpacking a word read from the hit buffer: one register (wiring and the none-code
    /// compare; `units::hit_record::UNPACK_LATENCY_CYCLES`).
    pub hit_unpack: UnitTiming,
}

impl Default for UnitTimings {
    fn default() -> Self {
        Self::for_datapath(&DatapathConfig::default())
    }
}

impl UnitTimings {
    /// The units by name, in pipeline order (the names `validate` uses).
    pub fn named(&self) -> [(&'static str, UnitTiming); 9] {
        [
            ("raygen", self.raygen),
            ("sphere", self.sphere),
            ("sqrt", self.sqrt),
            ("sorter", self.sorter),
            ("transform", self.transform),
            ("reciprocal", self.reciprocal),
            ("walker_root", self.walker_root),
            ("hit_pack", self.hit_pack),
            ("hit_unpack", self.hit_unpack),
        ]
    }
}

/// How a walker keeps the frames of its explicit stack (DESIGN.md §4, "exact pop").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StackStorage {
    /// Each frame holds the node's full t-interval (t0, t1 on three axes), as
    /// `units::walker` does: 6·|t| + 68 bits per frame.
    FullT,
    /// Each frame holds the three low bits the midpoint shifts dropped, from which a pop
    /// rebuilds the parent's interval exactly: 3 + 68 bits per frame.
    ExactPop,
}

/// The walker pool.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WalkerPool {
    /// W: octree walkers. Default 32 of 8 contexts each (issue 29): the best pool whose
    /// estimate fits the XCVU9P's LUTs (67.2 % on crowd_1000 at 1280×768) once the barrel
    /// walkers and the walker pool were synthesised (`sim explore` over
    /// `configs/explore_fit_1280.ron`, docs/explore.md §6: 87.9–100 % of the 48 × 16 pool's
    /// frame rate on the car, moving_camera, vox_traffic and crowd_1000). Issue 28 had chosen
    /// 48 of 16 on an estimate without the pool's own logic; synthesised, that pool takes
    /// 135.9 % of the LUTs (`configs/default_48x16.ron` keeps it). 32 of 8 was also the
    /// default before issue 28 (`configs/baseline.ron`, with other fields of its time).
    pub walkers: u32,
    /// R: ray contexts per walker, interleaved so one context's node fetch does not stall the
    /// walker. Default 8 (issue 29; 16 from issue 28, `configs/default_48x16.ron`): a step
    /// takes `step_latency_cycles` (4) plus an on-chip or cache fetch (3–4), so 8 contexts
    /// keep a walker busy on on-chip hits; the walker pool's multiplexers grow with W·R and
    /// the barrel's state with R, so more contexts to hide DRAM misses cost LUTs the part
    /// does not have.
    pub contexts_per_walker: u32,
    /// Cycles the walker's datapath is busy per child examined (its II). Default 1: a step
    /// is muxes, 62-bit compares and midpoint adders (no DSP), pipelined.
    pub step_cycles: u32,
    /// Cycles from a context's step issuing to the same context's next step: the step
    /// pipeline (child interval select and entry/exit compares, next-child logic, midpoint
    /// adders). Default 4 (issue 29; 3 before, `configs/default_2026_11.ron`): the RTL's barrel
    /// walker (`svo_walker_barrel.v`, R > 1) steps in four stages (issue, apply of an arrived
    /// descriptor, stage A, stage B) to make 300 MHz by the clock rule and refuses less; the
    /// single-context walker (`svo_walker.v`, R = 1) makes 3 or more. Other contexts issue in
    /// between.
    pub step_latency_cycles: u32,
    /// Stack frames per context. Default 21 = `svo::MAX_DEPTH` + 1, the most `units::walker`
    /// ever pushes, so any image the builders make fits.
    pub stack_depth: u8,
    /// What a stack frame holds. Default [`StackStorage::FullT`]: what the functional walker
    /// and the RTL do (700-bit frames as the RTL stacks them, `HwConfig::stack_frame_bits`);
    /// 10 BRAM36 per walker of 8 or 16 contexts (700 bits wide), 320 at the default (15 % of
    /// the part), so the exact-pop logic (no RTL) is not yet worth it.
    pub stack: StackStorage,
    /// Node reads a walker may send per cycle: its request ports to the node memory. Default
    /// 1 (issue 29): a walker interleaves its R contexts in one datapath (a barrel design), so
    /// the RTL has one request port; when more of its contexts want to read in one cycle (two
    /// step latencies end together, or a read completes into the next read — far word then
    /// child descriptor, leaf slot then attribute record — while another context's step ends)
    /// the rest wait in the walker's send queue, oldest first (`walker_pool.rs`,
    /// `stalls.walker_read_port`). 0 = unlimited, every context sends the cycle it wants to:
    /// the model before issue 29 (`configs/explored_default.ron`, `configs/baseline.ron`).
    /// At most `contexts_per_walker` (more could never be used). The node memory's crossbars
    /// are priced for `walkers × read_ports` requesters; 0 is priced as one port per walker,
    /// as the model before issue 29 priced it (an idealisation: its timing let every context
    /// send, its estimate built one port), so the files that name that model keep both its
    /// cycles and its estimate.
    pub read_ports: u32,
    /// Registers between the node memory's response and the pool (issue 29, for 300 MHz):
    /// 0 (default) or 1. At 1 the pool sees a completion one cycle after the memory gives it,
    /// so the context moves on (and sends its next read) one cycle later
    /// (`walker_pool.rs`, "Registered response and request"). Other values are refused.
    #[serde(default)]
    pub response_register_cycles: u32,
    /// Registers between a walker's request port and the node memory (issue 29): 0 (default)
    /// or 1. At 1 a read the port picks in cycle C reaches the node memory in C + 1, where its
    /// merge with the fills in flight is decided (`walker_pool.rs`). Other values are refused.
    #[serde(default)]
    pub request_register_cycles: u32,
}

impl WalkerPool {
    /// Request ports one walker is priced for: `read_ports`, and 1 for 0 (unlimited in
    /// timing, priced as the pre-issue-29 model's one port: see `read_ports`).
    pub fn priced_read_ports(&self) -> u32 {
        self.read_ports.max(1)
    }
}

impl Default for WalkerPool {
    fn default() -> Self {
        Self {
            walkers: 32,
            contexts_per_walker: 8,
            step_cycles: 1,
            step_latency_cycles: 4,
            stack_depth: MAX_DEPTH + 1,
            stack: StackStorage::FullT,
            read_ports: 1,
            response_register_cycles: 0,
            request_register_cycles: 0,
        }
    }
}

/// Depths (entries) of the valid/ready FIFOs between stages, in pipeline order.
///
/// All are assumed to be LUTRAM/SRL FIFOs and are not counted as block RAM (see
/// [`HwConfig::resources`]).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FifoDepths {
    /// Ray generation → sphere tests. Default 4: both II = 1; covers the ready round trip.
    pub raygen_to_sphere: u32,
    /// Sphere tests → sorter (a ray's candidates). Default 4: as above.
    pub sphere_to_sorter: u32,
    /// Sorter → hit-buffer check. Default 8: absorbs the sorter's merge passes on rays with
    /// more candidates than lanes (a few cycles each).
    pub sorter_to_check: u32,
    /// Hit-buffer check → transform (rays to trace; a ray takes a walker slot only when its
    /// first walk enters the transform). Default 1024: the rays of the image rows where most
    /// pixels need walks wait here while the reused and empty pixels behind them keep flowing
    /// to the write port; with 32 the front end stalls behind every traced region and a still
    /// camera gains almost nothing from the hit buffer (cycle model: 0.43 against 0.41 rays
    /// per cycle). At about 360 bits per entry (pixel and its sorted candidates) it is 10
    /// BRAM36, not yet in the estimate (see `resources`).
    pub check_to_transform: u32,
    /// Transform → reciprocal. Default 4: both II = 1. A FIFO takes pushes against its
    /// registered occupancy, so it passes at most half its depth a cycle: 4 carries the
    /// default's two walk-issue lanes, and k lanes need 2k.
    pub transform_to_reciprocal: u32,
    /// Reciprocal → walker root. Default 4, as `transform_to_reciprocal`.
    pub reciprocal_to_root: u32,
    /// Walker root → dispatcher (walks waiting for a free context). Default 64: holds about
    /// one walk per context (W·R/2) so a context freed is refilled at once.
    pub root_to_dispatch: u32,
    /// Walkers → early termination / hit record. Default 16: one per walker.
    pub walker_to_record: u32,
    /// Hit record → hit-buffer write and frame buffer. Default 8: covers the write port's
    /// and the frame-buffer stream's short stalls.
    pub record_to_write: u32,
}

impl Default for FifoDepths {
    fn default() -> Self {
        Self {
            raygen_to_sphere: 4,
            sphere_to_sorter: 4,
            sorter_to_check: 8,
            check_to_transform: 1024,
            transform_to_reciprocal: 4,
            reciprocal_to_root: 4,
            root_to_dispatch: 64,
            walker_to_record: 16,
            record_to_write: 8,
        }
    }
}

impl FifoDepths {
    /// The FIFOs by name, in pipeline order (the names `validate` uses).
    pub fn named(&self) -> [(&'static str, u32); 9] {
        [
            ("raygen_to_sphere", self.raygen_to_sphere),
            ("sphere_to_sorter", self.sphere_to_sorter),
            ("sorter_to_check", self.sorter_to_check),
            ("check_to_transform", self.check_to_transform),
            ("transform_to_reciprocal", self.transform_to_reciprocal),
            ("reciprocal_to_root", self.reciprocal_to_root),
            ("root_to_dispatch", self.root_to_dispatch),
            ("walker_to_record", self.walker_to_record),
            ("record_to_write", self.record_to_write),
        ]
    }
}

/// Where a per-pixel table lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Placement {
    /// On chip in block RAM (RAMB36E2).
    Bram,
    /// On chip in UltraRAM (URAM288, 4K×72).
    Uram,
    /// In external DRAM (sharing its bandwidth with the node fetches).
    External,
}

/// The per-pixel hit buffer (paper §4.3).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HitBuffer {
    /// Whether the pipeline has a hit buffer. Default true; false when no pixel can ever be
    /// reused (scene-driven elaboration: the camera moves between every two frames): the
    /// check stage then reads nothing and passes rays on after its unpack register, and the
    /// buffer costs no memory.
    pub present: bool,
    /// Where it lives. Default URAM: the 1280×768 buffer of 72-bit words is 240 URAM288
    /// (a quarter of the part's) against 1,920 BRAM36 (89 % of them);
    /// `docs/units/hit-record.md` §6.
    pub placement: Placement,
    /// Read ports per cycle. 1, the only value: the check stage reads one pixel per cycle
    /// (one ray per clock), so a second read port would never be used and is refused.
    pub read_ports: u8,
    /// Write paths per cycle, 1 or 2. Default 2 (issue 28): with one, the records of walked
    /// rays and the words the check stage writes straight back (reused pixels, rays without a
    /// candidate) share one write port, the record stage first (`stages/check.rs`), which
    /// capped a frame with 69 % reuse near 0.83 rays per cycle. 2: the buffer is built as two
    /// banks interleaved on pixel parity, each a simple-dual-port memory (read port, write
    /// port) of half the pixels, so the same URAM288 count up to rounding; the record stage
    /// and the check stage each have their own write FIFO, and both write in one cycle unless
    /// their pixels fall in the same bank: the check's word first (it feeds on the front
    /// end's one ray a cycle), the record waits in its FIFO.
    pub write_ports: u8,
    /// Walked records the write stage takes per cycle, 1 or 2 (issue 28). Default 2. With 1 the
    /// record path writes one word a cycle, while the walk lanes pack up to one record each a
    /// cycle, so with two walk lanes and few reused pixels `record_to_write` fills in bursts
    /// and holds the record stage (the bound line's `record_write`). 2 needs the two banks of
    /// `write_ports: 2`: each bank's write port then takes the check's word, the record
    /// FIFO's head or the entry behind it (a 3:1 multiplexer per bit, and a second read port
    /// of `record_to_write`, both priced in `cost::structures`); in a cycle the check's word
    /// goes to its bank, the head record to the other bank if it falls there, and with no
    /// check word the record behind the head too if it falls in the other bank. With the buffer absent the same two paths carry the words out.
    pub record_writes: u8,
    /// Cycles from read address to word. Default 4: URAM read, output register and two
    /// pipeline registers of the cascade and output multiplexer of a 240-block array spread
    /// over several URAM columns. (External: the model uses the DRAM's latency instead.)
    pub read_latency_cycles: u32,
}

impl Default for HitBuffer {
    fn default() -> Self {
        Self {
            present: true,
            placement: Placement::Uram,
            read_ports: 1,
            write_ports: 2,
            record_writes: 2,
            read_latency_cycles: 4,
        }
    }
}

/// The largest frame the per-pixel memories are built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrameSize {
    /// Pixels per row. Default 1280 (the paper's resolution).
    pub width: u32,
    /// Rows. Default 768.
    pub height: u32,
}

impl Default for FrameSize {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 768,
        }
    }
}

impl FrameSize {
    /// Pixels of the frame.
    pub fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }
}

/// The whole hardware configuration.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HwConfig {
    /// Target part and its budget. Default [`Part::xcvu9p`].
    pub part: Part,
    /// Clock, MHz. Default 300: the DDR4-2400 controller's user-interface clock (4:1 to the
    /// 1200 MHz memory clock), so the pipeline and the memory controller share one clock
    /// without a crossing; well inside the -2 speed grade's limits (DSP48E2 with all
    /// registers 775 MHz, and 410 MHz even without its pipeline registers, DS923), leaving
    /// room for the 62-bit adders and the routing of a large three-die design; and 300 M
    /// rays/s at one ray per clock is 305 fps at 1280×768, twice the 150 fps target.
    pub clock_mhz: u32,
    /// Largest frame the hit buffer and direction table are built for.
    pub frame: FrameSize,
    /// Latency and II of each fixed unit.
    pub units: UnitTimings,
    /// Sphere-test lanes (each with its own square root): instances tested per cycle.
    /// Default 8: the default scene's instances, so a ray's tests take one cycle.
    pub sphere_units: u32,
    /// Lanes of the sorting network, 1 to [`MAX_SORTER_LANES`] (255); must equal the
    /// datapath's `sorter.n`. Default 16, the default datapath's.
    pub sorter_lanes: u32,
    /// Transform units, each taking one walk per initiation interval: `n` units are `n`
    /// parallel walk-issue lanes (docs/cycle-model.md §2.1). Default 2 (issue 28): the car
    /// needs 1.32 walks per ray, so one lane capped it at 0.757 rays per cycle whatever the
    /// memory; two lanes let it reach the clock. 1 before issue 28 (`configs/baseline.ron`).
    pub transform_units: u32,
    /// Whether the transform units have their 18 products. Default true; false only when no
    /// instance ever rotates (scene-driven elaboration, `docs/elaboration.md`): R = I makes
    /// the unit o − c and its rounding, exactly, with no DSP48E2 and
    /// `units::transform::LATENCY_WITHOUT_PRODUCTS` stages.
    pub transform_products: bool,
    /// Reciprocal units, one axis each: every three are one walk-issue lane (one walk per
    /// cycle); 1 or 2 take a walk in several passes; other values above 3 that are not a
    /// multiple of 3 are refused. Default 6: two walk-issue lanes, as the transform units.
    pub reciprocal_units: u32,
    /// Walker-root units (root slabs), shared by the pool as a stage before the dispatcher;
    /// `n` units are `n` walk-issue lanes. Default 2, as the transform units; one per walker
    /// would cost 36 DSP each for a unit busy one cycle in a dozen.
    pub walker_root_units: u32,
    /// The walker pool.
    pub walker_pool: WalkerPool,
    /// FIFO depths between stages.
    pub fifos: FifoDepths,
    /// Node memory: on-chip top levels, cache, DRAM — the node-memory model's own
    /// configuration (`cycle::memory`), whose fields and defaults are documented there.
    pub node_memory: NodeMemoryConfig,
    /// Hit buffer.
    pub hit_buffer: HitBuffer,
    /// Where the per-pixel direction table (`units::raygen`, 3 × 32 bits per pixel) lives.
    /// Default URAM: 480 URAM288 at 1280×768. The alternative, a sequential DRAM stream
    /// through a prefetch FIFO (12 bytes per ray, 9 % of the DRAM's peak at 150 fps), would
    /// save them, but it would take DRAM bandwidth that the node-memory model does not
    /// count; on chip, the DRAM carries only the node and attribute reads the model times.
    /// With the 105-bit hit record (`include_voxel`) the two tables no longer fit the
    /// part's URAM together, and this is the one to move out.
    pub direction_table: Placement,
    /// The order ray generation visits the pixels in (`cycle::ray_order`): `Scanline`,
    /// `Tiles(n)` or `Morton`. Timing only: neighbouring rays in flight together share node
    /// reads. Default `Scanline`, the order before issue 28.
    pub ray_order: RayOrder,
}

impl Default for HwConfig {
    fn default() -> Self {
        Self::for_datapath(&DatapathConfig::default())
    }
}

impl HwConfig {
    /// The default configuration with the unit timings and sorter lanes of `dp`.
    pub fn for_datapath(dp: &DatapathConfig) -> Self {
        Self {
            part: Part::default(),
            clock_mhz: 300,
            frame: FrameSize::default(),
            units: UnitTimings::for_datapath(dp),
            sphere_units: 8,
            sorter_lanes: u32::from(dp.sorter.n),
            transform_units: 2,
            transform_products: true,
            reciprocal_units: 6,
            walker_root_units: 2,
            walker_pool: WalkerPool::default(),
            fifos: FifoDepths::default(),
            node_memory: NodeMemoryConfig::default(),
            hit_buffer: HitBuffer::default(),
            direction_table: Placement::Uram,
            ray_order: RayOrder::Scanline,
        }
    }

    /// Walks the reciprocal units take per cycle: one per three units (a walk's three axes);
    /// with fewer than three units, one walk in several passes.
    pub fn reciprocal_walk_lanes(&self) -> u32 {
        (self.reciprocal_units / 3).max(1)
    }

    /// Width of the walk section's glue: the FIFOs from the transform to the dispatcher and the
    /// loop back, the dispatcher, the walker pool's retire port and the record stage take up to
    /// this many walks per cycle. The widest of the walk-issue units (`transform_units`,
    /// [`reciprocal_walk_lanes`](Self::reciprocal_walk_lanes), `walker_root_units`), so that
    /// the glue never binds before the units the configuration paid for
    /// (docs/cycle-model.md §2.1, "Walk issue of width k").
    pub fn walk_lanes(&self) -> u32 {
        self.transform_units
            .max(self.reciprocal_walk_lanes())
            .max(self.walker_root_units)
    }

    fn ray_slots_wide(&self) -> u64 {
        let w = &self.walker_pool;
        u64::from(w.walkers) * u64::from(w.contexts_per_walker)
            + u64::from(self.fifos.root_to_dispatch)
    }

    /// Ray slots of the pipeline: every walker context, plus the walks that can wait for one
    /// at the dispatcher (`fifos.root_to_dispatch`); the depth of the loop-back FIFO.
    /// [`validate`](Self::validate) keeps it within the deepest FIFO (65,536); saturates on an
    /// unvalidated configuration.
    pub fn ray_slots(&self) -> u32 {
        u32::try_from(self.ray_slots_wide()).unwrap_or(u32::MAX)
    }

    /// The longest single wait the configuration can make a transaction take: the largest
    /// latency or initiation interval of any unit, walker step, memory or hit-buffer read.
    /// The cycle model's no-progress watchdog scales with it.
    pub fn longest_wait_cycles(&self) -> u32 {
        let nm = &self.node_memory;
        let w = &self.walker_pool;
        let units = self
            .units
            .named()
            .into_iter()
            .flat_map(|(_, t)| [t.latency_cycles, t.ii]);
        units
            .chain([
                w.step_cycles,
                w.step_latency_cycles,
                nm.onchip.latency,
                nm.cache.hit_latency,
                nm.dram.latency,
                self.hit_buffer.read_latency_cycles,
            ])
            .max()
            .unwrap_or(1)
    }
}
