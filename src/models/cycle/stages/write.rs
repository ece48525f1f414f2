//! The write stage: one record per cycle and write path into the hit buffer.
//!
//! Pipeline position: the last stage (evaluated first in a cycle), `record_to_write` → the
//! hit-buffer BRAM's write port (docs/cycle-model.md §2.1). With two write paths
//! (`hit_buffer.write_ports: 2`) the check stage's words come through their own FIFO,
//! `check_to_write`, into a second port: the buffer is two banks on pixel parity, one write
//! port each, so both write in a cycle unless their pixels share a bank, when the check's
//! word goes first and the record waits (counted in [`Write::bank_conflicts`]; the check
//! stage feeds on the front end's one ray a cycle, the record has its FIFO to wait in); with
//! `hit_buffer.record_writes: 2` the record behind the head takes the other bank when the
//! check has no word for it. The word lands at the clock edge,
//! so a read of the same pixel in this cycle still sees the previous frame's word
//! (READ_FIRST). The first records' stamps are kept for the transaction log (§2.5).

use super::{id, internal, FrameCounts, Rec};
use crate::models::cycle::error::CycleError;
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::StageStamp;
use rtl_model::cycle::fifo::Fifo;
use rtl_model::cycle::stage_stats::StageState;

/// The write stage.
pub struct Write {
    /// Records whose stamps the transaction log keeps, per run.
    log_limit: usize,
    /// Cycles the head record waited for its bank behind the check's word (two write paths).
    pub bank_conflicts: u64,
    /// Records written per cycle at most (`hit_buffer.record_writes`).
    record_writes: u8,
}

impl Write {
    /// The stage, keeping the stamps of the first `log_limit` records of the run, writing
    /// up to `record_writes` records a cycle.
    pub fn new(log_limit: usize, record_writes: u8) -> Self {
        Self {
            log_limit,
            bank_conflicts: 0,
            record_writes,
        }
    }

    /// One cycle: the head record of `input` (always asked for: the port is ready every
    /// cycle) is written to `bram`; with a second path `second`, its head first, and the
    /// record only if it falls in the other bank.
    #[inline]
    pub fn eval(
        &mut self,
        input: &mut Fifo<Rec>,
        second: Option<&mut Fifo<Rec>>,
        bram: &mut Bram<u128>,
        log: &mut Vec<(u32, Vec<StageStamp>)>,
        counts: &mut FrameCounts,
        now: u64,
    ) -> Result<StageState, CycleError> {
        // Two write paths: the check's word goes first. The check stage takes one ray a
        // cycle from the front end, so a word of it that waits stops ray generation, while a
        // record that waits a cycle sits in `record_to_write` and costs nothing until that
        // FIFO fills (the car's still frames lost 8.5 % of their cycles with the record
        // first). The record head then takes the other bank, or waits (a bank conflict).
        let mut wrote = false;
        let mut check_bank = None;
        if let Some(f) = second {
            if let Some(r) = f.try_pop().map_err(internal)? {
                check_bank = Some(r.payload.pixel & 1);
                self.write(r, bram, log, counts, now)?;
                wrote = true;
            }
        }
        let head_bank = input.peek().map(|r| r.payload.pixel & 1);
        if head_bank.is_some() && head_bank == check_bank {
            self.bank_conflicts += 1;
        } else if let Some(r) = input.try_pop().map_err(internal)? {
            self.write(r, bram, log, counts, now)?;
            wrote = true;
            // `record_writes: 2`: the record behind the head takes the other bank when the
            // check's word did not (validation allows it only with the two banks).
            if self.record_writes >= 2 && check_bank.is_none() {
                let next_bank = input.peek().map(|r| r.payload.pixel & 1);
                if next_bank.is_some() && next_bank != head_bank {
                    if let Some(r) = input.try_pop().map_err(internal)? {
                        self.write(r, bram, log, counts, now)?;
                    }
                }
            }
        }
        Ok(if wrote {
            StageState::Busy
        } else if counts.written < counts.pixels {
            StageState::Starved
        } else {
            StageState::Idle
        })
    }

    /// Writes record `r` and logs it.
    #[inline]
    fn write(
        &mut self,
        mut r: rtl_model::cycle::clocked::Stamped<Rec>,
        bram: &mut Bram<u128>,
        log: &mut Vec<(u32, Vec<StageStamp>)>,
        counts: &mut FrameCounts,
        now: u64,
    ) -> Result<(), CycleError> {
        r.enter(id::WRITE, now);
        let _ = r.leave(id::WRITE, now);
        bram.write(r.payload.pixel as usize, r.payload.word)
            .map_err(internal)?;
        if log.len() < self.log_limit {
            log.push((r.payload.pixel, r.stamps().to_vec()));
        }
        counts.written += 1;
        Ok(())
    }
}
