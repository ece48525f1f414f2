//! The cycle-accurate, transaction-level model of the pipeline (DESIGN.md §6): the frame's
//! stages stepped clock by clock over the timing parts of `rtl_model::cycle` (FIFOs, unit
//! pipes, walker pool, node memory, hit-buffer BRAM), bit-exact with the functional
//! fixed-point model, with per-frame cycle reports and waveforms.
//!
//! Pipeline position: `sim` (the default model). Per frame: the functional model runs the
//! frame in parallel and records its work (`models::fixed::trace`); `pipeline::CycleModel`
//! times it and checks every decision and the final hit buffer against it.

pub mod bench;
pub mod layout;
pub mod pipeline;
pub mod runner;
pub mod stats;
pub mod waves;

pub use layout::SceneLayout;
pub use pipeline::{CycleError, CycleModel, CycleOptions};
pub use stats::CycleFrame;
