//! Node-memory model (`rtl_model::cycle::memory`) against checks that share no code with it.
//!
//! - Cache contents: an independent LRU (a `Vec` of entries per set with explicit last-use
//!   timestamps, keyed by (region, line)) agrees request by request on hit or miss, for seeded
//!   random address streams over several geometries and for a walk trace of a real image
//!   (root reads on every ray, sibling slots, far words, attribute records).
//! - On-chip whitelist: recomputed from the image's own accessors (descriptor, far word and
//!   leaf slot of every node above the level limit) and compared word by word.
//! - Timing: exact latencies of isolated reads (on chip, hit, cold miss with and without a
//!   line that is a multiple of the bus width, merged misses), port conflicts, the MSHR
//!   limit, the per-cycle byte budget and saturation of a streaming pattern.
//! - Random stress over random configurations: every request completes exactly once, `tick`
//!   returns each completion in its cycle, port and MSHR limits hold when recomputed from the
//!   completions, service order is (cycle, requester, id), statistics add up.
//! - Determinism: identical runs give identical completions and statistics, and the order in
//!   which one cycle's requests are made does not change anything.
//!
//! Run with `-- --nocapture` to see seeds; `SVO_TEST_SEED` replays.

mod common;
use common::Rng;
use std::collections::{BTreeMap, HashMap, HashSet};

use rtl_model::cycle::memory::{
    CacheConfig, Completion, ConfigError, DramConfig, FetchKind, MemoryLayout, NodeMemory,
    NodeMemoryConfig, OnChipConfig, RequestError, RequestId, Source,
};
use rtl_model::svo::{ChildRef, LeafAttr, LeafSet, SvoImage};

fn seed(test: &str, default: u64) -> u64 {
    let s = common::seed(default);
    println!("{test}: seed = {s} (SVO_TEST_SEED replays)");
    s
}

/// A configuration from the few numbers a test cares about.
#[allow(clippy::too_many_arguments)]
fn config(
    onchip_latency: u32,
    banks: u32,
    ports_per_bank: u32,
    cache_bytes: u64,
    ways: u32,
    line_bytes: u32,
    hit_latency: u32,
    cache_ports: u32,
    dram_latency: u32,
    bytes_per_cycle: u32,
    mshrs: u32,
) -> NodeMemoryConfig {
    NodeMemoryConfig {
        onchip: OnChipConfig {
            levels: 0,
            max_bytes: 0,
            latency: onchip_latency,
            banks,
            ports_per_bank,
        },
        cache: CacheConfig {
            size_bytes: cache_bytes,
            ways,
            line_bytes,
            hit_latency,
            ports: cache_ports,
            attr_cached: true,
        },
        dram: DramConfig {
            latency: dram_latency,
            bytes_per_cycle,
            mshrs,
        },
    }
}

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
    let mut rng = Rng(seed("random_streams", 0x5eed_3e30_0001));
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
        // The top levels are scattered through a depth-first image, not a prefix.
        if levels == 4 {
            let max = *want.iter().max().unwrap();
            assert!(u64::from(max) > 4 * layout.onchip_words());
            println!(
                "levels 4: {} words on chip in {} ranges, up to word {max}",
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
    let mut rng = Rng(seed("walk_traces", 0x5eed_3e30_0002));
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

// ---------------------------------------------------------------------------------------
// Exact latencies.

fn one(mem: &mut NodeMemory, cycle: u64, addr: u32, kind: FetchKind) -> Completion {
    let id = mem.request(cycle, addr, kind, 0).unwrap();
    let c = mem.drain();
    assert_eq!(c.len(), 1);
    assert_eq!(c[0].id, id);
    c[0]
}

#[test]
fn isolated_reads_take_exactly_their_latency() {
    for &(onchip_lat, hit_lat, dram_lat, bpc, line) in &[
        (3u32, 4u32, 60u32, 64u32, 64u32),
        (1, 1, 1, 1, 8),
        (2, 5, 30, 24, 64), // a line is not a multiple of the bus: ⌈64/24⌉ = 3 beats
        (4, 2, 100, 16, 128), // 8 beats
    ] {
        let mut cfg = config(
            onchip_lat, 1, 2, 8192, 4, line, hit_lat, 2, dram_lat, bpc, 8,
        );
        cfg.cache.attr_cached = true;
        let layout = MemoryLayout::with_onchip_ranges(1 << 20, 1 << 13, vec![(0, 100)]).unwrap();
        let mut mem = NodeMemory::new(cfg, layout).unwrap();
        let beats = u64::from(line.div_ceil(bpc));
        let c = one(&mut mem, 10, 50, FetchKind::Node);
        assert_eq!(
            (c.source, c.cycle_done),
            (Source::OnChip { bank: 0 }, 10 + u64::from(onchip_lat))
        );
        let t = mem.now() + 7;
        let c = one(&mut mem, t, 5000, FetchKind::Node);
        assert_eq!(c.source, Source::Miss);
        assert_eq!(c.cycle_done, t + u64::from(dram_lat) + beats, "cold miss");
        let t = mem.now() + 3;
        let c = one(&mut mem, t, 5001, FetchKind::Far); // same line
        assert_eq!(
            (c.source, c.cycle_done),
            (Source::CacheHit, t + u64::from(hit_lat))
        );
        // Regions are separate: record 2500 sits at the same byte offset in the attribute
        // array as node word 5000 (cached above) in node memory, yet it misses.
        let t = mem.now();
        let c = one(&mut mem, t, 2500, FetchKind::Attr);
        assert_eq!(
            (c.source, c.cycle_done),
            (Source::Miss, t + u64::from(dram_lat) + beats)
        );
        let t = mem.now();
        let c = one(&mut mem, t, 2501, FetchKind::Attr);
        let same_line = (8 * 2500) / line == (8 * 2501) / line;
        assert_eq!(c.source == Source::CacheHit, same_line);
    }
}

#[test]
fn misses_to_one_line_merge_and_complete_together() {
    let cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 60, 64, 4);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 20, 16).unwrap()).unwrap();
    let a = mem.request(0, 1600, FetchKind::Node, 3).unwrap(); // line 100
    let b = mem.request(0, 1601, FetchKind::Node, 1).unwrap(); // same line, same cycle
    let c = mem.request(5, 1615, FetchKind::Far, 2).unwrap(); // same line, later
    let d = mem.request(61, 1602, FetchKind::Node, 0).unwrap(); // the fill completes at 61
    let done: HashMap<RequestId, Completion> = mem.drain().into_iter().map(|c| (c.id, c)).collect();
    assert_eq!(done.len(), 4);
    // Requester 1 is served first in cycle 0, so it issues the fill.
    assert_eq!((done[&b].source, done[&b].cycle_done), (Source::Miss, 61));
    assert_eq!((done[&a].source, done[&a].cycle_done), (Source::Merged, 61));
    assert_eq!((done[&c].source, done[&c].cycle_done), (Source::Merged, 61));
    assert_eq!(
        (done[&d].source, done[&d].cycle_done),
        (Source::CacheHit, 65)
    );
    let s = mem.stats();
    assert_eq!(
        (s.cache_misses, s.cache_merged, s.cache_hits, s.dram_fills),
        (1, 2, 1, 1)
    );
    assert_eq!(s.dram_bytes, 64);
}

#[test]
fn uncached_attributes_bypass_the_cache() {
    let mut cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 20, 64, 4);
    cfg.cache.attr_cached = false;
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1024, 1024).unwrap()).unwrap();
    let c1 = one(&mut mem, 0, 9, FetchKind::Attr);
    let t = mem.now();
    let c2 = one(&mut mem, t, 9, FetchKind::Attr);
    assert_eq!((c1.source, c2.source), (Source::Miss, Source::Miss));
    let s = mem.stats();
    assert_eq!((s.uncached_reads, s.cache_lookups, s.dram_fills), (2, 0, 2));
}

// ---------------------------------------------------------------------------------------
// Ports, MSHRs, bandwidth.

#[test]
fn three_reads_on_a_dual_port_bram_one_waits() {
    let cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 60, 64, 4);
    let layout = MemoryLayout::with_onchip_ranges(1 << 16, 16, vec![(0, 4096)]).unwrap();
    let mut mem = NodeMemory::new(cfg, layout).unwrap();
    // Made in the order 2, 0, 1: served by requester id.
    let r2 = mem.request(5, 30, FetchKind::Node, 2).unwrap();
    let r0 = mem.request(5, 10, FetchKind::Node, 0).unwrap();
    let r1 = mem.request(5, 20, FetchKind::Far, 1).unwrap();
    assert!(mem.tick(7).is_empty());
    let at8 = mem.tick(8);
    assert_eq!(at8.iter().map(|c| c.id).collect::<Vec<_>>(), vec![r0, r1]);
    let at9 = mem.tick(9);
    assert_eq!(at9.len(), 1);
    assert_eq!(
        (at9[0].id, at9[0].cycle_served, at9[0].cycle_done),
        (r2, 6, 9)
    );
    let s = mem.stats();
    assert_eq!(
        (s.port_wait, s.port_conflict_cycles, s.onchip_reads),
        (1, 1, 3)
    );

    // Banks: with two banks, words 0 and 2 share bank 0 (one port each here), word 1 does not.
    let cfg = config(3, 2, 1, 8192, 4, 64, 4, 2, 60, 64, 4);
    let layout = MemoryLayout::with_onchip_ranges(1 << 16, 16, vec![(0, 4096)]).unwrap();
    let mut mem = NodeMemory::new(cfg, layout).unwrap();
    for (req, addr) in [(0u32, 0u32), (1, 1), (2, 2)] {
        mem.request(0, addr, FetchKind::Node, req).unwrap();
    }
    let done: Vec<(u32, u64)> = mem.drain().iter().map(|c| (c.addr, c.cycle_done)).collect();
    assert_eq!(done, vec![(0, 3), (1, 3), (2, 4)]);

    // The cache has its own lookup ports: three hits to a 2-port cache, one waits.
    let cfg = config(3, 1, 2, 8192, 4, 64, 4, 2, 10, 64, 4);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 16, 16).unwrap()).unwrap();
    one(&mut mem, 0, 100, FetchKind::Node);
    let t = mem.now();
    for r in 0..3 {
        mem.request(t, 100 + r, FetchKind::Node, r).unwrap();
    }
    let done: Vec<u64> = mem.drain().iter().map(|c| c.cycle_done - t).collect();
    assert_eq!(done, vec![4, 4, 5]);
}

#[test]
fn more_misses_than_mshrs_stall_and_none_is_lost() {
    let cfg = config(3, 1, 2, 1 << 16, 4, 64, 4, 2, 10, 64, 2);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 20, 16).unwrap()).unwrap();
    // Ten different lines in one cycle, two MSHRs.
    let ids: Vec<RequestId> = (0..10)
        .map(|i| mem.request(0, i * 16, FetchKind::Node, i).unwrap())
        .collect();
    let done = mem.drain();
    let got: Vec<RequestId> = {
        let mut v: Vec<RequestId> = done.iter().map(|c| c.id).collect();
        v.sort();
        v
    };
    assert_eq!(got, ids, "every request completes exactly once");
    // Pairs: fills of (0, 1) complete at 11 and 12; the third is served at 11, and so on.
    let by_req: BTreeMap<u32, &Completion> = done.iter().map(|c| (c.requester, c)).collect();
    assert_eq!((by_req[&0].cycle_served, by_req[&0].cycle_done), (0, 11));
    assert_eq!((by_req[&1].cycle_served, by_req[&1].cycle_done), (0, 12));
    assert_eq!((by_req[&2].cycle_served, by_req[&2].cycle_done), (11, 22));
    assert_eq!((by_req[&3].cycle_served, by_req[&3].cycle_done), (12, 23));
    assert_eq!(max_in_flight(&done), 2);
    let s = mem.stats();
    println!("{s:?}");
    assert_eq!(s.mshr_max_in_use, 2);
    assert_eq!(s.cache_misses, 10);
    // From cycle 1 the pipeline is blocked until the last read gets its MSHR in cycle 45
    // (cycle 0 ran out of lookup ports instead).
    assert_eq!(s.mshr_full_cycles, 44);
    assert_eq!(s.port_wait, 8);
    assert!(s.mshr_wait > s.mshr_full_cycles);
    let waited: u64 = done
        .iter()
        .map(|c| c.cycle_served - c.cycle_requested)
        .sum();
    assert_eq!(waited, s.mshr_wait + s.port_wait);
}

/// Most line fills in flight at once, from the completions: a fill occupies its MSHR over
/// [served, done).
fn max_in_flight(done: &[Completion]) -> usize {
    let mut events: Vec<(u64, i32)> = Vec::new();
    for c in done.iter().filter(|c| c.source == Source::Miss) {
        events.push((c.cycle_served, 1));
        events.push((c.cycle_done, -1));
    }
    events.sort(); // frees (-1) sort before allocations at the same cycle
    let (mut cur, mut max) = (0i32, 0i32);
    for (_, d) in events {
        cur += d;
        max = max.max(cur);
    }
    max as usize
}

#[test]
fn dram_never_exceeds_its_byte_budget_and_saturates_when_streaming() {
    // Budget: 24 B/cycle with 64-byte lines (fills share cycles), lots of MSHRs.
    for &(bpc, line) in &[(24u32, 64u32), (64, 64), (16, 128), (100, 32)] {
        let cfg = config(3, 1, 2, 1 << 16, 4, line, 4, 2, 40, bpc, 256);
        let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 24, 16).unwrap()).unwrap();
        let words = u64::from(line / 4);
        for i in 0..3000u64 {
            mem.request(i / 2, (i * words) as u32, FetchKind::Node, (i % 2) as u32)
                .unwrap();
        }
        let done = mem.drain();
        let s = mem.stats();
        assert!(s.dram_max_bytes_in_cycle <= u64::from(bpc));
        assert!(s.dram_bytes <= s.window_cycles * u64::from(bpc));
        assert_eq!(s.dram_bytes, 3000 * u64::from(line));
        // Independently: the n-th fill cannot finish before n lines fit through the bus after
        // the first data could arrive.
        let mut dones: Vec<u64> = done.iter().map(|c| c.cycle_done).collect();
        dones.sort();
        for (n, &d) in dones.iter().enumerate() {
            let bytes = (n as u64 + 1) * u64::from(line);
            assert!(d >= 40 + bytes.div_ceil(u64::from(bpc)), "fill {n} at {d}");
        }
        println!(
            "bus {bpc} B/cycle, line {line}: {:.1} % of peak, busy {:.1} %",
            s.dram_bandwidth_pct(),
            s.dram_busy_pct()
        );
    }

    // Saturation: one new line per cycle at 64 B/cycle, more MSHRs than latency × rate.
    let cfg = config(3, 1, 2, 1 << 16, 4, 64, 4, 2, 60, 64, 128);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 24, 16).unwrap()).unwrap();
    for i in 0..4096u32 {
        mem.request(u64::from(i), i * 16, FetchKind::Node, 0)
            .unwrap();
    }
    mem.drain();
    let s = mem.stats();
    println!(
        "streaming: {:.2} % of peak over {} cycles",
        s.dram_bandwidth_pct(),
        s.window_cycles
    );
    assert!(s.dram_bandwidth_pct() > 95.0);
    assert!(s.dram_bandwidth_pct() <= 100.0);

    // Little's law: 16 MSHRs over 60 + 1 cycles carry at most 16 lines per 61 cycles.
    let cfg = config(3, 1, 2, 1 << 16, 4, 64, 4, 2, 60, 64, 16);
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(1 << 24, 16).unwrap()).unwrap();
    for i in 0..4096u32 {
        mem.request(u64::from(i), i * 16, FetchKind::Node, 0)
            .unwrap();
    }
    mem.drain();
    let pct = mem.stats().dram_bandwidth_pct();
    println!(
        "16 MSHRs: {pct:.2} % of peak (bound {:.2} %)",
        100.0 * 16.0 / 61.0
    );
    assert!(pct <= 100.0 * 16.0 / 61.0 + 0.5 && pct > 20.0);
}

// ---------------------------------------------------------------------------------------
// Random stress and determinism.

struct Issued {
    cycle: u64,
    addr: u32,
    kind: FetchKind,
    requester: u32,
}

fn random_config(rng: &mut Rng) -> NodeMemoryConfig {
    let line = 8u32 << rng.below(5); // 8 ..= 128
    let ways = 1u32 << rng.below(4);
    let sets = 1u64 << rng.below(6);
    let size = if rng.below(8) == 0 {
        0
    } else {
        sets * u64::from(ways) * u64::from(line)
    };
    let mut cfg = config(
        1 + rng.below(4) as u32,
        1 + rng.below(4) as u32,
        1 + rng.below(2) as u32,
        size,
        ways,
        line,
        1 + rng.below(5) as u32,
        1 + rng.below(3) as u32,
        1 + rng.below(80) as u32,
        1 + rng.below(80) as u32,
        1 + rng.below(12) as u32,
    );
    cfg.cache.attr_cached = rng.below(3) != 0;
    cfg
}

fn random_requests(rng: &mut Rng, n: usize, node_words: u64, attrs: u64) -> Vec<Issued> {
    let mut v = Vec::with_capacity(n);
    let mut cycle = 0u64;
    let hot: Vec<u32> = (0..32).map(|_| rng.below(node_words) as u32).collect();
    for _ in 0..n {
        if rng.below(3) == 0 {
            let span = if rng.below(20) == 0 { 200 } else { 4 };
            cycle += rng.below(span);
        }
        let kind = match rng.below(6) {
            0 => FetchKind::Far,
            1 => FetchKind::Attr,
            _ => FetchKind::Node,
        };
        let addr = if kind == FetchKind::Attr {
            rng.below(attrs) as u32
        } else if rng.below(2) == 0 {
            hot[rng.below(32) as usize] + rng.below(8) as u32
        } else {
            rng.below(node_words) as u32
        };
        v.push(Issued {
            cycle,
            addr: addr.min(node_words as u32 - 1),
            kind,
            requester: rng.below(16) as u32,
        });
    }
    v
}

/// Runs the requests, calling `tick` at random cycles (skipping many); checks that each tick
/// returns exactly the completions due by its cycle.
fn run_ticked(
    cfg: &NodeMemoryConfig,
    layout: &MemoryLayout,
    reqs: &[Issued],
    rng: &mut Rng,
) -> (Vec<Completion>, rtl_model::cycle::memory::NodeMemoryStats) {
    let mut mem = NodeMemory::new(cfg.clone(), layout.clone()).unwrap();
    let mut out = Vec::new();
    let mut last_tick = 0u64;
    let mut i = 0;
    while i < reqs.len() {
        let c = reqs[i].cycle;
        if c > last_tick && rng.below(2) == 0 {
            let t = last_tick + 1 + rng.below(c - last_tick);
            for d in mem.tick(t) {
                // Due by t, and not due at an earlier tick (those returned it already).
                assert!(d.cycle_done <= t && d.cycle_done > last_tick);
                out.push(d);
            }
            last_tick = t;
        }
        let r = &reqs[i];
        mem.request(r.cycle, r.addr, r.kind, r.requester).unwrap();
        i += 1;
    }
    for d in mem.drain() {
        assert!(d.cycle_done > last_tick);
        out.push(d);
    }
    (out, mem.stats())
}

#[test]
fn random_stress_invariants() {
    let mut rng = Rng(seed("random_stress", 0x5eed_3e30_0003));
    let node_words = 1u64 << 14;
    let attrs = 1u64 << 10;
    for round in 0..60 {
        let cfg = random_config(&mut rng);
        cfg.validate().unwrap();
        // Random on-chip ranges.
        let mut ranges = Vec::new();
        let mut at = 0u32;
        while at < node_words as u32 - 64 && ranges.len() < 12 {
            let s = at + rng.below(2000) as u32;
            let e = s + 1 + rng.below(300) as u32;
            if u64::from(e) > node_words {
                break;
            }
            ranges.push((s, e));
            at = e;
        }
        let onchip_set: HashSet<u32> = ranges.iter().flat_map(|&(s, e)| s..e).collect();
        let layout = MemoryLayout::with_onchip_ranges(node_words, attrs, ranges).unwrap();
        let reqs = random_requests(&mut rng, 3000, node_words, attrs);
        let (done, s) = run_ticked(&cfg, &layout, &reqs, &mut rng);
        let what = format!("round {round} cfg {cfg:?}");

        // Every request completes exactly once; ids are 0..n in call order.
        let mut ids: Vec<u64> = done.iter().map(|c| c.id.0).collect();
        ids.sort();
        assert_eq!(ids, (0..reqs.len() as u64).collect::<Vec<_>>(), "{what}");
        let by_id: BTreeMap<u64, &Completion> = done.iter().map(|c| (c.id.0, c)).collect();

        let line = u64::from(cfg.cache.line_bytes);
        let line_key = |c: &Completion| match c.kind {
            FetchKind::Attr => (1u8, 8 * u64::from(c.addr) / line),
            _ => (0u8, 4 * u64::from(c.addr) / line),
        };
        let beats = line.div_ceil(u64::from(cfg.dram.bytes_per_cycle));
        let mut per_bank: HashMap<(u32, u64), u32> = HashMap::new();
        let mut per_cache_cycle: HashMap<u64, u32> = HashMap::new();
        let mut fills: HashMap<(u8, u64), Vec<&Completion>> = HashMap::new();
        for (i, r) in reqs.iter().enumerate() {
            let c = by_id[&(i as u64)];
            assert_eq!(
                (c.addr, c.kind, c.requester, c.cycle_requested),
                (r.addr, r.kind, r.requester, r.cycle)
            );
            assert!(
                c.cycle_served >= c.cycle_requested && c.cycle_done > c.cycle_served,
                "{what}"
            );
            let onchip = r.kind != FetchKind::Attr && onchip_set.contains(&r.addr);
            match c.source {
                Source::OnChip { bank } => {
                    assert!(onchip, "{what}");
                    assert_eq!(bank, r.addr % cfg.onchip.banks);
                    assert_eq!(c.cycle_done - c.cycle_served, u64::from(cfg.onchip.latency));
                    *per_bank.entry((bank, c.cycle_served)).or_default() += 1;
                }
                src => {
                    assert!(!onchip, "{what}");
                    *per_cache_cycle.entry(c.cycle_served).or_default() += 1;
                    match src {
                        Source::CacheHit => {
                            assert!(cfg.cache.size_bytes > 0);
                            assert!(r.kind != FetchKind::Attr || cfg.cache.attr_cached);
                            assert_eq!(
                                c.cycle_done - c.cycle_served,
                                u64::from(cfg.cache.hit_latency)
                            );
                        }
                        Source::Miss => {
                            assert!(
                                c.cycle_done
                                    >= c.cycle_served + u64::from(cfg.dram.latency) + beats
                            );
                            fills.entry(line_key(c)).or_default().push(c);
                        }
                        _ => {}
                    }
                }
            }
        }
        let bank_ports = cfg.onchip.ports_per_bank;
        assert!(per_bank.values().all(|&n| n <= bank_ports), "{what}");
        assert!(
            per_cache_cycle.values().all(|&n| n <= cfg.cache.ports),
            "{what}"
        );
        assert!(max_in_flight(&done) <= cfg.dram.mshrs as usize, "{what}");
        // A merged read joined a fill of its line that was in flight when it was served.
        for c in done.iter().filter(|c| c.source == Source::Merged) {
            let f = fills[&line_key(c)]
                .iter()
                .find(|f| f.cycle_served <= c.cycle_served && c.cycle_served < f.cycle_done)
                .unwrap_or_else(|| panic!("{what}: merged read {c:?} without its fill"));
            assert_eq!(f.cycle_done, c.cycle_done);
        }
        // Service order: within one queue, (cycle, requester, id) order is never overtaken.
        let mut queues: BTreeMap<(bool, u32), Vec<&Completion>> = BTreeMap::new();
        for c in &done {
            let key = match c.source {
                Source::OnChip { bank } => (true, bank),
                _ => (false, 0),
            };
            queues.entry(key).or_default().push(c);
        }
        for q in queues.values_mut() {
            q.sort_by_key(|c| (c.cycle_requested, c.requester, c.id));
            assert!(
                q.windows(2).all(|w| w[0].cycle_served <= w[1].cycle_served),
                "{what}"
            );
        }
        // Statistics add up.
        let n = reqs.len() as u64;
        assert_eq!(s.fetches.total(), n);
        assert_eq!(s.served, n);
        assert_eq!(
            s.cache_lookups,
            s.cache_hits + s.cache_misses + s.cache_merged
        );
        assert_eq!(s.onchip_reads + s.cache_lookups + s.uncached_reads, n);
        let misses = done.iter().filter(|c| c.source == Source::Miss).count() as u64;
        assert_eq!(s.dram_fills, misses);
        assert_eq!(s.dram_bytes, misses * line);
        assert!(s.dram_max_bytes_in_cycle <= u64::from(cfg.dram.bytes_per_cycle));
        assert!(s.mshr_max_in_use <= u64::from(cfg.dram.mshrs));
        let waited: u64 = done
            .iter()
            .map(|c| c.cycle_served - c.cycle_requested)
            .sum();
        assert_eq!(waited, s.port_wait + s.mshr_wait, "{what}");
        let lat: Vec<u64> = done
            .iter()
            .map(|c| c.cycle_done - c.cycle_requested)
            .collect();
        assert_eq!(s.latency_sum, lat.iter().sum::<u64>());
        assert_eq!(s.latency_max, *lat.iter().max().unwrap());
        let words: u64 = reqs.iter().map(|r| r.kind.words()).sum();
        assert_eq!((s.words, s.bytes), (words, 4 * words));
    }
}

#[test]
fn same_requests_give_same_completions() {
    let mut rng = Rng(seed("determinism", 0x5eed_3e30_0004));
    let node_words = 1u64 << 14;
    let attrs = 1u64 << 10;
    for _ in 0..10 {
        let cfg = random_config(&mut rng);
        let layout =
            MemoryLayout::with_onchip_ranges(node_words, attrs, vec![(0, 200), (5000, 5600)])
                .unwrap();
        let reqs = random_requests(&mut rng, 3000, node_words, attrs);
        let tick_seed = rng.next();
        let a = run_ticked(&cfg, &layout, &reqs, &mut Rng(tick_seed));
        let b = run_ticked(&cfg, &layout, &reqs, &mut Rng(tick_seed));
        assert_eq!(a, b);
        // Different tick points change nothing either (once sorted the same way).
        let mut c = run_ticked(&cfg, &layout, &reqs, &mut Rng(tick_seed ^ 1));
        let mut a0 = a.0.clone();
        a0.sort_by_key(|c| c.id);
        c.0.sort_by_key(|c| c.id);
        assert_eq!(a0, c.0);
        assert_eq!(a.1, c.1);

        // The order in which one cycle's requests are made does not matter: each requester
        // makes at most one request per cycle, made here in a shuffled order per cycle.
        let mut seen = HashSet::new();
        let unique: Vec<&Issued> = reqs
            .iter()
            .filter(|r| seen.insert((r.cycle, r.requester)))
            .collect();
        let outcome = |order: &[&Issued]| {
            let mut mem = NodeMemory::new(cfg.clone(), layout.clone()).unwrap();
            for r in order {
                mem.request(r.cycle, r.addr, r.kind, r.requester).unwrap();
            }
            let mut v: Vec<_> = mem
                .drain()
                .into_iter()
                .map(|c| {
                    (
                        c.cycle_requested,
                        c.requester,
                        c.cycle_served,
                        c.cycle_done,
                        c.source,
                    )
                })
                .collect();
            v.sort_by_key(|x| (x.0, x.1));
            (v, mem.stats())
        };
        let mut shuffled = unique.clone();
        let mut start = 0;
        while start < shuffled.len() {
            let mut end = start;
            while end < shuffled.len() && shuffled[end].cycle == shuffled[start].cycle {
                end += 1;
            }
            for i in (start + 1..end).rev() {
                let j = start + rng.below((i - start + 1) as u64) as usize;
                shuffled.swap(i, j);
            }
            start = end;
        }
        assert_eq!(outcome(&unique), outcome(&shuffled));
    }
}

// ---------------------------------------------------------------------------------------
// Errors and configuration.

#[test]
fn bad_requests_are_refused_and_counted() {
    let cfg = NodeMemoryConfig::default();
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(100, 10).unwrap()).unwrap();
    assert!(matches!(
        mem.request(0, 100, FetchKind::Node, 0),
        Err(RequestError::OutOfRange { limit: 100, .. })
    ));
    assert!(matches!(
        mem.request(0, 10, FetchKind::Attr, 0),
        Err(RequestError::OutOfRange { limit: 10, .. })
    ));
    assert!(mem.request(0, u32::MAX, FetchKind::Far, 0).is_err());
    assert!(matches!(
        mem.request(1 << 63, 1, FetchKind::Node, 0),
        Err(RequestError::CycleTooLarge(_))
    ));
    mem.request(5, 1, FetchKind::Node, 0).unwrap();
    assert!(mem.tick(3).is_empty());
    assert!(matches!(
        mem.request(2, 1, FetchKind::Node, 0),
        Err(RequestError::InPast { cycle: 2, now: 3 })
    ));
    assert_eq!(mem.stats().out_of_range, 3);
    assert_eq!(mem.drain().len(), 1);
    assert!(mem.is_idle());
    // A huge tick after going idle is cheap and safe.
    assert!(mem.tick(u64::MAX).is_empty());
    // Empty layouts refuse everything.
    let mut mem = NodeMemory::new(NodeMemoryConfig::default(), MemoryLayout::default()).unwrap();
    assert!(mem.request(0, 0, FetchKind::Node, 0).is_err());
}

#[test]
fn configurations_are_validated() {
    let d = NodeMemoryConfig::default();
    d.validate().unwrap();
    // The documented defaults (300 MHz, one DDR4-2400 channel).
    assert_eq!(
        (
            d.onchip.levels,
            d.onchip.latency,
            d.onchip.banks,
            d.onchip.ports_per_bank
        ),
        (6, 3, 4, 2)
    );
    assert_eq!(
        (
            d.cache.size_bytes,
            d.cache.ways,
            d.cache.line_bytes,
            d.cache.hit_latency
        ),
        (256 * 1024, 4, 64, 4)
    );
    assert_eq!(
        (d.dram.latency, d.dram.bytes_per_cycle, d.dram.mshrs),
        (60, 64, 32)
    );
    assert_eq!(d.cache_sets(), 1024);
    let r = d.resources(37449);
    println!("default resources for 37449 on-chip words: {r:?}");
    assert_eq!(r.onchip_bram36, 4 * 10);
    assert_eq!(r.cache_uram, 16);

    let bad: Vec<(NodeMemoryConfig, &str)> = vec![
        (
            {
                let mut c = d.clone();
                c.onchip.latency = 0;
                c
            },
            "onchip.latency",
        ),
        (
            {
                let mut c = d.clone();
                c.onchip.banks = 0;
                c
            },
            "onchip.banks",
        ),
        (
            {
                let mut c = d.clone();
                c.onchip.ports_per_bank = 0;
                c
            },
            "onchip.ports_per_bank",
        ),
        (
            {
                let mut c = d.clone();
                c.onchip.levels = 22;
                c
            },
            "levels",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.line_bytes = 48;
                c
            },
            "line_bytes",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.line_bytes = 4;
                c
            },
            "line_bytes",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.ways = 0;
                c
            },
            "cache.ways",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.ports = 0;
                c
            },
            "cache.ports",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.hit_latency = 0;
                c
            },
            "cache.hit_latency",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.size_bytes = 3 * 64 * 4;
                c
            },
            "power-of-two",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.size_bytes = 1000;
                c
            },
            "power-of-two",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.size_bytes = 1 << 40;
                c
            },
            "larger",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.latency = 0;
                c
            },
            "dram.latency",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.latency = u32::MAX;
                c
            },
            "dram.latency",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.bytes_per_cycle = 0;
                c
            },
            "dram.bytes_per_cycle",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.mshrs = 0;
                c
            },
            "dram.mshrs",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.mshrs = 1 << 20;
                c
            },
            "dram.mshrs",
        ),
    ];
    for (c, field) in bad {
        let e = c.validate().unwrap_err();
        assert!(e.to_string().contains(field), "{e} should name {field}");
        assert_eq!(NodeMemory::new(c, MemoryLayout::default()).unwrap_err(), e);
    }
    // A disabled cache is valid, and three ways with a power-of-two set count too.
    let mut c = d.clone();
    c.cache.size_bytes = 0;
    c.validate().unwrap();
    c.cache.ways = 3;
    c.cache.size_bytes = 3 * 64 * 16;
    c.validate().unwrap();
    assert!(matches!(
        {
            let mut c = d.clone();
            c.cache.line_bytes = 3;
            c
        }
        .validate(),
        Err(ConfigError::LineBytes(3))
    ));

    // Layout errors.
    assert!(MemoryLayout::with_onchip_ranges(100, 0, vec![(5, 5)]).is_err());
    assert!(MemoryLayout::with_onchip_ranges(100, 0, vec![(50, 60), (55, 70)]).is_err());
    assert!(MemoryLayout::with_onchip_ranges(100, 0, vec![(90, 101)]).is_err());
    assert!(MemoryLayout::flat(1 << 33, 0).is_err());
}

#[test]
fn configuration_files_reject_unknown_fields() {
    use serde::de::value::{Error, MapDeserializer};
    use serde::Deserialize;
    let ok = DramConfig::deserialize(MapDeserializer::<_, Error>::new(
        vec![("latency", 90u32)].into_iter(),
    ))
    .unwrap();
    assert_eq!(
        ok,
        DramConfig {
            latency: 90,
            ..DramConfig::default()
        }
    );
    let typo = DramConfig::deserialize(MapDeserializer::<_, Error>::new(
        vec![("latency", 90u32), ("mshr", 8)].into_iter(),
    ));
    assert!(typo.unwrap_err().to_string().contains("mshr"));
}

/// On-chip banks against a cycle-by-cycle oracle: per bank a queue served `ports` reads per
/// cycle in (cycle, requester, id) order. Checks every read's service cycle, and the port-wait
/// and port-conflict counts, also when the statistics window is split at random cycles and
/// when ticks skip many cycles.
#[test]
fn onchip_banks_agree_with_a_per_cycle_queue_oracle() {
    let s = seed(
        "onchip_banks_agree_with_a_per_cycle_queue_oracle",
        0xba4c_5107,
    );
    let mut rng = Rng(s);
    for case in 0..40 {
        let banks = 1 + rng.below(6) as u32;
        let ports = 1 + rng.below(2) as u32;
        let latency = 1 + rng.below(5) as u32;
        let cfg = config(latency, banks, ports, 8192, 4, 64, 4, 2, 60, 64, 4);
        let layout = MemoryLayout::with_onchip_ranges(1 << 12, 16, vec![(0, 1 << 12)]).unwrap();
        let mut mem = NodeMemory::new(cfg, layout).unwrap();
        // Bursts (hot banks, long queues) and quiet stretches (skipped cycles).
        let mut reqs: Vec<(u64, u32, u32, u64)> = Vec::new(); // (cycle, requester, addr, id)
        let mut cycle = 0u64;
        for _ in 0..60 {
            cycle += if rng.below(4) == 0 {
                5 + rng.below(40)
            } else {
                rng.below(2)
            };
            let hot = rng.below(u64::from(banks)) as u32;
            let mut requesters: Vec<u32> = (0..16).collect();
            for _ in 0..rng.below(7) {
                let k = rng.below(requesters.len() as u64) as usize;
                let requester = requesters.swap_remove(k);
                let addr = if rng.below(2) == 0 {
                    hot + banks * rng.below(50) as u32
                } else {
                    rng.below(1 << 12) as u32
                };
                reqs.push((cycle, requester, addr, 0));
            }
        }
        // Make them in cycle order, ticking now and then, and split the statistics window.
        let mut windows = Vec::new();
        let mut done: Vec<Completion> = Vec::new();
        for r in reqs.iter_mut() {
            if r.0 > mem.now() && rng.below(3) == 0 {
                done.extend(mem.tick(r.0));
                if rng.below(3) == 0 {
                    windows.push(mem.reset_stats());
                }
            }
            r.3 = mem.request(r.0, r.2, FetchKind::Node, r.1).unwrap().0;
        }
        done.extend(mem.drain());
        windows.push(mem.stats());

        // The oracle.
        let mut order = reqs.clone();
        order.sort_by_key(|&(c, req, _, id)| (c, req, id));
        let mut queues: Vec<std::collections::VecDeque<(u64, u64)>> =
            vec![Default::default(); banks as usize]; // (id, request cycle)
        let mut served: HashMap<u64, u64> = HashMap::new();
        let (mut wait, mut conflicts) = (0u64, 0u64);
        let mut next = 0;
        let mut k = 0u64;
        while served.len() < order.len() {
            while next < order.len() && order[next].0 == k {
                let (_, _, addr, id) = order[next];
                queues[(addr % banks) as usize].push_back((id, k));
                next += 1;
            }
            let mut left_any = false;
            for q in queues.iter_mut() {
                for _ in 0..ports {
                    if let Some((id, _)) = q.pop_front() {
                        served.insert(id, k);
                    }
                }
                wait += q.len() as u64;
                left_any |= !q.is_empty();
            }
            conflicts += u64::from(left_any);
            k += 1;
        }
        let what = format!("seed {s}, case {case}: {banks} banks × {ports} ports");
        assert_eq!(done.len(), reqs.len(), "{what}");
        for c in &done {
            assert_eq!(
                Some(&c.cycle_served),
                served.get(&c.id.0),
                "{what}: read {}",
                c.id.0
            );
            assert_eq!(c.cycle_done, c.cycle_served + u64::from(latency), "{what}");
        }
        let total = |f: fn(&rtl_model::cycle::memory::NodeMemoryStats) -> u64| -> u64 {
            windows.iter().map(f).sum()
        };
        assert_eq!(total(|w| w.port_wait), wait, "{what}: port wait");
        assert_eq!(
            total(|w| w.port_conflict_cycles),
            conflicts,
            "{what}: conflict cycles"
        );
        assert_eq!(total(|w| w.onchip_reads), reqs.len() as u64, "{what}");
    }
}
