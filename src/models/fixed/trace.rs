//! Watching the per-pixel flow of the functional fixed-point model: the [`PixelObserver`]
//! hooks `FramePlan::pixel` calls at every step, and the observer that records the work a
//! frame gave the pipeline for the cycle model to time ([`RowRecorder`] into [`RowTrace`]: per
//! pixel its sorted candidates, whether the hit buffer was reused, and per walk the walker's
//! issue slots and memory reads in order).
//!
//! Pipeline position: the interface of the functional/timing split (DESIGN.md §6). The
//! functional model (`frame.rs`, in parallel over rows) runs `FramePlan::pixel` with
//! [`NoPixelObserver`] (every hook is an empty generic call that compiles away) or, for a
//! streamed cycle run, with one [`RowRecorder`] per image row; the cycle model
//! (`crate::models::cycle`) replays the [`RowTrace`]s in raster order, making every decision
//! that depends on its own state (hit-buffer reuse from its BRAM, early termination, the
//! winning walk) itself and checking it against the trace; with `cross_check` it also
//! re-executes every sphere test, sort, transform and walk in its stages and compares. The
//! HDL-vector capture (`crate::studies::vectors::capture`) is the other observer: it records
//! each unit's inputs from the same calls, so there is one per-pixel flow.

use super::frame::FixedRecord;
pub use rtl_model::cycle::walk_op::{OpRecorder, WalkOp};
use rtl_model::units::hit_record::HitRecordFields;
use rtl_model::units::normal::NormalMatrix;
use rtl_model::units::sphere::{SphereHit, SphereRaw};
use rtl_model::units::transform::InstanceRaw;
use rtl_model::units::walker::{NoObserver, WalkObserver, WalkOutcome, WalkerInput, WalkerT};

/// What one pixel of `FramePlan::pixel` does, step by step, in program order: the sphere
/// test of every instance, the candidates before and after the sorter, then either the
/// hit-buffer reuse or, per candidate walked, its transform, three reciprocals and the walk,
/// then the record; last the pixel's end. Every hook but the walk's has an empty default;
/// observers are generic parameters, never `dyn`, so the unobserved model pays nothing.
pub trait PixelObserver {
    /// What a walk reports its steps, pops and reads to.
    type Walk<'w>: WalkObserver
    where
        Self: 'w;

    /// The sphere test of instance `k`: ray origin `o`, direction `d`, the sphere as the host
    /// programmed it, and the result (`None`: culled).
    #[inline]
    fn on_sphere(
        &mut self,
        _k: u16,
        _o: [i64; 3],
        _d: [i64; 3],
        _sphere: &SphereRaw,
        _hit: Option<SphereHit>,
    ) {
    }

    /// The candidates (entry key, instance) in instance order, as the sorter receives them.
    #[inline]
    fn on_candidates(&mut self, _unsorted: &[(i64, u16)]) {}

    /// The candidates front to back, as the sorter returns them.
    #[inline]
    fn on_sorted(&mut self, _sorted: &[(i64, u16)]) {}

    /// The hit buffer's word was reused (refreshed to `word`): no walk, no record.
    #[inline]
    fn on_reuse(&mut self, _word: u128) {}

    /// The transform of ray (`o`, `d`) into instance `k`'s frame.
    #[inline]
    fn on_transform(&mut self, _k: u16, _o: [i64; 3], _d: [i64; 3], _inst: &InstanceRaw) {}

    /// One reciprocal: a local direction component and its sign bit.
    #[inline]
    fn on_reciprocal(&mut self, _d_local: i64, _negative: bool) {}

    /// A walk of instance `k` with inputs `input` begins: the observer it reports to.
    fn begin_walk(&mut self, k: u16, input: &WalkerInput) -> Self::Walk<'_>;

    /// The walk's observer is done (before [`PixelObserver::on_walk`]).
    #[inline]
    fn end_walk(_walk: Self::Walk<'_>) {}

    /// The walk of instance `k` ended with `out`.
    #[inline]
    fn on_walk(&mut self, _k: u16, _out: &WalkOutcome) {}

    /// A traced pixel's record: its fields as quantised before packing, and the packed word.
    #[inline]
    fn on_record(&mut self, _fields: &HitRecordFields, _word: u128) {}

    /// A hit's record normal: the normal unit's inputs, the attribute's normal word and the
    /// instance's matrix.
    #[inline]
    fn on_normal(&mut self, _oct16: u32, _m: &NormalMatrix) {}

    /// The pixel is done: `rec` is the buffer entry it ends the frame with.
    #[inline]
    fn on_pixel_end(&mut self, _rec: &FixedRecord) {}
}

/// Observes nothing: the functional model's hot path.
pub struct NoPixelObserver;

impl PixelObserver for NoPixelObserver {
    type Walk<'w> = NoObserver;

    #[inline]
    fn begin_walk(&mut self, _k: u16, _input: &WalkerInput) -> NoObserver {
        NoObserver
    }
}

/// One pixel's work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelWork {
    /// First of its candidates in [`RowTrace::candidates`] (sorted front to back).
    pub cand_start: u32,
    /// Candidates (rays whose sphere test passed).
    pub cand_len: u16,
    /// Whether the hit buffer's word was reused (no walk).
    pub reused: bool,
    /// First of its walks in [`RowTrace::walks`].
    pub walk_start: u32,
    /// Walks done (candidates walked before early termination).
    pub walk_len: u16,
}

/// One walk's work.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WalkWork {
    /// Walker t (raw, walker t format) of its hit, `None` for a miss or a stopped walk.
    pub hit_t: Option<WalkerT>,
    /// First op in [`RowTrace::ops`].
    pub op_start: u32,
    /// Ops.
    pub op_len: u32,
}

/// The work of one image row.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RowTrace {
    /// One per pixel, left to right.
    pub pixels: Vec<PixelWork>,
    /// Sorted candidates (sorter key, instance) of every pixel.
    pub candidates: Vec<(i64, u16)>,
    /// Walks of every pixel.
    pub walks: Vec<WalkWork>,
    /// Packed [`WalkOp`]s of every walk.
    pub ops: Vec<u64>,
    /// The hit-buffer word each pixel ends the frame with, left to right: what the cycle
    /// model's record and write stages must produce.
    pub words: Vec<u128>,
}

impl RowTrace {
    /// Candidates of a pixel.
    pub fn candidates_of(&self, p: &PixelWork) -> &[(i64, u16)] {
        let s = p.cand_start as usize;
        self.candidates
            .get(s..s + usize::from(p.cand_len))
            .unwrap_or(&[])
    }

    /// Walks of a pixel.
    pub fn walks_of(&self, p: &PixelWork) -> &[WalkWork] {
        let s = p.walk_start as usize;
        self.walks
            .get(s..s + usize::from(p.walk_len))
            .unwrap_or(&[])
    }

    /// Ops of a walk.
    pub fn ops_of(&self, w: &WalkWork) -> &[u64] {
        let s = w.op_start as usize;
        self.ops.get(s..s + w.op_len as usize).unwrap_or(&[])
    }
}

/// Records a row's pixels into a [`RowTrace`] (emptied first), one pixel after another.
pub struct RowRecorder<'t> {
    trace: &'t mut RowTrace,
    /// The pixel being recorded.
    work: PixelWork,
    /// First op of the walk being recorded.
    op_start: u32,
}

impl<'t> RowRecorder<'t> {
    /// Records into `trace`, clearing it.
    pub fn new(trace: &'t mut RowTrace) -> Self {
        trace.pixels.clear();
        trace.candidates.clear();
        trace.walks.clear();
        trace.ops.clear();
        trace.words.clear();
        Self {
            trace,
            work: PixelWork::default(),
            op_start: 0,
        }
    }
}

impl PixelObserver for RowRecorder<'_> {
    type Walk<'w>
        = OpRecorder<'w>
    where
        Self: 'w;

    fn on_sorted(&mut self, sorted: &[(i64, u16)]) {
        let t = &mut *self.trace;
        self.work = PixelWork {
            cand_start: t.candidates.len() as u32,
            cand_len: sorted.len().min(usize::from(u16::MAX)) as u16,
            walk_start: t.walks.len() as u32,
            ..PixelWork::default()
        };
        t.candidates.extend_from_slice(sorted);
    }

    fn on_reuse(&mut self, _word: u128) {
        self.work.reused = true;
    }

    fn begin_walk(&mut self, _k: u16, _input: &WalkerInput) -> OpRecorder<'_> {
        self.op_start = self.trace.ops.len() as u32;
        OpRecorder::new(&mut self.trace.ops)
    }

    fn end_walk(walk: OpRecorder<'_>) {
        walk.finish();
    }

    fn on_walk(&mut self, _k: u16, out: &WalkOutcome) {
        let hit_t = match out {
            WalkOutcome::Hit(h) => Some(h.t),
            _ => None,
        };
        let t = &mut *self.trace;
        t.walks.push(WalkWork {
            hit_t,
            op_start: self.op_start,
            op_len: t.ops.len() as u32 - self.op_start,
        });
        self.work.walk_len += 1;
    }

    fn on_pixel_end(&mut self, rec: &FixedRecord) {
        self.trace.pixels.push(self.work);
        self.trace.words.push(rec.word);
    }
}
