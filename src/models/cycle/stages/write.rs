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

use super::io::PopPort;
use super::{id, Cx, Rec};
use crate::models::cycle::error::CycleError;
use rtl_model::cycle::clocked::Stamped;
use rtl_model::cycle::stage_stats::StageState;

/// The write stage.
pub struct Write {
    /// Cycles the head record waited for its bank behind the check's word (two write paths).
    pub bank_conflicts: u64,
    /// Records written per cycle at most (`hit_buffer.record_writes`).
    record_writes: u8,
}

/// The write stage's ports: the record FIFO, the check stage's own write FIFO with two write
/// paths, and the records it writes (into the BRAM, the transaction log and the frame's
/// count at the commit).
pub struct WriteIo<'a> {
    /// `record_to_write`.
    pub input: PopPort<'a, Rec>,
    /// `check_to_write`, with two write paths.
    pub second: Option<PopPort<'a, Rec>>,
    /// The records written this cycle, in port order.
    pub writes: &'a mut Vec<Stamped<Rec>>,
}

impl Write {
    /// The stage, writing up to `record_writes` records a cycle.
    pub fn new(record_writes: u8) -> Self {
        Self {
            bank_conflicts: 0,
            record_writes,
        }
    }

    /// One cycle: the head record of `input` (always asked for: the port is ready every
    /// cycle) is written; with a second path `second`, its head first, and the record only
    /// if it falls in the other bank.
    #[inline]
    pub fn eval(
        &mut self,
        io: &mut WriteIo<'_>,
        cx: &Cx<'_, '_>,
    ) -> Result<StageState, CycleError> {
        let now = cx.now;
        // Two write paths: the check's word goes first. The check stage takes one ray a
        // cycle from the front end, so a word of it that waits stops ray generation, while a
        // record that waits a cycle sits in `record_to_write` and costs nothing until that
        // FIFO fills (the car's still frames lost 8.5 % of their cycles with the record
        // first). The record head then takes the other bank, or waits (a bank conflict).
        let mut check_bank = None;
        let written = io.writes.len();
        if let Some(f) = io.second.as_mut() {
            if let Some(r) = f.pop(now)? {
                check_bank = Some(r.payload.pixel & 1);
                Self::write(r, io.writes, now);
            }
        }
        let input = &mut io.input;
        let head_bank = input.peek().map(|r| r.payload.pixel & 1);
        if head_bank.is_some() && head_bank == check_bank {
            self.bank_conflicts += 1;
        } else if let Some(r) = input.pop(now)? {
            Self::write(r, io.writes, now);
            // `record_writes: 2`: the record behind the head takes the other bank when the
            // check's word did not (validation allows it only with the two banks).
            if self.record_writes >= 2 && check_bank.is_none() {
                let next_bank = input.peek().map(|r| r.payload.pixel & 1);
                if next_bank.is_some() && next_bank != head_bank {
                    if let Some(r) = input.pop(now)? {
                        Self::write(r, io.writes, now);
                    }
                }
            }
        }
        let wrote = (io.writes.len() - written) as u64;
        let c = cx.counts;
        Ok(if wrote > 0 {
            StageState::Busy
        } else if c.written < c.pixels {
            StageState::Starved
        } else {
            StageState::Idle
        })
    }

    /// Stamps record `r` through the write port and hands it to the commit.
    #[inline]
    fn write(mut r: Stamped<Rec>, writes: &mut Vec<Stamped<Rec>>, now: u64) {
        r.enter(id::WRITE, now);
        let _ = r.leave(id::WRITE, now);
        writes.push(r);
    }
}
