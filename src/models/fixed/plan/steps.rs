//! The per-pixel steps of a prepared frame, in pipeline order: sphere tests (per tile with the
//! two-level lists), sort or order, hit-buffer reuse, the walk input (transform and
//! reciprocals) and the walk, early termination, and the record; and [`FramePlan::pixel`],
//! which runs them back to back.
//!
//! Pipeline position: called per pixel by the functional model (`pixel`, program order) and
//! per stage by the cycle model (in cycle order, under `cross_check`); each step reports to a
//! [`PixelObserver`].

use super::super::frame::FixedRecord;
use super::super::trace::{NoPixelObserver, PixelObserver};
use super::{Best, FramePlan, Inst, PixelCounters, NOT_PIERCED, SPHERE_SIG, TR_SIG};
use crate::models::reference::SphereCount;
use glam::DVec3;
use rtl_model::datapath::signals;
use rtl_model::fixed::to_f64;
use rtl_model::units::hit_record::{
    pack, quantise, reuse as hit_record_reuse, HitRecordF64, ReuseInputs,
};
use rtl_model::units::normal::normal_code;
use rtl_model::units::sphere::{sphere_test_prepared, SphereRay};
use rtl_model::units::transform::{transform_direction, transform_origin};
use rtl_model::units::walker::{
    walk_fixed_observed, WalkObserver, WalkOutcome, WalkerInput, WalkerPos, WalkerT,
};

impl<'a> FramePlan<'a> {
    /// Sphere tests of direction `d` against every instance: the candidates (entry key,
    /// instance) in instance order, unsorted.
    pub fn candidates(&self, d: [i64; 3], out: &mut Vec<(i64, u16)>, c: &mut PixelCounters) {
        self.candidates_observed(None, d, out, c, &mut NoPixelObserver);
    }

    /// [`FramePlan::candidates`], reporting each test to `obs`.
    /// With `pixel` given and the two-level lists present, only that pixel's tile's instances
    /// (ascending, so the candidates come out in the same order as from every instance).
    fn candidates_observed<P: PixelObserver>(
        &self,
        pixel: Option<u32>,
        d: [i64; 3],
        out: &mut Vec<(i64, u16)>,
        c: &mut PixelCounters,
        obs: &mut P,
    ) {
        out.clear();
        let listed = match (&self.lists, pixel) {
            (Some(l), Some(p)) => Some(l.list(p)),
            _ => None,
        };
        let tested = listed.map_or(self.insts.len(), <[u16]>::len);
        let ray = SphereRay::new(d);
        let mut test = |k: u16, inst: &Inst<'_>| {
            let sphere = &inst.host.sphere;
            let hit = sphere_test_prepared(
                &inst.sphere_origin,
                &ray,
                sphere,
                &self.cfg.sphere,
                &mut c.ov,
                SPHERE_SIG,
            );
            obs.on_sphere(k, self.origin, d, sphere, hit);
            if let Some(s) = hit {
                out.push((s.t_enter, k));
            }
        };
        match listed {
            Some(l) => {
                for &k in l {
                    test(k, &self.insts[usize::from(k)]);
                }
            }
            None => {
                for (k, inst) in self.insts.iter().enumerate() {
                    test(k as u16, inst);
                }
            }
        }
        c.tests += tested as u64;
        c.culled += (tested - out.len()) as u64;
    }

    /// The sorter: candidates front to back.
    pub fn sort(&self, cands: &mut Vec<(i64, u16)>, c: &mut PixelCounters) {
        self.sorter.sort_in_place(cands, &mut c.sorter);
    }

    /// The pierced candidates (instance order, as the sphere tests list them) made into the
    /// walk list the switches ask for: sorted front to back (or left in instance order), then
    /// without culling every other instance added with key [`NOT_PIERCED`] — after the sorted
    /// ones, or in its place in instance order when unsorted.
    pub fn order(&self, cands: &mut Vec<(i64, u16)>, c: &mut PixelCounters) {
        let s = self.switches;
        if s.sort {
            self.sort(cands, c);
        }
        let n = self.insts.len();
        if s.culling || cands.len() >= n {
            return;
        }
        if s.sort {
            let pierced: Vec<u16> = cands.iter().map(|c| c.1).collect();
            cands.extend(
                (0..n as u16)
                    .filter(|i| !pierced.contains(i))
                    .map(|i| (NOT_PIERCED, i)),
            );
        } else {
            let mut all = vec![(NOT_PIERCED, 0u16); n];
            for (i, a) in all.iter_mut().enumerate() {
                a.1 = i as u16;
            }
            for &(key, i) in cands.iter() {
                all[usize::from(i)].0 = key;
            }
            *cands = all;
        }
    }

    /// The walk list of direction `d` against every instance: sphere tests, then
    /// [`FramePlan::order`] (what the cycle model's cross-check recomputes).
    pub fn walk_list(&self, d: [i64; 3], out: &mut Vec<(i64, u16)>, c: &mut PixelCounters) {
        self.candidates(d, out, c);
        self.order(out, c);
    }

    /// The hit-buffer rule: the refreshed word if `prev` (the buffer's word) can be reused for
    /// a ray with these candidates, `None` if the ray must be traced.
    /// `cands` is the ray's walk list: only its pierced entries count (without culling it
    /// lists every instance).
    pub fn reuse(&self, prev: u128, cands: &[(i64, u16)], c: &mut PixelCounters) -> Option<u128> {
        let mut pierced = cands.iter().filter(|c| c.0 != NOT_PIERCED);
        let (first, count) = match pierced.next() {
            Some(f) => (Some(f), 1 + pierced.count()),
            None => (None, 0),
        };
        let (candidate, instance_dirty) = match (first, count) {
            // An instance the frame does not know is treated as moved: never reused.
            (Some((_, k)), 1) => (
                *k,
                self.dirty
                    .instances
                    .get(usize::from(*k))
                    .copied()
                    .unwrap_or(true),
            ),
            _ => (0, false),
        };
        let inp = ReuseInputs {
            buffer: self.use_hit_buffer,
            camera_dirty: self.dirty.camera,
            candidates: count,
            candidate,
            instance_dirty,
        };
        hit_record_reuse(
            prev,
            &inp,
            &self.cfg.hit_record,
            &mut c.ov,
            signals::HIT_RECORD,
        )
    }

    /// Early termination: whether the best hit so far (walker t) is no farther than the next
    /// candidate's entry key. Never without early termination or without sorting (no order
    /// puts the remaining candidates behind the best hit).
    pub fn stops(&self, best_t: WalkerT, key: i64) -> bool {
        self.switches.terminates() && best_t.at_most(self.t_fmt, key, self.key_fmt)
    }

    /// Transform, reciprocals and walk of direction `d` in instance `k`, reporting the walk to
    /// `obs`. Returns the outcome and the transformed direction's signs.
    pub fn walk<O: WalkObserver>(
        &self,
        d: [i64; 3],
        k: u16,
        c: &mut PixelCounters,
        obs: &mut O,
    ) -> (WalkOutcome, [bool; 3]) {
        let Some(inst) = self.insts.get(usize::from(k)) else {
            return (WalkOutcome::Miss, [false; 3]);
        };
        let (inp, signs) = self.walk_input(d, k, inst, c, &mut NoPixelObserver);
        (self.run_walk(inst, &inp, c, obs), signs)
    }

    /// The transform and the three reciprocals of direction `d` for instance `k` (`inst`),
    /// reported to `obs`: the walker's inputs and the local direction's signs.
    #[inline]
    fn walk_input<P: PixelObserver>(
        &self,
        d: [i64; 3],
        k: u16,
        inst: &Inst<'_>,
        c: &mut PixelCounters,
        obs: &mut P,
    ) -> (WalkerInput, [bool; 3]) {
        obs.on_transform(k, self.origin, d, &inst.host.raw);
        let o_local = match inst.o_local {
            Some(o) => o,
            None => transform_origin(
                self.origin,
                &inst.host.raw,
                &self.cfg.transform,
                &mut c.ov,
                TR_SIG.origin,
            ),
        };
        let (d_local, signs) = transform_direction(
            d,
            &inst.host.raw,
            &self.cfg.transform,
            &mut c.ov,
            TR_SIG.dir,
        );
        let mut inp = WalkerInput {
            origin: WalkerPos::of(o_local),
            half: inst.host.half,
            ..WalkerInput::default()
        };
        for a in 0..3 {
            obs.on_reciprocal(d_local[a], signs[a]);
            let r = self
                .recip
                .eval(d_local[a], signs[a], &mut c.ov, signals::RECIPROCAL);
            inp.set_axis(a, &r);
            c.flushes += u64::from(r.flushed);
        }
        (inp, signs)
    }

    /// The walker on `inst`'s image with inputs `inp`, reporting to `obs`.
    #[inline]
    fn run_walk<O: WalkObserver>(
        &self,
        inst: &Inst<'_>,
        inp: &WalkerInput,
        c: &mut PixelCounters,
        obs: &mut O,
    ) -> WalkOutcome {
        c.walks += 1;
        let out = walk_fixed_observed(
            inst.image,
            inp,
            &self.cfg.walker,
            &mut c.ov,
            signals::WALKER_T,
            &mut c.walker,
            obs,
        );
        if out == WalkOutcome::StepLimit {
            c.ov.hit(signals::WALKER_STEP_LIMIT);
        }
        out
    }

    /// The record of a traced ray: its best hit, or the miss word for its sphere count.
    pub fn finish(
        &self,
        best: Option<Best>,
        spheres: SphereCount,
        c: &mut PixelCounters,
    ) -> FixedRecord {
        self.finish_observed(best, spheres, c, &mut NoPixelObserver)
    }

    /// [`FramePlan::finish`], reporting the record's fields and word to `obs`.
    fn finish_observed<P: PixelObserver>(
        &self,
        best: Option<Best>,
        spheres: SphereCount,
        c: &mut PixelCounters,
        obs: &mut P,
    ) -> FixedRecord {
        let Some((t, k, hit, signs)) = best else {
            let (fields, word) = &self.miss[usize::from(spheres.code())];
            obs.on_record(fields, *word);
            return FixedRecord {
                word: *word,
                ..FixedRecord::default()
            };
        };
        c.hits += 1;
        let inst = &self.insts[usize::from(k)];
        let attr = inst.image.attrs()[hit.attr as usize];
        let [r, g, b, _] = attr.rgba();
        let mut f = quantise(
            &HitRecordF64 {
                kind: spheres,
                instance: Some(k),
                t: to_f64(t.raw, self.t_fmt), // the host's f64 path, as the reference's
                normal: [0.0; 3],             // the normal unit's code replaces it below
                colour: [r, g, b],
                voxel: hit.voxel,
            },
            &self.cfg.hit_record,
            &mut c.ov,
            signals::HIT_RECORD,
        );
        // The record stage's normal unit: fixed point, no host (docs/units/normal.md).
        obs.on_normal(attr.normal_oct16, &inst.host.nmat);
        f.normal = normal_code(
            attr.normal_oct16,
            &inst.host.nmat,
            self.cfg.hit_record.normal_bits,
        );
        let mut local = [0.0; 3];
        let axis = usize::from(hit.entry_axis);
        local[axis] = if signs[axis] { 1.0 } else { -1.0 };
        let face = (inst.world_from_local * DVec3::from_array(local))
            .to_array()
            .map(|v| (v * 127.0).round() as i8);
        let word = pack(&f, &self.cfg.hit_record, &mut c.ov, signals::HIT_RECORD);
        obs.on_record(&f, word);
        FixedRecord {
            word,
            hit: true,
            t: hit.t,
            voxel: hit.voxel,
            face,
        }
    }

    /// One pixel in program order: the functional model's whole pipeline for direction `d`,
    /// updating `rec` (the buffer's entry), every step reported to `obs`.
    pub fn pixel<P: PixelObserver>(
        &self,
        d: [i64; 3],
        rec: &mut FixedRecord,
        c: &mut PixelCounters,
        cands: &mut Vec<(i64, u16)>,
        obs: &mut P,
    ) {
        self.pixel_at(None, d, rec, c, cands, obs);
    }

    /// [`FramePlan::pixel`] for pixel `p` (raster order), whose tile's list selects the
    /// sphere tests when the two-level lists are present.
    pub fn pixel_at<P: PixelObserver>(
        &self,
        p: Option<u32>,
        d: [i64; 3],
        rec: &mut FixedRecord,
        c: &mut PixelCounters,
        cands: &mut Vec<(i64, u16)>,
        obs: &mut P,
    ) {
        self.candidates_observed(p, d, cands, c, obs);
        let spheres = SphereCount::from_count(cands.len());
        obs.on_candidates(cands);
        self.order(cands, c);
        obs.on_sorted(cands);
        if let Some(word) = self.reuse(rec.word, cands, c) {
            rec.word = word;
            c.reused += 1;
            c.hits += u64::from(rec.hit);
            obs.on_reuse(word);
            obs.on_pixel_end(rec);
            return;
        }
        c.candidates += cands.len() as u64;
        let mut best: Option<Best> = None;
        for &(key, k) in cands.iter() {
            if let Some((bt, _, _, _)) = best {
                if self.stops(bt, key) {
                    c.early += 1;
                    break;
                }
            }
            // Candidates come from this plan's instances, so `k` is one of them.
            let inst = &self.insts[usize::from(k)];
            let (inp, signs) = self.walk_input(d, k, inst, c, obs);
            let mut w = obs.begin_walk(k, &inp);
            let out = self.run_walk(inst, &inp, c, &mut w);
            P::end_walk(w);
            obs.on_walk(k, &out);
            if let WalkOutcome::Hit(hit) = out {
                if best.is_none_or(|(bt, _, _, _)| hit.t < bt) {
                    best = Some((hit.t, k, hit, signs));
                }
            }
        }
        *rec = self.finish_observed(best, spheres, c, obs);
        obs.on_pixel_end(rec);
    }
}
