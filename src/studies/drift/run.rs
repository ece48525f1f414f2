//! The drift experiment: a long animation rendered by the f64 reference and, every frame, by
//! the fixed-point model with the instance's matrix from each pose path, with the matrix's
//! orthonormality, its error against the exact pose, and the image's accuracy per frame.
//!
//! Pipeline position: `sim drift`. The reference renders the exact keyframe pose; the fixed
//! model renders the same frame with the matrix of [`Mode`] (its codes are exact in f64, so
//! the host's quantisation in `render_frame_fixed` keeps them bit for bit).

use super::pose::{pose_overflow_table, IncrementalPath, KeyframePath};
use super::scene::drift_scene;
use crate::error::{AssetError, SceneError};
use crate::models::fixed::explain::{judge, JudgeCtx};
use crate::models::fixed::{render_frame_fixed, to_hit_records, FixedBuffer, FixedError};
use crate::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use crate::world::assets::{build_assets, Asset, Materialise};
use crate::world::scene::Scene;
use glam::{DMat3, DVec3};
use rtl_model::datapath::{signals, DatapathConfig};
use rtl_model::fixed::{to_f64, Format};
use rtl_model::units::keyframe::{angle_error_bound, matrix_error_bound, KeyframeConfig};
use rtl_model::units::rotation::{
    incremental_pose_error_bound, orthonormality_error, rounding_orthonormality,
    steady_state_orthonormality_bound, MatRaw, RotationConfig,
};
use serde::Serialize;
use std::path::Path;
use thiserror::Error;

/// Why the experiment cannot run.
#[derive(Debug, Error)]
pub enum DriftError {
    /// SIGINT or SIGTERM stopped the study (nothing is written).
    #[error("{0}")]
    Interrupted(#[from] crate::output::interrupt::Interrupted),
    /// The options make no valid scene.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The asset cannot be built.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// The fixed-point model refused the frame.
    #[error(transparent)]
    Fixed(#[from] FixedError),
    /// A frame's state could not be formed, or a configuration is invalid.
    #[error("{0}")]
    Invalid(String),
}

/// What to run.
#[derive(Clone, Debug)]
pub struct DriftOptions {
    /// Frames (at least 2).
    pub frames: u32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Octree depth of the spinning part.
    pub depth: u8,
    /// The datapath (its `raygen.mat` must be the pose paths' matrix format).
    pub datapath: DatapathConfig,
    /// Keyframe path formats.
    pub keyframe: KeyframeConfig,
    /// Incremental path formats.
    pub rotation: RotationConfig,
}

impl DriftOptions {
    /// The documented defaults at a size.
    pub fn new(frames: u32, width: u32, height: u32, depth: u8) -> Self {
        Self {
            frames,
            width,
            height,
            depth,
            datapath: DatapathConfig::default(),
            keyframe: KeyframeConfig::default(),
            rotation: RotationConfig::default(),
        }
    }
}

/// The pose paths compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// (a) Recomputed from the keyframes in fixed point every frame.
    Keyframe,
    /// (b) Composed incrementally, re-orthonormalised every frame.
    Incremental,
    /// (b) without re-orthonormalisation.
    IncrementalNoReorth,
}

impl Mode {
    /// All modes, in report order.
    pub const ALL: [Mode; 3] = [Mode::Keyframe, Mode::Incremental, Mode::IncrementalNoReorth];

    /// The name used in CSV, JSON and the plot.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Keyframe => "keyframe",
            Mode::Incremental => "incremental",
            Mode::IncrementalNoReorth => "incremental_no_reorth",
        }
    }
}

/// One frame of one mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameDrift {
    /// Frame number.
    pub frame: u32,
    /// Pose path.
    pub mode: Mode,
    /// max |RᵀR − I| of the matrix the transform used (exact).
    pub orthonormality: f64,
    /// max |R − R_exact| over the entries.
    pub matrix_error: f64,
    /// The bound on `matrix_error` at this frame: (a)'s constant, or (b)'s linear bound
    /// (the same for both incremental paths; only the corrected one is claimed to meet it).
    pub matrix_bound: f64,
    /// Largest |t_fixed − t_ref| over pixels both hit on the same leaf (metres).
    pub t_err_max: f64,
    /// RMS of the same.
    pub t_err_rms: f64,
    /// Largest t error divided by its per-pixel bound (≤ 1 within the bound).
    pub t_err_over_bound: f64,
    /// Pixels one model hit and the other missed.
    pub hit_mismatches: u64,
    /// Pixels hit on different instances.
    pub instance_mismatches: u64,
    /// Pixels hit on different leaves.
    pub voxel_mismatches: u64,
    /// Mismatches of any kind, and t errors, beyond the bound (datapath bound plus the mode's
    /// matrix bound).
    pub beyond_bound: u64,
    /// Mismatches and t errors beyond the bound that holds for (a) — the datapath bound plus
    /// (a)'s constant matrix bound: where an incremental path's pixels leave what a pose
    /// rebuilt from the keys guarantees.
    pub beyond_keyframe_bound: u64,
    /// Largest t error over its per-pixel bound with (a)'s matrix bound.
    pub t_err_over_keyframe_bound: f64,
    /// Saturations in the datapath and the pose path.
    pub saturations: u64,
}

/// The bounds the claims are checked against.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DriftBounds {
    /// (a): each matrix entry within this of the exact rotation, every frame.
    pub keyframe_matrix: f64,
    /// (a): orthonormality error, every frame.
    pub keyframe_orthonormality: f64,
    /// (b) with re-orthonormalisation: orthonormality error, every frame, for ever.
    pub incremental_orthonormality: f64,
    /// (b) with re-orthonormalisation: matrix error bound at the last frame (it grows
    /// linearly with the frame number: the per-frame rotation's quantised angle).
    pub incremental_matrix_at_end: f64,
}

/// Per-mode summary over all frames.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModeSummary {
    /// Pose path.
    pub mode: Mode,
    /// Largest orthonormality error.
    pub orthonormality_max: f64,
    /// Orthonormality error of the last frame.
    pub orthonormality_last: f64,
    /// Largest matrix error.
    pub matrix_error_max: f64,
    /// Largest t error (metres).
    pub t_err_max: f64,
    /// Largest t error over its per-pixel bound.
    pub t_err_over_bound_max: f64,
    /// Largest t error over the first tenth of the frames.
    pub t_err_max_first_tenth: f64,
    /// Largest t error over the last tenth of the frames.
    pub t_err_max_last_tenth: f64,
    /// Mismatches of all kinds, all frames.
    pub mismatches: u64,
    /// Mismatches beyond the bound, all frames.
    pub beyond_bound: u64,
    /// Mismatches and t errors beyond (a)'s bound, all frames.
    pub beyond_keyframe_bound: u64,
    /// Largest t error over its per-pixel bound with (a)'s matrix bound.
    pub t_err_over_keyframe_bound_max: f64,
    /// First frame with a pixel beyond (a)'s bound, if any.
    pub first_frame_beyond_keyframe_bound: Option<u32>,
    /// Saturations, all frames.
    pub saturations: u64,
}

/// The claims of the experiment, each checked with numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DriftClaims {
    /// (a) stays within its constant bounds every frame, with no mismatch beyond the bound.
    pub keyframe_bounded: bool,
    /// (b) with re-orthonormalisation stays within its orthonormality bound every frame and
    /// its matrix-error bound, with no mismatch beyond the bound.
    pub incremental_bounded: bool,
    /// (b) without re-orthonormalisation leaves the orthonormality bound by the last frame
    /// (by a factor of at least 10).
    pub no_reorth_drifts: bool,
}

/// The whole result.
#[derive(Clone, Debug, Serialize)]
pub struct DriftResult {
    /// Frames.
    pub frames: u32,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Octree depth of the part.
    pub depth: u8,
    /// Bounds.
    pub bounds: DriftBounds,
    /// Per-mode summaries.
    pub summary: Vec<ModeSummary>,
    /// The claims.
    pub claims: DriftClaims,
    /// Every frame of every mode, frame-major (not in the JSON: the CSV has it).
    #[serde(skip)]
    pub rows: Vec<FrameDrift>,
}

fn dmat(m: &MatRaw, f: Format) -> DMat3 {
    DMat3::from_cols_array_2d(&m.map(|c| c.map(|v| to_f64(v, f))))
}

fn matrix_error(m: &MatRaw, f: Format, exact: &DMat3) -> f64 {
    let e = dmat(m, f) - *exact;
    e.to_cols_array().iter().fold(0.0, |a, v| a.max(v.abs()))
}

/// Runs the experiment, calling `progress(frame)` after each frame.
pub fn run_drift(
    opts: &DriftOptions,
    mut progress: impl FnMut(u32),
) -> Result<DriftResult, DriftError> {
    if opts.frames < 2 {
        return Err(DriftError::Invalid(format!(
            "--frames {}: the drift experiment needs at least 2 frames",
            opts.frames
        )));
    }
    let dp = &opts.datapath;
    dp.validate()
        .map_err(|m| DriftError::Invalid(format!("datapath configuration: {m}")))?;
    opts.keyframe.validate().map_err(DriftError::Invalid)?;
    opts.rotation.validate().map_err(DriftError::Invalid)?;
    let file = drift_scene(opts.frames, opts.width, opts.height, opts.depth);
    let scene = Scene::from_file(file, "<drift scene>", Path::new("."))?;
    let assets: Vec<Asset> = build_assets(&scene, &[opts.depth], Materialise::Auto)?;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let depths = vec![assets[0].depth()];
    let (w, h) = scene.file.resolution;
    let state_at = |n: u32| {
        scene
            .frame_state(n, &half)
            .map_err(|m| DriftError::Invalid(format!("frame {n}: {m}")))
    };
    let first = state_at(0)?;
    let second = state_at(1)?;
    let r0 = first.poses[0].world_from_local;
    // ΔR = R(0)ᵀ·R(1): the local-frame rotation per frame (constant for this animation).
    let delta = r0.transpose() * second.poses[0].world_from_local;
    let mut pose_ov = pose_overflow_table();
    let keyframe = KeyframePath::new(&scene.file.instances[0].keys, &opts.keyframe);
    let mut incremental = IncrementalPath::new(&r0, &delta, true, &opts.rotation, &mut pose_ov);
    let mut raw = IncrementalPath::new(&r0, &delta, false, &opts.rotation, &mut pose_ov);
    // (a)'s bounds: one segment spanning every frame, |step| = the spin in turns per frame.
    let step_turns = super::scene::SPIN_DEG_PER_FRAME / 360.0;
    // Integer keys: k is exact.
    let ang = angle_error_bound(&opts.keyframe, f64::from(opts.frames), step_turns, true);
    let key_mat = matrix_error_bound(&opts.keyframe, ang);
    let bounds = DriftBounds {
        keyframe_matrix: key_mat,
        keyframe_orthonormality: rounding_orthonormality(key_mat),
        incremental_orthonormality: steady_state_orthonormality_bound(&opts.rotation),
        incremental_matrix_at_end: incremental_pose_error_bound(
            &opts.rotation,
            u64::from(opts.frames - 1),
        ),
    };
    let no_hb = RenderOptions {
        use_hit_buffer: false,
        ..RenderOptions::default()
    };
    let mut reference = HitBuffer::new(w, h);
    let mut buffers: Vec<FixedBuffer> = Mode::ALL.iter().map(|_| FixedBuffer::new(w, h)).collect();
    let mut rows = Vec::with_capacity(opts.frames as usize * Mode::ALL.len());
    for n in 0..opts.frames {
        let total = opts.frames;
        crate::output::interrupt::check(|| format!("frame {n} of {total}"), String::new)?;
        if n > 0 {
            incremental.advance(&mut pose_ov);
            raw.advance(&mut pose_ov);
        }
        let exact = state_at(n)?;
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &exact,
        };
        render_frame(&input, &mut reference, no_hb);
        let r_exact = exact.poses[0].world_from_local;
        for (mode, buffer) in Mode::ALL.into_iter().zip(buffers.iter_mut()) {
            let before = pose_ov.total();
            let (m, fmt, centre, mat_bound) = match mode {
                Mode::Keyframe => {
                    let (m, c) = keyframe.at(n, &mut pose_ov);
                    let centre = DVec3::from_array(c.map(|v| to_f64(v, opts.keyframe.pos)));
                    (m, opts.keyframe.mat, centre, key_mat)
                }
                Mode::Incremental | Mode::IncrementalNoReorth => {
                    let path = if mode == Mode::Incremental {
                        &incremental
                    } else {
                        &raw
                    };
                    let b = incremental_pose_error_bound(&opts.rotation, u64::from(n));
                    (*path.matrix(), opts.rotation.acc, exact.poses[0].centre, b)
                }
            };
            let mut state = exact.clone();
            state.poses[0].world_from_local = dmat(&m, fmt);
            state.poses[0].centre = centre;
            let fx = render_frame_fixed(
                &FrameInput {
                    scene: &scene,
                    assets: &assets,
                    state: &state,
                },
                buffer,
                dp,
                false,
            )?;
            let records = to_hit_records(buffer, dp);
            let ctx = JudgeCtx {
                cfg: dp,
                camera: &exact.camera,
                size: (w, h),
                poses: &exact.poses,
                depths: &depths,
                mat_err: mat_bound,
            };
            let j = judge(&ctx, &reference.records, &records);
            let jk = if mode == Mode::Keyframe {
                j.clone()
            } else {
                judge(
                    &JudgeCtx {
                        mat_err: key_mat,
                        ..ctx
                    },
                    &reference.records,
                    &records,
                )
            };
            let ov = fx
                .overflows
                .as_ref()
                .map_or(0, |o| o.total() - o.count(signals::WALKER_STEP_LIMIT));
            let a = &j.accuracy;
            rows.push(FrameDrift {
                frame: n,
                mode,
                orthonormality: orthonormality_error(&m, fmt),
                matrix_error: matrix_error(&m, fmt, &r_exact),
                matrix_bound: mat_bound,
                t_err_max: a.t_err_max,
                t_err_rms: a.t_err_rms,
                t_err_over_bound: j.t_err_over_bound_max,
                hit_mismatches: a.hit_mismatches,
                instance_mismatches: a.instance_mismatches,
                voxel_mismatches: a.voxel_mismatches,
                beyond_bound: j.all_beyond_bound(),
                beyond_keyframe_bound: jk.all_beyond_bound(),
                t_err_over_keyframe_bound: jk.t_err_over_bound_max,
                saturations: ov + (pose_ov.total() - before),
            });
        }
        progress(n);
    }
    let summary: Vec<ModeSummary> = Mode::ALL
        .iter()
        .map(|&m| summarise(&rows, m, opts.frames))
        .collect();
    let claims = check_claims(&rows, &bounds);
    Ok(DriftResult {
        frames: opts.frames,
        width: w,
        height: h,
        depth: opts.depth,
        bounds,
        summary,
        claims,
        rows,
    })
}

fn summarise(rows: &[FrameDrift], mode: Mode, frames: u32) -> ModeSummary {
    let mine: Vec<&FrameDrift> = rows.iter().filter(|r| r.mode == mode).collect();
    let tenth = (frames / 10).max(1);
    let max = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0f64, f64::max);
    ModeSummary {
        mode,
        orthonormality_max: max(&mut mine.iter().map(|r| r.orthonormality)),
        orthonormality_last: mine.last().map_or(0.0, |r| r.orthonormality),
        matrix_error_max: max(&mut mine.iter().map(|r| r.matrix_error)),
        t_err_max: max(&mut mine.iter().map(|r| r.t_err_max)),
        t_err_over_bound_max: max(&mut mine.iter().map(|r| r.t_err_over_bound)),
        t_err_max_first_tenth: max(&mut mine
            .iter()
            .filter(|r| r.frame < tenth)
            .map(|r| r.t_err_max)),
        t_err_max_last_tenth: max(&mut mine
            .iter()
            .filter(|r| r.frame >= frames - tenth)
            .map(|r| r.t_err_max)),
        mismatches: mine
            .iter()
            .map(|r| r.hit_mismatches + r.instance_mismatches + r.voxel_mismatches)
            .sum(),
        beyond_bound: mine.iter().map(|r| r.beyond_bound).sum(),
        beyond_keyframe_bound: mine.iter().map(|r| r.beyond_keyframe_bound).sum(),
        t_err_over_keyframe_bound_max: max(&mut mine.iter().map(|r| r.t_err_over_keyframe_bound)),
        first_frame_beyond_keyframe_bound: mine
            .iter()
            .find(|r| r.beyond_keyframe_bound > 0)
            .map(|r| r.frame),
        saturations: mine.iter().map(|r| r.saturations).sum(),
    }
}

fn check_claims(rows: &[FrameDrift], b: &DriftBounds) -> DriftClaims {
    let of = |m: Mode| rows.iter().filter(move |r| r.mode == m);

    let keyframe_bounded = of(Mode::Keyframe).all(|r| {
        r.orthonormality <= b.keyframe_orthonormality
            && r.matrix_error <= b.keyframe_matrix
            && r.beyond_bound == 0
            && r.saturations == 0
    });
    let incremental_bounded = of(Mode::Incremental).all(|r| {
        r.orthonormality <= b.incremental_orthonormality
            && r.matrix_error <= r.matrix_bound
            && r.beyond_bound == 0
            && r.saturations == 0
    });
    let no_reorth_drifts = of(Mode::IncrementalNoReorth)
        .next_back()
        .is_some_and(|r| r.orthonormality > 10.0 * b.incremental_orthonormality);
    DriftClaims {
        keyframe_bounded,
        incremental_bounded,
        no_reorth_drifts,
    }
}
