//! The cycle-accurate pipeline of one frame: every stage evaluated once per clock, joined by
//! valid/ready FIFOs, with the walker pool, node memory and hit-buffer memory.
//!
//! Pipeline position: the whole datapath of docs/cycle-model.md §2 in time. [`Pipeline::step`]
//! is one clock: the stage kernels (`super::stages`, one file each) in the order below,
//! consumers first, each reading only registered state through read-only ports
//! (`stages::io`) and returning its effects into the reused buffers of `commit::Effects`, so the
//! order cannot change any result (the record stage's same-cycle signals excepted, see
//! [`EvalOrder`]); then one commit, `Effects::apply`, that drives the FIFOs, the ray slots,
//! the hit buffer, the counts and the transaction log with every stage's effects, and one
//! edge that commits every FIFO and the hit-buffer BRAM together (`Clock::edge`; the clocking
//! discipline is described in `rtl_model::cycle::clocked`).
//!
//! | stage | unit | in → out |
//! |---|---|---|
//! | write | hit-buffer write port | `record_to_write` → BRAM |
//! | record | early termination, best hit, pack | `walker_to_record` → loop-back or `record_to_write` |
//! | walkers | pool: wake, retire, dispatch, issue | `root_to_dispatch` → `walker_to_record` |
//! | root | walker-root units | `reciprocal_to_root` → `root_to_dispatch` |
//! | reciprocal | 3 reciprocal units | `transform_to_reciprocal` → `reciprocal_to_root` |
//! | transform | transform unit | loop-back (first) or `check_to_transform` → `transform_to_reciprocal` |
//! | check | hit-buffer read, reuse rule | `sorter_to_check` → `check_to_transform` or `record_to_write` |
//! | sorter | sorting network (+ merge passes) | `sphere_to_sorter` → `sorter_to_check` |
//! | sphere | sphere lanes with square roots | `raygen_to_sphere` → `sphere_to_sorter` |
//! | raygen | direction-table read | pixel counter → `raygen_to_sphere` |
//!
//! A ray's candidates are walked one after the other, front to back: after each walk the
//! record stage decides (early termination, paper §4.2) whether the next candidate is needed,
//! and sends it back to the transform through a loop-back FIFO that has priority over new
//! rays. A ray takes one of `ray_slots` slots at the transform until its record leaves; the
//! loop-back FIFO has one entry per slot, so it can always take a returning ray and the loop
//! cannot deadlock. Rays with no candidate, and reused pixels, go from the check stage
//! straight to the write port; the record stage has priority there.
//!
//! Functional/timing split (docs/cycle-model.md §2.4): the functional model has already run
//! the frame, or is running it on another thread, and records its work
//! (`models::fixed::trace`). This model makes every decision that depends on its own state
//! itself — reuse from its own hit-buffer BRAM and the host's dirty flags, early termination,
//! the best hit — and checks each against the trace; the walks' timing comes from their
//! recorded ops. With `cross_check` every stage also re-executes its arithmetic from its own
//! inputs (sphere tests, sort, transform, reciprocals, walk, record packing) and compares with
//! the trace. After the frame its BRAM must equal the functional buffer word for word
//! ([`Pipeline::check_hit_buffer`]).
//!
//! Files: this one holds the pipeline's state, the clock (`step`, the commit, the stuck
//! watch) and the frame's report; `eval` evaluates one stage within a clock and holds the
//! evaluation order; `idle` skips idle cycles.

mod eval;
mod idle;

use super::commit::{Effects, Targets};
use super::error::CycleError;
use super::fifos::Fifos;
use super::machine::Machine;
use super::sample::{walking_in_row, warm_gap, Sampler};
use super::stages::check::Check;
use super::stages::passthrough::PassThrough;
use super::stages::raygen::Raygen;
use super::stages::record::Record;
use super::stages::sorter::Sorter;
use super::stages::sphere::Sphere;
use super::stages::tile_list::TilePasses;
use super::stages::transform::Transform;
use super::stages::walkers::Walkers;
use super::stages::write::Write;
use super::stages::{internal, FrameCounts, FrameInputs, RaySlots};
use super::stats::{CycleFrame, FrameMeasures, StallCounts};
use super::waves::WaveSample;
use eval::{Wires, PRODUCERS_FIRST};
use rtl_model::cycle::clocked::{Commit, StageStamp};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::{StageCycles, StageState};

pub use super::stages::STAGE_NAMES;
pub use eval::EvalOrder;

/// The report's stage rows, in pipeline order; indices below.
const STAGE_ROWS: [&str; 10] = [
    "raygen",
    "sphere",
    "sorter",
    "check",
    "transform",
    "reciprocal",
    "root",
    "walkers",
    "record",
    "write",
];
const S_RAYGEN: usize = 0;
const S_SPHERE: usize = 1;
const S_SORTER: usize = 2;
const S_CHECK: usize = 3;
const S_TRANSFORM: usize = 4;
const S_RECIP: usize = 5;
const S_ROOT: usize = 6;
const S_WALK: usize = 7;
const S_RECORD: usize = 8;
const S_WRITE: usize = 9;

/// One frame's pipeline: the stages with their registers, the FIFOs between them, the ray
/// slots, the frame's counters and stage accounting, over the machine's persistent parts.
pub struct Pipeline<'f> {
    hw: &'f HwConfig,
    frame: FrameInputs<'f>,
    machine: &'f mut Machine,
    log: &'f mut Vec<(u32, Vec<StageStamp>)>,
    /// Records whose stamps the transaction log keeps, per run.
    log_limit: usize,
    fifos: Fifos,
    /// The cycle's effects, applied in one commit after every stage (buffers reused).
    fx: Effects,
    raygen: Raygen,
    sphere: Sphere,
    sorter: Sorter,
    check: Check,
    transform: Transform,
    recip: PassThrough,
    root: PassThrough,
    walkers: Walkers,
    record: Record,
    write: Write,
    slots: RaySlots,
    counts: FrameCounts,
    stages: [StageCycles; 10],
    /// Each stage's state in the last cycle stepped (what skipped cycles repeat).
    states: [StageState; 10],
    /// Whether idle cycles are skipped (off: every cycle is stepped, for the comparison).
    skip: bool,
    /// [`Pipeline::activity`] after the last cycle.
    last_activity: u64,
    /// Cycles of the frame taken at once by idle-cycle skipping.
    skipped: u64,
    /// The cycle the frame started at.
    start: u64,
    /// The last cycle anything moved, and the progress measure then.
    last_progress: (u64, u64),
    /// Cycles without progress after which the frame is reported stuck.
    stuck_limit: u64,
    /// Sampled timing: the frame's timed segments (docs/cycle-model.md §3.5).
    sampler: Option<Sampler>,
    /// Sampled timing: the walk queue (`check_to_transform`) as the last segment's ray
    /// generation ended, once recorded.
    carry: Option<usize>,
    /// Sampled timing: the transform waits until the walk queue holds this many rays (or is
    /// full, or generation reaches this pixel), so a segment starts with the backlog the last
    /// one ended with (docs/cycle-model.md §3.5).
    hold: Option<(usize, u64)>,
    /// The stages' evaluation order within a clock.
    order: EvalOrder,
    /// The frame's per-cause stall counters so far (the pipeline's; the pool's and the
    /// memory's are added in the report).
    stalls: StallCounts,
    /// Which of the pipeline's stall causes held in the last cycle stepped (what skipped
    /// cycles repeat): walk issue, write port, ray generation.
    stall_now: [bool; 6],
}

impl<'f> Pipeline<'f> {
    /// An empty pipeline for the frame of `frame` on `hw`, starting at the machine's current
    /// cycle; the memories' statistics and the pool's cycle counts start afresh.
    pub fn new(
        hw: &'f HwConfig,
        frame: FrameInputs<'f>,
        machine: &'f mut Machine,
        log: &'f mut Vec<(u32, Vec<StageStamp>)>,
        log_limit: usize,
        skip: bool,
    ) -> Result<Self, CycleError> {
        let start = machine.clock.now();
        // No skipping while waveforms are recorded: they sample every cycle.
        let skip = skip && machine.waves.is_none();
        // Every context, plus the walks that can wait for one.
        let ray_slots = hw.ray_slots();
        let fifos = Fifos::new(hw, ray_slots, start)?;
        let instances = frame.plan.instances();
        let tiles = TilePasses::of(frame.plan, hw);
        // Rays keep their whole stamp history only while the transaction log wants more.
        let track = log.len() < log_limit;
        machine.mem.reset_stats();
        machine.pool.take_cycles();
        Ok(Self {
            hw,
            counts: FrameCounts::new(frame.pixels()),
            frame,
            machine,
            log,
            log_limit,
            fifos,
            fx: Effects::default(),
            raygen: Raygen::new(hw, track),
            sphere: Sphere::new(hw, instances).with_tiles(tiles),
            sorter: Sorter::new(hw, instances),
            check: Check::new(hw),
            transform: Transform::new(hw),
            recip: PassThrough::reciprocal(hw),
            root: PassThrough::root(hw),
            walkers: Walkers::default(),
            record: Record::new(hw),
            write: Write::new(hw.hit_buffer.record_writes),
            slots: RaySlots::new(ray_slots),
            stages: STAGE_ROWS.map(StageCycles::named),
            states: [StageState::Idle; 10],
            skip,
            last_activity: u64::MAX,
            skipped: 0,
            start,
            last_progress: (start, 0),
            // Far longer than any one wait the configuration allows, whichever latency is
            // longest (a 2^20-cycle cache hit is slow, not stuck).
            stuck_limit: 1_000_000 + 100 * u64::from(hw.longest_wait_cycles()),
            sampler: None,
            carry: None,
            hold: None,
            order: EvalOrder::default(),
            stalls: StallCounts::default(),
            stall_now: [false; 6],
        })
    }

    /// Times only the segments of `sampler`; the pixels between them are applied
    /// functionally once the pipeline has drained (docs/cycle-model.md §3.5).
    pub fn with_sampler(mut self, mut sampler: Sampler) -> Result<Self, CycleError> {
        let next = sampler.next_planned(&mut |j| walking_of(&mut self.frame, j))?;
        if let Some((from, to)) = next {
            self.raygen.jump(from, to);
        }
        self.sampler = Some(sampler);
        Ok(self)
    }

    /// Evaluates the stages in `order` within each clock (a test hook: docs/architecture.md §4
    /// says which orders give the same cycles).
    pub fn with_order(mut self, order: EvalOrder) -> Self {
        self.order = order;
        self
    }

    /// The trace's rows received so far (all of them after the frame).
    pub fn rows(&self) -> &[&'f crate::models::fixed::trace::RowTrace] {
        self.frame.rows()
    }

    /// The cycle the frame started at.
    pub fn start(&self) -> u64 {
        self.start
    }

    /// The sampler, if the frame is sampled (taken for its estimate after the frame).
    pub fn take_sampler(&mut self) -> Option<Sampler> {
        self.sampler.take()
    }

    /// Sampled timing after the edge: once ray generation reached the end of its segment and
    /// every pixel before it is written (nothing in flight: no walk, no node read, no MSHR),
    /// the pixels up to the next segment are applied functionally and generation moves on.
    fn next_segment(&mut self) -> Result<(), CycleError> {
        let at = self.raygen.next_pixel();
        let done = self.done();
        let Some(s) = self.sampler.as_mut() else {
            return Ok(());
        };
        if at != s.segment_end() || self.counts.written != at || done || !self.machine.mem.is_idle()
        {
            return Ok(());
        }
        let next = s.next_planned(&mut |j| walking_of(&mut self.frame, j))?;
        if let Some((from, to)) = next {
            warm_gap(&mut self.frame, self.machine, &mut self.counts, (at, from))?;
            self.raygen.jump(from, to);
            // The backlog the last segment ended with: the walk queue refills before the
            // transform starts (or until the band's first pixel is generated).
            self.hold = self.carry.take().map(|q| (q, s.segment_band()));
        }
        Ok(())
    }

    /// Whether every pixel has been written.
    #[inline]
    pub fn done(&self) -> bool {
        self.counts.written >= self.counts.pixels
    }

    /// One clock: every stage evaluated, consumers first (or in the order the test hook
    /// [`Pipeline::with_order`] asked for), then the edge; then, if nothing moved in it, the idle
    /// cycles that follow are taken at once (`Pipeline::skip_idle`).
    pub fn step(&mut self) -> Result<(), CycleError> {
        let now = self.machine.clock.now();
        // Sampled timing's hold on the transform ends on registered state only (the walk
        // queue's occupancy, the pixel counter as the cycle starts).
        if let Some((target, until)) = self.hold {
            let q = &self.fifos.ck_tr;
            if q.occupancy() >= target || !q.ready() || self.raygen.next_pixel() >= until {
                self.hold = None;
            }
        }
        // What the stages' starved/idle accounting reads of the frame's counters, as the
        // cycle starts, so that no stage sees another's count of this cycle.
        let c = &self.counts;
        let mut wires = Wires {
            upstream_more: [
                c.passed[0] < c.pixels,
                c.passed[1] < c.pixels,
                c.passed[2] < c.pixels,
            ],
            walked: c.walks_entered > 0,
            more_walks: c.more_walks(),
            more_rays: c.passed[3] < c.pixels,
            record_done: false,
        };
        match self.order {
            // Written out with constant stages, so that each call's dispatch folds away: a
            // loop over the order made the model about 25 % slower.
            EvalOrder::ConsumersFirst => {
                let w = &mut wires;
                self.states[S_WRITE] = self.eval_stage(S_WRITE, now, w)?;
                self.states[S_RECORD] = self.eval_stage(S_RECORD, now, w)?;
                self.states[S_WALK] = self.eval_stage(S_WALK, now, w)?;
                self.states[S_ROOT] = self.eval_stage(S_ROOT, now, w)?;
                self.states[S_RECIP] = self.eval_stage(S_RECIP, now, w)?;
                self.states[S_TRANSFORM] = self.eval_stage(S_TRANSFORM, now, w)?;
                self.states[S_CHECK] = self.eval_stage(S_CHECK, now, w)?;
                self.states[S_SORTER] = self.eval_stage(S_SORTER, now, w)?;
                self.states[S_SPHERE] = self.eval_stage(S_SPHERE, now, w)?;
                self.states[S_RAYGEN] = self.eval_stage(S_RAYGEN, now, w)?;
            }
            EvalOrder::ProducersFirst => {
                for &stage in &PRODUCERS_FIRST {
                    self.states[stage] = self.eval_stage(stage, now, &mut wires)?;
                }
            }
        }
        let st = &self.states;
        for (row, &s) in self.stages.iter_mut().zip(st.iter()) {
            row.count(s);
        }
        // Per-cause stalls (docs/cycle-model.md §2.2). A transform starved while the check
        // stage holds a word for the write path waits for that path, not for ray generation
        // (the rays behind the held one cannot pass); a held sampling transform is starved by
        // design.
        // A starved transform is then charged to the front-end unit nearest it that held a
        // waiting ray for a further pass (the sorter's merges, the sphere lanes' passes), else
        // to ray generation.
        let write_blocked = self.check.write_blocked;
        let starved = self.transform.input_starved && !write_blocked && self.hold.is_none();
        let sorter = starved && self.sorter.held;
        let sphere = starved && !sorter && self.sphere.held;
        self.stall_now = [
            self.transform.issue_stall || self.recip.issue_stall || self.root.issue_stall,
            write_blocked,
            starved && !sorter && !sphere,
            sorter,
            sphere,
            self.record.write_blocked,
        ];
        self.count_stalls(1);
        self.commit(now)?;
        self.watch(now)?;
        if let Some(s) = self.sampler.as_mut() {
            // The walk queue as generation reaches the segment's end, before the drain.
            if self.carry.is_none() && self.raygen.next_pixel() == s.segment_end() {
                self.carry = Some(self.fifos.ck_tr.occupancy());
            }
            s.written(self.counts.written, now);
            self.next_segment()?;
        }
        if self.skip {
            self.skip_idle(now)?;
        }
        Ok(())
    }

    /// Adds `k` cycles of the last cycle's stall causes.
    #[inline]
    fn count_stalls(&mut self, k: u64) {
        let [issue, write, raygen, sorter, sphere, record_write] = self.stall_now;
        let s = &mut self.stalls;
        s.walk_issue += u64::from(issue) * k;
        s.write_port += u64::from(write) * k;
        s.ray_generation += u64::from(raygen) * k;
        s.sorter += u64::from(sorter) * k;
        s.sphere += u64::from(sphere) * k;
        s.record_write += u64::from(record_write) * k;
    }

    /// Records cycle `now` in the waveforms, if any.
    fn sample_waves(&mut self, now: u64) {
        let m = &mut *self.machine;
        if let Some(wv) = m.waves.as_mut() {
            let occupancy = self.fifos.occupancy();
            wv.sample(&WaveSample {
                now,
                occupancy: &occupancy.each_ref(),
                valid_ready: &self.fifos.handshakes(),
                pool: &m.pool,
                mem: &m.mem,
                generated: self.raygen.next_pixel(),
                written: self.counts.written,
                frame: self.frame.setup.frame,
            });
        }
    }

    /// The end of stepped cycle `now`: every stage's effects applied in one place
    /// ([`Effects::apply`]), the cycle sampled into the waveforms, then the clock edge that
    /// commits every FIFO and the BRAM together.
    fn commit(&mut self, now: u64) -> Result<(), CycleError> {
        let m = &mut *self.machine;
        self.fx.apply(Targets {
            fifos: &mut self.fifos,
            slots: &mut self.slots,
            bram: &mut m.bram,
            counts: &mut self.counts,
            frame: &mut self.frame,
            log: self.log,
            log_limit: self.log_limit,
        })?;
        self.sample_waves(now);
        let f = &mut self.fifos;
        let m = &mut *self.machine;
        // The FIFOs are one part (`Fifos` commits each directly), the BRAM the other.
        m.clock
            .edge(&mut [f as &mut dyn Commit, &mut m.bram])
            .map_err(internal)?;
        Ok(())
    }

    /// The stuck check after cycle `now`: something must move (a pixel generated, passed or
    /// written, a walker slot issued) within a bound far above any latency.
    fn watch(&mut self, now: u64) -> Result<(), CycleError> {
        let c = &self.counts;
        let progress = c.written
            + c.passed.iter().sum::<u64>()
            + self.machine.pool.cycles().slots
            + self.raygen.next_pixel();
        if progress != self.last_progress.1 {
            self.last_progress = (now, progress);
        } else if now - self.last_progress.0 > self.stuck_limit {
            return Err(CycleError::Stuck {
                frame: self.frame.setup.frame,
                cycles: now - self.last_progress.0,
                at: now,
                written: c.written,
                pixels: c.pixels,
            });
        }
        Ok(())
    }

    /// Cycles of the frame taken at once by idle-cycle skipping so far.
    pub fn skipped(&self) -> u64 {
        self.skipped
    }

    /// After the frame: this model's hit buffer must equal the functional model's, word for
    /// word, and every row of the trace must have arrived.
    pub fn check_hit_buffer(&self) -> Result<(), CycleError> {
        let rows = self.frame.rows();
        let height = self.frame.setup.height;
        if rows.len() != height as usize {
            return Err(CycleError::Internal(format!(
                "frame ended with {} of {height} rows received",
                rows.len(),
            )));
        }
        let words = rows.iter().flat_map(|r| r.words.iter());
        for (p, &theirs) in words.enumerate() {
            let mine = self.machine.bram.peek(p).copied().unwrap_or(0);
            if mine != theirs {
                return Err(self.frame.mismatch(
                    p as u32,
                    format!("hit-buffer word {mine:#x} here, {theirs:#x} in the functional model"),
                ));
            }
        }
        Ok(())
    }

    /// The frame's cycle report; `sim_wall_s` is the wall time it took. Takes the pool's
    /// cycle counts and the memory's statistics for the frame.
    pub fn report(mut self, sim_wall_s: f64) -> CycleFrame {
        let cycles = self.machine.clock.now() - self.start;
        let c = &self.counts;
        let walks = self.machine.pool.cycles().walks;
        for (i, s) in self.stages.iter_mut().enumerate() {
            s.transactions = match i {
                S_RAYGEN | S_SPHERE | S_SORTER | S_CHECK => c.passed[i],
                S_TRANSFORM | S_RECIP | S_ROOT | S_WALK => walks,
                S_RECORD => c.walks_entered,
                _ => c.written,
            };
        }
        let m = &mut *self.machine;
        CycleFrame::new(
            self.hw,
            FrameMeasures {
                frame: self.frame.setup.frame,
                cycles,
                pixels: c.pixels,
                stages: self.stages.into(),
                fifos: &self.fifos.stats(),
                walkers: m.pool.take_cycles(),
                mem: m.mem.reset_stats(),
                reused: c.reused,
                early: c.early,
                traced: c.walks_entered,
                stalls: StallCounts {
                    write_bank_conflicts: self.write.bank_conflicts,
                    ..self.stalls
                },
                sim_wall_s,
            },
        )
    }
}

/// The pixels of row `j` that walk, from the trace (waiting for the row if need be): what
/// sizes sampled timing's detailed warming.
fn walking_of(frame: &mut FrameInputs<'_>, j: u32) -> Result<u64, CycleError> {
    frame.need_row(j as usize)?;
    let row = frame.rows().get(j as usize).copied().ok_or_else(|| {
        CycleError::Internal(format!("sampled timing: row {j} of the trace is missing"))
    })?;
    Ok(walking_in_row(row))
}
