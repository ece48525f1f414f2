//! One frame of the functional fixed-point model.

use crate::assets::{Asset, AssetTree};
use crate::reference::hit_buffer::Dirty;
use crate::reference::ray::primary_ray;
use crate::reference::{FrameInput, HitRecord, SphereCount};
use crate::scene::FrameState;
use glam::{DMat3, DVec3};
use rayon::prelude::*;
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use rtl_model::fixed::{from_f64, to_f64, Overflows};
use rtl_model::svo::SvoImage;
use rtl_model::units::hit_record::{pack, quantise, unpack, HitRecordF64};
use rtl_model::units::raygen::direction_entry;
use rtl_model::units::reciprocal::ReciprocalUnit;
use rtl_model::units::sorter::{Sorter, SorterStats};
use rtl_model::units::sphere::{sphere_test, SphereRaw, SphereSignals};
use rtl_model::units::transform::{transform_with_signs, InstanceRaw, TransformSignals};
use rtl_model::units::walker::{walk_fixed, WalkOutcome, WalkerInput, WalkerStats};
use std::time::Instant;
use thiserror::Error;

/// Why a frame cannot run on the fixed-point model.
#[derive(Debug, Error)]
pub enum FixedError {
    /// The datapath configuration is inconsistent.
    #[error("datapath configuration: {0}")]
    Config(String),
    /// An asset has no memory image (walked implicitly), which the hardware cannot read.
    #[error("asset \"{0}\" has no memory image (it is walked implicitly from its SDF); the fixed-point model needs a materialised octree: use a smaller --depth")]
    Implicit(String),
}

/// A hit-buffer entry: the packed BRAM word the hardware keeps, plus instrumentation the
/// model keeps beside it for accuracy checks (not hardware state).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FixedRecord {
    /// The packed record (`rtl_model::units::hit_record` layout).
    pub word: u128,
    /// Hit.
    pub hit: bool,
    /// Walker t (raw, walker t format) of the hit.
    pub t_raw: i64,
    /// Leaf coordinates of the hit.
    pub voxel: [u32; 3],
    /// Entry face in world space, rounded to axes ×127 (for dumps).
    pub face: [i8; 3],
}

/// The fixed-point model's hit buffer across frames.
pub struct FixedBuffer {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// One entry per pixel.
    pub records: Vec<FixedRecord>,
    prev: Option<FrameState>,
    /// The per-pixel direction table (raw codes) and the camera it was written for: the host
    /// rewrites it only when the camera changes.
    dir_table: Vec<[i64; 3]>,
    table_camera: Option<crate::scene::Camera>,
}

impl FixedBuffer {
    /// Empty: the first frame traces every pixel.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            records: vec![FixedRecord::default(); width as usize * height as usize],
            prev: None,
            dir_table: Vec::new(),
            table_camera: None,
        }
    }
}

/// Counters of a fixed-point frame.
#[derive(Clone, Debug, Default)]
pub struct FixedStats {
    /// Rays.
    pub rays: u64,
    /// Ray–sphere tests.
    pub sphere_tests: u64,
    /// Tests that culled.
    pub spheres_culled: u64,
    /// Candidates of traced (not reused) rays.
    pub candidates: u64,
    /// Rays that stopped with candidates left.
    pub early_terminations: u64,
    /// Pixels that hit.
    pub hits: u64,
    /// Walks.
    pub walks: u64,
    /// Direction components flushed to zero by the reciprocal unit (§3.3 approximation).
    pub zero_flushes: u64,
    /// Pixels reused from the hit buffer.
    pub hit_buffer_reused: u64,
    /// Walker counters.
    pub walker: WalkerStats,
    /// Sorter counters.
    pub sorter: SorterStats,
    /// Saturations and wraps per signal.
    pub overflows: Option<Overflows>,
    /// Wall time, seconds.
    pub wall_s: f64,
}

struct Inst<'a> {
    raw: InstanceRaw,
    sphere: SphereRaw,
    half: [i64; 3],
    image: &'a SvoImage,
    world_from_local: DMat3,
    normal_to_world: DMat3,
}

struct Row {
    ov: Overflows,
    walker: WalkerStats,
    sorter: SorterStats,
    walks: u64,
    reused: u64,
    tests: u64,
    culled: u64,
    candidates: u64,
    early: u64,
    hits: u64,
    flushes: u64,
}

/// Renders one frame through the fixed-point units into `buffer`.
pub fn render_frame_fixed(
    input: &FrameInput<'_>,
    buffer: &mut FixedBuffer,
    cfg: &DatapathConfig,
    use_hit_buffer: bool,
) -> Result<FixedStats, FixedError> {
    cfg.validate().map_err(FixedError::Config)?;
    let start = Instant::now();
    let (w, h) = input.scene.file.resolution;
    let mut host_ov = overflow_table();
    let rg = cfg.raygen;
    let insts: Vec<Inst<'_>> = input
        .state
        .poses
        .iter()
        .zip(&input.scene.instance_asset)
        .map(|(pose, &ai)| {
            let asset: &Asset = &input.assets[ai];
            let AssetTree::Image(image) = &asset.tree else {
                return Err(FixedError::Implicit(asset.name.clone()));
            };
            let r = pose.world_from_local;
            let q =
                |v: DVec3, f, ov: &mut Overflows, s| v.to_array().map(|x| from_f64(x, f, ov, s));
            let centre = q(pose.centre, rg.pos, &mut host_ov, signals::RAYGEN_POS);
            let scale = pose.half_extent / asset.half_size;
            Ok(Inst {
                raw: InstanceRaw {
                    axes: [r.x_axis, r.y_axis, r.z_axis]
                        .map(|c| q(c, rg.mat, &mut host_ov, signals::RAYGEN_MAT)),
                    centre,
                },
                sphere: SphereRaw::new(centre, pose.sphere_radius(), &cfg.sphere),
                half: q(
                    pose.half_extent,
                    cfg.walker.pos,
                    &mut host_ov,
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
        .map(|x| from_f64(x, rg.pos, &mut host_ov, signals::RAYGEN_POS));
    let sphere_sig = SphereSignals {
        tca: signals::SPHERE_TCA,
        sq: signals::SPHERE_SQ,
        t_enter: signals::SPHERE_T_ENTER,
        reach: signals::SPHERE_REACH,
    };
    let tr_sig = TransformSignals {
        origin: signals::TRANSFORM_ORIGIN,
        dir: signals::TRANSFORM_DIR,
    };
    let sorter = Sorter::new(&cfg.sorter);
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
            &mut host_ov,
            signals::HIT_RECORD,
        );
        pack(&f, &cfg.hit_record, &mut host_ov, signals::HIT_RECORD)
    });
    let recip = ReciprocalUnit::new(&cfg.reciprocal);
    let t_fmt = cfg.walker.t;
    let key_fmt = cfg.sorter.key;
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
    let table = &buffer.dir_table;
    let rows: Vec<Row> = buffer
        .records
        .par_chunks_mut(w as usize)
        .enumerate()
        .map(|(j, records)| {
            let mut row = Row {
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
            };
            let mut cands: Vec<(i64, u16)> = Vec::with_capacity(insts.len());
            for (i, rec) in records.iter_mut().enumerate() {
                // Ray generation: the pixel's direction table entry.
                let d = table[j * w as usize + i];
                cands.clear();
                for (k, inst) in insts.iter().enumerate() {
                    if let Some(s) = sphere_test(
                        origin,
                        d,
                        &inst.sphere,
                        &cfg.sphere,
                        &mut row.ov,
                        sphere_sig,
                    ) {
                        cands.push((s.t_enter, k as u16));
                    }
                }
                row.tests += insts.len() as u64;
                row.culled += (insts.len() - cands.len()) as u64;
                let spheres = SphereCount::from_count(cands.len());
                if use_hit_buffer && !dirty.camera && cands.len() == 1 {
                    let k = cands[0].1;
                    let prev = unpack(rec.word, &cfg.hit_record);
                    if !dirty.instances[usize::from(k)]
                        && (prev.instance.is_none() || prev.instance == Some(k))
                    {
                        // Refresh the sphere count from this frame's tests, as the reference does.
                        let mut f = prev;
                        f.kind = spheres;
                        rec.word = pack(&f, &cfg.hit_record, &mut row.ov, signals::HIT_RECORD);
                        row.reused += 1;
                        row.hits += u64::from(rec.hit);
                        continue;
                    }
                }
                row.candidates += cands.len() as u64;
                sorter.sort_in_place(&mut cands, &mut row.sorter);
                let order: &[(i64, u16)] = &cands;
                let mut best: Option<(i64, u16, rtl_model::units::walker::WalkerHit, [bool; 3])> =
                    None;
                for &(key, k) in order {
                    if let Some((bt, _, _, _)) = best {
                        // Early termination: the best hit is no farther than this entry.
                        let lhs = i128::from(bt) << (key_fmt.frac.max(t_fmt.frac) - t_fmt.frac);
                        let rhs = i128::from(key) << (key_fmt.frac.max(t_fmt.frac) - key_fmt.frac);
                        if lhs <= rhs {
                            row.early += 1;
                            break;
                        }
                    }
                    let inst = &insts[usize::from(k)];
                    let (o_local, d_local, signs) = transform_with_signs(
                        origin,
                        d,
                        &inst.raw,
                        &cfg.transform,
                        &mut row.ov,
                        tr_sig,
                    );
                    let mut inp = WalkerInput {
                        origin: o_local,
                        half: inst.half,
                        ..WalkerInput::default()
                    };
                    for a in 0..3 {
                        let r = recip.eval(d_local[a], signs[a], &mut row.ov, signals::RECIPROCAL);
                        inp.inv[a] = r.raw.saturating_abs();
                        row.flushes += u64::from(r.flushed);
                        inp.zero[a] = r.zero;
                        inp.negative[a] = r.negative;
                    }
                    row.walks += 1;
                    match walk_fixed(
                        inst.image,
                        &inp,
                        &cfg.walker,
                        &mut row.ov,
                        signals::WALKER_T,
                        &mut row.walker,
                    ) {
                        WalkOutcome::Hit(hit) => {
                            if best.is_none_or(|(bt, _, _, _)| hit.t < bt) {
                                best = Some((hit.t, k, hit, signs));
                            }
                        }
                        WalkOutcome::Miss => {}
                        WalkOutcome::StepLimit => row.ov.hit(signals::WALKER_STEP_LIMIT),
                    }
                }
                *rec = match best {
                    None => FixedRecord {
                        word: miss_words[usize::from(spheres.code())],
                        ..FixedRecord::default()
                    },
                    Some((t, k, hit, signs)) => {
                        row.hits += 1;
                        let inst = &insts[usize::from(k)];
                        let attr = inst.image.attrs()[hit.attr as usize];
                        let n = (inst.normal_to_world * DVec3::from_array(attr.normal()))
                            .normalize_or_zero();
                        let [r, g, b, _] = attr.rgba();
                        let f = quantise(
                            &HitRecordF64 {
                                kind: spheres,
                                instance: Some(k),
                                t: to_f64(t, t_fmt),
                                normal: n.to_array(),
                                colour: [r, g, b],
                                voxel: hit.voxel,
                            },
                            &cfg.hit_record,
                            &mut row.ov,
                            signals::HIT_RECORD,
                        );
                        let mut local = [0.0; 3];
                        let axis = usize::from(hit.entry_axis);
                        local[axis] = if signs[axis] { 1.0 } else { -1.0 };
                        let face = (inst.world_from_local * DVec3::from_array(local))
                            .to_array()
                            .map(|v| (v * 127.0).round() as i8);
                        FixedRecord {
                            word: pack(&f, &cfg.hit_record, &mut row.ov, signals::HIT_RECORD),
                            hit: true,
                            t_raw: t,
                            voxel: hit.voxel,
                            face,
                        }
                    }
                };
            }
            row
        })
        .collect();
    let mut st = FixedStats {
        rays: u64::from(w) * u64::from(h),
        ..FixedStats::default()
    };
    let mut ov = host_ov;
    for r in &rows {
        ov.merge(&r.ov);
        st.walks += r.walks;
        st.sphere_tests += r.tests;
        st.spheres_culled += r.culled;
        st.candidates += r.candidates;
        st.early_terminations += r.early;
        st.hits += r.hits;
        st.zero_flushes += r.flushes;
        st.hit_buffer_reused += r.reused;
        st.walker.steps += r.walker.steps;
        st.walker.fetches += r.walker.fetches;
        st.walker.step_limit_hits += r.walker.step_limit_hits;
        st.walker.max_stack = st.walker.max_stack.max(r.walker.max_stack);
        st.sorter.merge(&r.sorter);
    }
    st.overflows = Some(ov);
    st.wall_s = start.elapsed().as_secs_f64();
    Ok(st)
}

/// The fixed-point records as the reference's record type, for PNGs, dumps and comparisons:
/// t from the walker, colour and shading normal from the packed word.
pub fn to_hit_records(buffer: &FixedBuffer, cfg: &DatapathConfig) -> Vec<HitRecord> {
    buffer
        .records
        .iter()
        .map(|r| {
            let f = unpack(r.word, &cfg.hit_record);
            if !r.hit {
                return HitRecord {
                    spheres: f.kind,
                    ..HitRecord::MISS
                };
            }
            let n =
                rtl_model::units::hit_record::decode_normal(f.normal, cfg.hit_record.normal_bits);
            let c = f.colour;
            HitRecord {
                hit: true,
                spheres: f.kind,
                instance: f.instance.unwrap_or(crate::reference::record::NO_INSTANCE),
                t: to_f64(r.t_raw, cfg.walker.t),
                voxel: r.voxel,
                face_normal: r.face.map(|v| f32::from(v) / 127.0),
                shade_normal: n.map(|v| v as f32),
                colour: [c[0], c[1], c[2], 255],
            }
        })
        .collect()
}
