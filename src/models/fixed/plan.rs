//! One frame's prepared fixed-point datapath: the host's quantised per-instance data and the
//! per-pixel steps of the pipeline (sphere tests, sort, hit-buffer reuse, transform and walk,
//! early termination, record), as functions both models call.
//!
//! Pipeline position: the functional model (`frame.rs`) runs a pixel's steps back to back in
//! program order ([`FramePlan::pixel`]); the cycle model (`crate::models::cycle`) runs the same
//! steps in its stages, in cycle order with many rays in flight, under `cross_check`. One
//! implementation of each step means the cross-check tests the cycle model's ordering, state
//! and decisions, not a second copy of the arithmetic (which the unit tests and the f64 oracle
//! check). Whoever needs to see inside a pixel — the trace for the cycle model, the HDL-vector
//! capture — passes a [`PixelObserver`] to `pixel` rather than repeating its flow.

use super::frame::{FixedBuffer, FixedError, FixedRecord};
use super::trace::{NoPixelObserver, PixelObserver};
use crate::models::reference::cull::TileLists;
use crate::models::reference::hit_buffer::Dirty;
use crate::models::reference::ray::primary_ray;
use crate::models::reference::{FrameInput, RaySwitches, SphereCount};
use crate::world::assets::{Asset, AssetTree};
use glam::{DMat3, DVec3};
use rayon::prelude::*;
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use rtl_model::fixed::{from_f64, to_f64, Format, Overflows};
use rtl_model::svo::SvoImage;
use rtl_model::units::hit_record::{
    pack, quantise, reuse as hit_record_reuse, HitRecordF64, HitRecordFields, ReuseInputs,
};
use rtl_model::units::normal::{normal_code, NormalMatrix};
use rtl_model::units::raygen::direction_entry;
use rtl_model::units::reciprocal::ReciprocalUnit;
use rtl_model::units::sorter::{Sorter, SorterStats};
use rtl_model::units::sphere::{sphere_test, SphereRaw, SphereSignals};
use rtl_model::units::transform::{
    transform_direction, transform_origin, InstanceRaw, TransformSignals,
};
use rtl_model::units::walker::{
    walk_fixed_observed, WalkObserver, WalkOutcome, WalkerHit, WalkerInput, WalkerPos, WalkerStats,
    WalkerT,
};

/// What the host programs per instance and frame, as the datapath's units read it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostInstance {
    /// Rotation columns and centre (transform unit).
    pub raw: InstanceRaw,
    /// Bounding sphere (sphere unit).
    pub sphere: SphereRaw,
    /// Half extents of the octree's box (walker).
    pub half: [WalkerPos; 3],
    /// Normal matrix R·diag(1/scale), scaled and quantised (normal unit, record stage).
    pub nmat: NormalMatrix,
}

struct Inst<'a> {
    host: HostInstance,
    image: &'a SvoImage,
    world_from_local: DMat3,
    /// The transform unit's o' = Rᵀ(o − c) for the camera origin, which is every primary
    /// ray's: computed once per frame instead of once per walk. `None` when computing it
    /// saturated, so that each walk recomputes it and counts its saturations as before.
    o_local: Option<[i64; 3]>,
}

/// Counters a worker accumulates over its pixels.
#[derive(Clone, Debug)]
pub struct PixelCounters {
    /// Saturations and wraps.
    pub ov: Overflows,
    /// Walker counters.
    pub walker: WalkerStats,
    /// Sorter counters.
    pub sorter: SorterStats,
    /// Walks.
    pub walks: u64,
    /// Pixels reused.
    pub reused: u64,
    /// Sphere tests.
    pub tests: u64,
    /// Tests that culled.
    pub culled: u64,
    /// Candidates of traced rays.
    pub candidates: u64,
    /// Rays stopped early.
    pub early: u64,
    /// Pixels that hit.
    pub hits: u64,
    /// Reciprocal zero flushes.
    pub flushes: u64,
}

impl Default for PixelCounters {
    fn default() -> Self {
        Self {
            ov: overflow_table(),
            walker: WalkerStats::default(),
            sorter: SorterStats::default(),
            walks: 0,
            reused: 0,
            tests: 0,
            culled: 0,
            candidates: 0,
            early: 0,
            hits: 0,
            flushes: 0,
        }
    }
}

impl PixelCounters {
    /// Adds `o` into `self`.
    pub fn merge(&mut self, o: &Self) {
        self.ov.merge(&o.ov);
        self.walker.steps += o.walker.steps;
        self.walker.fetches += o.walker.fetches;
        self.walker.step_limit_hits += o.walker.step_limit_hits;
        self.walker.max_stack = self.walker.max_stack.max(o.walker.max_stack);
        self.sorter.merge(&o.sorter);
        self.walks += o.walks;
        self.reused += o.reused;
        self.tests += o.tests;
        self.culled += o.culled;
        self.candidates += o.candidates;
        self.early += o.early;
        self.hits += o.hits;
        self.flushes += o.flushes;
    }
}

/// The best hit of a ray so far: walker t, instance, the walker's hit and the direction signs.
pub type Best = (WalkerT, u16, WalkerHit, [bool; 3]);

/// A frame's prepared datapath (see the module doc).
pub struct FramePlan<'a> {
    cfg: &'a DatapathConfig,
    insts: Vec<Inst<'a>>,
    /// Dirty flags the host computed for this frame (all set without the hit buffer).
    pub dirty: Dirty,
    /// Whether reuse is allowed.
    pub use_hit_buffer: bool,
    /// Camera position (raw, `raygen.pos`); private because the instances' cached local
    /// origins were computed from it.
    origin: [i64; 3],
    sorter: Sorter,
    recip: ReciprocalUnit,
    /// A miss's record fields and word per sphere count (they depend on nothing else).
    miss: [(HitRecordFields, u128); 3],
    t_fmt: Format,
    key_fmt: Format,
    /// The two-level scheme's per-tile instance lists, when used (`super::cull`); `None`
    /// tests every instance (the flat scheme).
    pub lists: Option<TileLists>,
    /// Culling, sorting and early termination (all on unless [`FramePlan::with_switches`]).
    switches: RaySwitches,
}

/// The sort key of a candidate whose bounding sphere the ray misses (walked only without
/// culling): above every key the sorter's format can hold, so it is never taken for a pierced
/// sphere's, and early termination skips it once a hit is found (its entry is +∞).
pub const NOT_PIERCED: i64 = i64::MAX;

const SPHERE_SIG: SphereSignals = SphereSignals {
    tca: signals::SPHERE_TCA,
    sq: signals::SPHERE_SQ,
    t_enter: signals::SPHERE_T_ENTER,
    reach: signals::SPHERE_REACH,
};
const TR_SIG: TransformSignals = TransformSignals {
    origin: signals::TRANSFORM_ORIGIN,
    dir: signals::TRANSFORM_DIR,
};

impl<'a> FramePlan<'a> {
    /// Prepares a frame: quantises the instances and camera, computes the dirty flags against
    /// `buffer`'s previous frame (and records this one), and rewrites `buffer`'s direction table
    /// if the camera changed. Host saturations land in `host_ov`.
    pub fn new(
        input: &FrameInput<'a>,
        buffer: &mut FixedBuffer,
        cfg: &'a DatapathConfig,
        use_hit_buffer: bool,
        host_ov: &mut Overflows,
    ) -> Result<Self, FixedError> {
        cfg.validate().map_err(FixedError::Config)?;
        let (w, h) = input.scene.file.resolution;
        let rg = cfg.raygen;
        let mut insts: Vec<Inst<'a>> = input
            .state
            .poses
            .iter()
            .zip(&input.scene.instance_asset)
            .map(|(pose, &ai)| {
                let asset: &'a Asset = &input.assets[ai];
                let AssetTree::Image(image) = &asset.tree else {
                    return Err(FixedError::Implicit(asset.name.clone()));
                };
                let r = pose.world_from_local;
                let q = |v: DVec3, f, ov: &mut Overflows, s| {
                    v.to_array().map(|x| from_f64(x, f, ov, s))
                };
                let centre = q(pose.centre, rg.pos, host_ov, signals::RAYGEN_POS);
                let scale = pose.half_extent / asset.half_size;
                Ok(Inst {
                    host: HostInstance {
                        raw: InstanceRaw {
                            axes: [r.x_axis, r.y_axis, r.z_axis]
                                .map(|c| q(c, rg.mat, host_ov, signals::RAYGEN_MAT)),
                            centre,
                        },
                        sphere: SphereRaw::new(centre, pose.sphere_radius(), &cfg.sphere),
                        half: WalkerPos::of(q(
                            pose.half_extent,
                            cfg.walker.pos,
                            host_ov,
                            signals::RAYGEN_POS,
                        )),
                        // Row-major (glam's matrices are column-major: transpose).
                        nmat: NormalMatrix::quantise(
                            (r * DMat3::from_diagonal(scale.recip()))
                                .transpose()
                                .to_cols_array_2d(),
                        ),
                    },
                    image,
                    world_from_local: r,
                    o_local: None,
                })
            })
            .collect::<Result<_, _>>()?;
        let dirty = if use_hit_buffer {
            Dirty::between(buffer.prev.as_ref(), input.state)
        } else {
            Dirty {
                camera: true,
                instances: vec![true; insts.len()],
            }
        };
        buffer.prev = Some(input.state.clone());
        let cam = input.state.camera;
        let origin = cam
            .position
            .to_array()
            .map(|x| from_f64(x, rg.pos, host_ov, signals::RAYGEN_POS));
        // Per-instance constants of the datapath (model speed-up, same results): the local
        // origin, kept only if it computes without a saturation (the per-walk counts stay).
        for inst in &mut insts {
            let mut scratch = overflow_table();
            let o_local = transform_origin(
                origin,
                &inst.host.raw,
                &cfg.transform,
                &mut scratch,
                TR_SIG.origin,
            );
            inst.o_local = (scratch.total() == 0).then_some(o_local);
        }
        // A miss's record depends only on the sphere count: pack the three words once.
        let miss = [SphereCount::None, SphereCount::One, SphereCount::Several].map(|kind| {
            let f = quantise(
                &HitRecordF64 {
                    kind,
                    instance: None,
                    t: f64::INFINITY,
                    normal: [0.0; 3],
                    colour: [0; 3],
                    voxel: [0; 3],
                },
                &cfg.hit_record,
                host_ov,
                signals::HIT_RECORD,
            );
            (f, pack(&f, &cfg.hit_record, host_ov, signals::HIT_RECORD))
        });
        if buffer.table_camera != Some(cam) || buffer.dir_table.len() != buffer.records.len() {
            // The host writes the direction table: f64 rays quantised into `raygen.dir`.
            let parts: Vec<(Vec<[i64; 3]>, Overflows)> = (0..h)
                .into_par_iter()
                .map(|j| {
                    let mut ov = overflow_table();
                    let row = (0..w)
                        .map(|i| {
                            let ray = primary_ray(&cam, w, h, i, j);
                            direction_entry(ray.dir.to_array(), &rg, &mut ov, signals::RAYGEN_DIR)
                        })
                        .collect();
                    (row, ov)
                })
                .collect();
            buffer.dir_table.clear();
            for (row, ov) in parts {
                buffer.dir_table.extend(row);
                host_ov.merge(&ov);
            }
            buffer.table_camera = Some(cam);
        }
        Ok(Self {
            cfg,
            insts,
            dirty,
            use_hit_buffer,
            origin,
            sorter: Sorter::new(&cfg.sorter),
            recip: ReciprocalUnit::new(&cfg.reciprocal),
            miss,
            t_fmt: cfg.walker.t,
            key_fmt: cfg.sorter.key,
            lists: None,
            switches: RaySwitches::default(),
        })
    }

    /// Camera position (raw, `raygen.pos`): every primary ray's origin.
    pub fn origin(&self) -> [i64; 3] {
        self.origin
    }

    /// The plan with culling, sorting and early termination as `s` says.
    pub fn with_switches(mut self, s: RaySwitches) -> Self {
        self.switches = s;
        self
    }

    /// Culling, sorting and early termination of this plan.
    pub fn switches(&self) -> RaySwitches {
        self.switches
    }

    /// The spheres a walk list's ray pierced (its entries with a key): the record's "nature
    /// of the hit".
    pub fn sphere_count(cands: &[(i64, u16)]) -> SphereCount {
        SphereCount::from_count(cands.iter().filter(|c| c.0 != NOT_PIERCED).count())
    }

    /// Instances in the frame.
    pub fn instances(&self) -> usize {
        self.insts.len()
    }

    /// The memory image instance `k` walks.
    pub fn image(&self, k: u16) -> Option<&'a SvoImage> {
        self.insts.get(usize::from(k)).map(|i| i.image)
    }

    /// What the host programmed for instance `k`.
    pub fn host_instance(&self, k: u16) -> Option<&HostInstance> {
        self.insts.get(usize::from(k)).map(|i| &i.host)
    }

    /// The datapath configuration.
    pub fn config(&self) -> &DatapathConfig {
        self.cfg
    }

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
        let mut test = |k: u16, inst: &Inst<'_>| {
            let sphere = &inst.host.sphere;
            let hit = sphere_test(
                self.origin,
                d,
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
