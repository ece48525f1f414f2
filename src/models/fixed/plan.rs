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
//! capture — passes a [`PixelObserver`](super::trace::PixelObserver) to `pixel` rather than
//! repeating its flow.
//!
//! This file prepares the frame (the host's per-instance data, the camera, the dirty flags);
//! `plan/steps.rs` holds the per-pixel steps and `plan/counters.rs` what they count.

mod counters;
mod steps;

use super::frame::{FixedBuffer, FixedError};
use crate::models::reference::cull::TileLists;
use crate::models::reference::hit_buffer::Dirty;
use crate::models::reference::ray::primary_ray;
use crate::models::reference::{FrameInput, RaySwitches, SphereCount};
use crate::world::assets::{Asset, AssetTree};
use glam::{DMat3, DVec3};
use rayon::prelude::*;
use rtl_model::datapath::{overflow_table, signals, DatapathConfig};
use rtl_model::fixed::{from_f64, Format, Overflows};
use rtl_model::svo::SvoImage;
use rtl_model::units::hit_record::{pack, quantise, HitRecordF64, HitRecordFields};
use rtl_model::units::normal::NormalMatrix;
use rtl_model::units::raygen::direction_entry;
use rtl_model::units::reciprocal::ReciprocalUnit;
use rtl_model::units::sorter::Sorter;
use rtl_model::units::sphere::{SphereOrigin, SphereRaw, SphereSignals};
use rtl_model::units::transform::{transform_origin, InstanceRaw, TransformSignals};
use rtl_model::units::walker::{WalkerHit, WalkerPos, WalkerT};

pub use counters::PixelCounters;

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
    /// The sphere unit's origin-only work (l = c − o, the reach guards, l·l) for the camera
    /// origin, computed once per frame (`SphereOrigin`); each ray's test adds its direction.
    sphere_origin: SphereOrigin,
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
                    sphere_origin: SphereOrigin::new([0; 3], &SphereRaw::default()),
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
            inst.sphere_origin = SphereOrigin::new(origin, &inst.host.sphere);
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
}
