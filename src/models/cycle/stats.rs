//! A frame's cycle report: cycles, frame rate at the clock, rays per cycle, each stage's
//! busy / starved / back-pressured / idle cycles, FIFO occupancy, the walker pool, the node
//! memory, and which limit holds the frame rate.
//!
//! Pipeline position: produced by `pipeline.rs` per frame; printed by `sim` and written into
//! the JSON report (`frames[]`, documented in `docs/report.md`).

use rtl_model::cycle::fifo::FifoStats;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::memory::{DramDeviceStats, NodeMemoryStats};
use rtl_model::cycle::stage_stats::StageCycles;
use rtl_model::cycle::walker_pool::PoolCycles;
use serde::Serialize;

/// One FIFO's occupancy over the frame.
#[derive(Clone, Debug, Serialize)]
pub struct FifoReport {
    /// FIFO name (`HwConfig::fifos` field, or `loop_back`).
    pub name: String,
    /// Depth.
    pub depth: u64,
    /// Mean occupancy.
    pub mean_occupancy: f64,
    /// Maximum occupancy.
    pub max_occupancy: u64,
    /// Cycles a producer had data and the FIFO was full.
    pub full_cycles: u64,
    /// Mean cycles an item spent inside.
    pub mean_latency: f64,
}

/// The node memory over the frame.
#[derive(Clone, Debug, Serialize)]
pub struct MemoryReport {
    /// Node reads (descriptors and leaf slots).
    pub node_fetches: u64,
    /// Far-word reads.
    pub far_fetches: u64,
    /// Attribute-record reads.
    pub attr_fetches: u64,
    /// Bytes the walkers read.
    pub bytes: u64,
    /// Reads served on chip.
    pub onchip_reads: u64,
    /// Cache hit rate of the off-chip reads (hits / lookups).
    pub cache_hit_rate: f64,
    /// Bytes moved from DRAM.
    pub dram_bytes: u64,
    /// DRAM bandwidth used, % of peak over the frame.
    pub dram_bandwidth_pct: f64,
    /// Mean read latency, cycles.
    pub mean_latency: f64,
    /// Request-cycles waiting for an MSHR.
    pub mshr_wait: u64,
    /// Request-cycles waiting for a port.
    pub port_wait: u64,
    /// The DRAMsim3 device's figures, when it times the fills (absent with the built-in
    /// DRAM model).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dram_device: Option<DramDeviceReport>,
}

/// The DRAMsim3 backend over the frame (docs/cycle-model.md, DRAM; docs/report.md).
#[derive(Clone, Debug, Serialize)]
pub struct DramDeviceReport {
    /// The device (bundled DRAMsim3 configuration).
    pub device: String,
    /// Line fills and the read bursts they made.
    pub fills: u64,
    /// Read bursts (DRAMsim3 transactions).
    pub transactions: u64,
    /// Achieved bandwidth, bytes per pipeline cycle (completed bursts over the frame).
    pub bytes_per_cycle: f64,
    /// Row-buffer hit rate of the READ commands (from DRAMsim3's epochs in the frame).
    pub row_hit_rate: f64,
    /// READ commands, and of them row-buffer hits.
    pub read_cmds: u64,
    /// Row-buffer hits.
    pub row_hits: u64,
    /// ACTIVATE commands.
    pub activates: u64,
    /// Row conflicts: precharges forced by a request to another row of an open bank.
    pub row_conflicts: u64,
    /// REFRESH commands.
    pub refreshes: u64,
    /// DRAM clocks a burst waited for room in DRAMsim3's transaction queue.
    pub queue_full_clocks: u64,
}

impl DramDeviceReport {
    fn of(d: &DramDeviceStats, window_cycles: u64) -> Self {
        Self {
            device: d.device.clone(),
            fills: d.fills,
            transactions: d.transactions,
            bytes_per_cycle: d.bytes as f64 / window_cycles.max(1) as f64,
            row_hit_rate: d.row_hit_rate(),
            read_cmds: d.read_cmds,
            row_hits: d.row_hits,
            activates: d.activates,
            row_conflicts: d.row_conflicts,
            refreshes: d.refreshes,
            queue_full_clocks: d.queue_full_clocks,
        }
    }
}

impl MemoryReport {
    fn of(m: &NodeMemoryStats) -> Self {
        Self {
            node_fetches: m.fetches.node,
            far_fetches: m.fetches.far,
            attr_fetches: m.fetches.attr,
            bytes: m.bytes,
            onchip_reads: m.onchip_reads,
            cache_hit_rate: m.hit_rate(),
            dram_bytes: m.dram_bytes,
            dram_bandwidth_pct: m.dram_bandwidth_pct(),
            mean_latency: m.avg_latency(),
            mshr_wait: m.mshr_wait,
            port_wait: m.port_wait,
            dram_device: m
                .dram_device
                .as_ref()
                .map(|d| DramDeviceReport::of(d, m.window_cycles)),
        }
    }
}

/// Operations per pixel (averages over the frame's pixels), counted per unit invocation as
/// `docs/cycle-model.md` ("Operation counts") lists them.
#[derive(Clone, Debug, Default, Serialize)]
pub struct OpCounts {
    /// Multiplies.
    pub multiplies: f64,
    /// Adds, subtractions and compares.
    pub adds: f64,
    /// Square roots.
    pub square_roots: f64,
    /// Reciprocals.
    pub reciprocals: f64,
}

impl OpCounts {
    /// From a frame's unit invocation counts: sphere tests, walks (one transform, three
    /// reciprocals and one root each), walker steps and descents.
    pub fn per_pixel(
        pixels: u64,
        sphere_tests: u64,
        walks: u64,
        steps: u64,
        descents: u64,
    ) -> Self {
        let p = pixels.max(1) as f64;
        let (s, w, st, d) = (
            sphere_tests as f64,
            walks as f64,
            steps as f64,
            descents as f64,
        );
        // Sphere: l = c − o (3 adds), l·d and l·l (6 mul, 4 adds), t_ca² (1 mul), p² and its
        // compare (2 adds), T − p² (1 add), the root, t_ca − Δt − √ (2 adds).
        // Transform: o − c (3 adds), two 3×3 products (18 mul, 12 adds).
        // Root: ±e − o (6 adds), six products, entry/exit max/min and compares (6 adds).
        // Step: child interval select, entry/exit max/min (4), two compares; descent: three
        // midpoint adders.
        Self {
            multiplies: (7.0 * s + 18.0 * w + 6.0 * w) / p,
            adds: (12.0 * s + 15.0 * w + 12.0 * w + 6.0 * st + 3.0 * d) / p,
            square_roots: s / p,
            reciprocals: 3.0 * w / p,
        }
    }
}

/// Which limit holds the frame rate.
#[derive(Clone, Debug, Serialize)]
pub struct Bound {
    /// `clock` (the front end at one ray per cycle), `walkers`, `memory`, or a fixed unit.
    pub limit: String,
    /// Why, with the figures.
    pub reason: String,
}

/// One frame of the cycle model.
#[derive(Clone, Debug, Serialize)]
pub struct CycleFrame {
    /// Frame index (the report's `frame` field already says it).
    #[serde(skip)]
    pub frame: u32,
    /// Cycles from the first ray generated to the last record written.
    pub cycles: u64,
    /// Frames per second at the configured clock if every frame took this long.
    pub fps_at_clock: f64,
    /// Pixels per cycle.
    pub rays_per_cycle: f64,
    /// The ideal: one ray per clock per pipeline.
    pub rays_per_cycle_ideal: f64,
    /// Per stage.
    pub stages: Vec<StageCycles>,
    /// Per FIFO.
    pub fifos: Vec<FifoReport>,
    /// The walker pool (walker-cycles).
    pub walkers: PoolCycles,
    /// Mean busy contexts / all contexts.
    pub context_occupancy: f64,
    /// Node memory.
    pub memory: MemoryReport,
    /// Pixels reused from the hit buffer (the report's `hit_buffer_reused`).
    #[serde(skip)]
    pub reused: u64,
    /// Rays that stopped with candidates left (the report's `early_terminations`).
    #[serde(skip)]
    pub early_terminations: u64,
    /// Rays that walked.
    pub traced: u64,
    /// Operations per pixel.
    pub ops_per_pixel: OpCounts,
    /// Which limit holds.
    pub bound: Bound,
    /// Wall time of the cycle simulation (without the functional model), seconds.
    pub sim_wall_s: f64,
    /// Sampled timing (`--sample`): `cycles`, `fps_at_clock` and `rays_per_cycle` are then
    /// estimates, this says how they were drawn and gives their 95 % interval; the stage, FIFO,
    /// pool and memory figures cover the timed segments only (docs/cycle-model.md §3.5).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampled: Option<super::sample::SampledCycles>,
}

/// Frames per second at the clock: `frames` frames in `cycles` cycles at `clock_mhz` MHz. The
/// one place a frame rate is computed from cycles — frame lines, run summaries and sampled
/// estimates all call it, so one figure never prints as two.
pub fn fps_at_clock(clock_mhz: u32, frames: f64, cycles: f64) -> f64 {
    frames * f64::from(clock_mhz) * 1e6 / cycles.max(1.0)
}

impl CycleFrame {
    /// Assembles the report.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        hw: &HwConfig,
        frame: u32,
        cycles: u64,
        pixels: u64,
        stages: Vec<StageCycles>,
        fifos: &[(&str, usize, FifoStats)],
        walkers: PoolCycles,
        mem: NodeMemoryStats,
        reused: u64,
        early: u64,
        traced: u64,
        sim_wall_s: f64,
    ) -> Self {
        let c = cycles.max(1) as f64;
        let contexts = f64::from(hw.walker_pool.walkers * hw.walker_pool.contexts_per_walker);
        let fifos = fifos
            .iter()
            .map(|(n, depth, s)| FifoReport {
                name: (*n).to_string(),
                depth: *depth as u64,
                mean_occupancy: s.mean_occupancy(),
                max_occupancy: s.max_occupancy,
                full_cycles: s.full_cycles,
                mean_latency: s.mean_latency(),
            })
            .collect();
        let bound = bound_of(hw, &stages, &walkers, cycles, pixels);
        Self {
            frame,
            cycles,
            fps_at_clock: fps_at_clock(hw.clock_mhz, 1.0, c),
            rays_per_cycle: pixels as f64 / c,
            rays_per_cycle_ideal: 1.0,
            stages,
            fifos,
            context_occupancy: walkers.busy_context_cycles as f64 / c / contexts.max(1.0),
            walkers,
            memory: MemoryReport::of(&mem),
            reused,
            early_terminations: early,
            traced,
            ops_per_pixel: OpCounts::default(),
            bound,
            sim_wall_s,
            sampled: None,
        }
    }

    /// Turns the report of a sampled frame into its estimate: `cycles`, `fps_at_clock` and
    /// `rays_per_cycle` from the estimated cycles of `pixels` pixels, the sample in
    /// `sampled`. The rest keeps the timed segments' figures.
    pub fn set_sampled(&mut self, hw: &HwConfig, pixels: u64, est: super::sample::SampledCycles) {
        let c = est.cycles_estimate.max(1.0);
        self.cycles = c.round() as u64;
        self.fps_at_clock = fps_at_clock(hw.clock_mhz, 1.0, c);
        self.rays_per_cycle = pixels as f64 / c;
        // The limit from what was simulated: the timed pixels over the cycles simulated.
        self.bound = bound_of(
            hw,
            &self.stages,
            &self.walkers,
            est.cycles_simulated,
            est.pixels_timed,
        );
        self.sampled = Some(est);
    }
}

/// The limit: the front end if ray generation was busy nearly every cycle; otherwise the
/// walker pool, split by what its walker-cycles were spent on (issuing: the walkers' step
/// rate; waiting on reads: memory); a fixed unit if it was busy nearly every cycle.
fn bound_of(
    hw: &HwConfig,
    stages: &[StageCycles],
    w: &PoolCycles,
    cycles: u64,
    pixels: u64,
) -> Bound {
    let c = cycles.max(1) as f64;
    // A unit's throughput use: transactions per cycle (every unit here has II 1 per
    // transaction; a long pipeline with one item inside is not "busy" in this sense).
    let share = |n: &str| {
        stages
            .iter()
            .find(|s| s.name == n)
            .map_or(0.0, |s| s.transactions as f64 / c)
    };
    let wc = (w.issuing + w.memory_wait + w.latency_wait + w.backpressured + w.empty).max(1) as f64;
    let issuing = w.issuing as f64 / wc;
    let mem = w.memory_wait as f64 / wc;
    let lat = w.latency_wait as f64 / wc;
    let raygen = pixels as f64 / c;
    if raygen >= 0.9 {
        return Bound {
            limit: "clock".into(),
            reason: format!(
                "the front end generates {:.2} rays per cycle of the ideal 1: the frame rate is the clock's ({} MHz)",
                raygen, hw.clock_mhz
            ),
        };
    }
    for unit in [
        "transform",
        "reciprocal",
        "root",
        "sorter",
        "sphere",
        "check",
    ] {
        if share(unit) >= 0.95 && issuing < 0.5 {
            return Bound {
                limit: unit.into(),
                reason: format!(
                    "the {unit} stage is busy {:.0}% of cycles",
                    100.0 * share(unit)
                ),
            };
        }
    }
    let detail = format!(
        "walker-cycles: {:.0}% issuing, {:.0}% waiting on node reads, {:.0}% on the step pipeline, {:.0}% empty",
        100.0 * issuing,
        100.0 * mem,
        100.0 * lat,
        100.0 * w.empty as f64 / wc
    );
    if mem > issuing && mem > lat {
        Bound {
            limit: "memory".into(),
            reason: detail,
        }
    } else {
        Bound {
            limit: "walkers".into(),
            reason: detail,
        }
    }
}
