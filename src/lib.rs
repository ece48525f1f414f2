//! `svo_sim`: scenes, SVO assets, the f64 reference of the animated-SVO ray tracer of
//! Espe, Gjermundnes & Hendseth (2019), and the `sim` command line.
//!
//! Data flow of a frame (see `docs/reference.md`): [`scene`] gives the camera and every
//! instance's pose; [`reference`] generates a ray per pixel, tests it against each instance's
//! bounding sphere, sorts the candidates front to back, transforms the ray into each
//! candidate's local frame and walks its octree ([`assets`] built it, in the memory image of
//! [`rtl_model::svo`]) until the nearest hit is certain; the hit buffer lets unchanged pixels
//! skip all of that in the next frame. [`output`] turns records into PNGs, dumps and reports.
#![forbid(unsafe_code)]

pub mod assets;
pub mod cycle_model;
pub mod drift;
pub mod elaborate;
pub mod error;
pub mod fixed_model;
pub mod output;
pub mod reference;
pub mod run;
pub mod scene;
pub mod sdf;
pub mod stress;
pub mod sweep;
pub mod vectors;

pub use error::{AssetError, SceneError};
