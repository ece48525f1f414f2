//! Captures one real frame's transactions, stage by stage, for the vectors: the frame is
//! prepared as the functional fixed-point model prepares it (`FramePlan::new`, frame 0 of a
//! run: no hit buffer, so every pixel is traced) and every pixel runs through
//! `FramePlan::pixel` with an observer that records each unit's inputs and each pixel's end
//! result. The capture repeats none of the per-pixel flow: it watches the model's.
//!
//! Pipeline position: the root package's side of `sim vectors`; `rtl_model::vectors` turns
//! the recorded inputs into rows with the golden model's outputs. The per-pixel words this
//! produces are checked against `render_frame_fixed` in `tests/vectors.rs`.

use super::VectorsError;
use crate::models::fixed::frame::{FixedBuffer, FixedError, FixedRecord};
use crate::models::fixed::plan::{FramePlan, PixelCounters};
use crate::models::fixed::trace::PixelObserver;
use crate::models::reference::ray::primary_ray;
use crate::models::reference::FrameInput;
use crate::models::reference::SphereCount;
use crate::world::assets::Asset;
use crate::world::scene::{FrameState, Scene};
use rtl_model::datapath::{overflow_table, DatapathConfig};
use rtl_model::units::hit_record::{HitRecordFields, ReuseInputs};
use rtl_model::units::normal::NormalMatrix;
use rtl_model::units::sphere::{SphereHit, SphereRaw};
use rtl_model::units::transform::InstanceRaw;
use rtl_model::units::walker::{NoObserver, WalkerInput};
use rtl_model::vectors::frame::{FrameInstance, FramePixel};
use rtl_model::vectors::stage::hit_record::HitRecordTxn;
use rtl_model::vectors::stage::raygen::RaygenTxn;
use rtl_model::vectors::stage::sorter::rows_max_keys;
use rtl_model::vectors::stage::sphere::{SphereStage, SphereTxn};
use rtl_model::vectors::stage::transform::TransformTxn;
use rtl_model::vectors::stage::walker::WalkTxn;
use rtl_model::vectors::Captured;

/// A captured frame: every unit's inputs, and the end-to-end view.
pub struct FrameCapture {
    /// Per-stage inputs.
    pub captured: Captured,
    /// Camera position codes.
    pub origin: [i64; 3],
    /// The hit-buffer word of a pixel without candidates (a constant of the frame: the
    /// check stage writes it without a walk).
    pub miss_word: u128,
    /// What the host programs per instance.
    pub instances: Vec<FrameInstance>,
    /// Every pixel in raster order.
    pub pixels: Vec<FramePixel>,
}

/// The observer: appends each unit's inputs to `cap` and each finished pixel to `pixels`.
struct Recorder<'s> {
    cap: Captured,
    pixels: Vec<FramePixel>,
    /// The sphere stage, for the square root's radicands.
    sphere_stage: SphereStage,
    /// Most keys of a sorter row: longer candidate lists are not captured.
    sorter_max: usize,
    /// Asset (memory image) of each instance.
    instance_asset: &'s [usize],
    /// The pixel being run: column and row, direction-table entry, candidates, walks.
    xy: [u16; 2],
    dir: [i64; 3],
    candidates: u32,
    first_candidate: u16,
    walks: u32,
}

impl PixelObserver for Recorder<'_> {
    type Walk<'w>
        = NoObserver
    where
        Self: 'w;

    fn on_sphere(
        &mut self,
        _k: u16,
        o: [i64; 3],
        d: [i64; 3],
        sphere: &SphereRaw,
        _hit: Option<SphereHit>,
    ) {
        let txn = SphereTxn::of(o, d, sphere);
        self.cap.sphere.push(txn);
        if let Some(x) = self.sphere_stage.radicand(&txn) {
            self.cap.sqrt.push(x);
        }
    }

    fn on_candidates(&mut self, unsorted: &[(i64, u16)]) {
        self.candidates = unsorted.len() as u32;
        self.first_candidate = unsorted.first().map_or(0, |c| c.1);
        if unsorted.len() <= self.sorter_max {
            self.cap.sorter.push(unsorted.to_vec());
        }
    }

    fn on_transform(&mut self, _k: u16, o: [i64; 3], d: [i64; 3], inst: &InstanceRaw) {
        self.cap.transform.push(TransformTxn { o, d, inst: *inst });
    }

    fn on_reciprocal(&mut self, d_local: i64, negative: bool) {
        self.cap.reciprocal.push((d_local, negative));
    }

    fn begin_walk(&mut self, k: u16, input: &WalkerInput) -> NoObserver {
        self.walks += 1;
        self.cap.walker.push(WalkTxn {
            image: self.instance_asset[usize::from(k)],
            input: *input,
        });
        NoObserver
    }

    fn on_record(&mut self, fields: &HitRecordFields, word: u128) {
        // The check of the next frame with a still camera: this word read back, this ray's
        // candidates again.
        self.cap.hit_record.push(HitRecordTxn {
            record: *fields,
            prev: word,
            check: ReuseInputs {
                buffer: true,
                camera_dirty: false,
                candidates: self.candidates as usize,
                candidate: self.first_candidate,
                instance_dirty: false,
            },
        });
    }

    fn on_normal(&mut self, oct16: u32, m: &NormalMatrix) {
        self.cap.normal.push((oct16, *m));
    }

    fn on_pixel_end(&mut self, rec: &FixedRecord) {
        self.pixels.push(FramePixel {
            xy: self.xy,
            dir: self.dir,
            candidates: self.candidates,
            walks: self.walks,
            hit: rec.hit,
            t: rec.t,
            voxel: rec.voxel,
            word: rec.word,
        });
    }
}

/// Runs `state` (a frame of `scene` at its resolution) through the functional model's
/// per-pixel flow and records it.
pub fn capture_frame(
    scene: &Scene,
    assets: &[Asset],
    state: &FrameState,
    dp: &DatapathConfig,
) -> Result<FrameCapture, VectorsError> {
    let (w, h) = scene.file.resolution;
    let input = FrameInput {
        scene,
        assets,
        state,
    };
    // Frame 0 of a run: an empty buffer and no hit buffer, so no pixel is reused.
    let mut buffer = FixedBuffer::new(w, h);
    let plan = FramePlan::new(&input, &mut buffer, dp, false, &mut overflow_table()).map_err(
        |e| match e {
            FixedError::Config(m) => VectorsError::Datapath(m),
            FixedError::Implicit(name) => VectorsError::Implicit(name),
        },
    )?;
    let mut rec = Recorder {
        cap: Captured::default(),
        pixels: Vec::with_capacity(w as usize * h as usize),
        sphere_stage: SphereStage::new(dp),
        sorter_max: rows_max_keys(&dp.sorter),
        instance_asset: &scene.instance_asset,
        xy: [0; 2],
        dir: [0; 3],
        candidates: 0,
        first_candidate: 0,
        walks: 0,
    };
    // Counters and overflows are not what the capture is for (the rows carry their own
    // flags).
    let mut c = PixelCounters::default();
    let mut cands: Vec<(i64, u16)> = Vec::with_capacity(plan.instances());
    let cam = state.camera;
    for j in 0..h {
        for i in 0..w {
            // The host's ray generation: the f64 ray the direction table entry quantises.
            let ray = primary_ray(&cam, w, h, i, j);
            rec.cap.raygen.push(RaygenTxn {
                pixel: [i as u16, j as u16],
                dir: ray.dir.to_array(),
                origin: cam.position.to_array(),
            });
            rec.xy = [i as u16, j as u16];
            rec.dir = buffer.dir_table[j as usize * w as usize + i as usize];
            rec.walks = 0;
            let mut entry = FixedRecord::default();
            plan.pixel(rec.dir, &mut entry, &mut c, &mut cands, &mut rec);
        }
    }
    let instances = (0..plan.instances())
        .filter_map(|k| {
            let host = plan.host_instance(k as u16)?;
            Some(FrameInstance {
                raw: host.raw,
                threshold: host.sphere.threshold,
                inside: host.sphere.inside,
                delta_t: host.sphere.delta_t,
                reach: host.sphere.reach,
                half: host.half,
                image: scene.instance_asset[k],
                nmat: host.nmat,
            })
        })
        .collect();
    let miss_word = plan.finish(None, SphereCount::None, &mut c).word;
    Ok(FrameCapture {
        captured: rec.cap,
        origin: plan.origin(),
        miss_word,
        instances,
        pixels: rec.pixels,
    })
}
