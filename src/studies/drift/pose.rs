//! The two fixed-point pose paths the drift experiment compares, for one instance:
//!
//! - [`KeyframePath`]: every frame, the Euler angles and translation are interpolated from
//!   the keys in fixed point and the matrix is rebuilt by CORDIC (`units::keyframe`); nothing
//!   carries over from one frame to the next.
//! - [`IncrementalPath`]: the matrix lives in a register, starts from the first frame's pose
//!   and is updated by composing the per-frame rotation ΔR, R ← R·ΔR (`units::rotation`),
//!   optionally followed by one Newton–Schulz re-orthonormalisation step.
//!
//! Pipeline position: host/pose side of each frame; the matrices feed the transform unit in
//! place of the host's f64 pose (`super::run`).

use crate::world::scene::InstanceKey;
use glam::DMat3;
use rtl_model::fixed::{from_f64, Overflows, SignalId};
use rtl_model::units::cordic::Cordic;
use rtl_model::units::keyframe::{angle_at, euler_matrix, position_at, KeyframeConfig, Segment};
use rtl_model::units::rotation::{mul, orthonormalise, MatRaw, RotationConfig, RotationSignals};

/// Names of the pose path's overflow signals, in [`signals`] order.
pub const POSE_SIGNAL_NAMES: [&str; 4] = [
    "pose/host",
    "pose/position",
    "pose/matrix",
    "pose/correction",
];

/// Ids of [`POSE_SIGNAL_NAMES`].
pub mod signals {
    use rtl_model::fixed::SignalId;
    /// A host-written value (key, step, frame count, ΔR) out of its format.
    pub const HOST: SignalId = SignalId(0);
    /// Interpolated translation out of range.
    pub const POSITION: SignalId = SignalId(1);
    /// A matrix entry out of range.
    pub const MATRIX: SignalId = SignalId(2);
    /// The Newton–Schulz correction out of its format.
    pub const CORRECTION: SignalId = SignalId(3);
}

/// A fresh overflow table of the pose path.
pub fn pose_overflow_table() -> Overflows {
    Overflows::new(&POSE_SIGNAL_NAMES)
}

/// Angle in degrees as a binary angle at a key: turns, reduced to [−½, ½).
fn turns(deg: f64) -> f64 {
    let t = deg / 360.0;
    t - t.round()
}

/// The key segment around `frame` and the frames since its first key (the host's control
/// logic): before the first key and after the last, the value holds (step 0).
fn bracket(keys: &[InstanceKey], frame: f64) -> (usize, Option<usize>, f64) {
    let last = keys.len() - 1;
    if frame <= keys[0].frame {
        return (0, None, 0.0);
    }
    if frame >= keys[last].frame {
        return (last, None, 0.0);
    }
    let hi = keys.partition_point(|k| k.frame <= frame);
    (hi - 1, Some(hi), frame - keys[hi - 1].frame)
}

/// Keyframes interpolated in fixed point every frame.
pub struct KeyframePath {
    keys: Vec<InstanceKey>,
    cfg: KeyframeConfig,
    cordic: Cordic,
}

impl KeyframePath {
    /// The path for an instance's keys (at least one).
    pub fn new(keys: &[InstanceKey], cfg: &KeyframeConfig) -> Self {
        Self {
            keys: keys.to_vec(),
            cfg: *cfg,
            cordic: Cordic::new(&cfg.cordic),
        }
    }

    /// The world-from-local matrix (columns, `mat`) and translation (`pos`) at `frame`.
    pub fn at(&self, frame: u32, ov: &mut Overflows) -> (MatRaw, [i64; 3]) {
        let c = &self.cfg;
        let (lo, hi, k) = bracket(&self.keys, f64::from(frame));
        let (a, b) = (&self.keys[lo], hi.map(|h| &self.keys[h]));
        let span = b.map_or(1.0, |b| b.frame - a.frame);
        let kc = from_f64(k, c.frame, ov, signals::HOST);
        let angles = [0, 1, 2].map(|i| {
            let step = b.map_or(0.0, |b| {
                (b.rotation_deg[i] - a.rotation_deg[i]) / 360.0 / span
            });
            let s = Segment {
                base: from_f64(turns(a.rotation_deg[i]), c.angle_base, ov, signals::HOST),
                step: from_f64(step, c.angle_step, ov, signals::HOST),
            };
            angle_at(&s, kc, c)
        });
        let centre = [0, 1, 2].map(|i| {
            let step = b.map_or(0.0, |b| (b.translation[i] - a.translation[i]) / span);
            let s = Segment {
                base: from_f64(a.translation[i], c.pos, ov, signals::HOST),
                step: from_f64(step, c.pos_step, ov, signals::HOST),
            };
            position_at(&s, kc, c, ov, signals::POSITION)
        });
        let m = euler_matrix(angles, &self.cordic, c, ov, signals::MATRIX);
        (m, centre)
    }
}

/// A matrix register updated by composing a per-frame rotation.
pub struct IncrementalPath {
    r: MatRaw,
    delta: MatRaw,
    reorthonormalise: bool,
    cfg: RotationConfig,
}

/// A matrix quantised into a format (the host writing it).
fn quantised(m: &DMat3, f: rtl_model::fixed::Format, ov: &mut Overflows, sig: SignalId) -> MatRaw {
    [m.x_axis, m.y_axis, m.z_axis].map(|c| c.to_array().map(|v| from_f64(v, f, ov, sig)))
}

impl IncrementalPath {
    /// Starts from the exact first pose `r0` and the exact per-frame rotation `delta` (both
    /// quantised once by the host).
    pub fn new(
        r0: &DMat3,
        delta: &DMat3,
        reorthonormalise: bool,
        cfg: &RotationConfig,
        ov: &mut Overflows,
    ) -> Self {
        Self {
            r: quantised(r0, cfg.acc, ov, signals::HOST),
            delta: quantised(delta, cfg.delta, ov, signals::HOST),
            reorthonormalise,
            cfg: *cfg,
        }
    }

    /// The current matrix (columns, `acc`).
    pub fn matrix(&self) -> &MatRaw {
        &self.r
    }

    /// One frame: R ← R·ΔR, then (if enabled) one Newton–Schulz step.
    pub fn advance(&mut self, ov: &mut Overflows) {
        let c = &self.cfg;
        self.r = mul(
            &self.r,
            c.acc,
            &self.delta,
            c.delta,
            c.acc,
            ov,
            signals::MATRIX,
        );
        if self.reorthonormalise {
            let sig = RotationSignals {
                mat: signals::MATRIX,
                corr: signals::CORRECTION,
            };
            self.r = orthonormalise(&self.r, c, ov, sig);
        }
    }
}
