//! The FIFOs between the stages of a frame's pipeline, in pipeline order, with their depths
//! and ports from the hardware configuration.
//!
//! Pipeline position: owned by `pipeline::Pipeline`; the stage kernels read them through
//! `stages::io` ports, `commit::Effects::apply` drives them, the clock edge commits them
//! (docs/cycle-model.md §2.1) as one part: [`Fifos`] is a [`Commit`] that checks and commits
//! each FIFO by a direct call, so the edge makes one indirect call for all eleven.

use super::error::CycleError;
use super::stages::{id, Ray, Rec, Walk};
use rtl_model::cycle::clocked::{ClockError, Commit, StageId};
use rtl_model::cycle::fifo::{Fifo, FifoStats};
use rtl_model::cycle::hw_config::HwConfig;

/// The FIFOs between the stages, in pipeline order.
pub struct Fifos {
    pub(super) rg_sp: Fifo<Ray>,
    pub(super) sp_so: Fifo<Ray>,
    pub(super) so_ck: Fifo<Ray>,
    pub(super) ck_tr: Fifo<Ray>,
    pub(super) loop_back: Fifo<Walk>,
    pub(super) tr_rc: Fifo<Walk>,
    pub(super) rc_rt: Fifo<Walk>,
    pub(super) rt_dp: Fifo<Walk>,
    pub(super) wk_rc: Fifo<Walk>,
    pub(super) rc_wr: Fifo<Rec>,
    /// The check stage's own write FIFO, used with two hit-buffer write paths
    /// (`hit_buffer.write_ports: 2`); otherwise it stays empty and out of the report.
    pub(super) ck_wr: Fifo<Rec>,
    /// Whether `ck_wr` is in use.
    pub(super) two_write_paths: bool,
}

fn fifo<T>(id: StageId, depth: u32, now: u64) -> Result<Fifo<T>, CycleError> {
    wide(id, depth, 1, now)
}

/// A FIFO of `ports` pushes and pops per cycle (the walk section's, docs/cycle-model.md §2.1).
fn wide<T>(id: StageId, depth: u32, ports: u32, now: u64) -> Result<Fifo<T>, CycleError> {
    Fifo::new_wide_at(id, depth as usize, ports as usize, now)
        .map_err(|e| CycleError::Config(e.to_string()))
}

impl Fifos {
    /// Empty FIFOs of `hw`'s depths, out of reset at cycle `now`; the loop-back FIFO has one
    /// entry per ray slot. The walk section's FIFOs, from the walk queue to the write FIFO,
    /// take `hw.walk_lanes()` pushes and pops per cycle; the check stage's own write FIFO
    /// has `record_to_write`'s depth.
    pub(super) fn new(hw: &HwConfig, ray_slots: u32, now: u64) -> Result<Self, CycleError> {
        let fd = &hw.fifos;
        let k = hw.walk_lanes();
        Ok(Self {
            rg_sp: fifo(id::F_RG_SP, fd.raygen_to_sphere, now)?,
            sp_so: fifo(id::F_SP_SO, fd.sphere_to_sorter, now)?,
            so_ck: fifo(id::F_SO_CK, fd.sorter_to_check, now)?,
            ck_tr: wide(id::F_CK_TR, fd.check_to_transform, k, now)?,
            loop_back: wide(id::F_LOOP, ray_slots, k, now)?,
            tr_rc: wide(id::F_TR_RC, fd.transform_to_reciprocal, k, now)?,
            rc_rt: wide(id::F_RC_RT, fd.reciprocal_to_root, k, now)?,
            rt_dp: wide(id::F_RT_DP, fd.root_to_dispatch, k, now)?,
            wk_rc: wide(id::F_WK_RC, fd.walker_to_record, k, now)?,
            // Two records a cycle leave it with `hit_buffer.record_writes: 2`.
            rc_wr: wide(
                id::F_RC_WR,
                fd.record_to_write,
                k.max(u32::from(hw.hit_buffer.record_writes)),
                now,
            )?,
            ck_wr: fifo(id::F_CK_WR, fd.record_to_write, now)?,
            two_write_paths: hw.hit_buffer.write_ports >= 2,
        })
    }

    /// Registered occupancy of each FIFO, in pipeline order.
    pub(super) fn occupancy(&self) -> [usize; 10] {
        [
            self.rg_sp.occupancy(),
            self.sp_so.occupancy(),
            self.so_ck.occupancy(),
            self.ck_tr.occupancy(),
            self.loop_back.occupancy(),
            self.tr_rc.occupancy(),
            self.rc_rt.occupancy(),
            self.rt_dp.occupancy(),
            self.wk_rc.occupancy(),
            self.rc_wr.occupancy(),
        ]
    }

    /// Registered (valid, ready) of each FIFO, in pipeline order.
    pub(super) fn handshakes(&self) -> [(bool, bool); 10] {
        fn vr<T>(f: &Fifo<T>) -> (bool, bool) {
            (f.valid(), f.ready())
        }
        [
            vr(&self.rg_sp),
            vr(&self.sp_so),
            vr(&self.so_ck),
            vr(&self.ck_tr),
            vr(&self.loop_back),
            vr(&self.tr_rc),
            vr(&self.rc_rt),
            vr(&self.rt_dp),
            vr(&self.wk_rc),
            vr(&self.rc_wr),
        ]
    }

    /// Name, depth and counters of each FIFO, for the report (`check_to_write` only with two
    /// write paths).
    pub(super) fn stats(&self) -> Vec<(&'static str, usize, FifoStats)> {
        fn s<T>(name: &'static str, f: &Fifo<T>) -> (&'static str, usize, FifoStats) {
            (name, f.depth(), f.stats())
        }
        let mut v = vec![
            s("raygen_to_sphere", &self.rg_sp),
            s("sphere_to_sorter", &self.sp_so),
            s("sorter_to_check", &self.so_ck),
            s("check_to_transform", &self.ck_tr),
            s("loop_back", &self.loop_back),
            s("transform_to_reciprocal", &self.tr_rc),
            s("reciprocal_to_root", &self.rc_rt),
            s("root_to_dispatch", &self.rt_dp),
            s("walker_to_record", &self.wk_rc),
            s("record_to_write", &self.rc_wr),
        ];
        if self.two_write_paths {
            v.push(s("check_to_write", &self.ck_wr));
        }
        v
    }
}

impl Commit for Fifos {
    /// The first FIFO's cycle; [`Commit::check`] checks every FIFO's.
    fn cycle(&self) -> u64 {
        self.rg_sp.cycle()
    }

    /// Every FIFO must be on cycle `now`; the first that is not is the error.
    fn check(&self, now: u64) -> Result<(), ClockError> {
        let f = self;
        f.rg_sp.check(now)?;
        f.sp_so.check(now)?;
        f.so_ck.check(now)?;
        f.ck_tr.check(now)?;
        f.loop_back.check(now)?;
        f.tr_rc.check(now)?;
        f.rc_rt.check(now)?;
        f.rt_dp.check(now)?;
        f.wk_rc.check(now)?;
        f.rc_wr.check(now)?;
        f.ck_wr.check(now)
    }

    /// Commits every FIFO (each by a direct, inlined call).
    fn commit(&mut self) {
        let f = self;
        f.rg_sp.commit();
        f.sp_so.commit();
        f.so_ck.commit();
        f.ck_tr.commit();
        f.loop_back.commit();
        f.tr_rc.commit();
        f.rc_rt.commit();
        f.rt_dp.commit();
        f.wk_rc.commit();
        f.rc_wr.commit();
        f.ck_wr.commit();
    }
}
