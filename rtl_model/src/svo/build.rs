//! Packs a [`LeafSet`] into an [`SvoImage`]: the group layout with far pointers.
//!
//! Pipeline position: run offline, once per asset, before the walkers read the image.
//!
//! Layout ("top levels first"): the root descriptor at word 0; then the groups of the nodes
//! at levels 0 ..= [`PREFIX_LEVELS`] − 2, level by level (Morton order within a level), so
//! the image's top `L` levels are the words `[0, end_L)` for every `L ≤ PREFIX_LEVELS`; then,
//! for each node at level `PREFIX_LEVELS − 1` in Morton order, its whole subtree depth first
//! (a group, its far words, then its children's subtrees in label order). Why: an RTL on-chip
//! store that holds the top levels can then test an address with one compare against
//! `end_L` and keep each word at its own address, with no address translation; below the
//! top, depth-first placement keeps children close to their parents, so the 15-bit near
//! pointer reaches them. Where it does not reach (the top's widest levels, and the
//! descriptors of level `PREFIX_LEVELS − 1`, whose subtrees lie after the top), the
//! descriptor points to a far word placed right after its own group. The measurements that
//! chose this layout over plain depth first: `docs/svo-format.md` §4.

use super::descriptor::NEAR_PTR_MAX;
use super::{ChildDescriptor, LeafSet, SvoImage, SvoStats};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Levels the image lays out first, level by level: the root word and the groups of the
/// nodes at levels 0 ..= `PREFIX_LEVELS − 2` (the descriptors of levels 0 .. `PREFIX_LEVELS`,
/// their far words and any leaf slots there) occupy the words `[0, prefix_end)`, and each
/// shorter top is a shorter prefix. 8 = the default hardware's `node_memory.onchip.levels`,
/// so its on-chip set is one prefix per image; `configs/baseline.ron`'s 6 levels are one too.
pub const PREFIX_LEVELS: u8 = 8;

/// How [`SvoImage::build_with`] orders the groups in node memory. The image format (descriptors,
/// far words) is the same in both; only the addresses differ, so the functional models give
/// the same pixels and the cycle model different memory traffic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ImageLayout {
    /// The top [`PREFIX_LEVELS`] levels first, level by level, then each deeper subtree depth
    /// first: the on-chip top levels are one prefix of the image (the module documentation
    /// says why). The default since issue 29.
    #[default]
    TopLevelsFirst,
    /// Every subtree depth first right after its parent's group: the layout before issue 29,
    /// kept so that figures measured on it (`configs/baseline.ron`,
    /// `configs/default_2026_11.ron`) stay reproducible (`sim --image-layout depth-first`).
    DepthFirst,
}

impl ImageLayout {
    /// The levels laid out level by level before the depth-first subtrees (1: none, the
    /// root's group is simply the first group of a depth-first layout).
    pub fn top_levels(self) -> u8 {
        match self {
            ImageLayout::TopLevelsFirst => PREFIX_LEVELS,
            ImageLayout::DepthFirst => 1,
        }
    }

    /// The name the CLI and the report use.
    pub fn name(self) -> &'static str {
        match self {
            ImageLayout::TopLevelsFirst => "top-levels-first",
            ImageLayout::DepthFirst => "depth-first",
        }
    }
}

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
    /// Builds the memory image of a leaf set in the default layout
    /// ([`ImageLayout::TopLevelsFirst`]).
    pub fn build(set: &LeafSet) -> Result<Self, BuildError> {
        Self::build_with(set, ImageLayout::default())
    }

    /// Builds the memory image of a leaf set in the given layout.
    pub fn build_with(set: &LeafSet, layout: ImageLayout) -> Result<Self, BuildError> {
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

        let d = usize::from(depth);
        let groups = group_order(&levels, d, layout.top_levels());
        let Placement { start, far, words } = place(&levels, d, &groups)?;
        let mut nodes = vec![0u32; words as usize];
        let mut far_words = 0u64;
        // The root's group is always the first, at word 1.
        nodes[0] = descriptor(&levels, 0, 0, d, 1, false);
        for &(l, i) in &groups {
            let (l, i) = (usize::from(l), i as usize);
            let lv = &levels[l];
            let g = start[l][i];
            let k = u64::from(lv.valid[i].count_ones());
            let first = lv.first_child[i] as usize;
            if l + 1 == d {
                for p in 0..k {
                    nodes[(g + p) as usize] = (first as u64 + p) as u32;
                }
                continue;
            }
            let mask = far[l][i];
            let mut j = 0u64;
            for p in 0..k {
                let c = first + p as usize;
                let offset = start[l + 1][c] - (g + p);
                let word = if mask & (1 << p) != 0 {
                    // offset < words < 2^32 (checked by `place`).
                    nodes[(g + k + j) as usize] = offset as u32;
                    let ptr = k - p + j;
                    j += 1;
                    far_words += 1;
                    descriptor(&levels, l + 1, c, d, ptr, true)
                } else {
                    descriptor(&levels, l + 1, c, d, offset, false)
                };
                nodes[(g + p) as usize] = word;
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

/// The order of the groups in node memory after the root word. First the groups of the nodes
/// at levels `0 ..= top − 2`, level by level and in Morton order within a level: with the
/// root word they are the image's top `top` levels, and every shorter top is a prefix of them
/// too. Then, for every node at level `top − 1` in Morton order, its whole subtree depth first
/// (a group, then its children's subtrees in label order), so that below the top, children
/// stay close to their parents and near pointers reach them. A tree of fewer levels is laid
/// out level by level throughout. Each entry is (level, index in that level).
fn group_order(levels: &[Level], d: usize, top: u8) -> Vec<(u8, u32)> {
    let groups: usize = levels.iter().map(|lv| lv.code.len()).sum();
    let mut order = Vec::with_capacity(groups);
    // Levels are below 2^8 (MAX_DEPTH) and indices below 2^32 (leaves are).
    let cut = usize::from(top.saturating_sub(1)).clamp(1, d);
    for (l, lv) in levels.iter().enumerate().take(cut) {
        order.extend((0..lv.code.len()).map(|i| (l as u8, i as u32)));
    }
    if cut < d {
        let mut stack = Vec::new();
        for i in 0..levels[cut].code.len() {
            stack.push((cut, i));
            while let Some((l, i)) = stack.pop() {
                order.push((l as u8, i as u32));
                if l + 1 == d {
                    continue;
                }
                let first = levels[l].first_child[i] as usize;
                let k = levels[l].valid[i].count_ones() as usize;
                // Reversed, so that the lowest label is popped (placed) first.
                stack.extend((first..first + k).rev().map(|c| (l + 1, c)));
            }
        }
    }
    order
}

/// Where [`place`] puts the groups: per level and node, its group's first word and which of
/// its children have far words; and the image's size in words.
struct Placement {
    start: Vec<Vec<u64>>,
    far: Vec<Vec<u8>>,
    words: u64,
}

/// Word addresses of every group in `order` and which of its children need far words, and
/// the image's size. A descriptor gets a far word exactly when its distance to its group
/// exceeds `NEAR_PTR_MAX`. Far words move every later group, so iterate to the fixed point:
/// a group always lies after the descriptors that point to it, so inserting words only
/// lengthens distances and the far set only grows.
fn place(levels: &[Level], d: usize, order: &[(u8, u32)]) -> Result<Placement, BuildError> {
    let mut start: Vec<Vec<u64>> = levels.iter().map(|lv| vec![0; lv.code.len()]).collect();
    let mut far: Vec<Vec<u8>> = levels.iter().map(|lv| vec![0; lv.code.len()]).collect();
    loop {
        let mut pos = 1u64;
        for &(l, i) in order {
            let (l, i) = (usize::from(l), i as usize);
            start[l][i] = pos;
            pos += u64::from(levels[l].valid[i].count_ones() + far[l][i].count_ones());
        }
        let mut changed = false;
        for &(l, i) in order {
            let (l, i) = (usize::from(l), i as usize);
            if l + 1 == d {
                continue;
            }
            let g = start[l][i];
            let first = levels[l].first_child[i] as usize;
            for p in 0..levels[l].valid[i].count_ones() as usize {
                let offset = start[l + 1][first + p] - (g + p as u64);
                if offset > u64::from(NEAR_PTR_MAX) && far[l][i] & (1 << p) == 0 {
                    far[l][i] |= 1 << p;
                    changed = true;
                }
            }
        }
        if !changed {
            if pos > u64::from(u32::MAX) {
                return Err(BuildError::TooLarge { words: pos });
            }
            return Ok(Placement {
                start,
                far,
                words: pos,
            });
        }
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
