//! Outputs of a run: shaded PNGs, per-pixel record dumps, the JSON report, and the atomic
//! file writing they share (nothing half-written is ever left under the final name).

pub mod atomic;
pub mod config_text;
pub mod dump;
pub mod figure;
pub mod model_dump;
pub mod png;
pub mod report;
pub mod text;
