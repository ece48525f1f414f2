//! A frame's cycle report: cycles, frame rate at the clock, rays per cycle, each stage's
//! busy / starved / back-pressured / idle cycles, FIFO occupancy, the walker pool, the node
//! memory, and which limit holds the frame rate (the rule that names it: `stats/bound.rs`).
//!
//! Pipeline position: produced by `pipeline.rs` per frame; printed by `sim` and written into
//! the JSON report (`frames[]`, documented in `docs/report.md`).

mod bound;

use rtl_model::cycle::fifo::FifoStats;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::memory::{DramDeviceStats, NodeMemoryStats};
use rtl_model::cycle::stage_stats::StageCycles;
use rtl_model::cycle::walker_pool::PoolCycles;
use serde::Serialize;

use bound::bound_of;
pub use bound::{Bound, LIMITS};

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

/// Per-cause stall counters of a frame (docs/cycle-model.md §2.2): what each limit held back.
/// The pipeline's are cycles; the node memory's are request-cycles (one read waiting one cycle
/// counts one), a split of the reads' summed latency.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct StallCounts {
    /// Cycles in which a walk waited at a transform, reciprocal or walker-root unit with
    /// every unit of the stage busy and room after it: the walk-issue width.
    pub walk_issue: u64,
    /// Cycles in which the check stage held a decided word (reused pixel, ray without a
    /// candidate) because its write path had no port or room.
    pub write_port: u64,
    /// Cycles in which the head record waited because the check stage's word took its
    /// hit-buffer bank (two write paths; the check's word goes first).
    pub write_bank_conflicts: u64,
    /// Cycles in which the transform had a free unit and no walk at its inputs while rays of
    /// the frame were still to come: the walk section waited for ray generation (ray
    /// generation, spheres, sorter, check).
    pub ray_generation: u64,
    /// Cycles in which the walk section waited for rays (as `ray_generation`) while the sorter
    /// held a waiting ray at its input for the network issues and merge passes of a ray with
    /// more candidates than lanes (`units::sorter::pipe_cost`). Counted instead of
    /// `ray_generation`.
    pub sorter: u64,
    /// Cycles in which the walk section waited for rays while the sphere lanes held a waiting
    /// ray for a ray's further passes (more instances, or a tile's list, than lanes), and the
    /// sorter did not. Counted instead of `ray_generation`.
    pub sphere: u64,
    /// Cycles in which the record stage held a packed record that `record_to_write` had no
    /// room for: walked records arrive in bursts of up to the walk lanes per cycle and are
    /// written at one per cycle. While it is held no walk result is decided, so the walkers
    /// keep finished walks (back-pressured) and their contexts fill.
    pub record_write: u64,
    /// Cycles in which a walk waited at the dispatcher with every context busy.
    pub walkers_full: u64,
    /// Node reads: request-cycles waiting in a walker's send queue for one of its request
    /// ports (`walker_pool.read_ports`), before the read reaches the node memory (the pool's
    /// `read_port_waits`).
    pub walker_read_port: u64,
    /// Node reads: request-cycles waiting for a bank's or the cache's port.
    pub memory_ports: u64,
    /// Node reads: request-cycles waiting behind a miss with no free MSHR.
    pub mshr_full: u64,
    /// Node reads: the nominal latency of on-chip and cache hits (request-cycles).
    pub hit_latency: u64,
    /// Node reads: the DRAM latency: the fills' nominal latency (fills × `dram.latency`) and
    /// the part of the rest (below) the bus was idle for.
    pub dram_latency: u64,
    /// Node reads: the rest of their latency (waiting for the DRAM bus, or for a fill in
    /// flight), times the fraction of cycles the DRAM bus was busy: the bandwidth's share.
    pub dram_bandwidth: u64,
}

impl StallCounts {
    /// The node memory's part, from its statistics and `hw`'s nominal latencies.
    pub fn with_memory(mut self, hw: &HwConfig, m: &NodeMemoryStats) -> Self {
        let nm = &hw.node_memory;
        self.memory_ports = m.port_wait;
        self.mshr_full = m.mshr_wait;
        self.hit_latency = m.onchip_reads * u64::from(nm.onchip.latency)
            + m.cache_lookups * u64::from(nm.cache.hit_latency);
        let fills = m.dram_fills * u64::from(nm.dram.latency);
        // The rest of the reads' latency waited for the DRAM bus or for a fill in flight (a
        // merged miss). A read can only queue for the bus while the bus is busy, so the rest
        // is split by the bus's busy fraction: that share to bandwidth, the other to latency.
        let rest = m
            .latency_sum
            .saturating_sub(self.memory_ports + self.mshr_full + self.hit_latency + fills);
        let busy = m.dram_busy_cycles.min(m.window_cycles) as f64 / m.window_cycles.max(1) as f64;
        self.dram_bandwidth = (rest as f64 * busy).round() as u64;
        self.dram_latency = fills + (rest - self.dram_bandwidth.min(rest));
        self
    }

    /// The counters with `o`'s added.
    pub fn add(&mut self, o: &Self) {
        self.walk_issue += o.walk_issue;
        self.write_port += o.write_port;
        self.write_bank_conflicts += o.write_bank_conflicts;
        self.ray_generation += o.ray_generation;
        self.sorter += o.sorter;
        self.sphere += o.sphere;
        self.record_write += o.record_write;
        self.walkers_full += o.walkers_full;
        self.walker_read_port += o.walker_read_port;
        self.memory_ports += o.memory_ports;
        self.mshr_full += o.mshr_full;
        self.hit_latency += o.hit_latency;
        self.dram_latency += o.dram_latency;
        self.dram_bandwidth += o.dram_bandwidth;
    }
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
    /// Per-cause stall counters.
    pub stalls: StallCounts,
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

/// What a frame's pipeline measured, for [`CycleFrame::new`].
pub struct FrameMeasures<'a> {
    /// Frame number.
    pub frame: u32,
    /// Cycles of the frame.
    pub cycles: u64,
    /// Pixels in the frame.
    pub pixels: u64,
    /// The stage rows, in pipeline order.
    pub stages: Vec<StageCycles>,
    /// Name, depth and counters of each FIFO.
    pub fifos: &'a [(&'a str, usize, FifoStats)],
    /// The walker pool's cycle counts.
    pub walkers: PoolCycles,
    /// The node memory's statistics.
    pub mem: NodeMemoryStats,
    /// Pixels reused from the hit buffer.
    pub reused: u64,
    /// Rays that stopped with candidates left.
    pub early: u64,
    /// Rays that entered the walk section.
    pub traced: u64,
    /// The pipeline's per-cause stall counters.
    pub stalls: StallCounts,
    /// Wall time the frame took.
    pub sim_wall_s: f64,
}

impl CycleFrame {
    /// Assembles the report of a frame on `hw` from what its pipeline measured.
    pub fn new(hw: &HwConfig, m: FrameMeasures<'_>) -> Self {
        let FrameMeasures {
            frame,
            cycles,
            pixels,
            stages,
            fifos,
            walkers,
            mem,
            reused,
            early,
            traced,
            stalls,
            sim_wall_s,
        } = m;
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
        let stalls = StallCounts {
            walkers_full: walkers.dispatch_stalls,
            walker_read_port: walkers.read_port_waits,
            ..stalls
        }
        .with_memory(hw, &mem);
        let bound = bound_of(hw, &stages, &walkers, &stalls, cycles, pixels);
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
            stalls,
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
            &self.stalls,
            est.cycles_simulated,
            est.pixels_timed,
        );
        self.sampled = Some(est);
    }
}
