//! The console text of a run: the per-frame lines, the last frame's cycle tables, the asset
//! list and the summary, as `sim` prints them (`docs/report.md` §1 explains every field).
//!
//! Pipeline position: after each frame of [`crate::run::run`] (through its progress
//! callback) and after the run; the JSON report (`output::report`) carries the same numbers.
//! Each function returns text so that the command line only prints it. They take plain
//! values (the scene, the renderer's switches, [`Destinations`]), not the run's configuration,
//! so that this layer does not import the run layer (docs/architecture.md §1).

use super::report::{AssetReport, CycleSummary, FrameReport, Summary};
use crate::models::cycle::CycleFrame;
use crate::models::reference::{FrameStats, RenderOptions};
use crate::world::scene::Scene;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// The run's opening line: scene, resolution, frames, instances, threads and options.
pub fn run_header(scene: &Scene, options: &RenderOptions, threads: usize) -> String {
    let (w, h) = scene.file.resolution;
    let on = |b: bool| if b { "on" } else { "off" };
    format!(
        "sim: {} — {}x{}, {} frames, {} instances, {} threads, hit buffer {}, early termination {}, culling {}, sort {}",
        scene.origin,
        w,
        h,
        scene.file.frames,
        scene.file.instances.len(),
        threads,
        on(options.use_hit_buffer),
        on(options.early_termination),
        on(options.culling),
        on(options.sort),
    )
}

/// A frame's counters: rays, sphere tests, candidates, walks, reuse and wall time.
pub fn frame_line(st: &FrameStats, frames: u32) -> String {
    let cand = st.candidates as f64 / (st.rays - st.hit_buffer_reused).max(1) as f64;
    format!(
        "frame {:>4}/{frames}  rays {:>8}  sphere tests {:>9}  culled {:>9}  cand/ray {:>5.2}  walks {:>8}  steps {:>10}  early-term {:>7}  reused {:>8} ({:>5.1}%)  {:>8.1} ms  {:>7.2} M rays/s",
        st.frame,
        st.rays,
        st.sphere_tests,
        st.spheres_culled,
        cand,
        st.walks,
        st.walker_steps,
        st.early_terminations,
        st.hit_buffer_reused,
        100.0 * st.hit_buffer_reused as f64 / st.rays.max(1) as f64,
        st.wall_s * 1e3,
        st.rays_per_s / 1e6
    )
}

/// A frame's lines: the counters, then the accuracy and cycle lines when the model has them.
pub fn frame_lines(f: &FrameReport, frames: u32, clock_mhz: u32) -> String {
    let mut s = frame_line(&f.stats, frames);
    if let Some(acc) = &f.accuracy {
        let _ = write!(
            s,
            "\n           accuracy: {} px  hit/miss {}  instance {}  voxel {} ({} beyond bound)  t err max {:.3e} m rms {:.3e} m  saturations {}  step limits {}  zero flushes {}  reference {:.1} ms",
            acc.pixels,
            acc.hit_mismatches,
            acc.instance_mismatches,
            acc.voxel_mismatches,
            acc.voxel_mismatches_beyond_bound,
            acc.t_err_max,
            acc.t_err_rms,
            acc.saturations,
            acc.step_limit_hits,
            acc.zero_flushes,
            f.reference_wall_s.unwrap_or(0.0) * 1e3
        );
    }
    if let Some(sm) = f.cycle.as_ref().and_then(|c| c.sampled.as_ref()) {
        let _ = write!(
            s,
            "\n           SAMPLED (1 band in {} of {} rows, {} of {} bands timed): cycles ≈ {:.0} (95% CI {:.0}–{:.0})  ≈ {:.1} fps (95% CI {:.1}–{:.1})",
            sm.period,
            sm.band_rows,
            sm.bands_timed,
            sm.bands,
            sm.cycles_estimate,
            sm.cycles_low,
            sm.cycles_high,
            f.cycle.as_ref().map_or(0.0, |c| c.fps_at_clock),
            sm.fps_low,
            sm.fps_high
        );
    }
    if let Some(c) = &f.cycle {
        let _ = write!(
            s,
            "\n           cycles {:>9}  {:>8.1} fps @ {} MHz  {:.3} rays/cycle (ideal 1)  walkers {:>3.0}% issuing {:>3.0}% on memory  cache hit {:>5.1}%  DRAM {:>4.1}% of peak  bound: {}",
            c.cycles,
            c.fps_at_clock,
            clock_mhz,
            c.rays_per_cycle,
            100.0 * c.walkers.issuing as f64 / walker_cycles(c),
            100.0 * c.walkers.memory_wait as f64 / walker_cycles(c),
            100.0 * c.memory.cache_hit_rate,
            c.memory.dram_bandwidth_pct,
            c.bound.limit
        );
    }
    s
}

/// Walker-cycles of a frame (every walker, every cycle), the denominator of the shares.
fn walker_cycles(c: &CycleFrame) -> f64 {
    let w = &c.walkers;
    (w.issuing + w.memory_wait + w.latency_wait + w.backpressured + w.empty).max(1) as f64
}

/// A frame's stage, FIFO and memory tables (printed for the last frame).
pub fn cycle_tables(c: &CycleFrame) -> String {
    let mut s = String::new();
    let cyc = c.cycles.max(1) as f64;
    match &c.sampled {
        // Sampled timing: the rows cover the cycles simulated, not the estimate.
        Some(sm) => {
            let cyc = sm.cycles_simulated.max(1) as f64;
            let _ = writeln!(
                s,
                "last frame, SAMPLED: per stage (% of the {} cycles simulated for {} of {} pixels):",
                sm.cycles_simulated, sm.pixels_timed, sm.pixels
            );
            return stage_tables(s, c, cyc);
        }
        None => {
            let _ = writeln!(s, "last frame, per stage (% of {} cycles):", c.cycles);
        }
    }
    stage_tables(s, c, cyc)
}

/// The stage, walker, FIFO, memory and bound lines of [`cycle_tables`] after its header;
/// `cyc` is the cycles the stage rows cover.
fn stage_tables(mut s: String, c: &CycleFrame, cyc: f64) -> String {
    let _ = writeln!(
        s,
        "  {:<11} {:>7} {:>8} {:>14} {:>6} {:>12}",
        "stage", "busy", "starved", "backpressured", "idle", "transactions"
    );
    for st in &c.stages {
        let _ = writeln!(
            s,
            "  {:<11} {:>6.1}% {:>7.1}% {:>13.1}% {:>5.1}% {:>12}",
            st.name,
            100.0 * st.busy as f64 / cyc,
            100.0 * st.starved as f64 / cyc,
            100.0 * st.backpressured as f64 / cyc,
            100.0 * st.idle as f64 / cyc,
            st.transactions
        );
    }
    let w = &c.walkers;
    let wc = walker_cycles(c);
    let _ = writeln!(
        s,
        "  walkers: {} walks, {} issue slots; walker-cycles {:.1}% issuing, {:.1}% waiting on memory, {:.1}% on the step pipeline, {:.1}% back-pressured, {:.1}% empty; contexts {:.1}% occupied; {} dispatch stalls; {} read-port waits",
        w.walks,
        w.slots,
        100.0 * w.issuing as f64 / wc,
        100.0 * w.memory_wait as f64 / wc,
        100.0 * w.latency_wait as f64 / wc,
        100.0 * w.backpressured as f64 / wc,
        100.0 * w.empty as f64 / wc,
        100.0 * c.context_occupancy,
        w.dispatch_stalls,
        w.read_port_waits
    );
    let _ = writeln!(s, "  FIFOs (depth, mean / max occupancy, full cycles):");
    for f in &c.fifos {
        let _ = writeln!(
            s,
            "    {:<24} {:>4}  {:>6.2} / {:<4} {:>8}",
            f.name, f.depth, f.mean_occupancy, f.max_occupancy, f.full_cycles
        );
    }
    let m = &c.memory;
    let _ = writeln!(
        s,
        "  node memory: {} node + {} far + {} attr reads, {} bytes; {} on chip; cache hit rate {:.1}%; DRAM {} bytes = {:.1}% of peak; mean latency {:.1} cycles",
        m.node_fetches,
        m.far_fetches,
        m.attr_fetches,
        m.bytes,
        m.onchip_reads,
        100.0 * m.cache_hit_rate,
        m.dram_bytes,
        m.dram_bandwidth_pct,
        m.mean_latency
    );
    if let Some(d) = &m.dram_device {
        let _ = writeln!(
            s,
            "  DRAM (DRAMsim3 {}): {} fills in {} bursts, {:.1} bytes/cycle achieved; row-buffer hit rate {:.1}% ({} of {} reads), {} activates, {} row conflicts, {} refreshes; queue full {} DRAM clocks",
            d.device,
            d.fills,
            d.transactions,
            d.bytes_per_cycle,
            100.0 * d.row_hit_rate,
            d.row_hits,
            d.read_cmds,
            d.activates,
            d.row_conflicts,
            d.refreshes,
            d.queue_full_clocks
        );
    }
    let o = &c.ops_per_pixel;
    let _ = writeln!(
        s,
        "  per pixel: {:.1} multiplies, {:.1} adds, {:.2} square roots, {:.2} reciprocals",
        o.multiplies, o.adds, o.square_roots, o.reciprocals
    );
    let _ = write!(s, "  bound: {} — {}", c.bound.limit, c.bound.reason);
    s
}

/// Each asset's memory image: kind, depth, nodes, leaves, far pointers, size, build time.
pub fn assets_table(assets: &[AssetReport]) -> String {
    let mut s = String::from("assets:");
    for r in assets {
        let _ = write!(
            s,
            "\n  {:<16} {:<3} depth {:>2}  nodes {:>9}  leaves {:>9}  far {:>5}  {:>8.2} MiB  built in {:.2} s",
            r.name,
            r.kind,
            r.depth,
            r.nodes,
            r.leaves,
            r.far_words,
            (r.node_bytes + r.attr_bytes) as f64 / (1 << 20) as f64,
            r.build_s
        );
    }
    s
}

/// The closing summary, and with the cycle model its frame rate and the resource estimate.
/// The `--lift` line: the frame rate with `limit` made ideal against the run's
/// (docs/cycle-model.md §2.2).
pub fn lift_line(limit: &str, before: &CycleSummary, after: &CycleSummary) -> String {
    let gain = 100.0 * (after.fps_at_clock / before.fps_at_clock.max(f64::MIN_POSITIVE) - 1.0);
    format!(
        "lift {limit}: {:.1} → {:.1} fps ({gain:+.1}%), {:.3} → {:.3} rays/cycle; bound then: {}",
        before.fps_at_clock,
        after.fps_at_clock,
        before.rays_per_cycle,
        after.rays_per_cycle,
        after.bound
    )
}

pub fn summary(s: &Summary) -> String {
    let mut t = format!(
        "summary: {} frames, {} rays in {:.3} s = {:.2} M rays/s; hit buffer reused {} pixels ({:.1}%); {} walker steps; assets built in {:.2} s",
        s.frames,
        s.rays,
        s.wall_s,
        s.rays_per_s / 1e6,
        s.hit_buffer_reused,
        100.0 * s.reuse_fraction,
        s.walker_steps,
        s.build_s
    );
    if let Some(sm) = s.cycle.as_ref().and_then(|c| c.sampled.as_ref()) {
        let _ = write!(
            t,
            "\ncycle model, SAMPLED timing (estimates; {}): {:.0} cycles (95% CI {:.0}–{:.0}) = {:.1} fps (95% CI {:.1}–{:.1})",
            sm.method, sm.cycles_estimate, sm.cycles_low, sm.cycles_high, sm.fps, sm.fps_low, sm.fps_high
        );
    }
    if let Some(c) = &s.cycle {
        let _ = write!(
            t,
            "\ncycle model: {} cycles = {:.1} fps at {} MHz (slowest frame {:.1} fps), {:.3} rays/cycle; bound: {}; simulated {:.2} M rays/s, {:.2} M cycles/s\n{}",
            c.cycles,
            c.fps_at_clock,
            c.clock_mhz,
            c.fps_at_clock_min,
            c.rays_per_cycle,
            c.bound,
            c.sim_rays_per_s / 1e6,
            c.sim_cycles_per_s / 1e6,
            c.resources
        );
        if let Some(fab) = &c.fabric {
            let _ = write!(t, "\n{fab}");
        }
    }
    t
}

/// The files a run was asked to write, as plain paths: what [`written`] lists. The run layer
/// fills it from its configuration (`RunConfig::destinations`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Destinations<'a> {
    /// Folder of the PNGs (`--out`).
    pub out_dir: Option<&'a Path>,
    /// Waveforms of the cycle model.
    pub vcd: Option<&'a Path>,
    /// Transaction log of the cycle model.
    pub transaction_log: Option<&'a Path>,
    /// JSON report.
    pub report_json: Option<&'a Path>,
    /// Hit-record dump.
    pub dump_hits: Option<&'a Path>,
    /// The model wrote `diff_NNNN.png` beside each frame (the fixed and cycle models).
    pub diff_pngs: bool,
}

/// The PNG line: what was written into `dir`, counted and named — `frame_NNNN.png` per frame,
/// and for the fixed and cycle models also `diff_NNNN.png` (where the model differs from the
/// reference) per frame.
fn written_pngs(diffs: bool, frames: u32, dir: &Path) -> String {
    let last = frames.saturating_sub(1);
    let range = |kind: &str| {
        if frames == 1 {
            format!("{kind}_0000.png")
        } else {
            format!("{kind}_0000.png … {kind}_{last:04}.png")
        }
    };
    if !diffs {
        format!(
            "wrote {frames} PNGs to {}: {} (the frames)",
            dir.display(),
            range("frame")
        )
    } else {
        format!(
            "wrote {} PNGs to {}: {} (the frames) and {} (where the model differs from the reference)",
            2 * u64::from(frames),
            dir.display(),
            range("frame"),
            range("diff")
        )
    }
}

/// What the run wrote, one `wrote …` line each.
pub fn written(to: &Destinations<'_>, frames: u32) -> String {
    let name = |p: &Path| {
        if p.as_os_str() == "-" {
            "to standard output".to_string()
        } else {
            p.display().to_string()
        }
    };
    let mut lines = Vec::new();
    if let Some(dir) = to.out_dir {
        lines.push(written_pngs(to.diff_pngs, frames, dir));
    }
    if let Some(p) = to.vcd {
        lines.push(format!("wrote waveforms {}", name(p)));
    }
    if let Some(p) = to.transaction_log {
        lines.push(format!("wrote transaction log {}", name(p)));
    }
    if let Some(p) = to.report_json {
        lines.push(format!("wrote report {}", name(p)));
    }
    if let Some(p) = to.dump_hits {
        lines.push(format!("wrote hit records {}", name(p)));
    }
    lines.join("\n")
}

/// The run's saturations, if any: how many, in how many frames, and on which signals (most
/// first), with where the formats' ranges are documented. `None` when every value fitted.
pub fn saturation_warning(frames: &[FrameReport]) -> Option<String> {
    let total: u64 = frames
        .iter()
        .filter_map(|f| f.accuracy.as_ref())
        .map(|a| a.saturations)
        .sum();
    if total == 0 {
        return None;
    }
    let hit = frames
        .iter()
        .filter(|f| f.accuracy.as_ref().is_some_and(|a| a.saturations > 0))
        .count();
    let mut by_signal: BTreeMap<&str, u64> = BTreeMap::new();
    for (name, n) in frames.iter().filter_map(|f| f.overflows.as_ref()).flatten() {
        *by_signal.entry(name.as_str()).or_default() += n;
    }
    let mut signals: Vec<(&str, u64)> = by_signal.into_iter().collect();
    signals.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    let list: Vec<String> = signals.iter().map(|(s, n)| format!("{s} {n}")).collect();
    Some(format!(
        "{total} datapath values saturated in {hit} of {} frames ({}): the scene does not fit the \
         datapath's formats (ranges in docs/number-formats.md §2); scale the scene, move it \
         nearer the origin, or widen the formats with --datapath",
        frames.len(),
        list.join(", ")
    ))
}
