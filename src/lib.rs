//! `svo_sim`: a cycle-accurate, transaction-level model of the FPGA ray-tracing pipeline for
//! animated sparse voxel octrees of Espe, Gjermundnes & Hendseth (2019), with the octree walk of
//! Revelles et al. (2000).
//!
//! The crate is four layers over the hardware-visible crate `rtl_model` (memory image,
//! fixed-point layer, units, cycle parts, vector encoding); `docs/architecture.md` draws them:
//!
//! - [`world`] — what is rendered: scenes (RON, validation, keyframes), procedural SDF shapes,
//!   and asset building (voxeliser, `.vox` loader) into SVO memory images.
//! - [`models`] — three models of one frame, each checked against the one before it: the f64
//!   [`models::reference`], the bit-exact fixed-point functional model [`models::fixed`], and
//!   the cycle model [`models::cycle`] that times the functional model's work clock by clock.
//! - [`run`] — running a model over an animation: elaboration of the pipeline a scene needs,
//!   the frame loop, accuracy and the report; [`output`] writes PNGs, dumps and reports.
//! - [`studies`] — what is run many times: accuracy against cost (`sweep`), error over run time
//!   (`drift`), stiff and extreme cases (`stress`), and HDL test vectors (`vectors`).
//!
//! Every input file is read through [`input`], which caps its size.
//!
//! The command line (`src/bin/sim/`) parses arguments and calls into these layers; no clap type
//! lives in the library.
#![forbid(unsafe_code)]

pub mod error;
pub mod input;
pub mod models;
pub mod output;
pub mod run;
pub mod studies;
pub mod world;

pub use error::{AssetError, SceneError};
