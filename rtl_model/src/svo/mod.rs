//! The SVO memory image: what the octree walker reads from node memory.
//!
//! Pipeline position: produced offline by the asset builders (root package), read by the
//! octree walker once per node descent. The bit layout is specified in `docs/svo-format.md`
//! and implemented by [`descriptor`] (node words), [`attr`] (leaf attributes) and
//! [`build`] (the layout of nodes in memory); [`fetch`] names the kinds of word a walker
//! reads.

pub mod attr;
pub mod build;
pub mod descriptor;
pub mod fetch;
pub mod image;
pub mod leaf_set;
pub mod morton;

pub use attr::LeafAttr;
pub use build::{BuildError, ImageLayout};
pub use descriptor::ChildDescriptor;
pub use fetch::FetchKind;
pub use image::{ChildRef, SvoImage, SvoStats};
pub use leaf_set::{LeafSet, LeafSetError, MAX_DEPTH};
