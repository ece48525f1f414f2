//! Does a scene fit the datapath's formats? Checked before a fixed-point or cycle run, frame by
//! frame, on exactly the host-side values the hardware is programmed with, so that a scene the
//! formats cannot represent stops with an error naming the value, the format's range and the
//! remedy, before any file is written, rather than running on saturated values.
//!
//! Pipeline position: in [`super::frames::run`], after the assets are built (their half sizes
//! give each instance's extent) and before the first output. What is checked, per frame:
//! - the camera position and every instance's centre, against the ray-generation position
//!   format (`raygen.pos`, quantised once per frame by the host);
//! - the distance from the camera to every instance's centre, against the sphere unit's reach
//!   (`sphere.reach`; beyond it the unit keeps the sphere with entry 0 and counts it);
//! - the camera in every instance's frame, Rᵀ(o − c), against the transform's local position
//!   format (`transform.local_pos`).
//!
//! A run that saturates anyway (a format narrowed by `--datapath` below what a value inside
//! these ranges needs) is still caught after the run (`output::text::saturation_warning`).

use crate::world::scene::Scene;
use glam::DVec3;
use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::Format;
use thiserror::Error;

/// Why a scene does not fit the datapath.
#[derive(Debug, Error, PartialEq)]
pub enum RangeError {
    /// A value outside the range of the datapath format it is carried in.
    #[error("{}: frame {}: {} = {:.3} m is outside {} ({}); {}", .0.origin, .0.frame, .0.what, .0.value, .0.signal, .0.range, .0.remedy)]
    OutOfRange(Box<OutOfRange>),
    /// The frame's state could not be computed (a scene error the loader did not catch).
    #[error("{origin}: frame {frame}: {message}")]
    Frame {
        /// The scene, for the message.
        origin: String,
        /// The frame.
        frame: u32,
        /// What went wrong.
        message: String,
    },
}

/// A scene value outside the range of the datapath format it is carried in.
#[derive(Debug, PartialEq)]
pub struct OutOfRange {
    /// The scene, for the message.
    pub origin: String,
    /// The first frame where it happens.
    pub frame: u32,
    /// Which value (the camera, an instance's centre or distance).
    pub what: String,
    /// The value, metres.
    pub value: f64,
    /// The datapath signal that carries it.
    pub signal: &'static str,
    /// The signal's range, as text.
    pub range: String,
    /// What the user can do.
    pub remedy: &'static str,
}

const REMEDY: &str = "scale the scene down or move it nearer the origin (positions are in \
metres), or widen the format with --datapath (docs/number-formats.md §2)";

fn format_range(f: Format) -> (f64, f64, String) {
    let (lo, hi) = (f.min_value(), f.max_value());
    (lo, hi, format!("{}: {lo} to {hi} m", f.name()))
}

/// Checks every frame of `scene` (assets of half sizes `half`) against `dp`'s formats.
pub fn check_scene_ranges(
    scene: &Scene,
    half: &[f64],
    dp: &DatapathConfig,
) -> Result<(), RangeError> {
    let (pos_lo, pos_hi, pos_text) = format_range(dp.raygen.pos);
    let (loc_lo, loc_hi, loc_text) = format_range(dp.transform.local_pos);
    let names: Vec<&str> = scene
        .file
        .instances
        .iter()
        .map(|i| i.name.as_str())
        .collect();
    let err = |frame, what: String, value, signal, range: &str| {
        RangeError::OutOfRange(Box::new(OutOfRange {
            origin: scene.origin.clone(),
            frame,
            what,
            value,
            signal,
            range: range.to_string(),
            remedy: REMEDY,
        }))
    };
    // The component of `v` furthest outside [lo, hi], if any.
    let outside =
        |v: DVec3, lo: f64, hi: f64| (0..3).map(|k| v[k]).find(|&x| !(lo..=hi).contains(&x));
    for f in 0..scene.file.frames {
        let state = scene
            .frame_state(f, half)
            .map_err(|message| RangeError::Frame {
                origin: scene.origin.clone(),
                frame: f,
                message,
            })?;
        let o = state.camera.position;
        if let Some(x) = outside(o, pos_lo, pos_hi) {
            return Err(err(
                f,
                "the camera position".into(),
                x,
                "raygen.pos",
                &pos_text,
            ));
        }
        for (k, pose) in state.poses.iter().enumerate() {
            let name = names.get(k).copied().unwrap_or("?");
            if let Some(x) = outside(pose.centre, pos_lo, pos_hi) {
                return Err(err(
                    f,
                    format!("the centre of instance {name}"),
                    x,
                    "raygen.pos",
                    &pos_text,
                ));
            }
            let dist = (pose.centre - o).length();
            if dist > dp.sphere.reach {
                return Err(err(
                    f,
                    format!("the distance from the camera to instance {name}"),
                    dist,
                    "sphere.reach",
                    &format!("at most {} m", dp.sphere.reach),
                ));
            }
            let r = pose.world_from_local;
            let local = r.transpose() * (o - pose.centre);
            if let Some(x) = outside(local, loc_lo, loc_hi) {
                return Err(err(
                    f,
                    format!("the camera in the frame of instance {name}"),
                    x,
                    "transform.local_pos",
                    &loc_text,
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rtl_model::fixed::Quant;

    fn car() -> (Scene, Vec<f64>) {
        let scene = Scene::default_car().expect("the embedded scene");
        let half = vec![2.0; scene.file.assets.len()];
        (scene, half)
    }

    fn out_of_range(r: Result<(), RangeError>) -> OutOfRange {
        match r {
            Err(RangeError::OutOfRange(e)) => *e,
            other => panic!("expected a value out of range, got {other:?}"),
        }
    }

    #[test]
    fn the_default_scene_fits_the_default_formats() {
        let (scene, half) = car();
        assert_eq!(
            check_scene_ranges(&scene, &half, &DatapathConfig::default()),
            Ok(())
        );
    }

    #[test]
    fn each_range_is_checked_and_named() {
        let (scene, half) = car();
        // The camera is about 6.7 m from the body's centre.
        let mut dp = DatapathConfig::default();
        dp.sphere.reach = 2.0;
        let e = out_of_range(check_scene_ranges(&scene, &half, &dp));
        assert_eq!((e.frame, e.signal), (0, "sphere.reach"));
        assert!(e.what.contains("instance body"), "{e:?}");
        let mut dp = DatapathConfig::default();
        dp.transform.local_pos = Format::sq(3, 20).with_quant(Quant::RndConv); // ±4 m
        let e = out_of_range(check_scene_ranges(&scene, &half, &dp));
        assert_eq!(e.signal, "transform.local_pos");
        assert!(e.range.contains("sQ3.20: -4 to"), "{e:?}");
        let mut dp = DatapathConfig::default();
        dp.raygen.pos = Format::sq(3, 20).with_quant(Quant::RndConv);
        let e = out_of_range(check_scene_ranges(&scene, &half, &dp));
        assert_eq!((e.signal, e.value), ("raygen.pos", 4.6));
    }
}
