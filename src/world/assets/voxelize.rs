//! Sparse surface voxelisation of an SDF: the rules that decide which octree nodes and leaves
//! exist, used both to build a memory image and to walk an octree too large to store.
//!
//! Pipeline position: offline asset build, before [`rtl_model::svo::SvoImage::build`]; and,
//! for trees too deep to materialise, on demand inside the reference walker
//! ([`crate::models::reference::octree`]).
//!
//! A leaf of half-size h with centre c is solid iff −2h < sdf(c) ≤ 0: an inner shell one
//! voxel thick. The shell is watertight for rays: between face-adjacent voxels the centre
//! distance is 2h, so the (1-Lipschitz) SDF changes by at most 2h and a walk from outside
//! (sdf > 0) to deep inside (sdf ≤ −2h) must step on a shell voxel.
//! An internal node of half-size H is kept only if some leaf centre inside it could be in
//! the shell: its leaf centres lie within ρ = (H − h)·√3 of its centre C, so the node is
//! culled when sdf(C) − ρ > 0 or sdf(C) + ρ ≤ −2h. Culling is exact for exact SDFs and
//! conservative for bounds (a culled node never holds a shell leaf).
//! A leaf's colour is the SDF's paint at its centre; its normal is the SDF gradient at its
//! parent's centre (tetrahedral difference, step 2h), shared by siblings to save evaluations.

use crate::world::sdf::Sdf;
use glam::DVec3;
use rayon::prelude::*;
use rtl_model::svo::{morton, LeafAttr};

/// Levels expanded serially before the subtrees are handed to worker threads
/// (up to 8^3 = 512 tasks, enough to balance 2 to 64 cores).
const SPLIT_LEVEL: u8 = 3;

/// An SDF seen as an octree: node and leaf existence by the shell rules above.
#[derive(Clone, Debug)]
pub struct SdfOctree {
    sdf: Sdf,
    depth: u8,
    /// Half-size of the root cube.
    half: f64,
    /// Half-size of a leaf voxel.
    leaf_half: f64,
}

impl SdfOctree {
    /// The octree of `sdf` in a cube of half-size `half` centred on the origin, `depth` levels
    /// (1..=20, checked by the caller).
    pub fn new(sdf: Sdf, half: f64, depth: u8) -> Self {
        Self {
            sdf,
            depth,
            half,
            leaf_half: half / f64::from(1u32 << depth),
        }
    }

    /// Levels below the root.
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// The SDF.
    pub fn sdf(&self) -> &Sdf {
        &self.sdf
    }

    /// Half-size of the root cube.
    pub fn half(&self) -> f64 {
        self.half
    }

    fn node_half(&self, level: u8) -> f64 {
        // level ≤ MAX_DEPTH (20), so the shift cannot overflow.
        self.half / f64::from(1u32 << level)
    }

    /// Centre of the node with Morton `code` at `level` (root: level 0, code 0).
    pub fn node_centre(&self, code: u64, level: u8) -> DVec3 {
        let c = morton::decode(code);
        let h = self.node_half(level);
        DVec3::new(
            -self.half + (2.0 * f64::from(c[0]) + 1.0) * h,
            -self.half + (2.0 * f64::from(c[1]) + 1.0) * h,
            -self.half + (2.0 * f64::from(c[2]) + 1.0) * h,
        )
    }

    fn child_centre(&self, centre: DVec3, level: u8, label: u8) -> DVec3 {
        let q = self.node_half(level + 1);
        centre
            + DVec3::new(
                if label & 4 != 0 { q } else { -q },
                if label & 2 != 0 { q } else { -q },
                if label & 1 != 0 { q } else { -q },
            )
    }

    /// May the internal node at `level` (< depth) with this centre contain a shell leaf?
    pub fn keep(&self, centre: DVec3, level: u8) -> bool {
        let rho = (self.node_half(level) - self.leaf_half) * 3f64.sqrt();
        let d = self.sdf.dist(centre);
        d - rho <= 0.0 && d + rho > -2.0 * self.leaf_half
    }

    /// Is the leaf with this centre solid?
    pub fn solid(&self, centre: DVec3) -> bool {
        let d = self.sdf.dist(centre);
        d <= 0.0 && d > -2.0 * self.leaf_half
    }

    /// Attributes of a solid leaf, given its centre and its parent's centre.
    pub fn attr(&self, centre: DVec3, parent_centre: DVec3) -> LeafAttr {
        let n = self.sdf.normal(parent_centre, 2.0 * self.leaf_half);
        let [r, g, b] = self.sdf.sample(centre).rgb;
        LeafAttr::new([r, g, b, 255], n.to_array())
    }

    /// Appends the leaves below a kept node, in Morton order. `sdf` equals `self.sdf` within
    /// the node (it may be pruned, see [`Sdf::pruned`]); it is pruned again for the children
    /// while they still hold enough work to pay for it.
    fn subtree(
        &self,
        sdf: &Sdf,
        code: u64,
        centre: DVec3,
        level: u8,
        out: &mut Vec<(u64, LeafAttr)>,
    ) {
        if level + 1 == self.depth {
            let mut normal = None;
            for label in 0..8u8 {
                let cc = self.child_centre(centre, level, label);
                let d = sdf.dist(cc);
                if d <= 0.0 && d > -2.0 * self.leaf_half {
                    let n = *normal.get_or_insert_with(|| sdf.normal(centre, 2.0 * self.leaf_half));
                    let [r, g, b] = sdf.sample(cc).rgb;
                    out.push((
                        (code << 3) | u64::from(label),
                        LeafAttr::new([r, g, b, 255], n.to_array()),
                    ));
                }
            }
            return;
        }
        for label in 0..8u8 {
            let cc = self.child_centre(centre, level, label);
            let rho = (self.node_half(level + 1) - self.leaf_half) * 3f64.sqrt();
            let d = sdf.dist(cc);
            if d - rho <= 0.0 && d + rho > -2.0 * self.leaf_half {
                // Every evaluation below the child (centres, leaf centres, the normal's
                // samples at its level-(depth−1) corners) lies within its circumscribed ball.
                if sdf.terms() > 1 && self.depth - (level + 1) >= 3 {
                    let local = sdf.pruned(cc, self.node_half(level + 1) * 3f64.sqrt());
                    self.subtree(&local, (code << 3) | u64::from(label), cc, level + 1, out);
                } else {
                    self.subtree(sdf, (code << 3) | u64::from(label), cc, level + 1, out);
                }
            }
        }
    }

    /// Kept nodes at `level` (≤ depth − 1), in Morton order.
    fn frontier(&self, level: u8) -> Vec<(u64, DVec3)> {
        let mut nodes = if self.keep(DVec3::ZERO, 0) {
            vec![(0u64, DVec3::ZERO)]
        } else {
            vec![]
        };
        for l in 0..level {
            let mut next = Vec::with_capacity(nodes.len() * 8);
            for &(code, c) in &nodes {
                for label in 0..8u8 {
                    let cc = self.child_centre(c, l, label);
                    if self.keep(cc, l + 1) {
                        next.push(((code << 3) | u64::from(label), cc));
                    }
                }
            }
            nodes = next;
        }
        nodes
    }

    /// All solid leaves as (Morton code, attributes) in ascending code order. Uses all threads
    /// of the current rayon pool; the result does not depend on the thread count.
    pub fn leaves(&self) -> Vec<(u64, LeafAttr)> {
        let split = SPLIT_LEVEL.min(self.depth - 1);
        let tasks = self.frontier(split);
        let parts: Vec<Vec<(u64, LeafAttr)>> = tasks
            .par_iter()
            .map(|&(code, c)| {
                let mut v = Vec::new();
                let local = self.sdf.pruned(c, self.node_half(split) * 3f64.sqrt());
                self.subtree(&local, code, c, split, &mut v);
                v
            })
            .collect();
        let mut out = Vec::with_capacity(parts.iter().map(Vec::len).sum());
        for p in parts {
            out.extend(p);
        }
        out
    }
}

/// Solid shell leaves of `sdf` in a cube of half-size `half` centred on the origin, at
/// `depth` levels, as (Morton code, attributes) in ascending code order.
pub fn voxelize(sdf: &Sdf, half: f64, depth: u8) -> Vec<(u64, LeafAttr)> {
    SdfOctree::new(sdf.clone(), half, depth).leaves()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::sdf::Shape;

    /// Brute force over every leaf of a small grid: the same shell rule, no culling.
    fn brute(sdf: &Sdf, half: f64, depth: u8) -> Vec<u64> {
        let n = 1u32 << depth;
        let h = half / f64::from(n);
        let mut v = Vec::new();
        for x in 0..n {
            for y in 0..n {
                for z in 0..n {
                    let c = DVec3::new(
                        -half + (2.0 * f64::from(x) + 1.0) * h,
                        -half + (2.0 * f64::from(y) + 1.0) * h,
                        -half + (2.0 * f64::from(z) + 1.0) * h,
                    );
                    let d = sdf.dist(c);
                    if d <= 0.0 && d > -2.0 * h {
                        v.push(morton::encode(x, y, z));
                    }
                }
            }
        }
        v.sort_unstable();
        v
    }

    #[test]
    fn culling_loses_no_leaf() {
        let shapes = [
            Shape::Sphere { radius: 0.8 },
            Shape::Torus {
                major: 0.6,
                minor: 0.2,
                axis: crate::world::sdf::Axis::Z,
            },
            Shape::Difference {
                base: Box::new(Shape::RoundBox {
                    half: [0.9, 0.5, 0.7],
                    radius: 0.1,
                }),
                minus: vec![Shape::Cylinder {
                    radius: 0.3,
                    half_length: 1.0,
                    axis: crate::world::sdf::Axis::Y,
                }],
            },
        ];
        for (i, s) in shapes.iter().enumerate() {
            let sdf = Sdf::new(s, "t").unwrap();
            for depth in [1u8, 3, 5] {
                let fast: Vec<u64> = voxelize(&sdf, 1.0, depth)
                    .into_iter()
                    .map(|(c, _)| c)
                    .collect();
                assert_eq!(fast, brute(&sdf, 1.0, depth), "shape {i} depth {depth}");
            }
        }
    }

    /// Pruning must not change a single bit: compare leaves and attributes of the default
    /// car's assets (the richest CSG in the project) against an unpruned voxelisation.
    #[test]
    fn pruning_changes_nothing() {
        let scene = crate::world::scene::Scene::default_car().unwrap();
        for spec in &scene.file.assets {
            let crate::world::scene::AssetSource::Sdf { shape, half_extent } = &spec.source else {
                continue;
            };
            let sdf = Sdf::new(shape, "t").unwrap();
            let half = half_extent.unwrap();
            let tree = SdfOctree::new(sdf.clone(), half, 6);
            let pruned = tree.leaves();
            let mut plain = Vec::new();
            for (code, c) in tree.frontier(0) {
                unpruned_subtree(&tree, code, c, 0, &mut plain);
            }
            assert_eq!(pruned, plain, "asset {}", spec.name);
            assert!(!pruned.is_empty());
        }
    }

    /// The subtree walk without any pruning (reference for `pruning_changes_nothing`).
    fn unpruned_subtree(
        t: &SdfOctree,
        code: u64,
        centre: DVec3,
        level: u8,
        out: &mut Vec<(u64, LeafAttr)>,
    ) {
        for label in 0..8u8 {
            let cc = t.child_centre(centre, level, label);
            let child = (code << 3) | u64::from(label);
            if level + 1 == t.depth {
                if t.solid(cc) {
                    out.push((child, t.attr(cc, centre)));
                }
            } else if t.keep(cc, level + 1) {
                unpruned_subtree(t, child, cc, level + 1, out);
            }
        }
    }

    #[test]
    fn node_centres_match_child_centres() {
        let t = SdfOctree::new(
            Sdf::new(&Shape::Sphere { radius: 0.5 }, "t").unwrap(),
            2.0,
            4,
        );
        let c = t.child_centre(t.child_centre(DVec3::ZERO, 0, 5), 1, 2);
        assert_eq!(t.node_centre(0o52, 2), c);
    }
}
