//! Idle-cycle skipping (docs/cycle-model.md §3.3): after a cycle in which nothing moved, the
//! clock jumps to the next cycle at which time alone changes something, and every counter is
//! credited for the cycles in between as if they had been stepped.
//!
//! Pipeline position: the end of [`super::Pipeline::step`], after the edge; off while
//! waveforms are recorded.

use super::super::error::CycleError;
use super::Pipeline;

impl Pipeline<'_> {
    /// What changes whenever anything moves: every FIFO's pushes and pops, the pixel counter
    /// and the walker pool's activity (a unit's transaction enters from or leaves into a FIFO,
    /// a record's write pops one).
    fn activity(&self) -> u64 {
        let f = &self.fifos;
        f.rg_sp.moved()
            + f.sp_so.moved()
            + f.so_ck.moved()
            + f.ck_tr.moved()
            + f.loop_back.moved()
            + f.tr_rc.moved()
            + f.rc_rt.moved()
            + f.rt_dp.moved()
            + f.wk_rc.moved()
            + f.rc_wr.moved()
            + f.ck_wr.moved()
            + self.raygen.next_pixel()
            + self.machine.pool.activity()
    }

    /// Idle-cycle skipping (docs/cycle-model.md §3.3), after the edge that ended cycle `now`.
    /// If nothing moved in `now`, every state the stages read is what it was at its start, so
    /// each following cycle repeats it exactly until time alone changes something: a unit's
    /// result becomes ready or its initiation interval ends, a walker's step latency or II
    /// ends, or a node read may complete. The clock jumps to the first such cycle at once and
    /// every counter is credited for the cycles in between as if they had been stepped (the
    /// stage rows with `now`'s states, the FIFOs with their occupancy and starved/full
    /// cycles, the pool with its walkers' classes). The node memory catches up by itself at
    /// the next cycle it is asked about.
    pub(super) fn skip_idle(&mut self, now: u64) -> Result<(), CycleError> {
        let activity = self.activity();
        let idle = activity == self.last_activity;
        self.last_activity = activity;
        if !idle || self.done() {
            return Ok(());
        }
        let m = &*self.machine;
        let next = [
            self.raygen.next_change(now),
            self.sphere.next_change(now),
            self.sorter.next_change(now),
            self.check.next_change(now),
            self.transform.next_change(now),
            self.recip.next_change(now),
            self.root.next_change(now),
            self.record.next_change(now),
            m.pool.next_event(now, &m.mem),
        ]
        .into_iter()
        .flatten()
        .min();
        // Nothing due at all would be a stuck pipeline: step on and let the watch report it.
        let Some(next) = next else {
            return Ok(());
        };
        let k = next.saturating_sub(now + 1);
        if k == 0 {
            return Ok(());
        }
        for (row, &s) in self.stages.iter_mut().zip(self.states.iter()) {
            row.count_many(s, k);
        }
        self.count_stalls(k);
        let f = &mut self.fifos;
        for fifo in [&mut f.rg_sp, &mut f.sp_so, &mut f.so_ck, &mut f.ck_tr] {
            fifo.skip_idle(k);
        }
        for fifo in [
            &mut f.loop_back,
            &mut f.tr_rc,
            &mut f.rc_rt,
            &mut f.rt_dp,
            &mut f.wk_rc,
        ] {
            fifo.skip_idle(k);
        }
        f.rc_wr.skip_idle(k);
        f.ck_wr.skip_idle(k);
        let m = &mut *self.machine;
        m.bram.skip_idle(k);
        m.pool.skip_idle(k);
        let last = m.clock.skip(k) - 1;
        self.skipped += k;
        self.watch(last)
    }
}
