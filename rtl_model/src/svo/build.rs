//! Packs a [`LeafSet`] into an [`SvoImage`]: depth-first group layout with far pointers.
//!
//! Layout: the root descriptor at word 0, its children's group at word 1, and then for every
//! group, in label order, each internal child's whole subtree right after the group (and its
//! far words). Depth-first placement keeps a node's children close to it, so the 15-bit
//! near pointer covers every level except the top few of very large trees; where it does not
//! reach, the descriptor points to a far word placed right after its own group.

use super::descriptor::NEAR_PTR_MAX;
use super::{ChildDescriptor, LeafSet, SvoImage, SvoStats};
use thiserror::Error;

/// Why an image could not be built.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum BuildError {
    /// The node memory would exceed the 32-bit word address space.
    #[error("SVO image would need {words} node words, more than the 32-bit address space holds")]
    TooLarge {
        /// Words that would be needed.
        words: u64,
    },
    /// More leaves than a 32-bit attribute index can address.
    #[error("{leaves} leaves are more than a 32-bit attribute index addresses")]
    TooManyLeaves {
        /// Leaves in the set.
        leaves: u64,
    },
}

/// One level of the tree: per node its Morton code prefix, valid mask and first child index.
struct Level {
    code: Vec<u64>,
    valid: Vec<u8>,
    first_child: Vec<u32>,
}

impl SvoImage {
    /// Builds the memory image of a leaf set.
    pub fn build(set: &LeafSet) -> Result<Self, BuildError> {
        let depth = set.depth();
        let leaves = set.leaves();
        if leaves.len() as u64 > u64::from(u32::MAX) {
            return Err(BuildError::TooManyLeaves {
                leaves: leaves.len() as u64,
            });
        }
        // levels[l] holds the internal nodes at level l (0 = root) ... depth-1.
        let mut levels: Vec<Level> = Vec::with_capacity(usize::from(depth));
        let mut below: Vec<u64> = leaves.iter().map(|&(c, _)| c).collect();
        for _ in 0..depth {
            let mut lv = Level {
                code: Vec::new(),
                valid: Vec::new(),
                first_child: Vec::new(),
            };
            for (i, &c) in below.iter().enumerate() {
                let parent = c >> 3;
                let bit = 1u8 << (c & 7);
                if lv.code.last() == Some(&parent) {
                    *lv.valid.last_mut().expect("non-empty") |= bit;
                } else {
                    lv.code.push(parent);
                    lv.valid.push(bit);
                    lv.first_child.push(i as u32);
                }
            }
            below = lv.code.clone();
            levels.push(lv);
        }
        levels.reverse();
        if levels[0].code.is_empty() {
            // Empty tree: a root with no children.
            return Ok(Self::assemble(depth, vec![0], Vec::new(), &levels, 0));
        }

        // Bottom-up: words of each node's subtree below its own slot, and which of its
        // children need far words.
        let d = usize::from(depth);
        let mut size: Vec<Vec<u64>> = vec![Vec::new(); d];
        let mut far: Vec<Vec<u8>> = vec![Vec::new(); d];
        for l in (0..d).rev() {
            let lv = &levels[l];
            let n = lv.code.len();
            let mut sz = Vec::with_capacity(n);
            let mut fm = Vec::with_capacity(n);
            for i in 0..n {
                let k = lv.valid[i].count_ones() as u64;
                if l + 1 == d {
                    sz.push(k); // leaf slots only
                    fm.push(0);
                    continue;
                }
                let first = lv.first_child[i] as usize;
                let child_sizes = &size[l + 1][first..first + k as usize];
                let (mask, f) = far_mask(child_sizes);
                sz.push(k + u64::from(f) + child_sizes.iter().sum::<u64>());
                fm.push(mask);
            }
            size[l] = sz;
            far[l] = fm;
        }
        let total = 1 + size[0][0];
        if total > u64::from(u32::MAX) {
            return Err(BuildError::TooLarge { words: total });
        }
        let mut nodes = vec![0u32; total as usize];
        let mut far_words = 0u64;
        nodes[0] = descriptor(&levels, 0, 0, d, 1, false);
        // Explicit stack of groups to emit: (level, node index, group start word).
        let mut stack = vec![(0usize, 0usize, 1u64)];
        while let Some((l, i, g)) = stack.pop() {
            let lv = &levels[l];
            let k = lv.valid[i].count_ones() as u64;
            let first = lv.first_child[i] as usize;
            if l + 1 == d {
                for p in 0..k {
                    nodes[(g + p) as usize] = (first as u64 + p) as u32;
                }
                continue;
            }
            let mask = far[l][i];
            let f = u64::from(mask.count_ones());
            let mut cursor = g + k + f;
            let mut j = 0u64;
            for p in 0..k {
                let c = first + p as usize;
                let offset = cursor - (g + p);
                let word = if mask & (1 << p) != 0 {
                    nodes[(g + k + j) as usize] = offset as u32;
                    let ptr = k - p + j;
                    j += 1;
                    far_words += 1;
                    descriptor(&levels, l + 1, c, d, ptr, true)
                } else {
                    descriptor(&levels, l + 1, c, d, offset, false)
                };
                nodes[(g + p) as usize] = word;
                stack.push((l + 1, c, cursor));
                cursor += size[l + 1][c];
            }
        }
        let attrs = leaves.iter().map(|&(_, a)| a).collect();
        Ok(Self::assemble(depth, nodes, attrs, &levels, far_words))
    }

    fn assemble(
        depth: u8,
        nodes: Vec<u32>,
        attrs: Vec<super::LeafAttr>,
        levels: &[Level],
        far_words: u64,
    ) -> Self {
        // The root exists even in an empty tree (a descriptor with no children).
        let nodes_per_level: Vec<u64> = levels
            .iter()
            .enumerate()
            .map(|(l, lv)| if l == 0 { 1 } else { lv.code.len() as u64 })
            .collect();
        let stats = SvoStats {
            depth,
            nodes: nodes_per_level.iter().sum(),
            leaves: attrs.len() as u64,
            far_words,
            node_bytes: 4 * nodes.len() as u64,
            attr_bytes: 8 * attrs.len() as u64,
            nodes_per_level,
        };
        Self {
            depth,
            nodes,
            attrs,
            stats,
        }
    }
}

/// Which children of a group need far words, given the sizes of their subtrees, and how many.
/// Adding far words moves later subtrees further away, so iterate to the fixed point (the set
/// only grows, and it has at most 8 members).
fn far_mask(child_sizes: &[u64]) -> (u8, u32) {
    let k = child_sizes.len() as u64;
    let mut mask = 0u8;
    loop {
        let f = u64::from(mask.count_ones());
        let mut new_mask = 0u8;
        let mut before = 0u64;
        for (p, &s) in child_sizes.iter().enumerate() {
            // An internal child with an empty subtree cannot occur (every node has a leaf).
            let offset = k - p as u64 + f + before;
            if offset > u64::from(NEAR_PTR_MAX) {
                new_mask |= 1 << p;
            }
            before += s;
        }
        if new_mask == mask {
            return (mask, mask.count_ones());
        }
        mask |= new_mask;
    }
}

fn descriptor(levels: &[Level], l: usize, i: usize, depth: usize, ptr: u64, far: bool) -> u32 {
    let valid = levels[l].valid[i];
    let leaf = if l + 1 == depth { valid } else { 0 };
    ChildDescriptor {
        valid,
        leaf,
        ptr: ptr as u16,
        far,
    }
    .pack()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::svo::{ChildRef, LeafAttr};

    fn xorshift(s: &mut u64) -> u64 {
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        *s
    }

    #[test]
    fn round_trip_random_sets() {
        for seed in 1..=40u64 {
            let mut s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
            let depth = 1 + (xorshift(&mut s) % 7) as u8;
            let n = (xorshift(&mut s) % 3000) as usize;
            let side = 1u64 << depth;
            let leaves: Vec<_> = (0..n)
                .map(|i| {
                    let c = [0, 1, 2].map(|_| (xorshift(&mut s) % side) as u32);
                    (
                        c,
                        LeafAttr {
                            colour_rgba8: i as u32,
                            normal_oct16: 7,
                        },
                    )
                })
                .collect();
            let set = LeafSet::from_coords(depth, leaves.clone()).unwrap();
            let img = SvoImage::build(&set).unwrap();
            assert_eq!(img.to_leaf_set(), set, "seed {seed}");
            for (c, a) in set.coords() {
                assert_eq!(img.leaf_at(c), Some(a), "seed {seed} coord {c:?}");
            }
            assert_eq!(img.stats().leaves as usize, set.len());
        }
    }

    #[test]
    fn far_pointers_are_used_and_correct_in_a_wide_tree() {
        // A dense 64^3 block at depth 8 makes subtrees large enough that the top levels
        // need far words.
        let mut leaves = Vec::new();
        for x in 0..64u32 {
            for y in 0..64u32 {
                for z in 0..64u32 {
                    if (x + y + z) % 3 != 0 {
                        leaves.push(([x * 4, y * 4, z * 4], LeafAttr::default()));
                    }
                }
            }
        }
        let set = LeafSet::from_coords(8, leaves).unwrap();
        let img = SvoImage::build(&set).unwrap();
        assert!(
            img.stats().far_words > 0,
            "expected far words: {:?}",
            img.stats()
        );
        assert_eq!(img.to_leaf_set(), set);
    }

    #[test]
    fn empty_tree_has_empty_root() {
        let img = SvoImage::build(&LeafSet::empty(5).unwrap()).unwrap();
        assert_eq!(img.stats().nodes_per_level, vec![1, 0, 0, 0, 0]);
        assert_eq!(img.stats().nodes, 1);
        let d = img.descriptor(SvoImage::root());
        assert_eq!(d.valid, 0);
        assert_eq!(img.child(0, d, 3), ChildRef::Empty);
        assert_eq!(img.leaf_at([0, 0, 0]), None);
    }
}
