//! The image layout's on-chip prefix (`rtl_model::svo::build`, `PREFIX_LEVELS`): the top
//! levels of every image are the words `[0, prefix_end)`, so the RTL's on-chip store tests an
//! address with one compare and holds each word at its own address.
//!
//! - For seeded random leaf sets (clustered blobs, deep enough to have levels below the
//!   prefix and far words), `MemoryLayout::from_image` with every `levels` from 1 to
//!   `PREFIX_LEVELS` and no byte cap gives exactly one on-chip range, starting at word 0, and
//!   the image decodes back to its leaf set.
//! - Far words are exact: walking the image with its own accessors, a descriptor uses a far
//!   word exactly when the distance to its group exceeds `NEAR_PTR_MAX`, and the count equals
//!   `SvoStats::far_words`. (The round trip leaf set → image → leaf set is in `build.rs`.)
//!
//! Run with `-- --nocapture` to see seeds; `SVO_TEST_SEED` replays.

mod common;
use common::{printed_seed, Rng};

use rtl_model::cycle::memory::{MemoryLayout, OnChipConfig};
use rtl_model::svo::build::PREFIX_LEVELS;
use rtl_model::svo::descriptor::NEAR_PTR_MAX;
use rtl_model::svo::{ChildDescriptor, LeafAttr, LeafSet, SvoImage};

/// A leaf set of a few random hollow spheres ("surfaces", like the builders make), at a depth
/// of 8 to 11, so that the tree has levels below the prefix.
fn blobs(rng: &mut Rng) -> LeafSet {
    let depth = 8 + rng.below(4) as u8;
    let side = 1i64 << depth;
    let mut leaves = Vec::new();
    for _ in 0..1 + rng.below(3) {
        let r = 4 + rng.below((side / 6) as u64) as i64;
        let c = [0; 3].map(|_| rng.range(r, side - 1 - r));
        // One leaf per (x, y) column on each cap: a shell about one voxel thick.
        for x in -r..=r {
            for y in -r..=r {
                let zz = r * r - x * x - y * y;
                if zz < 0 {
                    continue;
                }
                let z = (zz as f64).sqrt() as i64;
                for s in [-1, 1] {
                    let p = [c[0] + x, c[1] + y, c[2] + s * z];
                    leaves.push((p.map(|v| v as u32), LeafAttr::default()));
                }
            }
        }
    }
    LeafSet::from_coords(depth, leaves).expect("coordinates inside the cube")
}

fn onchip(levels: u8) -> OnChipConfig {
    OnChipConfig {
        levels,
        max_bytes: u64::MAX / 2,
        ..OnChipConfig::default()
    }
}

#[test]
fn top_levels_are_one_prefix_range() {
    let seed = printed_seed("top_levels_are_one_prefix_range", 29);
    let mut rng = Rng::new(seed);
    for case in 0..12 {
        let set = blobs(&mut rng);
        let img = SvoImage::build(&set).expect("image");
        assert!(
            img.to_leaf_set() == set,
            "seed {seed} case {case}: round trip"
        );
        for levels in 1..=PREFIX_LEVELS {
            let layout = MemoryLayout::from_image(&img, &onchip(levels)).expect("layout");
            let ranges = layout.onchip_ranges();
            assert!(
                ranges.len() == 1 && ranges[0].0 == 0,
                "seed {seed} case {case} (depth {}, {} node words, {} far words): the top \
                 {levels} levels are {} on-chip ranges, not one range from word 0: {:?}",
                img.depth(),
                img.nodes().len(),
                img.stats().far_words,
                ranges.len(),
                &ranges[..ranges.len().min(4)],
            );
        }
    }
}

#[test]
fn far_words_exactly_where_near_pointers_do_not_reach() {
    let seed = printed_seed("far_words_exactly_where_near_pointers_do_not_reach", 2929);
    let mut rng = Rng::new(seed);
    let mut total_far = 0;
    for case in 0..12 {
        let set = blobs(&mut rng);
        let img = SvoImage::build(&set).expect("image");
        let nodes = img.nodes();
        let mut far = 0u64;
        // Every internal node's descriptor address, from the root down.
        let mut stack = vec![0usize];
        while let Some(a) = stack.pop() {
            let d = ChildDescriptor::unpack(nodes[a]);
            if d.valid == 0 || d.leaf == d.valid {
                continue;
            }
            let ptr = u64::from(d.ptr);
            let dist = if d.far {
                far += 1;
                u64::from(nodes[a + ptr as usize])
            } else {
                ptr
            };
            assert_eq!(
                d.far,
                dist > u64::from(NEAR_PTR_MAX),
                "seed {seed} case {case}: descriptor at word {a} is far = {} for a distance of \
                 {dist} words",
                d.far
            );
            let base = a + dist as usize;
            stack.extend((0..d.valid.count_ones() as usize).map(|p| base + p));
        }
        assert_eq!(far, img.stats().far_words, "seed {seed} case {case}");
        total_far += far;
    }
    assert!(total_far > 0, "seed {seed}: no case made a far word");
}
