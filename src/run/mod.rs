//! Running a model over an animation.
//!
//! Pipeline position: between the world and the outputs. [`elaborate`] derives from the scene
//! the pipeline it needs (units kept, left out or resized, with what each saves); [`frames`]
//! builds the assets and runs every frame through the chosen model — the f64 reference, the
//! fixed-point functional model, or the cycle model beside it — comparing each frame with the
//! reference and handing the results to [`crate::output`]; [`ranges`] first checks that the
//! scene fits the datapath's formats, [`memory`] that the run fits the machine's memory. [`render`] is the one run without a scene: a bare `.vox`
//! through the reference walk with a camera in the model's own coordinates (`sim render`).

pub mod bench;
pub mod config_files;
pub mod cycle_bench;
pub mod elaborate;
pub mod frame_models;
pub mod frames;
pub mod memory;
pub mod parallel;
pub mod peer_bench;
pub mod ranges;
pub mod render;
pub mod run_files;

pub use frames::{build, run, Model, RunConfig, RunOutput, VcdRequest};
