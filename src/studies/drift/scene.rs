//! The drift experiment's animation: one procedural part spinning about a tilted axis for as
//! many frames as asked, seen by a still camera.
//!
//! Pipeline position: the input of `sim drift`. Only the y Euler angle is keyed (x and z are
//! held at a tilt), so R(n) = Rz(c)·Ry(ω·n)·Rx(a) and R(n + 1) = R(n)·ΔR with the constant
//! ΔR = Rx(a)ᵀ·Ry(ω)·Rx(a): a rotation about a tilted axis that touches all nine matrix
//! entries, which both pose paths (keyframes and incremental updates) can follow exactly in
//! exact arithmetic. The part sits off the origin so that o − c is generic.

use crate::world::scene::{
    AssetSource, AssetSpec, CameraKey, InstanceKey, InstanceSpec, Light, SceneFile,
};
use crate::world::sdf::{Axis, Shape};

/// Spin per frame about the tilted axis, degrees (not a divisor of a turn, so no frame
/// repeats an earlier pose exactly).
pub const SPIN_DEG_PER_FRAME: f64 = 3.7;
/// Fixed tilt: Euler x and z angles, degrees.
pub const TILT_DEG: [f64; 2] = [23.0, 11.0];
/// Where the part's centre sits (metres).
pub const CENTRE: [f64; 3] = [0.3, 0.1, -0.2];

/// The part: a rounded slab pierced by a cylinder, with a sphere bitten out of one face and a
/// torus around it, so every view shows edges at several angles.
fn part() -> Shape {
    Shape::Union(vec![
        Shape::Paint {
            rgb: [200, 120, 60],
            shape: Box::new(Shape::Difference {
                base: Box::new(Shape::RoundBox {
                    half: [0.8, 0.5, 0.35],
                    radius: 0.1,
                }),
                minus: vec![
                    Shape::Moved {
                        offset: [0.0, 0.0, 0.35],
                        rotation_deg: [0.0; 3],
                        shape: Box::new(Shape::Sphere { radius: 0.25 }),
                    },
                    Shape::Cylinder {
                        radius: 0.15,
                        half_length: 1.0,
                        axis: Axis::X,
                    },
                ],
            }),
        },
        Shape::Paint {
            rgb: [60, 140, 210],
            shape: Box::new(Shape::Torus {
                major: 0.55,
                minor: 0.08,
                axis: Axis::Z,
            }),
        },
    ])
}

/// The scene for `frames` frames at `width`×`height`, the part at octree `depth`.
pub fn drift_scene(frames: u32, width: u32, height: u32, depth: u8) -> SceneFile {
    let last = f64::from(frames.saturating_sub(1).max(1));
    let key = |frame: f64, spin: f64| InstanceKey {
        frame,
        translation: CENTRE,
        rotation_deg: [TILT_DEG[0], spin, TILT_DEG[1]],
        scale: [1.0; 3],
    };
    SceneFile {
        resolution: (width, height),
        frames,
        background: [40, 44, 52],
        light: Light::default(),
        camera: vec![CameraKey {
            frame: 0.0,
            position: [0.4, 1.3, 3.2],
            look_at: CENTRE,
            up: [0.0, 1.0, 0.0],
            vfov_deg: 40.0,
        }],
        assets: vec![AssetSpec {
            name: "part".into(),
            depth,
            source: AssetSource::Sdf {
                shape: part(),
                half_extent: Some(1.0),
            },
        }],
        instances: vec![InstanceSpec {
            name: "spinner".into(),
            asset: "part".into(),
            pivot: [0.0; 3],
            keys: vec![key(0.0, 0.0), key(last, SPIN_DEG_PER_FRAME * last)],
        }],
        crowds: Vec::new(),
    }
}
