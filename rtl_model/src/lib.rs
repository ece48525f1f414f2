//! Hardware-visible side of the animated-SVO ray-tracing pipeline.
//!
//! This crate owns everything the hardware sees. Today that is the SVO memory image
//! ([`svo`]): the 32-bit child descriptors the octree walker fetches, the far-pointer escape,
//! and the separate leaf-attribute array. The fixed-point units, the cycle model and the
//! vector encoders join it later; the root package (`svo_sim`) builds inputs for it from
//! scenes and drives both the f64 reference and this model.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod cost;
pub mod cycle;
pub mod datapath;
pub mod fixed;
pub mod resources;
pub mod svo;
pub mod units;
pub mod vectors;
