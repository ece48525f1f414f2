//! The sorter: a ray's candidates ordered front to back by the sorting network, with merge
//! passes when a ray has more candidates than the network has lanes.
//!
//! Pipeline position: `sphere_to_sorter` → `sorter_to_check` (docs/cycle-model.md §2.1). A ray
//! occupies the network for the passes `units::sorter::pipe_cost` gives its candidate count
//! (from the trace) and leaves after the network's latency plus the merges. Under cross-check
//! this stage re-runs the sphere tests and the sort from the ray's direction and compares the
//! list with the trace (§2.4). With sorting switched off (`--no-sort`, docs/paper.md §2) a
//! ray passes the network's registers in one issue, in instance order; without culling only
//! the pierced candidates are sorted, the others follow.

use super::io::FrameFx;
use super::{hand_on, id, Cx, Ray, Scratch, UnitIo};
use crate::models::cycle::error::CycleError;
use crate::models::fixed::plan::NOT_PIERCED;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageState;
use rtl_model::cycle::unit_pipe::UnitPipe;
use rtl_model::units::sorter::pipe_cost;

/// Candidate counts whose sort cost is tabulated up front; beyond it, computed per ray.
const SORT_COST_TABLE: usize = 4096;

/// The sorter stage.
pub struct Sorter {
    /// In the last cycle evaluated, a ray waited at the input while the unit's initiation
    /// window kept it closed: its `ii`, or a ray's further network issues and merge
    /// passes (more candidates than lanes). The bound line's `sorter` cause
    /// (docs/cycle-model.md §2.2).
    pub held: bool,
    pipe: UnitPipe<Stamped<Ray>>,
    /// Passes and extra latency by candidate count (the network's timing is a pure function
    /// of the count; computing it per ray would rebuild the network).
    sort_cost: Vec<(u64, u64)>,
    lanes: u8,
    network_latency: u32,
    /// The cross-check's scratch.
    xc: Scratch,
}

/// Passes (initiation intervals) a ray of `n` candidates occupies the sorter for, and its
/// latency beyond the network's: `units::sorter::pipe_cost`, which the sorter's vectors use
/// too. A ray with more chunks than one holds the input until its merges are done (one
/// merger, results in order); before issue 15 it held it for max(chunks, merge cycles), which
/// let two rays' merges overlap in the one merger.
fn sort_cost_of(n: usize, lanes: u8, network_latency: u32) -> (u64, u64) {
    pipe_cost(n, lanes, network_latency)
}

impl Sorter {
    /// The first cycle after `now` in which the stage's unit can change by itself
    /// (idle-cycle skipping, docs/cycle-model.md §3.3).
    #[inline]
    pub fn next_change(&self, now: u64) -> Option<u64> {
        self.pipe.next_change(now)
    }

    /// The stage of `hw` for a frame of `instances` instances.
    pub fn new(hw: &HwConfig, instances: usize) -> Self {
        let u = &hw.units.sorter;
        // `validate` keeps the lanes within the datapath's 8-bit sorter.n.
        let lanes = u8::try_from(hw.sorter_lanes).unwrap_or(u8::MAX);
        Self {
            held: false,
            pipe: UnitPipe::new(u.latency_cycles, u.ii),
            sort_cost: (0..=instances.min(SORT_COST_TABLE))
                .map(|n| sort_cost_of(n, lanes, u.latency_cycles))
                .collect(),
            lanes,
            network_latency: u.latency_cycles,
            xc: Scratch::default(),
        }
    }

    /// One cycle: the ready ray leaves into `io.out`, the next one enters from `io.input`.
    /// `upstream_more`: the sphere stage had rays still to pass as the cycle started.
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut UnitIo<'_, Ray, Ray>,
        cx: &Cx<'_, '_>,
        fx: &mut FrameFx,
        upstream_more: bool,
    ) -> Result<StageState, CycleError> {
        let (now, frame) = (cx.now, cx.frame);
        let pushed = hand_on(&mut self.pipe, id::SORTER, &mut io.out, now)?;
        fx.passed[2] += u64::from(pushed);
        let input = &mut io.input;
        self.held = input.valid() && self.pipe.in_interval(now);
        if input.valid() && self.pipe.can_accept(now) {
            if let Some(mut ray) = input.pop(now)? {
                ray.enter(id::SORTER, now);
                let pixel = ray.payload.pixel;
                let (tr, pw, _) = frame.trace_at(pixel)?;
                if frame.setup.cross_check {
                    let d = frame.dir[pixel as usize];
                    let xc = &mut self.xc;
                    frame.plan.walk_list(d, &mut xc.cands, &mut xc.counters);
                    if xc.cands.as_slice() != tr.candidates_of(pw) {
                        return Err(frame.mismatch(
                            pixel,
                            format!(
                                "sorted candidates {:?} here, {:?} in the functional model",
                                xc.cands,
                                tr.candidates_of(pw)
                            ),
                        ));
                    }
                }
                let (passes, extra) = if frame.plan.switches().sort {
                    // The network sorts the pierced candidates; without culling the others
                    // follow them unsorted (`FramePlan::order`).
                    let cands = tr.candidates_of(pw);
                    let n = if frame.plan.switches().culling {
                        cands.len()
                    } else {
                        cands.iter().filter(|c| c.0 != NOT_PIERCED).count()
                    };
                    match self.sort_cost.get(n) {
                        Some(&c) => c,
                        None => sort_cost_of(n, self.lanes, self.network_latency),
                    }
                } else {
                    // No sorting: the candidates pass the network's registers in instance
                    // order, one issue per ray, no merges.
                    (1, 0)
                };
                self.pipe.accept(now, ray, passes, extra);
            }
        }
        Ok(self.pipe.state(now, !pushed, upstream_more))
    }
}
