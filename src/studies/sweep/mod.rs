//! Accuracy against cost over datapath configurations (`sim sweep`): which formats and unit
//! parameters buy how much error for how many cycles, DSP slices and RAM bits.
//!
//! Pipeline position: a study over the whole fixed-point datapath and the cycle model.
//! [`configs`] gives the configurations (a built-in list derived from the default, or a RON
//! file), [`run`] renders every scene with the f64 reference once and with the cycle model per
//! configuration, [`measure`] turns the record pairs into error figures and [`cost`] the
//! configuration into hardware figures, [`pareto`] finds the fronts and each configuration's
//! distance to them, and [`output`] and [`plot`] write CSV, JSON and two PNGs.
//! `docs/accuracy.md` defines every figure and shows a measured run.

pub mod command;
pub mod configs;
pub mod cost;
pub mod measure;
pub mod output;
pub mod pareto;
pub mod plot;
pub mod run;

pub use run::{run_sweep, NamedScene, SweepError, SweepOptions, SweepResult, SweepRow};
