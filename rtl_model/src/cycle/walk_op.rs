//! The walker's work as the cycle model times it: a walk is a list of ops, runs of issue slots
//! of the walker's datapath (each child examined, each stack pop) and the memory reads it
//! waits for, in order. The functional walker reports them through its observer
//! ([`crate::units::walker::WalkObserver`]); [`OpRecorder`] packs them, one `u64` per op.
//!
//! Pipeline position: produced by the functional model (or by the cycle model's own walk
//! under cross-check), consumed by the walker pool (`walker_pool.rs`).

use crate::svo::FetchKind;
use crate::units::walker::WalkObserver;

/// A walk op: `n` issue slots of the walker's datapath (steps and pops), or one memory read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WalkOp {
    /// Issue slots with no read between them.
    Issue(u32),
    /// A read the walker waits for before its next slot.
    Read(FetchKind, u32),
}

impl WalkOp {
    /// Packs into a word: bits 32..34 the kind (0 issue, 1 node, 2 far, 3 attr), low 32 the
    /// count or address.
    pub fn pack(self) -> u64 {
        match self {
            WalkOp::Issue(n) => u64::from(n),
            WalkOp::Read(kind, a) => {
                let k: u64 = match kind {
                    FetchKind::Node => 1,
                    FetchKind::Far => 2,
                    FetchKind::Attr => 3,
                };
                (k << 32) | u64::from(a)
            }
        }
    }

    /// Inverse of [`WalkOp::pack`].
    pub fn unpack(w: u64) -> Self {
        let a = w as u32;
        match w >> 32 {
            0 => WalkOp::Issue(a),
            1 => WalkOp::Read(FetchKind::Node, a),
            2 => WalkOp::Read(FetchKind::Far, a),
            _ => WalkOp::Read(FetchKind::Attr, a),
        }
    }
}

/// Records a walk's ops: consecutive steps and pops merge into one [`WalkOp::Issue`].
pub struct OpRecorder<'a> {
    ops: &'a mut Vec<u64>,
    run: u32,
}

impl<'a> OpRecorder<'a> {
    /// Appends to `ops`.
    pub fn new(ops: &'a mut Vec<u64>) -> Self {
        Self { ops, run: 0 }
    }

    fn flush(&mut self) {
        if self.run > 0 {
            self.ops.push(WalkOp::Issue(self.run).pack());
            self.run = 0;
        }
    }

    /// Ends the walk (flushes the last issue run).
    pub fn finish(mut self) {
        self.flush();
    }
}

impl WalkObserver for OpRecorder<'_> {
    #[inline]
    fn step(&mut self) {
        self.run += 1;
    }
    #[inline]
    fn pop(&mut self) {
        self.run += 1;
    }
    #[inline]
    fn read(&mut self, kind: FetchKind, addr: u32) {
        self.flush();
        self.ops.push(WalkOp::Read(kind, addr).pack());
    }
}
