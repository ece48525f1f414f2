//! The cycle-accurate, transaction-level model of the pipeline (docs/cycle-model.md §2): the
//! frame's stages stepped clock by clock over the timing parts of `rtl_model::cycle` (FIFOs,
//! unit pipes, walker pool, node memory, hit-buffer BRAM), bit-exact with the functional
//! fixed-point model, with per-frame cycle reports and waveforms.
//!
//! Pipeline position: `sim` (the default model). Per frame: the functional model runs the
//! frame beside it and records its work (`models::fixed::trace`); `model::CycleModel` builds
//! the frame's `pipeline::Pipeline` of `stages`, times the work and checks every decision and
//! the final hit buffer against it.

mod commit;
pub mod elaboration;
pub mod error;
mod fifos;
pub mod layout;
pub mod lift;
pub mod machine;
pub mod model;
pub mod pipeline;
pub mod runner;
pub mod sample;
mod stages;
pub mod stats;
pub mod validate;
pub mod waves;

pub use error::CycleError;
pub use layout::SceneLayout;
pub use model::{CycleModel, CycleOptions};
pub use stats::CycleFrame;
