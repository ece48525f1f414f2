//! `sim render`: one bare `.vox` model rendered by the f64 reference walk with a camera given in
//! the model's own voxel coordinates (MagicaVoxel axes, z up), every pixel's record in those
//! coordinates with the model's own voxel indices.
//!
//! Pipeline position: a run of the reference's octree walk alone (no scene, no instance
//! transform, no bounding sphere), between the `.vox` loader (`world::assets::vox::model_frame`
//! lays the leaves out along the model's axes) and the outputs (`output::model_dump`, PNG).
//! The camera contract (ray generation, orthographic rays, −0 → +0, the plane rule) is
//! `docs/render.md`; the OpenVDB peer in `tests/openvdb_peer/` implements the same contract
//! on its own and `tests/openvdb_peer.rs` compares the two pixel by pixel.

use std::path::Path;
use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;
use rtl_model::svo::{BuildError, SvoImage};
use thiserror::Error;

use crate::models::reference::octree::{ImageNode, Octree};
use crate::models::reference::ray::primary_ray;
use crate::models::reference::walk::{WalkCounters, WalkStack};
use crate::world::assets::vox::model_frame::{load_model_frame, ModelFrame};
use crate::world::assets::vox::VoxError;
use crate::world::scene::Camera;

// The result types live in the models layer so that `output` can write them without
// importing `run`; re-exported here, where `sim render` and its tests look for them.
pub use crate::models::reference::model_render::{ModelHit, ModelRender, Projection, MISS_T};

/// Largest image side.
pub const MAX_SIDE: u32 = 16384;
/// Largest image, in pixels (records are kept in memory: 2^24 of them take about 1.5 GB).
pub const MAX_PIXELS: u64 = 1 << 24;
/// Largest magnitude of a camera coordinate or view width, in voxels (2^40): far beyond any
/// model (an octree side is at most 2^20), and small enough that no ray computation
/// overflows.
pub const MAX_COORD: f64 = 1_099_511_627_776.0;

/// A camera in the model's own voxel coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelCamera {
    /// Eye (pinhole) or centre of the view plane (orthographic).
    pub eye: [f64; 3],
    /// A point on the view axis.
    pub look: [f64; 3],
    /// Up hint; must not be parallel to the view direction.
    pub up: [f64; 3],
    /// Pinhole or orthographic.
    pub projection: Projection,
}

/// Why a render could not be made. Nothing is written when one is returned.
#[derive(Debug, Error)]
pub enum RenderError {
    /// A camera number is NaN or infinite.
    #[error("camera {what} = {value} is not a finite number")]
    NotFinite {
        /// Which value (`eye.x`, `fov`, …).
        what: String,
        /// Its value.
        value: f64,
    },
    /// A camera coordinate is beyond [`MAX_COORD`].
    #[error("camera {what} = {value:e} voxels is outside ±{MAX_COORD:e} (2^40) voxels")]
    TooFar {
        /// Which value.
        what: String,
        /// Its value.
        value: f64,
    },
    /// Eye and look point coincide.
    #[error("camera eye {eye:?} and look {look:?} coincide (closer than 1e-9 voxels): no view direction")]
    NoView {
        /// The eye.
        eye: [f64; 3],
        /// The look point.
        look: [f64; 3],
    },
    /// The up hint is zero or parallel to the view direction.
    #[error("camera up {up:?} is zero or parallel to the view direction {forward:?}")]
    UpParallel {
        /// The up hint.
        up: [f64; 3],
        /// The unit view direction.
        forward: [f64; 3],
    },
    /// The field of view is outside (0, 180) degrees.
    #[error("--fov {0} degrees is outside (0, 180)")]
    Fov(f64),
    /// The orthographic view width is not positive.
    #[error("--ortho {0} voxels: the view width must be positive")]
    OrthoWidth(f64),
    /// The trace repeat count is out of range.
    #[error("--repeat {0}: the trace is repeated 1 to {MAX_REPEAT} times")]
    Repeat(u32),
    /// The image size is zero or too large.
    #[error("image size {width}x{height}: each side must be 1 to {MAX_SIDE}, and at most {MAX_PIXELS} pixels in all")]
    Size {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
    },
    /// The model could not be loaded.
    #[error(transparent)]
    Vox(#[from] VoxError),
    /// The model's voxel indices do not fit the dump's 32-bit fields.
    #[error("{path}: model voxel indices {min:?} to {max:?} do not fit 32-bit signed fields")]
    Indices {
        /// The model file.
        path: String,
        /// Smallest index.
        min: [i64; 3],
        /// Largest index.
        max: [i64; 3],
    },
    /// The memory image could not be built (an internal error).
    #[error("{path}: cannot build the octree image: {source}")]
    Build {
        /// The model file.
        path: String,
        /// Why.
        #[source]
        source: BuildError,
    },
}

/// The camera after validation: a basis and how pixels become rays.
#[derive(Clone, Copy, Debug)]
pub struct RayGen {
    cam: Camera,
    projection: Projection,
    width: u32,
    height: u32,
}

fn check_finite(what: &str, value: f64) -> Result<(), RenderError> {
    if !value.is_finite() {
        return Err(RenderError::NotFinite {
            what: what.to_string(),
            value,
        });
    }
    if value.abs() > MAX_COORD {
        return Err(RenderError::TooFar {
            what: what.to_string(),
            value,
        });
    }
    Ok(())
}

impl RayGen {
    /// Validates the camera and the image size.
    pub fn new(c: &ModelCamera, width: u32, height: u32) -> Result<Self, RenderError> {
        if width == 0
            || height == 0
            || width > MAX_SIDE
            || height > MAX_SIDE
            || u64::from(width) * u64::from(height) > MAX_PIXELS
        {
            return Err(RenderError::Size { width, height });
        }
        for (name, v) in [("eye", c.eye), ("look", c.look), ("up", c.up)] {
            for (axis, x) in ["x", "y", "z"].iter().zip(v) {
                check_finite(&format!("{name}.{axis}"), x)?;
            }
        }
        let tan_half_vfov = match c.projection {
            Projection::Pinhole { vfov_deg } => {
                if !vfov_deg.is_finite() {
                    return Err(RenderError::NotFinite {
                        what: "fov".into(),
                        value: vfov_deg,
                    });
                }
                if !(vfov_deg > 0.0 && vfov_deg < 180.0) {
                    return Err(RenderError::Fov(vfov_deg));
                }
                (vfov_deg.to_radians() * 0.5).tan()
            }
            Projection::Ortho { view_width } => {
                check_finite("ortho view width", view_width)?;
                if view_width <= 0.0 {
                    return Err(RenderError::OrthoWidth(view_width));
                }
                0.0
            }
        };
        let (eye, look, up_hint) = (
            DVec3::from_array(c.eye),
            DVec3::from_array(c.look),
            DVec3::from_array(c.up),
        );
        let view = look - eye;
        if view.length() < 1e-9 {
            return Err(RenderError::NoView {
                eye: c.eye,
                look: c.look,
            });
        }
        // The same basis as a scene camera (`world::scene`), so `primary_ray` applies.
        let forward = view.normalize();
        let side = forward.cross(up_hint);
        if up_hint.length() < 1e-12 || side.length() < 1e-9 * up_hint.length() {
            return Err(RenderError::UpParallel {
                up: c.up,
                forward: forward.to_array(),
            });
        }
        let right = side.normalize();
        let up = right.cross(forward);
        Ok(Self {
            cam: Camera {
                position: eye,
                forward,
                right,
                up,
                tan_half_vfov,
            },
            projection: c.projection,
            width,
            height,
        })
    }

    /// The ray of pixel (i, j): origin and unit direction, exact zeros of the direction as
    /// +0.0 (the plane rule, `docs/render.md` §3).
    #[inline]
    pub fn ray(&self, i: u32, j: u32) -> (DVec3, DVec3) {
        let (o, d) = match self.projection {
            Projection::Pinhole { .. } => {
                let r = primary_ray(&self.cam, self.width, self.height, i, j);
                (r.origin, r.dir)
            }
            Projection::Ortho { view_width } => {
                let half_w = view_width * 0.5;
                let half_h = half_w * f64::from(self.height) / f64::from(self.width);
                let u = (2.0 * (f64::from(i) + 0.5) / f64::from(self.width) - 1.0) * half_w;
                let v = (1.0 - 2.0 * (f64::from(j) + 0.5) / f64::from(self.height)) * half_h;
                let o = self.cam.position + self.cam.right * u + self.cam.up * v;
                (o, self.cam.forward)
            }
        };
        // x + 0.0 turns −0.0 into +0.0 and leaves every other value as it is.
        (o, d + DVec3::ZERO)
    }
}

/// Largest `repeat` of [`render_model`].
pub const MAX_REPEAT: u32 = 100;

/// Loads the model (the file's model `model` alone if given, see
/// [`crate::world::assets::vox::load_vox_model`]) and traces every pixel, `repeat` times (1 to
/// [`MAX_REPEAT`]): the records and counters are those of one trace (every trace gives the
/// same), `trace_seconds` the fastest. The records' memory is allocated and touched before the
/// clock starts, as the OpenVDB peer does, and the attribute normals (shading, not tracing) are
/// decoded after it stops, so the time is the trace's alone: ray generation, walk and the
/// record. A model file larger than `max_vox_bytes` is refused.
pub fn render_model(
    path: &Path,
    camera: &ModelCamera,
    (width, height): (u32, u32),
    repeat: u32,
    model: Option<usize>,
    max_vox_bytes: u64,
) -> Result<ModelRender, RenderError> {
    let gen = RayGen::new(camera, width, height)?;
    if !(1..=MAX_REPEAT).contains(&repeat) {
        return Err(RenderError::Repeat(repeat));
    }
    let model = load_model_frame(path, model, max_vox_bytes)?;
    let frame = model.frame;
    let fits = |v: i64| i32::try_from(v).is_ok();
    if !frame
        .solid_min
        .iter()
        .chain(&frame.solid_max)
        .all(|&v| fits(v))
    {
        return Err(RenderError::Indices {
            path: path.display().to_string(),
            min: frame.solid_min,
            max: frame.solid_max,
        });
    }
    let image = SvoImage::build(&model.leaves).map_err(|source| RenderError::Build {
        path: path.display().to_string(),
        source,
    })?;
    let lo = DVec3::from_array(frame.base.map(|b| b as f64));
    let hi = lo + DVec3::splat(frame.side() as f64);
    // The solid box (every leaf's cell lies in it), on voxel planes: the walk is clipped to it.
    let bounds = Bounds {
        lo,
        hi,
        solid_lo: DVec3::from_array(frame.solid_min.map(|v| v as f64)),
        solid_hi: DVec3::from_array(frame.solid_max.map(|v| (v + 1) as f64)),
    };
    let mut hits = vec![ModelHit::miss([0.0; 3], [0.0; 3]); width as usize * height as usize];
    let mut counters = WalkCounters::default();
    let mut trace_seconds = f64::INFINITY;
    for _ in 0..repeat {
        let start = Instant::now();
        let rows: Vec<WalkCounters> = hits
            .par_chunks_mut(width as usize)
            .enumerate()
            .map(|(j, row)| {
                let mut wc = WalkCounters::default();
                let mut stack = WalkStack::new();
                for (i, h) in row.iter_mut().enumerate() {
                    // i < width and j < height, both u32.
                    let (i, j) = (i as u32, j as u32);
                    *h = trace(&image, &frame, &gen, &bounds, i, j, &mut wc, &mut stack);
                }
                wc
            })
            .collect();
        trace_seconds = trace_seconds.min(start.elapsed().as_secs_f64());
        counters = WalkCounters::default();
        for wc in rows {
            counters.steps += wc.steps;
            counters.fetches += wc.fetches;
            counters.max_stack = counters.max_stack.max(wc.max_stack);
        }
    }
    // The attribute normals, for shading only (the PNG), outside the trace's time.
    hits.par_iter_mut().filter(|h| h.hit).for_each(|h| {
        h.normal = image.attr(h.leaf).normal().map(|v| v as f32);
    });
    Ok(ModelRender {
        frame,
        width,
        height,
        hits,
        counters,
        trace_seconds,
        notice: model.notice,
    })
}

/// The octree's box and the model's solid box, in model coordinates (integers).
struct Bounds {
    lo: DVec3,
    hi: DVec3,
    solid_lo: DVec3,
    solid_hi: DVec3,
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn trace(
    image: &SvoImage,
    frame: &ModelFrame,
    gen: &RayGen,
    b: &Bounds,
    i: u32,
    j: u32,
    wc: &mut WalkCounters,
    stack: &mut WalkStack<ImageNode>,
) -> ModelHit {
    let (o, d) = gen.ray(i, j);
    let (origin, dir) = (o.to_array(), d.to_array());
    let walk = stack.walk_box_clipped(image, b.lo, b.hi, b.solid_lo, b.solid_hi, o, d, wc);
    let Some(h) = walk else {
        return ModelHit::miss(origin, dir);
    };
    let attr = image.attr(h.attr);
    // Octree axes are the model's axes (no axis negated), so indices only shift; they fit
    // i32 (checked against the solid box before tracing).
    let voxel: [i32; 3] = std::array::from_fn(|k| (frame.base[k] + i64::from(h.voxel[k])) as i32);
    ModelHit {
        origin,
        dir,
        hit: true,
        t: h.t,
        voxel,
        face: h.face_normal.to_array().map(|v| v as i8),
        rgba: attr.rgba(),
        // Decoded after the clock stops (`render_model`): shading, not tracing.
        normal: [0.0; 3],
        leaf: h.attr,
    }
}
