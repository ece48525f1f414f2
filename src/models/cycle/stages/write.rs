//! The write stage: one record per cycle into the hit buffer.
//!
//! Pipeline position: the last stage (evaluated first in a cycle), `record_to_write` → the
//! hit-buffer BRAM's write port (docs/cycle-model.md §2.1). The word lands at the clock edge,
//! so a read of the same pixel in this cycle still sees the previous frame's word
//! (READ_FIRST). The first records' stamps are kept for the transaction log (§2.5).

use super::{id, internal, FrameCounts, Rec};
use crate::models::cycle::model::CycleError;
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::StageStamp;
use rtl_model::cycle::fifo::Fifo;
use rtl_model::cycle::stage_stats::StageState;

/// The write stage.
pub struct Write {
    /// Records whose stamps the transaction log keeps, per run.
    log_limit: usize,
}

impl Write {
    /// The stage, keeping the stamps of the first `log_limit` records of the run.
    pub fn new(log_limit: usize) -> Self {
        Self { log_limit }
    }

    /// One cycle: the head record of `input` (always asked for: the port is ready every
    /// cycle) is written to `bram`.
    #[inline]
    pub fn eval(
        &mut self,
        input: &mut Fifo<Rec>,
        bram: &mut Bram<u128>,
        log: &mut Vec<(u32, Vec<StageStamp>)>,
        counts: &mut FrameCounts,
        now: u64,
    ) -> Result<StageState, CycleError> {
        let Some(mut r) = input.try_pop().map_err(internal)? else {
            return Ok(if counts.written < counts.pixels {
                StageState::Starved
            } else {
                StageState::Idle
            });
        };
        r.enter(id::WRITE, now);
        let _ = r.leave(id::WRITE, now);
        bram.write(r.payload.pixel as usize, r.payload.word)
            .map_err(internal)?;
        if log.len() < self.log_limit {
            log.push((r.payload.pixel, r.stamps().to_vec()));
        }
        counts.written += 1;
        Ok(StageState::Busy)
    }
}
