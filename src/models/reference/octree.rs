//! What the walker needs from an octree, and its two implementations: the packed memory
//! image (what the hardware reads) and an SDF evaluated on demand (for trees too deep to
//! store, e.g. the default car at depth 16).
//!
//! Both give exactly the same solid leaves for an SDF asset (the image is built from
//! [`SdfOctree::leaves`], which applies the same rules), so a walk finds the same first leaf
//! with either; only the count of nodes visited may differ, because the implicit tree keeps
//! nodes that pass the culling test but hold no leaf.

use crate::world::assets::voxelize::SdfOctree;
use glam::DVec3;
use rtl_model::svo::{ChildDescriptor, ChildRef, LeafAttr, SvoImage};

/// A child of a node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Child<N, L> {
    /// No child with that label.
    Empty,
    /// A solid leaf.
    Leaf(L),
    /// An internal node.
    Node(N),
}

/// An octree the walker can descend.
pub trait Octree: Sync {
    /// Handle of an internal node (what the walker keeps on its stack).
    type Node: Copy + Default;
    /// Handle of a leaf.
    type Leaf: Copy;
    /// Levels below the root.
    fn depth(&self) -> u8;
    /// The root.
    fn root(&self) -> Self::Node;
    /// Child `label` (x = 4, y = 2, z = 1) of `node`.
    fn child(&self, node: &Self::Node, label: u8) -> Child<Self::Node, Self::Leaf>;
    /// False only if child `label` is certainly [`Child::Empty`]: a cheap test the walker
    /// makes before the child's t-interval (an image reads one descriptor bit; an implicit
    /// tree, where emptiness costs an SDF evaluation, always says it may).
    #[inline]
    fn may_have_child(&self, _node: &Self::Node, _label: u8) -> bool {
        true
    }
    /// A leaf's colour and normal.
    fn attr(&self, leaf: Self::Leaf) -> LeafAttr;
}

/// An image node: its address and its descriptor word (fetched on descent).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImageNode {
    /// Word address of the descriptor.
    pub addr: u32,
    /// The descriptor word.
    pub desc: u32,
}

impl Octree for SvoImage {
    type Node = ImageNode;
    /// Index into the attribute array.
    type Leaf = u32;

    fn depth(&self) -> u8 {
        SvoImage::depth(self)
    }

    #[inline]
    fn root(&self) -> ImageNode {
        let addr = SvoImage::root();
        ImageNode {
            addr,
            desc: self.nodes()[addr as usize],
        }
    }

    #[inline]
    fn child(&self, node: &ImageNode, label: u8) -> Child<ImageNode, u32> {
        match SvoImage::child(self, node.addr, ChildDescriptor::unpack(node.desc), label) {
            ChildRef::Empty => Child::Empty,
            ChildRef::Leaf(i) => Child::Leaf(i),
            ChildRef::Node(addr) => Child::Node(ImageNode {
                addr,
                desc: self.nodes()[addr as usize],
            }),
        }
    }

    #[inline]
    fn may_have_child(&self, node: &ImageNode, label: u8) -> bool {
        ChildDescriptor::unpack(node.desc).valid & (1 << label) != 0
    }

    #[inline]
    fn attr(&self, leaf: u32) -> LeafAttr {
        self.attrs()[leaf as usize]
    }
}

/// A node of an implicit SDF octree: its level and centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SdfNode {
    /// Level (root 0).
    pub level: u8,
    /// Centre in asset coordinates.
    pub centre: DVec3,
}

impl Octree for SdfOctree {
    type Node = SdfNode;
    /// (leaf centre, parent centre).
    type Leaf = (DVec3, DVec3);

    fn depth(&self) -> u8 {
        SdfOctree::depth(self)
    }

    fn root(&self) -> SdfNode {
        SdfNode {
            level: 0,
            centre: DVec3::ZERO,
        }
    }

    fn child(&self, node: &SdfNode, label: u8) -> Child<SdfNode, (DVec3, DVec3)> {
        if node.level == 0 && !self.keep(node.centre, 0) {
            return Child::Empty;
        }
        let q = self.half() / f64::from(1u32 << (node.level + 1));
        let c = node.centre
            + DVec3::new(
                if label & 4 != 0 { q } else { -q },
                if label & 2 != 0 { q } else { -q },
                if label & 1 != 0 { q } else { -q },
            );
        let level = node.level + 1;
        if level == self.depth() {
            if self.solid(c) {
                Child::Leaf((c, node.centre))
            } else {
                Child::Empty
            }
        } else if self.keep(c, level) {
            Child::Node(SdfNode { level, centre: c })
        } else {
            Child::Empty
        }
    }

    fn attr(&self, leaf: (DVec3, DVec3)) -> LeafAttr {
        SdfOctree::attr(self, leaf.0, leaf.1)
    }
}
