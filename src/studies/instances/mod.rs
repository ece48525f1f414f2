//! `sim instances`: frame rate against instance count for the flat and the two-level instance
//! scheme (docs/instances.md §8): modelled fps at 1280×768 for 1 … 10,000 instances, still
//! and moving camera, with the limit that holds at each point; the functional models' speed at
//! 1,000 instances against 8; the hit buffer's reuse against instance count and motion.
//!
//! Pipeline position: a study (many runs of the models); [`scene`] makes the crowds,
//! [`measure`] runs them, [`plot`] draws `instances.png`, [`command`] prints and writes.

pub mod command;
pub mod measure;
pub mod plot;
pub mod scene;
