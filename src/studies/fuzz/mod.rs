//! The parser fuzzer: seeded mutations of real `.vox` models, scene files and hardware and
//! datapath configurations, each run through the loader a user's input meets, so that every
//! input ends in a result or a clear error — never a panic, a hang or unbounded memory
//! (docs/fuzz.md).
//!
//! [`corpus`] (the seeds), [`mutate`] (the edits), [`targets`] (the parsers and what consumes
//! their output), [`runner`] (the loop under a time limit, panics caught) and [`command`]
//! (`sim fuzz`).

pub mod command;
pub mod corpus;
pub mod mutate;
pub mod runner;
pub mod targets;

pub use command::{fuzz, run_command, FuzzCommand, FuzzSummary};
pub use targets::Target;
