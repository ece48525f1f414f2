//! The hit-buffer reuse check: whether a pixel's word from the previous frame can stand for
//! this frame's ray, and the word written back when it can (paper §4.3, DESIGN.md §3).
//!
//! Pipeline position: the check stage, after the sorter: it reads the pixel's previous word
//! (unpacked, one register: `UNPACK_LATENCY_CYCLES`), this frame's candidate list and the
//! host's dirty flags. The functional model (`FramePlan::reuse`) and the cycle model's check
//! stage call [`reuse`]; the RTL is `testbench/rtl/svo_hit_check.v`.

use super::{pack, unpack, HitRecordConfig, SphereCount};
use crate::fixed::{Overflows, SignalId};

/// What the check knows about this frame besides the previous word.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ReuseInputs {
    /// The hit buffer is in use this frame (the run keeps one, and the frame is not the first).
    pub buffer: bool,
    /// The camera moved since the word was written: no pixel can be reused.
    pub camera_dirty: bool,
    /// Candidates (spheres pierced) of this frame's ray.
    pub candidates: usize,
    /// The only candidate's instance (read only when `candidates` is 1).
    pub candidate: u16,
    /// That instance moved since the word was written.
    pub instance_dirty: bool,
}

/// The rule: reuse when the buffer is in use, the camera is still, the ray pierces exactly one
/// sphere whose instance is still, and the previous word hit that instance or nothing. The
/// returned word is the previous one with its sphere count refreshed from this frame (never
/// the stored kind: an instance may have moved in front since), re-packed; `None` means the
/// ray must be traced.
pub fn reuse(
    prev: u128,
    inp: &ReuseInputs,
    cfg: &HitRecordConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> Option<u128> {
    if !inp.buffer || inp.camera_dirty || inp.candidates != 1 || inp.instance_dirty {
        return None;
    }
    let old = unpack(prev, cfg);
    if !(old.instance.is_none() || old.instance == Some(inp.candidate)) {
        return None;
    }
    let mut f = old;
    f.kind = SphereCount::from_count(inp.candidates);
    Some(pack(&f, cfg, ov, sig))
}
