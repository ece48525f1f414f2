//! One frame's prepared fixed-point datapath: the host's quantised per-instance data and the
//! per-pixel steps of the pipeline (sphere tests, sort, hit-buffer reuse, transform and walk,
//! early termination, record), as functions both models call.
//!
//! Pipeline position: the functional model (`frame.rs`) runs a pixel's steps back to back in
//! program order; the cycle model (`crate::models::cycle`) runs the same steps in its stages, in
//! cycle order with many rays in flight, under `cross_check`. One implementation of each step
//! means the cross-check tests the cycle model's ordering, state and decisions, not a second
//! copy of the arithmetic (which the unit tests and the f64 oracle check).

use super::frame::{FixedBuffer, FixedError, FixedRecord};
use super::trace::{OpRecorder, PixelWork, RowTrace, WalkWork};
use crate::models::reference::hit_buffer::Dirty;
use crate::models::reference::ray::primary_ray;
use crate::models::reference::{FrameInput, SphereCount};
use crate::world::assets::{Asset, AssetTree};
use glam::{DMat3, DVec3};
use rayon::prelude::*;
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use rtl_model::fixed::{from_f64, to_f64, Format, Overflows};
use rtl_model::svo::SvoImage;
use rtl_model::units::hit_record::{pack, quantise, unpack, HitRecordF64};
use rtl_model::units::raygen::direction_entry;
use rtl_model::units::reciprocal::ReciprocalUnit;
use rtl_model::units::sorter::{Sorter, SorterStats};
use rtl_model::units::sphere::{sphere_test, SphereRaw, SphereSignals};
use rtl_model::units::transform::{transform_with_signs, InstanceRaw, TransformSignals};
use rtl_model::units::walker::{
    walk_fixed_observed, NoObserver, WalkObserver, WalkOutcome, WalkerHit, WalkerInput, WalkerStats,
};

struct Inst<'a> {
    raw: InstanceRaw,
    sphere: SphereRaw,
    half: [i64; 3],
    image: &'a SvoImage,
    world_from_local: DMat3,
    normal_to_world: DMat3,
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
pub type Best = (i64, u16, WalkerHit, [bool; 3]);

/// A frame's prepared datapath (see the module doc).
pub struct FramePlan<'a> {
    cfg: &'a DatapathConfig,
    insts: Vec<Inst<'a>>,
    /// Dirty flags the host computed for this frame (all set without the hit buffer).
    pub dirty: Dirty,
    /// Whether reuse is allowed.
    pub use_hit_buffer: bool,
    /// Camera position (raw, `raygen.pos`).
    pub origin: [i64; 3],
    sorter: Sorter,
    recip: ReciprocalUnit,
    miss_words: [u128; 3],
    t_fmt: Format,
    key_fmt: Format,
}

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
        let insts: Vec<Inst<'a>> = input
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
                    raw: InstanceRaw {
                        axes: [r.x_axis, r.y_axis, r.z_axis]
                            .map(|c| q(c, rg.mat, host_ov, signals::RAYGEN_MAT)),
                        centre,
                    },
                    sphere: SphereRaw::new(centre, pose.sphere_radius(), &cfg.sphere),
                    half: q(
                        pose.half_extent,
                        cfg.walker.pos,
                        host_ov,
                        signals::RAYGEN_POS,
                    ),
                    image,
                    world_from_local: r,
                    normal_to_world: r * DMat3::from_diagonal(scale.recip()),
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
        // A miss's record depends only on the sphere count: pack the three words once.
        let miss_words = [SphereCount::None, SphereCount::One, SphereCount::Several].map(|kind| {
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
            pack(&f, &cfg.hit_record, host_ov, signals::HIT_RECORD)
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
            miss_words,
            t_fmt: cfg.walker.t,
            key_fmt: cfg.sorter.key,
        })
    }

    /// Instances in the frame.
    pub fn instances(&self) -> usize {
        self.insts.len()
    }

    /// The memory image instance `k` walks.
    pub fn image(&self, k: u16) -> Option<&'a SvoImage> {
        self.insts.get(usize::from(k)).map(|i| i.image)
    }

    /// The datapath configuration.
    pub fn config(&self) -> &DatapathConfig {
        self.cfg
    }

    /// Sphere tests of direction `d` against every instance: the candidates (entry key,
    /// instance) in instance order, unsorted.
    pub fn candidates(&self, d: [i64; 3], out: &mut Vec<(i64, u16)>, c: &mut PixelCounters) {
        out.clear();
        for (k, inst) in self.insts.iter().enumerate() {
            if let Some(s) = sphere_test(
                self.origin,
                d,
                &inst.sphere,
                &self.cfg.sphere,
                &mut c.ov,
                SPHERE_SIG,
            ) {
                out.push((s.t_enter, k as u16));
            }
        }
        c.tests += self.insts.len() as u64;
        c.culled += (self.insts.len() - out.len()) as u64;
    }

    /// The sorter: candidates front to back.
    pub fn sort(&self, cands: &mut Vec<(i64, u16)>, c: &mut PixelCounters) {
        self.sorter.sort_in_place(cands, &mut c.sorter);
    }

    /// The hit-buffer rule: the refreshed word if `prev` (the buffer's word) can be reused for
    /// a ray with these candidates, `None` if the ray must be traced.
    pub fn reuse(&self, prev: u128, cands: &[(i64, u16)], c: &mut PixelCounters) -> Option<u128> {
        if !self.use_hit_buffer || self.dirty.camera || cands.len() != 1 {
            return None;
        }
        let k = cands[0].1;
        let old = unpack(prev, &self.cfg.hit_record);
        if self.dirty.instances[usize::from(k)]
            || !(old.instance.is_none() || old.instance == Some(k))
        {
            return None;
        }
        // Refresh the sphere count from this frame's tests, as the reference does.
        let mut f = old;
        f.kind = SphereCount::from_count(cands.len());
        Some(pack(
            &f,
            &self.cfg.hit_record,
            &mut c.ov,
            signals::HIT_RECORD,
        ))
    }

    /// Early termination: whether the best hit so far (walker t) is no farther than the next
    /// candidate's entry key.
    pub fn stops(&self, best_t: i64, key: i64) -> bool {
        let (k, t) = (self.key_fmt.frac, self.t_fmt.frac);
        let lhs = i128::from(best_t) << (k.max(t) - t);
        let rhs = i128::from(key) << (k.max(t) - k);
        lhs <= rhs
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
        let (o_local, d_local, signs) = transform_with_signs(
            self.origin,
            d,
            &inst.raw,
            &self.cfg.transform,
            &mut c.ov,
            TR_SIG,
        );
        let mut inp = WalkerInput {
            origin: o_local,
            half: inst.half,
            ..WalkerInput::default()
        };
        for a in 0..3 {
            let r = self
                .recip
                .eval(d_local[a], signs[a], &mut c.ov, signals::RECIPROCAL);
            inp.inv[a] = r.raw.saturating_abs();
            c.flushes += u64::from(r.flushed);
            inp.zero[a] = r.zero;
            inp.negative[a] = r.negative;
        }
        c.walks += 1;
        let out = walk_fixed_observed(
            inst.image,
            &inp,
            &self.cfg.walker,
            &mut c.ov,
            signals::WALKER_T,
            &mut c.walker,
            obs,
        );
        if out == WalkOutcome::StepLimit {
            c.ov.hit(signals::WALKER_STEP_LIMIT);
        }
        (out, signs)
    }

    /// The record of a traced ray: its best hit, or the miss word for its sphere count.
    pub fn finish(
        &self,
        best: Option<Best>,
        spheres: SphereCount,
        c: &mut PixelCounters,
    ) -> FixedRecord {
        let Some((t, k, hit, signs)) = best else {
            return FixedRecord {
                word: self.miss_words[usize::from(spheres.code())],
                ..FixedRecord::default()
            };
        };
        c.hits += 1;
        let inst = &self.insts[usize::from(k)];
        let attr = inst.image.attrs()[hit.attr as usize];
        let n = (inst.normal_to_world * DVec3::from_array(attr.normal())).normalize_or_zero();
        let [r, g, b, _] = attr.rgba();
        let f = quantise(
            &HitRecordF64 {
                kind: spheres,
                instance: Some(k),
                t: to_f64(t, self.t_fmt),
                normal: n.to_array(),
                colour: [r, g, b],
                voxel: hit.voxel,
            },
            &self.cfg.hit_record,
            &mut c.ov,
            signals::HIT_RECORD,
        );
        let mut local = [0.0; 3];
        let axis = usize::from(hit.entry_axis);
        local[axis] = if signs[axis] { 1.0 } else { -1.0 };
        let face = (inst.world_from_local * DVec3::from_array(local))
            .to_array()
            .map(|v| (v * 127.0).round() as i8);
        FixedRecord {
            word: pack(&f, &self.cfg.hit_record, &mut c.ov, signals::HIT_RECORD),
            hit: true,
            t_raw: t,
            voxel: hit.voxel,
            face,
        }
    }

    /// One pixel in program order: the functional model's whole pipeline for direction `d`,
    /// updating `rec` (the buffer's entry) and, if given, recording the work in `trace`.
    pub fn pixel(
        &self,
        d: [i64; 3],
        rec: &mut FixedRecord,
        c: &mut PixelCounters,
        cands: &mut Vec<(i64, u16)>,
        mut trace: Option<&mut RowTrace>,
    ) {
        self.candidates(d, cands, c);
        let spheres = SphereCount::from_count(cands.len());
        self.sort(cands, c);
        let mut work = PixelWork::default();
        if let Some(t) = trace.as_deref_mut() {
            work.cand_start = t.candidates.len() as u32;
            work.cand_len = cands.len().min(usize::from(u16::MAX)) as u16;
            work.walk_start = t.walks.len() as u32;
            t.candidates.extend_from_slice(cands);
        }
        if let Some(word) = self.reuse(rec.word, cands, c) {
            rec.word = word;
            c.reused += 1;
            c.hits += u64::from(rec.hit);
            if let Some(t) = trace {
                work.reused = true;
                t.pixels.push(work);
            }
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
            let (out, signs) = match trace.as_deref_mut() {
                None => self.walk(d, k, c, &mut NoObserver),
                Some(t) => {
                    let op_start = t.ops.len() as u32;
                    let mut rec_ops = OpRecorder::new(&mut t.ops);
                    let r = self.walk(d, k, c, &mut rec_ops);
                    rec_ops.finish();
                    let hit_t = match r.0 {
                        WalkOutcome::Hit(h) => Some(h.t),
                        _ => None,
                    };
                    let op_len = t.ops.len() as u32 - op_start;
                    t.walks.push(WalkWork {
                        hit_t,
                        op_start,
                        op_len,
                    });
                    work.walk_len += 1;
                    r
                }
            };
            if let WalkOutcome::Hit(hit) = out {
                if best.is_none_or(|(bt, _, _, _)| hit.t < bt) {
                    best = Some((hit.t, k, hit, signs));
                }
            }
        }
        *rec = self.finish(best, spheres, c);
        if let Some(t) = trace {
            t.pixels.push(work);
        }
    }
}
