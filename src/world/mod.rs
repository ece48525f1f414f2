//! The world: what the pipeline renders, built offline before any frame.
//!
//! [`scene`] reads and validates a scene (RON) and gives each frame's camera and poses;
//! [`sdf`] holds the procedural shapes; [`assets`] turns a scene's asset specs (SDF or `.vox`)
//! into the SVO memory images of `rtl_model::svo` that every model walks.

pub mod assets;
pub mod scene;
pub mod sdf;
