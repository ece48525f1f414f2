//! Stiff and extreme cases (`sim stress`): one frame each, rendered by the f64 reference and
//! the fixed-point model, every difference checked against the datapath's documented bound,
//! and a verdict per case — pass, flagged (the default formats cannot represent the case and
//! the model reports it) or FAIL (a silently wrong pixel).
//!
//! Pipeline position: the whole frame pipeline (ray generation to hit record), driven with
//! exact frame states. [`cases`] lists the cases, [`build`] builds their frames,
//! [`measure`] renders and judges one, [`report`] writes the table (`docs/stability.md`),
//! CSV and JSON, and [`command`] is `sim stress`.

pub mod build;
pub mod cases;
pub mod command;
pub mod measure;
pub mod report;

pub use measure::{CaseResult, Verdict};
