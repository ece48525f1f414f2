//! A set of solid leaf voxels at one depth, in Morton order: the builders' output and the
//! memory-image builder's input.

use super::{morton, LeafAttr};
use thiserror::Error;

/// Deepest octree the image format and the walkers support: 20 levels keep a leaf's Morton
/// code within 60 bits and its coordinates within 20 bits per axis.
pub const MAX_DEPTH: u8 = 20;

/// Why a leaf set could not be made.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum LeafSetError {
    /// Depth outside 1..=MAX_DEPTH.
    #[error("octree depth {0} is out of range (1 to {MAX_DEPTH})")]
    Depth(u8),
    /// A coordinate does not fit the depth.
    #[error("leaf coordinate {coord:?} does not fit an octree of depth {depth} (each below {})", 1u64 << depth)]
    Coordinate {
        /// The offending coordinate.
        coord: [u32; 3],
        /// The depth.
        depth: u8,
    },
}

/// Solid leaves of an octree of `depth` levels below the root (2^depth voxels per axis),
/// sorted by Morton code, no duplicates.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeafSet {
    depth: u8,
    leaves: Vec<(u64, LeafAttr)>,
}

impl LeafSet {
    /// An empty set of the given depth.
    pub fn empty(depth: u8) -> Result<Self, LeafSetError> {
        if depth == 0 || depth > MAX_DEPTH {
            return Err(LeafSetError::Depth(depth));
        }
        Ok(Self {
            depth,
            leaves: Vec::new(),
        })
    }

    /// Builds a set from leaves in any order. Where a coordinate appears more than once the
    /// first occurrence wins (stable sort), so composition order is the priority order.
    pub fn from_coords(
        depth: u8,
        leaves: impl IntoIterator<Item = ([u32; 3], LeafAttr)>,
    ) -> Result<Self, LeafSetError> {
        let mut set = Self::empty(depth)?;
        let limit = 1u64 << depth;
        for (c, a) in leaves {
            if c.iter().any(|&v| u64::from(v) >= limit) {
                return Err(LeafSetError::Coordinate { coord: c, depth });
            }
            set.leaves.push((morton::encode(c[0], c[1], c[2]), a));
        }
        set.leaves.sort_by_key(|&(code, _)| code);
        set.leaves.dedup_by_key(|&mut (code, _)| code);
        Ok(set)
    }

    /// Builds a set from Morton codes, normally already sorted and unique (the SDF builder's
    /// output, taken as it is after a linear check). Codes must fit the depth; input that is
    /// not strictly increasing is sorted and deduplicated (the first occurrence wins).
    pub fn from_sorted_codes(
        depth: u8,
        leaves: Vec<(u64, LeafAttr)>,
    ) -> Result<Self, LeafSetError> {
        let mut set = Self::empty(depth)?;
        let limit = 1u64 << (3 * u32::from(depth));
        let sorted = leaves.windows(2).all(|w| w[0].0 < w[1].0);
        if let Some(&(code, _)) = leaves.iter().find(|&&(c, _)| c >= limit) {
            return Err(LeafSetError::Coordinate {
                coord: morton::decode(code),
                depth,
            });
        }
        set.leaves = leaves;
        if !sorted {
            set.leaves.sort_by_key(|&(code, _)| code);
            set.leaves.dedup_by_key(|&mut (code, _)| code);
        }
        Ok(set)
    }

    /// Levels below the root.
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// Number of solid leaves.
    pub fn len(&self) -> usize {
        self.leaves.len()
    }

    /// True when no voxel is solid.
    pub fn is_empty(&self) -> bool {
        self.leaves.is_empty()
    }

    /// (Morton code, attributes), ascending by code.
    pub fn leaves(&self) -> &[(u64, LeafAttr)] {
        &self.leaves
    }

    /// Leaves as integer coordinates with attributes, in Morton order.
    pub fn coords(&self) -> impl Iterator<Item = ([u32; 3], LeafAttr)> + '_ {
        self.leaves.iter().map(|&(c, a)| (morton::decode(c), a))
    }
}
