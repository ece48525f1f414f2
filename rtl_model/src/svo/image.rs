//! The packed SVO memory image and the accessors the walkers use.
//!
//! `nodes` is the node memory: word 0 is the root's descriptor; every internal node's
//! children occupy one contiguous group of slots, one word per valid child in label order —
//! a child descriptor for an internal child, an index into `attrs` for a leaf child — followed
//! by the group's far words. Layout and far-pointer rules: `docs/svo-format.md`.

use super::{morton, ChildDescriptor, LeafAttr, LeafSet};

/// What a child label of a node refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChildRef {
    /// No child with that label.
    Empty,
    /// A solid leaf voxel; index into the attribute array.
    Leaf(u32),
    /// An internal node; its descriptor's word address.
    Node(u32),
}

/// Sizes of an image, for reports.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SvoStats {
    /// Levels below the root.
    pub depth: u8,
    /// Internal nodes (child descriptors), root included.
    pub nodes: u64,
    /// Solid leaf voxels.
    pub leaves: u64,
    /// Far-pointer words.
    pub far_words: u64,
    /// Node memory in bytes (descriptors, leaf slots and far words).
    pub node_bytes: u64,
    /// Attribute memory in bytes.
    pub attr_bytes: u64,
    /// Internal nodes per level, root first.
    pub nodes_per_level: Vec<u64>,
}

/// A complete SVO memory image.
///
/// ```
/// use rtl_model::svo::{ChildRef, LeafAttr, LeafSet, SvoImage};
/// let red = LeafAttr::new([255, 0, 0, 255], [0.0, 1.0, 0.0]);
/// let set = LeafSet::from_coords(2, [([3, 0, 1], red)]).unwrap();
/// let img = SvoImage::build(&set).unwrap();
/// assert_eq!(img.leaf_at([3, 0, 1]), Some(red));
/// assert_eq!(img.leaf_at([0, 0, 0]), None);
/// // The root's only child is label 4 (x = 1 of the upper half), an internal node.
/// let root = img.descriptor(SvoImage::root());
/// assert_eq!(root.valid, 0b1_0000);
/// assert!(matches!(img.child(0, root, 4), ChildRef::Node(_)));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SvoImage {
    pub(super) depth: u8,
    pub(super) nodes: Vec<u32>,
    pub(super) attrs: Vec<LeafAttr>,
    pub(super) stats: SvoStats,
}

impl SvoImage {
    /// Levels below the root (leaves sit at this level).
    #[inline]
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// The node memory words.
    #[inline]
    pub fn nodes(&self) -> &[u32] {
        &self.nodes
    }

    /// The leaf attribute array.
    #[inline]
    pub fn attrs(&self) -> &[LeafAttr] {
        &self.attrs
    }

    /// Statistics computed at build time.
    pub fn stats(&self) -> &SvoStats {
        &self.stats
    }

    /// Address of the root descriptor.
    #[inline]
    pub const fn root() -> u32 {
        0
    }

    /// Fetches and decodes the descriptor at `addr` (one node-memory read).
    #[inline]
    pub fn descriptor(&self, addr: u32) -> ChildDescriptor {
        ChildDescriptor::unpack(self.nodes[addr as usize])
    }

    /// Word address of the children's group of the node at `addr` (a second read when the
    /// far escape is used).
    #[inline]
    pub fn group_base(&self, addr: u32, d: ChildDescriptor) -> u32 {
        let off = if d.far {
            self.nodes[(addr + u32::from(d.ptr)) as usize]
        } else {
            u32::from(d.ptr)
        };
        addr + off
    }

    /// Resolves child `label` (0..8) of the node at `addr` whose descriptor is `d`.
    #[inline]
    pub fn child(&self, addr: u32, d: ChildDescriptor, label: u8) -> ChildRef {
        let bit = 1u8 << label;
        if d.valid & bit == 0 {
            return ChildRef::Empty;
        }
        let slot = self.group_base(addr, d) + d.slot(label);
        if d.leaf & bit != 0 {
            ChildRef::Leaf(self.nodes[slot as usize])
        } else {
            ChildRef::Node(slot)
        }
    }

    /// The leaf at integer coordinates, found by descending from the root.
    pub fn leaf_at(&self, c: [u32; 3]) -> Option<LeafAttr> {
        let limit = 1u64 << self.depth;
        if c.iter().any(|&v| u64::from(v) >= limit) {
            return None;
        }
        let code = morton::encode(c[0], c[1], c[2]);
        let mut addr = Self::root();
        for level in (0..self.depth).rev() {
            let label = ((code >> (3 * u32::from(level))) & 7) as u8;
            match self.child(addr, self.descriptor(addr), label) {
                ChildRef::Empty => return None,
                ChildRef::Leaf(i) => return Some(self.attrs[i as usize]),
                ChildRef::Node(a) => addr = a,
            }
        }
        None
    }

    /// Decodes every leaf back into a [`LeafSet`] (depth-first walk of the whole image).
    pub fn to_leaf_set(&self) -> LeafSet {
        let mut out = Vec::with_capacity(self.attrs.len());
        let mut stack = vec![(Self::root(), 0u64, 0u8)];
        while let Some((addr, code, level)) = stack.pop() {
            let d = self.descriptor(addr);
            for label in (0..8u8).rev() {
                let child_code = (code << 3) | u64::from(label);
                match self.child(addr, d, label) {
                    ChildRef::Empty => {}
                    ChildRef::Leaf(i) => {
                        let shift = 3 * u32::from(self.depth - level - 1);
                        // A leaf above the last level stands for its whole block; the builders
                        // only make last-level leaves, so record its first voxel.
                        out.push((child_code << shift, self.attrs[i as usize]));
                    }
                    ChildRef::Node(a) => stack.push((a, child_code, level + 1)),
                }
            }
        }
        out.sort_by_key(|&(c, _)| c);
        LeafSet::from_sorted_codes(self.depth, out).expect("image depth is valid")
    }
}
