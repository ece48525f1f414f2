//! Signed distance functions for procedural assets: primitives, rigid placement, CSG, paint.
//!
//! Pipeline position: offline, before the SVO memory image. The voxeliser
//! ([`crate::world::assets::voxelize`]) evaluates these to decide which octree nodes can hold
//! surface voxels. Every shape here is 1-Lipschitz (an exact distance or a lower bound of
//! one), which is what makes the voxeliser's culling conservative.

mod eval;
mod shape;

pub use eval::{rotation_xyz_deg, Sdf, SdfSample};
pub use shape::{Axis, Shape};
