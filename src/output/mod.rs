//! Outputs of a run: shaded PNGs, per-pixel record dumps, the JSON report, and the one output
//! writer they all go through (`writer`: nothing half-written is ever left under the final
//! name, and a device, FIFO or symlink given as a path is written, never replaced), with the
//! registry of its temporaries and the clean exit on SIGINT/SIGTERM.

pub mod config_text;
pub mod dump;
pub mod figure;
pub mod interrupt;
pub mod model_dump;
pub mod png;
pub mod report;
pub mod temporaries;
pub mod text;
pub mod writer;
