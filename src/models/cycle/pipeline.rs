//! The cycle-accurate pipeline of one frame: every stage stepped once per clock, joined by
//! valid/ready FIFOs, with the walker pool, node memory and hit-buffer memory.
//!
//! Pipeline position: the whole of DESIGN.md §3 in time. Stages, in the order they are
//! evaluated within a cycle (consumers first, so a stage sees the registered state of the
//! FIFOs around it; FIFO `ready`/`valid` are registered, so the order cannot change any
//! result through them):
//!
//! | stage | unit | in → out |
//! |---|---|---|
//! | write | hit-buffer write port | `record_to_write` → BRAM |
//! | record | early termination, best hit, pack | `walker_to_record` → loop-back or `record_to_write` |
//! | walkers | pool: dispatch, issue, retire | `root_to_dispatch` → `walker_to_record` |
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
//! rays. A ray takes one of `ray_slots` slots from the check stage until its record leaves;
//! the loop-back FIFO has one entry per slot, so it can always take a returning ray and the
//! loop cannot deadlock. Rays with no candidate, and reused pixels, go from the check stage
//! straight to the write port; the record stage has priority there.
//!
//! Functional/timing split (DESIGN.md §6): the functional model has already run the frame and
//! recorded its work (`models::fixed::trace`). This model makes every decision that depends on
//! its own state itself — reuse from its own hit-buffer BRAM and the host's dirty flags, early
//! termination, the best hit — and checks each against the trace; the walks' timing comes
//! from their recorded ops. With `cross_check` every stage also re-executes its arithmetic
//! from its own inputs (sphere tests, sort, transform, reciprocals, walk, record packing)
//! and compares with the trace. After the frame its BRAM must equal the functional buffer
//! word for word.

use super::layout::SceneLayout;
use super::stats::CycleFrame;
use super::waves::PipelineWaves;
use crate::models::fixed::plan::{Best, FramePlan, PixelCounters};
use crate::models::fixed::row_feed::RowFeed;
use crate::models::fixed::trace::PixelWork;
use crate::models::fixed::trace::{OpRecorder, RowTrace, WalkOp};
use crate::models::reference::SphereCount;
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::{Clock, Commit, StageId, Stamped};
use rtl_model::cycle::fifo::Fifo;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::memory::{FetchKind, NodeMemory};
use rtl_model::cycle::stage_stats::{StageCycles, StageState};
use rtl_model::cycle::unit_pipe::UnitPipe;
use rtl_model::cycle::walker_pool::{PoolError, WalkerPoolModel};
use rtl_model::units::sorter::sort_timing;
use rtl_model::units::walker::WalkOutcome;
use std::time::Instant;
use thiserror::Error;

/// Why the cycle model stopped.
#[derive(Debug, Error)]
pub enum CycleError {
    /// The hardware configuration is invalid.
    #[error("hardware configuration: {0}")]
    Config(String),
    /// The cycle model and the functional model disagree (a bug in one of them).
    #[error("cross-check failed at frame {frame}, pixel ({i}, {j}): {what}")]
    Mismatch {
        /// Frame.
        frame: u32,
        /// Column.
        i: u32,
        /// Row.
        j: u32,
        /// What differs.
        what: String,
    },
    /// The walker pool or node memory refused something.
    #[error(transparent)]
    Pool(#[from] PoolError),
    /// The pipeline made no progress for far longer than any latency (a model bug).
    #[error("frame {frame}: no progress for {cycles} cycles at cycle {at} ({written} of {pixels} pixels written)")]
    Stuck {
        /// Frame.
        frame: u32,
        /// Cycles without progress.
        cycles: u64,
        /// Cycle.
        at: u64,
        /// Pixels written.
        written: u64,
        /// Pixels.
        pixels: u64,
    },
    /// A FIFO or BRAM was misused (a model bug).
    #[error("pipeline: {0}")]
    Internal(String),
}

// Stage ids for stamps and the report, in pipeline order.
const ST_RAYGEN: StageId = StageId(0);
const ST_F_RG_SP: StageId = StageId(1);
const ST_SPHERE: StageId = StageId(2);
const ST_F_SP_SO: StageId = StageId(3);
const ST_SORTER: StageId = StageId(4);
const ST_F_SO_CK: StageId = StageId(5);
const ST_CHECK: StageId = StageId(6);
const ST_F_CK_TR: StageId = StageId(7);
const ST_F_LOOP: StageId = StageId(8);
const ST_TRANSFORM: StageId = StageId(9);
const ST_F_TR_RC: StageId = StageId(10);
const ST_RECIP: StageId = StageId(11);
const ST_F_RC_RT: StageId = StageId(12);
const ST_ROOT: StageId = StageId(13);
const ST_F_RT_DP: StageId = StageId(14);
const ST_WALKER: StageId = StageId(15);
const ST_F_WK_RC: StageId = StageId(16);
const ST_RECORD: StageId = StageId(17);
const ST_F_RC_WR: StageId = StageId(18);
const ST_WRITE: StageId = StageId(19);

/// Names of the stage ids above, for transaction logs.
pub const STAGE_NAMES: [&str; 20] = [
    "raygen",
    "raygen_to_sphere",
    "sphere",
    "sphere_to_sorter",
    "sorter",
    "sorter_to_check",
    "check",
    "check_to_transform",
    "loop_back",
    "transform",
    "transform_to_reciprocal",
    "reciprocal",
    "reciprocal_to_root",
    "root",
    "root_to_dispatch",
    "walker",
    "walker_to_record",
    "record",
    "record_to_write",
    "write",
];

/// Passes (initiation intervals) a ray of `n` candidates occupies the sorter for, and its
/// latency beyond the network's.
fn sort_cost_of(n: usize, lanes: u8, network_latency: u32) -> (u64, u64) {
    let t = sort_timing(n, lanes);
    (
        t.network_busy.max(t.merger_busy).max(1),
        t.latency.saturating_sub(u64::from(network_latency)),
    )
}

fn mk<T>(id: StageId, depth: u32, now: u64) -> Result<Fifo<T>, CycleError> {
    Fifo::new_at(id, depth as usize, now).map_err(|e| CycleError::Config(e.to_string()))
}

/// A ray between ray generation and the check stage.
#[derive(Clone, Copy, Debug)]
struct Ray {
    pixel: u32,
}

/// One walk of a ray: its slot and candidate index.
#[derive(Clone, Copy, Debug)]
struct Walk {
    slot: u32,
    cand: u16,
}

/// A record on its way to the write port.
#[derive(Clone, Copy, Debug)]
struct Rec {
    pixel: u32,
    word: u128,
}

/// A ray in the walk section.
#[derive(Clone, Debug, Default)]
struct Slot {
    pixel: u32,
    /// Sorted candidates (from the trace, or this model's own sort under cross-check).
    cands: Vec<(i64, u16)>,
    /// Best hit so far: t, candidate index, and under cross-check the walker's own result.
    best: Option<(i64, u16)>,
    best_full: Option<Best>,
    walks: u16,
    stamps: Option<Stamped<Ray>>,
}

/// Per-run state of the cycle model: the memories and the pool keep their contents across
/// frames (cache lines, hit-buffer words), the pipeline drains between frames.
pub struct CycleModel {
    hw: HwConfig,
    layout: SceneLayout,
    mem: NodeMemory,
    pool: WalkerPoolModel,
    bram: Bram<u128>,
    width: u32,
    height: u32,
    clock: Clock,
    cross_check: bool,
    frame: u32,
    waves: Option<PipelineWaves>,
    /// Stamps of the first transactions, for transaction logs (pixel, stamps).
    pub log: Vec<(u32, Vec<rtl_model::cycle::clocked::StageStamp>)>,
    log_limit: usize,
}

/// Options of a cycle-model run.
#[derive(Default)]
pub struct CycleOptions {
    /// Re-execute every stage's arithmetic and compare with the functional model.
    pub cross_check: bool,
    /// Record waveforms.
    pub waves: Option<PipelineWaves>,
    /// Keep the stage stamps of this many records (in write order) per run.
    pub log_limit: usize,
}

impl CycleModel {
    /// A model for frames of `width`×`height` over the placed images.
    pub fn new(
        hw: &HwConfig,
        layout: SceneLayout,
        width: u32,
        height: u32,
        opts: CycleOptions,
    ) -> Result<Self, CycleError> {
        hw.validate()
            .map_err(|e| CycleError::Config(e.to_string()))?;
        let pixels = width as usize * height as usize;
        let mem = NodeMemory::new(hw.node_memory.clone(), layout.layout.clone())
            .map_err(|e| CycleError::Config(e.to_string()))?;
        let pool = WalkerPoolModel::new(&hw.walker_pool)?;
        let ports = hw.hit_buffer.read_ports + hw.hit_buffer.write_ports;
        let bram = Bram::new(pixels.max(1), ports, 0u128)
            .map_err(|e| CycleError::Config(e.to_string()))?;
        Ok(Self {
            hw: hw.clone(),
            layout,
            mem,
            pool,
            bram,
            width,
            height,
            clock: Clock::new(),
            cross_check: opts.cross_check,
            frame: 0,
            waves: opts.waves,
            log: Vec::new(),
            log_limit: opts.log_limit,
        })
    }

    /// The hardware configuration.
    pub fn config(&self) -> &HwConfig {
        &self.hw
    }

    /// The hit-buffer word of pixel `p` (after the last frame).
    pub fn word(&self, p: usize) -> Option<u128> {
        self.bram.peek(p).copied()
    }

    /// Takes the waveform recorder (to write it).
    pub fn take_waves(&mut self) -> Option<PipelineWaves> {
        self.waves.take()
    }

    fn mismatch(&self, pixel: u32, what: String) -> CycleError {
        CycleError::Mismatch {
            frame: self.frame,
            i: pixel % self.width.max(1),
            j: pixel / self.width.max(1),
            what,
        }
    }

    /// Runs one frame. `plan` is the frame's prepared datapath, `feed` the functional
    /// model's work per row (rows may still be arriving: ray generation waits for each row
    /// before its first pixel), `dir` the frame's direction table.
    pub fn run_frame(
        &mut self,
        plan: &FramePlan<'_>,
        feed: &RowFeed,
        dir: &[[i64; 3]],
        instance_asset: &[usize],
    ) -> Result<CycleFrame, CycleError> {
        let wall = Instant::now();
        let pixels = (self.width as u64) * (self.height as u64);
        if feed.len() != self.height as usize || dir.len() != pixels as usize {
            return Err(CycleError::Internal(
                "trace or direction table does not match the frame size".into(),
            ));
        }
        // The rows received so far from the functional model.
        let mut rows: Vec<&RowTrace> = Vec::with_capacity(self.height as usize);
        let hw = self.hw.clone();
        let fd = &hw.fifos;
        let t0 = self.clock.now();
        let mut f_rg_sp: Fifo<Ray> = mk(ST_F_RG_SP, fd.raygen_to_sphere, t0)?;
        let mut f_sp_so: Fifo<Ray> = mk(ST_F_SP_SO, fd.sphere_to_sorter, t0)?;
        let mut f_so_ck: Fifo<Ray> = mk(ST_F_SO_CK, fd.sorter_to_check, t0)?;
        let mut f_ck_tr: Fifo<Ray> = mk(ST_F_CK_TR, fd.check_to_transform, t0)?;
        let pool_ctx = hw.walker_pool.walkers * hw.walker_pool.contexts_per_walker;
        let ray_slots = pool_ctx + fd.root_to_dispatch;
        let mut f_loop: Fifo<Walk> = mk(ST_F_LOOP, ray_slots, t0)?;
        let mut f_tr_rc: Fifo<Walk> = mk(ST_F_TR_RC, fd.transform_to_reciprocal, t0)?;
        let mut f_rc_rt: Fifo<Walk> = mk(ST_F_RC_RT, fd.reciprocal_to_root, t0)?;
        let mut f_rt_dp: Fifo<Walk> = mk(ST_F_RT_DP, fd.root_to_dispatch, t0)?;
        let mut f_wk_rc: Fifo<Walk> = mk(ST_F_WK_RC, fd.walker_to_record, t0)?;
        let mut f_rc_wr: Fifo<Rec> = mk(ST_F_RC_WR, fd.record_to_write, t0)?;

        let u = &hw.units;
        let n_inst = plan.instances() as u64;
        let sphere_passes = n_inst.div_ceil(u64::from(hw.sphere_units.max(1))).max(1);
        let mut p_raygen: UnitPipe<Stamped<Ray>> =
            UnitPipe::new(u.raygen.latency_cycles, u.raygen.ii);
        let mut p_sphere: UnitPipe<Stamped<Ray>> = UnitPipe::new(
            u.sphere.latency_cycles + u.sqrt.latency_cycles,
            u.sphere.ii.max(u.sqrt.ii),
        );
        let mut p_sorter: UnitPipe<Stamped<Ray>> =
            UnitPipe::new(u.sorter.latency_cycles, u.sorter.ii);
        let hb_latency = hw.hit_buffer_read_cycles() + u.hit_unpack.latency_cycles;
        let mut p_check: UnitPipe<(Stamped<Ray>, u128)> = UnitPipe::new(hb_latency, 1);
        // Transform, reciprocal and root: `n` units of II `ii` act as one unit of II ii/n.
        let units_ii = |ii: u32, n: u32| ii.div_ceil(n.max(1)).max(1);
        let mut p_transform: UnitPipe<Stamped<Walk>> = UnitPipe::new(
            u.transform.latency_cycles,
            units_ii(u.transform.ii, hw.transform_units),
        );
        // Three reciprocal units per walk (one per axis).
        let recip_walks = (hw.reciprocal_units / 3).max(1);
        let recip_passes = if hw.reciprocal_units < 3 {
            u64::from(3u32.div_ceil(hw.reciprocal_units.max(1)))
        } else {
            1
        };
        let mut p_recip: UnitPipe<Stamped<Walk>> = UnitPipe::new(
            u.reciprocal.latency_cycles,
            units_ii(u.reciprocal.ii, recip_walks),
        );
        let mut p_root: UnitPipe<Stamped<Walk>> = UnitPipe::new(
            u.walker_root.latency_cycles,
            units_ii(u.walker_root.ii, hw.walker_root_units),
        );
        let mut p_pack: UnitPipe<Stamped<Rec>> =
            UnitPipe::new(u.hit_pack.latency_cycles, u.hit_pack.ii);

        // Sorter occupancy and extra latency by candidate count (the network's timing is a
        // pure function of the count; computing it per ray would rebuild the network).
        let sort_cost: Vec<(u64, u64)> = (0..=plan.instances().min(4096))
            .map(|n| sort_cost_of(n, hw.sorter_lanes, u.sorter.latency_cycles))
            .collect();
        let mut slots: Vec<Slot> = (0..ray_slots).map(|_| Slot::default()).collect();
        let mut free_slots: Vec<u32> = (0..ray_slots).rev().collect();

        let names = [
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
        let mut st: Vec<StageCycles> = names.iter().map(|n| StageCycles::named(n)).collect();
        let (
            s_raygen,
            s_sphere,
            s_sorter,
            s_check,
            s_transform,
            s_recip,
            s_root,
            s_walk,
            s_record,
            s_write,
        ) = (0, 1, 2, 3, 4, 5, 6, 7, 8, 9);

        let start = self.clock.now();
        self.mem.reset_stats();
        self.pool.take_cycles();
        let mut next_pixel: u64 = 0;
        let mut written: u64 = 0;
        let mut passed = [0u64; 4]; // rays that left raygen, sphere, sorter, check
        let mut walks_entered: u64 = 0;
        let mut early: u64 = 0;
        let mut reused: u64 = 0;
        let mut xc_cands: Vec<(i64, u16)> = Vec::new();
        let mut xc_counters = PixelCounters::default();
        let mut last_progress = (start, 0u64);
        let stuck_limit = 1_000_000u64 + 100 * u64::from(hw.node_memory.dram.latency);
        let frame = self.frame;
        let width = self.width;
        let cross = self.cross_check;

        while written < pixels {
            let now = self.clock.now();
            self.pool.wake(now, &mut self.mem)?;

            // --- write: one record per cycle into the hit buffer.
            let mut wrote = false;
            if let Some(r) = f_rc_wr
                .try_pop()
                .map_err(|e| CycleError::Internal(e.to_string()))?
            {
                let mut r = r;
                r.enter(ST_WRITE, now);
                let _ = r.leave(ST_WRITE, now);
                self.bram
                    .write(r.payload.pixel as usize, r.payload.word)
                    .map_err(|e| CycleError::Internal(e.to_string()))?;
                if self.log.len() < self.log_limit {
                    self.log.push((r.payload.pixel, r.stamps().to_vec()));
                }
                written += 1;
                wrote = true;
            }
            st[s_write].count(if wrote {
                StageState::Busy
            } else if written < pixels {
                StageState::Starved
            } else {
                StageState::Idle
            });

            // --- record: pack output first (it has the write FIFO's port), then one walk result.
            let mut rec_pushed = false;
            if p_pack.ready(now).is_some() && f_rc_wr.ready() {
                if let Some(mut r) = p_pack.pop(now) {
                    let _ = r.leave(ST_RECORD, now);
                    f_rc_wr
                        .try_push(r)
                        .map_err(|e| CycleError::Internal(e.to_string()))?;
                    rec_pushed = true;
                }
            }
            let mut rec_state = p_pack.state(now, !rec_pushed, walks_entered > 0);
            if f_wk_rc.valid() && p_pack.can_accept(now) {
                if let Some(wk) = f_wk_rc
                    .try_pop()
                    .map_err(|e| CycleError::Internal(e.to_string()))?
                {
                    let Walk { slot, cand } = wk.payload;
                    let s = &mut slots[slot as usize];
                    let (tr, pw, i) = trace_at(&rows, width, s.pixel)?;
                    let twalks = tr.walks_of(pw);
                    let Some(tw) = twalks.get(usize::from(cand)) else {
                        return Err(self.mismatch(
                            s.pixel,
                            format!(
                                "walk {cand} done here, the functional model did {}",
                                twalks.len()
                            ),
                        ));
                    };
                    if let Some(t) = tw.hit_t {
                        if s.best.is_none_or(|(bt, _)| t < bt) {
                            s.best = Some((t, cand));
                        }
                    }
                    s.walks += 1;
                    let next = usize::from(cand) + 1;
                    let more = next < s.cands.len()
                        && !s
                            .best
                            .is_some_and(|(bt, _)| plan.stops(bt, s.cands[next].0));
                    if more {
                        let mut w2 = wk.map(|_| Walk {
                            slot,
                            cand: next as u16,
                        });
                        w2.enter(ST_RECORD, now);
                        let _ = w2.leave(ST_RECORD, now);
                        f_loop
                            .try_push(w2)
                            .map_err(|e| CycleError::Internal(format!("loop-back: {e}")))?;
                    } else {
                        if next < s.cands.len() {
                            early += 1;
                        }
                        if s.walks != pw.walk_len {
                            return Err(self.mismatch(
                                s.pixel,
                                format!(
                                    "{} walks here, {} in the functional model (early termination differs)",
                                    s.walks, pw.walk_len
                                ),
                            ));
                        }
                        let word = if cross {
                            let spheres = SphereCount::from_count(s.cands.len());
                            plan.finish(s.best_full, spheres, &mut xc_counters).word
                        } else {
                            tr.words.get(i).copied().ok_or_else(|| {
                                CycleError::Internal(format!("no word for pixel {}", s.pixel))
                            })?
                        };
                        let mut ray = s
                            .stamps
                            .take()
                            .unwrap_or_else(|| Stamped::new(Ray { pixel: s.pixel }));
                        ray.enter(ST_RECORD, now);
                        let rec = ray.map(|r| Rec {
                            pixel: r.pixel,
                            word,
                        });
                        p_pack.accept(now, rec, 1, 0);
                        // The slot is initialised afresh when the transform allocates it.
                        free_slots.push(slot);
                    }
                    rec_state = StageState::Busy;
                }
            }
            st[s_record].count(rec_state);

            // --- walkers: retire one, dispatch one, issue.
            if self.pool.finished_head().is_some() && f_wk_rc.ready() {
                if let Some(tag) = self.pool.retire() {
                    let mut wk = Stamped::new(Walk {
                        slot: (tag >> 16) as u32,
                        cand: tag as u16,
                    });
                    wk.enter(ST_WALKER, now);
                    let _ = wk.leave(ST_WALKER, now);
                    f_wk_rc
                        .try_push(wk)
                        .map_err(|e| CycleError::Internal(e.to_string()))?;
                }
            }
            if f_rt_dp.valid() {
                if self.pool.has_free() {
                    if let Some(wk) = f_rt_dp
                        .try_pop()
                        .map_err(|e| CycleError::Internal(e.to_string()))?
                    {
                        let Walk { slot, cand } = wk.payload;
                        let s = &mut slots[slot as usize];
                        let (tr, pw, _) = trace_at(&rows, width, s.pixel)?;
                        let (_, k) = s.cands[usize::from(cand)];
                        let Some(tw) = tr.walks_of(pw).get(usize::from(cand)) else {
                            return Err(self.mismatch(
                                s.pixel,
                                format!(
                                    "walk {cand} wanted here, the functional model did {}",
                                    pw.walk_len
                                ),
                            ));
                        };
                        let asset = instance_asset.get(usize::from(k)).copied().unwrap_or(0);
                        let nb = self.layout.node_base.get(asset).copied().unwrap_or(0);
                        let ab = self.layout.attr_base.get(asset).copied().unwrap_or(0);
                        let ops = tr.ops_of(tw);
                        if cross {
                            // Re-execute the walk from this stage's own inputs.
                            let mut mine: Vec<u64> = Vec::with_capacity(ops.len());
                            let mut rec = OpRecorder::new(&mut mine);
                            let d = dir[s.pixel as usize];
                            let (out, signs) = plan.walk(d, k, &mut xc_counters, &mut rec);
                            rec.finish();
                            let hit_t = match out {
                                WalkOutcome::Hit(h) => Some(h.t),
                                _ => None,
                            };
                            if mine != ops || hit_t != tw.hit_t {
                                return Err(self.mismatch(
                                    s.pixel,
                                    format!("walk {cand} (instance {k}) differs: {} ops / t {:?} here, {} ops / t {:?} in the functional model", mine.len(), hit_t, ops.len(), tw.hit_t),
                                ));
                            }
                            if let WalkOutcome::Hit(h) = out {
                                if s.best_full.is_none_or(|(bt, _, _, _)| h.t < bt) {
                                    s.best_full = Some((h.t, k, h, signs));
                                }
                            }
                        }
                        // Node and attribute addresses are per asset: relocate them to the
                        // asset's place in the node memory as the context takes them.
                        let relocate = |o: &u64| match WalkOp::unpack(*o) {
                            WalkOp::Read(FetchKind::Attr, a) => {
                                WalkOp::Read(FetchKind::Attr, a + ab).pack()
                            }
                            WalkOp::Read(kind, a) => WalkOp::Read(kind, a + nb).pack(),
                            op => op.pack(),
                        };
                        self.pool
                            .dispatch_with((u64::from(slot) << 16) | u64::from(cand), |v| {
                                v.extend(ops.iter().map(relocate))
                            });
                    }
                } else {
                    self.pool.note_dispatch_stall();
                }
            }
            self.pool.issue();

            // --- root, reciprocal, transform: fixed pipes between FIFOs.
            fn pass_through(
                pipe: &mut UnitPipe<Stamped<Walk>>,
                stage: StageId,
                out: &mut Fifo<Walk>,
                now: u64,
            ) -> Result<bool, CycleError> {
                if pipe.ready(now).is_some() && out.ready() {
                    if let Some(mut w) = pipe.pop(now) {
                        let _ = w.leave(stage, now);
                        out.try_push(w)
                            .map_err(|e| CycleError::Internal(e.to_string()))?;
                        return Ok(true);
                    }
                }
                Ok(false)
            }
            let more_walks = walks_entered > 0 || passed[3] < pixels;
            let pushed = pass_through(&mut p_root, ST_ROOT, &mut f_rt_dp, now)?;
            if f_rc_rt.valid() && p_root.can_accept(now) {
                if let Some(mut w) = f_rc_rt
                    .try_pop()
                    .map_err(|e| CycleError::Internal(e.to_string()))?
                {
                    w.enter(ST_ROOT, now);
                    p_root.accept(now, w, 1, 0);
                }
            }
            st[s_root].count(p_root.state(now, !pushed, more_walks));
            let pushed = pass_through(&mut p_recip, ST_RECIP, &mut f_rc_rt, now)?;
            if f_tr_rc.valid() && p_recip.can_accept(now) {
                if let Some(mut w) = f_tr_rc
                    .try_pop()
                    .map_err(|e| CycleError::Internal(e.to_string()))?
                {
                    w.enter(ST_RECIP, now);
                    p_recip.accept(now, w, recip_passes, 0);
                }
            }
            st[s_recip].count(p_recip.state(now, !pushed, more_walks));
            let pushed = pass_through(&mut p_transform, ST_TRANSFORM, &mut f_tr_rc, now)?;
            if p_transform.can_accept(now) {
                if f_loop.valid() {
                    if let Some(mut w) = f_loop
                        .try_pop()
                        .map_err(|e| CycleError::Internal(e.to_string()))?
                    {
                        w.enter(ST_TRANSFORM, now);
                        p_transform.accept(now, w, 1, 0);
                    }
                } else if f_ck_tr.valid() && !free_slots.is_empty() {
                    // A new ray takes a slot as its first walk enters the transform.
                    if let Some(ray) = f_ck_tr
                        .try_pop()
                        .map_err(|e| CycleError::Internal(e.to_string()))?
                    {
                        let Some(slot) = free_slots.pop() else {
                            return Err(CycleError::Internal("no ray slot".into()));
                        };
                        let pixel = ray.payload.pixel;
                        let (tr, pw, _) = trace_at(&rows, width, pixel)?;
                        let s = &mut slots[slot as usize];
                        s.pixel = pixel;
                        s.cands.clear();
                        s.cands.extend_from_slice(tr.candidates_of(pw));
                        s.best = None;
                        s.best_full = None;
                        s.walks = 0;
                        s.stamps = Some(ray);
                        let mut w = Stamped::new(Walk { slot, cand: 0 });
                        w.enter(ST_TRANSFORM, now);
                        p_transform.accept(now, w, 1, 0);
                    }
                }
            }
            st[s_transform].count(p_transform.state(now, !pushed, more_walks));

            // --- check: hit-buffer read at entry, decision at exit.
            let mut check_blocked = false;
            if let Some(&(ref ray, prev)) = p_check.ready(now) {
                let pixel = ray.payload.pixel;
                let (tr, pw, _) = trace_at(&rows, width, pixel)?;
                let cands = tr.candidates_of(pw);
                let reuse = plan.reuse(prev, cands, &mut xc_counters);
                if reuse.is_some() != pw.reused {
                    return Err(self.mismatch(
                        pixel,
                        format!(
                            "hit-buffer reuse {} here, {} in the functional model",
                            reuse.is_some(),
                            pw.reused
                        ),
                    ));
                }
                let direct = reuse.or_else(|| {
                    cands
                        .is_empty()
                        .then(|| plan.finish(None, SphereCount::None, &mut xc_counters).word)
                });
                if let Some(word) = direct {
                    // Reused word, or a ray with no candidate: straight to the write port.
                    if !rec_pushed && f_rc_wr.ready() {
                        if let Some((mut ray, _)) = p_check.pop(now) {
                            let _ = ray.leave(ST_CHECK, now);
                            reused += u64::from(reuse.is_some());
                            f_rc_wr
                                .try_push(ray.map(|r| Rec {
                                    pixel: r.pixel,
                                    word,
                                }))
                                .map_err(|e| CycleError::Internal(e.to_string()))?;
                            passed[3] += 1;
                        }
                    } else {
                        check_blocked = true;
                    }
                } else if f_ck_tr.ready() {
                    if let Some((mut ray, _)) = p_check.pop(now) {
                        let _ = ray.leave(ST_CHECK, now);
                        f_ck_tr
                            .try_push(ray)
                            .map_err(|e| CycleError::Internal(e.to_string()))?;
                        walks_entered += 1;
                        passed[3] += 1;
                    }
                } else {
                    check_blocked = true;
                }
            }
            if f_so_ck.valid() && p_check.can_accept(now) {
                if let Some(mut ray) = f_so_ck
                    .try_pop()
                    .map_err(|e| CycleError::Internal(e.to_string()))?
                {
                    ray.enter(ST_CHECK, now);
                    let word = self
                        .bram
                        .read(ray.payload.pixel as usize)
                        .map_err(|e| CycleError::Internal(e.to_string()))?;
                    p_check.accept(now, (ray, word), 1, 0);
                }
            }
            st[s_check].count(p_check.state(now, check_blocked, passed[2] < pixels));

            // --- sorter.
            let pushed = {
                let mut pushed = false;
                if p_sorter.ready(now).is_some() && f_so_ck.ready() {
                    if let Some(mut r) = p_sorter.pop(now) {
                        let _ = r.leave(ST_SORTER, now);
                        f_so_ck
                            .try_push(r)
                            .map_err(|e| CycleError::Internal(e.to_string()))?;
                        passed[2] += 1;
                        pushed = true;
                    }
                }
                pushed
            };
            if f_sp_so.valid() && p_sorter.can_accept(now) {
                if let Some(mut ray) = f_sp_so
                    .try_pop()
                    .map_err(|e| CycleError::Internal(e.to_string()))?
                {
                    ray.enter(ST_SORTER, now);
                    let (tr, pw, _) = trace_at(&rows, width, ray.payload.pixel)?;
                    if cross {
                        let d = dir[ray.payload.pixel as usize];
                        plan.candidates(d, &mut xc_cands, &mut xc_counters);
                        plan.sort(&mut xc_cands, &mut xc_counters);
                        if xc_cands.as_slice() != tr.candidates_of(pw) {
                            return Err(self.mismatch(
                                ray.payload.pixel,
                                format!(
                                    "sorted candidates {:?} here, {:?} in the functional model",
                                    xc_cands,
                                    tr.candidates_of(pw)
                                ),
                            ));
                        }
                    }
                    let n = usize::from(pw.cand_len);
                    let (passes, extra) = match sort_cost.get(n) {
                        Some(&c) => c,
                        None => sort_cost_of(n, hw.sorter_lanes, u.sorter.latency_cycles),
                    };
                    p_sorter.accept(now, ray, passes, extra);
                }
            }
            st[s_sorter].count(p_sorter.state(
                now,
                !pushed && p_sorter.ready(now).is_some(),
                passed[1] < pixels,
            ));

            // --- sphere lanes.
            let mut pushed = false;
            if p_sphere.ready(now).is_some() && f_sp_so.ready() {
                if let Some(mut r) = p_sphere.pop(now) {
                    let _ = r.leave(ST_SPHERE, now);
                    f_sp_so
                        .try_push(r)
                        .map_err(|e| CycleError::Internal(e.to_string()))?;
                    passed[1] += 1;
                    pushed = true;
                }
            }
            if f_rg_sp.valid() && p_sphere.can_accept(now) {
                if let Some(mut ray) = f_rg_sp
                    .try_pop()
                    .map_err(|e| CycleError::Internal(e.to_string()))?
                {
                    ray.enter(ST_SPHERE, now);
                    p_sphere.accept(now, ray, sphere_passes, 0);
                }
            }
            st[s_sphere].count(p_sphere.state(
                now,
                !pushed && p_sphere.ready(now).is_some(),
                passed[0] < pixels,
            ));

            // --- ray generation.
            let mut pushed = false;
            if p_raygen.ready(now).is_some() && f_rg_sp.ready() {
                if let Some(mut r) = p_raygen.pop(now) {
                    let _ = r.leave(ST_RAYGEN, now);
                    f_rg_sp
                        .try_push(r)
                        .map_err(|e| CycleError::Internal(e.to_string()))?;
                    passed[0] += 1;
                    pushed = true;
                }
            }
            if next_pixel < pixels && p_raygen.can_accept(now) {
                let row = (next_pixel / u64::from(width)) as usize;
                if row >= rows.len() {
                    receive(feed, row, width, &mut rows)?;
                }
                let mut ray = Stamped::new(Ray {
                    pixel: next_pixel as u32,
                });
                ray.enter(ST_RAYGEN, now);
                p_raygen.accept(now, ray, 1, 0);
                next_pixel += 1;
            }
            st[s_raygen].count(p_raygen.state(
                now,
                !pushed && p_raygen.ready(now).is_some(),
                next_pixel < pixels,
            ));

            // Walker pool as a stage: busy if any walker issued.
            st[s_walk].count(if self.pool.issued_count() > 0 {
                StageState::Busy
            } else if self.pool.busy_contexts() > 0 {
                if f_wk_rc.ready() {
                    StageState::Idle
                } else {
                    StageState::Backpressured
                }
            } else if more_walks {
                StageState::Starved
            } else {
                StageState::Idle
            });

            if let Some(wv) = self.waves.as_mut() {
                wv.sample(
                    now,
                    &[
                        &f_rg_sp.occupancy(),
                        &f_sp_so.occupancy(),
                        &f_so_ck.occupancy(),
                        &f_ck_tr.occupancy(),
                        &f_loop.occupancy(),
                        &f_tr_rc.occupancy(),
                        &f_rc_rt.occupancy(),
                        &f_rt_dp.occupancy(),
                        &f_wk_rc.occupancy(),
                        &f_rc_wr.occupancy(),
                    ],
                    &[
                        (f_rg_sp.valid(), f_rg_sp.ready()),
                        (f_sp_so.valid(), f_sp_so.ready()),
                        (f_so_ck.valid(), f_so_ck.ready()),
                        (f_ck_tr.valid(), f_ck_tr.ready()),
                        (f_loop.valid(), f_loop.ready()),
                        (f_tr_rc.valid(), f_tr_rc.ready()),
                        (f_rc_rt.valid(), f_rc_rt.ready()),
                        (f_rt_dp.valid(), f_rt_dp.ready()),
                        (f_wk_rc.valid(), f_wk_rc.ready()),
                        (f_rc_wr.valid(), f_rc_wr.ready()),
                    ],
                    &self.pool,
                    &self.mem,
                    next_pixel,
                    written,
                    frame,
                );
            }

            // --- the clock edge: every FIFO and the BRAM commit together.
            self.clock
                .edge(&mut [
                    &mut f_rg_sp as &mut dyn Commit,
                    &mut f_sp_so,
                    &mut f_so_ck,
                    &mut f_ck_tr,
                    &mut f_loop,
                    &mut f_tr_rc,
                    &mut f_rc_rt,
                    &mut f_rt_dp,
                    &mut f_wk_rc,
                    &mut f_rc_wr,
                    &mut self.bram,
                ])
                .map_err(|e| CycleError::Internal(e.to_string()))?;
            let progress =
                written + passed.iter().sum::<u64>() + self.pool.cycles().slots + next_pixel;
            if progress != last_progress.1 {
                last_progress = (now, progress);
            } else if now - last_progress.0 > stuck_limit {
                return Err(CycleError::Stuck {
                    frame,
                    cycles: now - last_progress.0,
                    at: now,
                    written,
                    pixels,
                });
            }
        }
        let end = self.clock.now();
        // Bit-exact: the hit buffer equals the functional model's, word for word.
        if rows.len() != self.height as usize {
            return Err(CycleError::Internal(format!(
                "frame ended with {} of {} rows received",
                rows.len(),
                self.height
            )));
        }
        let words = rows.iter().flat_map(|r| r.words.iter());
        for (p, &theirs) in words.enumerate() {
            let mine = self.bram.peek(p).copied().unwrap_or(0);
            if mine != theirs {
                return Err(self.mismatch(
                    p as u32,
                    format!("hit-buffer word {mine:#x} here, {theirs:#x} in the functional model"),
                ));
            }
        }
        self.frame += 1;
        let cycles = end - start;
        let fifo_stats = [
            ("raygen_to_sphere", f_rg_sp.depth(), f_rg_sp.stats().clone()),
            ("sphere_to_sorter", f_sp_so.depth(), f_sp_so.stats().clone()),
            ("sorter_to_check", f_so_ck.depth(), f_so_ck.stats().clone()),
            (
                "check_to_transform",
                f_ck_tr.depth(),
                f_ck_tr.stats().clone(),
            ),
            ("loop_back", f_loop.depth(), f_loop.stats().clone()),
            (
                "transform_to_reciprocal",
                f_tr_rc.depth(),
                f_tr_rc.stats().clone(),
            ),
            (
                "reciprocal_to_root",
                f_rc_rt.depth(),
                f_rc_rt.stats().clone(),
            ),
            ("root_to_dispatch", f_rt_dp.depth(), f_rt_dp.stats().clone()),
            ("walker_to_record", f_wk_rc.depth(), f_wk_rc.stats().clone()),
            ("record_to_write", f_rc_wr.depth(), f_rc_wr.stats().clone()),
        ];
        for (s, n) in st.iter_mut().zip(names) {
            s.transactions = match n {
                "raygen" => passed[0],
                "sphere" => passed[1],
                "sorter" => passed[2],
                "check" => passed[3],
                "transform" | "reciprocal" | "root" | "walkers" => self.pool.cycles().walks,
                "record" => walks_entered,
                _ => written,
            };
        }
        Ok(CycleFrame::new(
            &hw,
            frame,
            cycles,
            pixels,
            st,
            &fifo_stats,
            self.pool.take_cycles(),
            self.mem.reset_stats(),
            reused,
            early,
            walks_entered,
            wall.elapsed().as_secs_f64(),
        ))
    }
}

/// The trace of pixel `p` (its row, its work and its column) from the rows received.
fn trace_at<'r>(
    rows: &[&'r RowTrace],
    width: u32,
    p: u32,
) -> Result<(&'r RowTrace, &'r PixelWork, usize), CycleError> {
    let (i, j) = ((p % width) as usize, (p / width) as usize);
    let row = rows.get(j).copied().ok_or_else(|| {
        CycleError::Internal(format!("pixel {p} used before its row {j} was received"))
    })?;
    let work = row
        .pixels
        .get(i)
        .ok_or_else(|| CycleError::Internal(format!("row {j} of the trace has no pixel {i}")))?;
    Ok((row, work, i))
}

/// Waits for row `row` of the functional model's trace and takes every row published up to
/// it, checking each is a whole row.
fn receive<'r>(
    feed: &'r RowFeed,
    row: usize,
    width: u32,
    rows: &mut Vec<&'r RowTrace>,
) -> Result<(), CycleError> {
    let published = feed
        .wait_for(row)
        .map_err(|e| CycleError::Internal(format!("trace feed: {e}")))?;
    for j in rows.len()..published {
        let t = feed
            .get(j)
            .ok_or_else(|| CycleError::Internal(format!("row {j} announced but absent")))?;
        if t.pixels.len() != width as usize || t.words.len() != width as usize {
            return Err(CycleError::Internal(format!(
                "row {j} of the trace has {} pixels and {} words, the frame is {width} wide",
                t.pixels.len(),
                t.words.len()
            )));
        }
        rows.push(t);
    }
    Ok(())
}
