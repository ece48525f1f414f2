//! Error over animation run time (`sim drift`): how the two ways of keeping an animated
//! instance's rotation matrix in fixed point behave over a long animation.
//!
//! Pipeline position: the pose path in front of the sphere and transform units. [`scene`]
//! is the animation (a part spinning about a tilted axis), [`pose`] the two fixed-point pose
//! paths — (a) matrices rebuilt from the keyframes every frame, (b) a matrix register
//! updated by composing the per-frame rotation, with or without the Newton–Schulz
//! re-orthonormalisation of `rtl_model::units::rotation` — [`run`] renders every frame with
//! the f64 reference and with the fixed-point model for each path and measures, and
//! [`output`] and [`plot`] write CSV, JSON and PNG. `docs/drift.md` has the bounds, their
//! derivation and the measured figures.

pub mod command;
pub mod output;
pub mod plot;
pub mod pose;
pub mod run;
pub mod scene;

pub use run::{run_drift, DriftError, DriftOptions, DriftResult, Mode};
