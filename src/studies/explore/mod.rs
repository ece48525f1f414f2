//! The hardware design space (`sim explore`): fps against LUT, FF, DSP48E2, BRAM36 and URAM288
//! over a cross product of hardware fields, on several scenes, with the points that fit the
//! part, the default and the best fitting point marked on the Pareto fronts.
//!
//! Pipeline position: a study over the hardware configuration and the cycle model. [`space`]
//! reads the space (fields by their path in the hardware file, scenes, sampled timing) and
//! checks every point, [`run`] times every point on every scene and prices it with the
//! resource and fabric estimates (`rtl_model::cost`), [`output`] and [`plot`] write CSV, JSON
//! and five PNGs, and [`command`] is the command line's text. docs/explore.md has the format
//! and a measured run.

pub mod command;
pub mod output;
pub mod plot;
pub mod run;
pub mod space;

pub use run::{run_explore, ExploreError, ExploreResult, ExploreRow};
pub use space::{Point, Space, SpaceError};
