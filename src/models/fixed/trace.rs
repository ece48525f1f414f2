//! The work a frame gave the pipeline, recorded by the functional fixed-point model for the
//! cycle model to time: per pixel its sorted candidates, whether the hit buffer was reused,
//! and per walk the walker's issue slots and memory reads in order.
//!
//! Pipeline position: the interface of the functional/timing split (DESIGN.md §6). The
//! functional model (`frame.rs`, in parallel over rows) writes one [`RowTrace`] per image row;
//! the cycle model (`crate::models::cycle`) replays them in raster order, making every decision
//! that depends on its own state (hit-buffer reuse from its BRAM, early termination, the
//! winning walk) itself and checking it against the trace; with `cross_check` it also
//! re-executes every sphere test, sort, transform and walk in its stages and compares.

pub use rtl_model::cycle::walk_op::{OpRecorder, WalkOp};

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
    /// Walker t (raw) of its hit, `None` for a miss or a stopped walk.
    pub hit_t: Option<i64>,
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
