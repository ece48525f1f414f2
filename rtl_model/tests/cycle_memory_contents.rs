//! Node-memory model (`rtl_model::cycle::memory`) against checks that share no code with it:
//! what the memories hold.
//!
//! - Cache contents: an independent LRU (a `Vec` of entries per set with explicit last-use
//!   timestamps, keyed by (region, line)) agrees request by request on hit or miss, for seeded
//!   random address streams over several geometries and for a walk trace of a real image
//!   (root reads on every ray, sibling slots, far words, attribute records).
//! - On-chip whitelist: recomputed from the image's own accessors (descriptor, far word and
//!   leaf slot of every node above the level limit) and compared word by word.
//!
//! Timing is in `cycle_memory_timing.rs`, random stress, determinism and refusals in
//! `cycle_memory_stress.rs`. Run with `-- --nocapture` to see seeds; `SVO_TEST_SEED` replays.

mod common;
mod memory_common;
use common::Rng;
use memory_common::{config, seed};
use std::collections::HashSet;

use rtl_model::cycle::memory::{
    Completion, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, OnChipConfig, Source,
};
use rtl_model::svo::build::PREFIX_LEVELS;
use rtl_model::svo::{ChildRef, LeafAttr, LeafSet, SvoImage};

// ---------------------------------------------------------------------------------------
// Independent reference cache.

/// Set-associative LRU written the plain way: per set a list of (key, last use) entries; a
/// miss fills an empty way or replaces the entry with the oldest timestamp.
struct RefLru {
    sets: u64,
    ways: usize,
    line: u64,
    clock: u64,
    entries: Vec<Vec<((u8, u64), u64)>>,
}

impl RefLru {
    fn new(size: u64, ways: u32, line: u32) -> Self {
        let sets = size / (u64::from(ways) * u64::from(line));
        Self {
            sets,
            ways: ways as usize,
            line: u64::from(line),
            clock: 0,
            entries: vec![Vec::new(); sets as usize],
        }
    }

    /// Region 0: node memory (4 bytes per word); region 1: attributes (8 bytes per record).
    fn access(&mut self, kind: FetchKind, addr: u32) -> bool {
        let (region, byte) = match kind {
            FetchKind::Node | FetchKind::Far => (0u8, 4 * u64::from(addr)),
            FetchKind::Attr => (1u8, 8 * u64::from(addr)),
        };
        let line = byte / self.line;
        let set = &mut self.entries[(line % self.sets) as usize];
        self.clock += 1;
        if let Some(e) = set.iter_mut().find(|e| e.0 == (region, line)) {
            e.1 = self.clock;
            return true;
        }
        if set.len() < self.ways {
            set.push(((region, line), self.clock));
        } else {
            let oldest = (0..set.len()).min_by_key(|&i| set[i].1).unwrap();
            set[oldest] = ((region, line), self.clock);
        }
        false
    }
}

/// Issues the reads one at a time, each after the previous has completed and its fill is
/// installed, so the model's cache sees exactly the sequence the reference sees.
fn run_serial(mem: &mut NodeMemory, reads: &[(u32, FetchKind)]) -> Vec<Completion> {
    let mut out = Vec::with_capacity(reads.len());
    for (i, &(addr, kind)) in reads.iter().enumerate() {
        let t = mem.now();
        mem.request(t, addr, kind, (i % 7) as u32).unwrap();
        let c = mem.drain();
        assert_eq!(c.len(), 1);
        out.push(c[0]);
    }
    out
}

fn compare_with_reference(
    cfg: &NodeMemoryConfig,
    layout: MemoryLayout,
    reads: &[(u32, FetchKind)],
    what: &str,
) -> (u64, u64) {
    let mut mem = NodeMemory::new(cfg.clone(), layout.clone()).unwrap();
    let got = run_serial(&mut mem, reads);
    let mut reference = RefLru::new(cfg.cache.size_bytes, cfg.cache.ways, cfg.cache.line_bytes);
    let (mut hits, mut misses) = (0, 0);
    for (i, (&(addr, kind), c)) in reads.iter().zip(&got).enumerate() {
        if kind != FetchKind::Attr && layout.is_onchip(addr) {
            assert!(
                matches!(c.source, Source::OnChip { .. }),
                "{what}: read {i} should be on chip"
            );
            continue;
        }
        let hit = reference.access(kind, addr);
        let expect = if hit { Source::CacheHit } else { Source::Miss };
        assert_eq!(
            c.source, expect,
            "{what}: read {i} ({kind:?} {addr}) disagrees"
        );
        if hit {
            hits += 1;
        } else {
            misses += 1;
        }
    }
    let s = mem.stats();
    assert_eq!(
        (s.cache_hits, s.cache_misses, s.cache_merged),
        (hits, misses, 0)
    );
    (hits, misses)
}

#[test]
fn cache_agrees_with_reference_lru_on_random_streams() {
    let mut rng = Rng::new(seed("random_streams", 0x5eed_3e30_0001));
    // (size, ways, line): direct mapped, set associative, fully associative, small lines.
    let geometries = [
        (4096u64, 1u32, 64u32),
        (4096, 2, 64),
        (8192, 4, 64),
        (2048, 8, 32),
        (1024, 16, 64), // one set: fully associative
        (512, 4, 8),
    ];
    for &(size, ways, line) in &geometries {
        let mut cfg = config(2, 2, 2, size, ways, line, 3, 2, 20, 16, 4);
        cfg.cache.attr_cached = true;
        let node_words = 1u64 << 16;
        let attrs = 1u64 << 12;
        let layout = MemoryLayout::flat(node_words, attrs).unwrap();
        let lines = size / u64::from(line);
        let words_per_line = u64::from(line) / 4;
        // A working set about twice the cache, plus sequential runs and uniform noise, so hits,
        // capacity misses and conflict misses all happen.
        let hot: Vec<u64> = (0..2 * lines)
            .map(|_| rng.below(node_words / words_per_line))
            .collect();
        let mut reads = Vec::new();
        let mut seq = 0u64;
        for _ in 0..6000 {
            let r = rng.below(10);
            let read = if r < 5 {
                let l = hot[rng.below(hot.len() as u64) as usize];
                (
                    (l * words_per_line + rng.below(words_per_line)) as u32,
                    FetchKind::Node,
                )
            } else if r < 7 {
                seq = (seq + 1) % node_words;
                (seq as u32, FetchKind::Far)
            } else if r < 9 {
                (rng.below(attrs) as u32, FetchKind::Attr)
            } else {
                (rng.below(node_words) as u32, FetchKind::Node)
            };
            reads.push(read);
        }
        let (h, m) = compare_with_reference(&cfg, layout, &reads, "random");
        println!("  size {size} ways {ways} line {line}: {h} hits, {m} misses");
        assert!(h > 500 && m > 500, "the stream should exercise both");
    }
}

// ---------------------------------------------------------------------------------------
// Real images and walk traces.

/// A spherical shell of voxels: a surface like the ones the builders make.
fn sphere_image(depth: u8, radius: f64) -> (SvoImage, LeafSet) {
    let n = 1u32 << depth;
    let c = f64::from(n) / 2.0;
    let mut leaves = Vec::new();
    for x in 0..n {
        for y in 0..n {
            for z in 0..n {
                let p = [
                    f64::from(x) + 0.5 - c,
                    f64::from(y) + 0.5 - c,
                    f64::from(z) + 0.5 - c,
                ];
                let d = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                if (d - radius).abs() < 0.9 {
                    let attr = LeafAttr::new([x as u8, y as u8, z as u8, 255], p);
                    leaves.push(([x, y, z], attr));
                }
            }
        }
    }
    let set = LeafSet::from_coords(depth, leaves).unwrap();
    (SvoImage::build(&set).unwrap(), set)
}

/// The reads of walks to a drifting sequence of leaves (neighbouring rays hit neighbouring
/// leaves): the root on every walk, a far word where a descriptor has one, each descriptor
/// on the path, now and then a sibling's descriptor (a subtree entered and left), the leaf
/// slot and the attribute record.
fn walk_trace(img: &SvoImage, set: &LeafSet, rng: &mut Rng, walks: usize) -> Vec<(u32, FetchKind)> {
    let leaves = set.leaves();
    let depth = u32::from(img.depth());
    let mut out = Vec::new();
    let mut at = rng.below(leaves.len() as u64) as i64;
    for _ in 0..walks {
        // Mostly small steps, sometimes a jump (a new object or screen region).
        at = if rng.below(50) == 0 {
            rng.below(leaves.len() as u64) as i64
        } else {
            (at + rng.below(41) as i64 - 20).rem_euclid(leaves.len() as i64)
        };
        let code = leaves[at as usize].0;
        let mut addr = SvoImage::root();
        out.push((addr, FetchKind::Node));
        for level in (0..depth).rev() {
            let label = ((code >> (3 * level)) & 7) as u8;
            let d = img.descriptor(addr);
            if d.far {
                out.push((addr + u32::from(d.ptr), FetchKind::Far));
            }
            let base = img.group_base(addr, d);
            if rng.below(3) == 0 {
                // A sibling visited first (its slot, in the same group).
                let sib = rng.below(u64::from(d.valid.count_ones())) as u32;
                out.push((base + sib, FetchKind::Node));
            }
            match img.child(addr, d, label) {
                ChildRef::Node(a) => {
                    out.push((a, FetchKind::Node));
                    addr = a;
                }
                ChildRef::Leaf(i) => {
                    out.push((base + d.slot(label), FetchKind::Node));
                    out.push((i, FetchKind::Attr));
                    break;
                }
                ChildRef::Empty => panic!("leaf {code:o} must exist"),
            }
        }
    }
    out
}

/// Every word the walker reads for nodes above level `levels`, found with the image's own
/// accessors: the descriptor of each internal node at level < L, the far word it uses to
/// reach its children, and the slot of each leaf at level < L.
fn onchip_oracle(img: &SvoImage, levels: u8) -> HashSet<u32> {
    let mut set = HashSet::new();
    if levels == 0 {
        return set;
    }
    let mut stack = vec![(SvoImage::root(), 0u8)];
    while let Some((addr, level)) = stack.pop() {
        if level >= levels {
            continue;
        }
        set.insert(addr);
        let d = img.descriptor(addr);
        if d.far {
            set.insert(addr + u32::from(d.ptr));
        }
        for label in 0..8u8 {
            match img.child(addr, d, label) {
                ChildRef::Empty => {}
                ChildRef::Node(a) => stack.push((a, level + 1)),
                ChildRef::Leaf(_) => {
                    if level + 1 < levels {
                        set.insert(img.group_base(addr, d) + d.slot(label));
                    }
                }
            }
        }
    }
    set
}

#[test]
fn onchip_whitelist_is_the_top_levels() {
    let (img, _) = sphere_image(7, 60.0);
    let st = img.stats();
    println!("sphere image: {st:?}");
    assert!(st.far_words > 0, "the test image should use far words");
    let n = img.nodes().len() as u32;
    for levels in 0..=img.depth() + 2 {
        let oc = OnChipConfig {
            levels,
            max_bytes: u64::MAX,
            ..OnChipConfig::default()
        };
        let layout = MemoryLayout::from_image(&img, &oc).unwrap();
        let want = onchip_oracle(&img, levels);
        for a in 0..n {
            assert_eq!(
                layout.is_onchip(a),
                want.contains(&a),
                "levels {levels} word {a}"
            );
        }
        assert_eq!(layout.onchip_words(), want.len() as u64);
        assert_eq!(layout.onchip_levels(), levels);
        assert!(!layout.is_onchip(n) && !layout.is_onchip(u32::MAX));
        // The image lays its top levels out first (svo/build.rs), so they are its first words.
        if (1..=PREFIX_LEVELS).contains(&levels) {
            let max = *want.iter().max().unwrap();
            assert_eq!(
                u64::from(max) + 1,
                layout.onchip_words(),
                "levels {levels}: the on-chip words are not the prefix [0, {})",
                layout.onchip_words()
            );
            println!(
                "levels {levels}: {} words on chip in {} ranges, up to word {max}",
                layout.onchip_words(),
                layout.onchip_ranges().len()
            );
        }
    }
    // A byte cap keeps whole levels only.
    let full5 = onchip_oracle(&img, 5).len() as u64;
    let oc = OnChipConfig {
        levels: 8,
        max_bytes: 4 * full5 + 3,
        ..OnChipConfig::default()
    };
    let layout = MemoryLayout::from_image(&img, &oc).unwrap();
    assert_eq!(layout.onchip_levels(), 5);
    assert_eq!(layout.onchip_words(), full5);
    let oc = OnChipConfig {
        levels: 8,
        max_bytes: 3,
        ..OnChipConfig::default()
    };
    assert_eq!(
        MemoryLayout::from_image(&img, &oc).unwrap().onchip_words(),
        0
    );
}

#[test]
fn cache_agrees_with_reference_lru_on_walk_traces() {
    let mut rng = Rng::new(seed("walk_traces", 0x5eed_3e30_0002));
    let (img, set) = sphere_image(7, 60.0);
    let reads = walk_trace(&img, &set, &mut rng, 3000);
    let roots = reads.iter().filter(|r| r.0 == 0).count();
    println!("walk trace: {} reads, {roots} root reads", reads.len());
    for &(levels, size, ways) in &[
        (0u8, 16384u64, 4u32),
        (3, 16384, 4),
        (4, 4096, 2),
        (0, 2048, 1),
    ] {
        let mut cfg = config(3, 4, 2, size, ways, 64, 4, 2, 60, 64, 32);
        cfg.onchip.levels = levels;
        cfg.onchip.max_bytes = u64::MAX;
        let layout = MemoryLayout::from_image(&img, &cfg.onchip).unwrap();
        let (h, m) = compare_with_reference(&cfg, layout, &reads, "walk");
        let oracle = onchip_oracle(&img, levels);
        let onchip = reads
            .iter()
            .filter(|r| r.1 != FetchKind::Attr && oracle.contains(&r.0))
            .count();
        println!(
            "  levels {levels} cache {size} B {ways}-way: {onchip} on chip, {h} hits, {m} misses, hit rate {:.3}",
            h as f64 / (h + m) as f64
        );
        assert_eq!(onchip as u64 + h + m, reads.len() as u64);
        if levels > 0 {
            assert!(onchip >= roots);
        }
    }
}
