//! Node memory: the cycle-level model of where the octree walkers' reads go and when they
//! come back.
//!
//! # Where it sits
//!
//! Between the walker pool and the memories of the part. Every walker context reads the SVO
//! image of `docs/svo-format.md` (§12 lists the traffic): one 32-bit word per child descriptor
//! (the root's included), one more word when a descriptor uses the far escape, one word per
//! leaf slot, and one 8-byte record (two words) from the separate attribute array for the leaf
//! a ray hits. The walker pool calls [`NodeMemory::request`] for each of those reads and
//! [`NodeMemory::tick`] once per cycle to collect the reads that have completed. The model
//! does not hold the data; the walkers read the words from the [`SvoImage`] themselves (the
//! functional result cannot depend on timing) and use this model only for *when*.
//!
//! # The three places a read can be served
//!
//! 1. **On-chip node store** (block RAM): the top [`OnChipConfig::levels`] levels of the tree.
//!    Fixed latency, `banks` word-interleaved banks of `ports_per_bank` ports each.
//! 2. **Cache** (set-associative, LRU, UltraRAM-sized) in front of external DRAM, shared by the
//!    rest of the node image and the attribute array.
//! 3. **External DRAM**: a fixed latency, a peak byte rate per cycle, and a limited number of
//!    outstanding line fills (MSHRs). A miss fills a whole cache line.
//!
//! # Why the on-chip part is "the top levels", not "the first bytes"
//!
//! The image is laid out depth first (`svo/build.rs`): word 0 is the root, then the root's
//! group, then the *whole* subtree of its first child, and so on. A prefix of the image is
//! therefore the root plus the leftmost corner of the tree down to the leaves, which helps
//! only the rays that look at that corner. The part every ray touches is the top of the tree:
//! each walk starts at the root and descends through levels 1, 2, …, so those few words are
//! read by every ray, and there are at most 8^l of them at level l (about 4^l for the surface
//! voxels the builders make). The on-chip region is therefore an address whitelist built from
//! the image's top levels ([`MemoryLayout::from_image`]): the root word and the groups (slots
//! and far words) of every internal node above level `levels − 1`, i.e. every descriptor of a
//! node at a level below `levels`, the far word needed to descend from it, and any leaf slot
//! at those levels. The whitelist is scattered through the image, but that costs the hardware
//! nothing: a walker knows the level of the node it is about to read (its stack depth), so the
//! on-chip test in RTL is `level < levels`, not an address compare; the builder copies those
//! groups to the block RAM and the model only needs their number (capacity) and timing. Whole
//! levels are kept, up to [`OnChipConfig::max_bytes`], because a partial level would need an
//! address compare after all. To size the store by bytes instead, set `levels` to its
//! maximum (21) and `max_bytes` to the budget: it then holds as many whole top levels as fit.
//!
//! # Use
//!
//! ```text
//! let layout = MemoryLayout::from_image(&image, &cfg.onchip)?;
//! let mut mem = NodeMemory::new(cfg, layout)?;
//! for cycle in 0.. {
//!     for c in mem.tick(cycle) { /* c.id's data is valid now: wake its walker context */ }
//!     /* evaluate the walkers; each read: */ mem.request(cycle, addr, FetchKind::Node, ctx)?;
//! }
//! let frame = mem.reset_stats(); // per-frame window: hit rate, DRAM % of peak, stalls
//! ```
//!
//! # Timing semantics
//!
//! * **Calling convention.** `tick(c)` is called at the *start* of cycle `c`: it finishes the
//!   arbitration of every cycle before `c` and returns the reads whose data is valid in cycle
//!   `c` (`cycle_done ≤ c`). Requests made during cycle `c` (after `tick(c)`) are arbitrated
//!   as cycle-`c` requests in the next `tick`. This is the two-phase discipline of
//!   [`super::clocked`]: what a walker sees in cycle `c` depends only on requests made in
//!   earlier cycles. Skipping cycles is safe: `tick(c)` processes every cycle before `c`.
//! * **Order.** In each cycle the requests waiting for a resource are served in the order
//!   (request cycle, requester id, request id): older first, then the lower requester, then the
//!   earlier call. Nothing depends on hash order or wall time, so the same request sequence
//!   gives the same completions and statistics on every run.
//! * **Latency.** A request made in cycle `c` and served (given a port) in cycle `s ≥ c`
//!   completes at
//!   - on chip: `s + onchip.latency`;
//!   - cache hit: `s + cache.hit_latency`;
//!   - miss: when its line fill completes; an isolated miss completes at
//!     `s + dram.latency + ⌈line_bytes / bytes_per_cycle⌉` (the fill data is forwarded to the
//!     waiting reads as it is written, so no hit latency is added);
//!   - miss to a line already being filled (merged): with that fill.
//! * **Ports.** Each on-chip bank serves at most `ports_per_bank` reads per cycle; the cache
//!   pipeline looks up at most `cache.ports` reads per cycle. The rest wait to the next cycle
//!   (counted as port-wait request-cycles).
//! * **MSHRs.** A miss needs a free MSHR unless its line is already in flight (then it merges;
//!   an MSHR takes any number of merged reads). When none is free the in-order lookup pipeline
//!   stalls until a fill completes, as a non-blocking cache does when its miss table is full:
//!   reads behind the stalled one wait too (counted as MSHR-wait request-cycles, and the cycle
//!   as an MSHR-full cycle). An MSHR is freed, and the line installed as most recently used,
//!   in the cycle its fill completes; a lookup in that same cycle hits.
//! * **Bandwidth.** Fills share one data bus of `bytes_per_cycle` bytes per cycle, in the
//!   order they were issued. A fill issued in cycle `s` may start to transfer at cycle
//!   `s + latency` (latency overlaps with other fills' transfers) and occupies `line_bytes` of
//!   the bus's byte budget; a cycle never moves more than `bytes_per_cycle` bytes, also when
//!   the line is not a multiple of it (two fills then share a cycle).
//!
//! Simplifications (stated so reports can be read correctly): DRAM refresh, bank and row
//! effects are folded into the fixed latency; refills write the cache through their own port
//! (the data array is built from 1R1W copies, see [`NodeMemoryConfig::resources`]); the
//! on-chip store is read only during a frame (it is loaded between frames), so it has no
//! read-during-write case.

use super::completion_wheel::CompletionWheel;
use crate::svo::{ChildDescriptor, SvoImage};
use serde::{Deserialize, Serialize};
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};
use thiserror::Error;

/// Largest request cycle accepted. Keeping cycles below 2^62 leaves room for every latency
/// and byte-slot sum without overflow checks on the hot path.
pub const MAX_CYCLE: u64 = 1 << 62;

/// Byte address at which the attribute array starts in the model's unified address space.
/// Node words occupy bytes `0 .. 4·2^32 = 2^34`; attribute record `i` is at
/// `ATTR_REGION_BASE + 8·i`. The base is a multiple of every valid `sets · line_bytes`, so an
/// attribute record's cache set is `(8·i / line_bytes) mod sets`, as for a node word.
pub const ATTR_REGION_BASE: u64 = 1 << 40;

/// Largest cache accepted by [`NodeMemoryConfig::validate`] (64 MiB): far above the on-chip
/// memory of any part, and small enough that the tag array the model allocates (8 bytes per
/// line) stays reasonable.
pub const MAX_CACHE_BYTES: u64 = 1 << 26;

/// Largest latency accepted (cycles); anything larger is a typo in a configuration.
pub const MAX_LATENCY: u32 = 1 << 20;

/// Largest number of banks, ports or MSHRs accepted.
pub const MAX_PARALLEL: u32 = 4096;

/// What a read fetches; decides its size and which counters it lands in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum FetchKind {
    /// A child descriptor or a leaf slot (one word of node memory).
    Node,
    /// A far-pointer word (one word of node memory).
    Far,
    /// A leaf attribute record (two words of the attribute array); the address is the
    /// attribute index held in the leaf slot.
    Attr,
}

impl FetchKind {
    /// 32-bit words the read returns.
    pub const fn words(self) -> u64 {
        match self {
            FetchKind::Node | FetchKind::Far => 1,
            FetchKind::Attr => 2,
        }
    }
}

/// On-chip node store: the top levels of the tree in block RAM.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OnChipConfig {
    /// Tree levels held on chip, counting the root as level 0: descriptors of nodes at levels
    /// `0 .. levels` (and their far words) are on chip. 0 disables the on-chip store.
    ///
    /// Default 6: levels 0..5 hold at most 1 + 8 + … + 8^5 = 37 449 descriptors (146 KiB, a
    /// completely dense tree) and typically a few thousand for surface voxels, and they are
    /// the reads every ray makes; level 6 could be 8× more for a dense tree.
    pub levels: u8,
    /// Capacity cap in bytes: whole levels are kept while their words fit. Default 256 KiB
    /// (64 BRAM36 of 1024 × 32-bit words), enough for the default six levels of any tree.
    pub max_bytes: u64,
    /// Read latency in cycles (≥ 1). Default 3: an address register, the block RAM with its
    /// output register (needed to reach 300 MHz) and one mux stage across the cascaded
    /// BRAM36 blocks.
    pub latency: u32,
    /// Word-interleaved banks (bank = word address mod banks). Default 4: the walkers' reads
    /// of one group's consecutive slots land in different banks, so 4 × 2 ports serve eight
    /// top-level reads per cycle, about what a pool of 16–32 walkers asks for near the root.
    pub banks: u32,
    /// Ports per bank per cycle (2 = true dual port, the BRAM36 maximum). Reads beyond this in
    /// a cycle wait. Default 2.
    pub ports_per_bank: u32,
}

impl Default for OnChipConfig {
    fn default() -> Self {
        Self {
            levels: 6,
            max_bytes: 256 * 1024,
            latency: 3,
            banks: 4,
            ports_per_bank: 2,
        }
    }
}

/// The set-associative LRU cache in front of DRAM (node image and attribute array).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CacheConfig {
    /// Capacity in bytes; 0 disables the cache (every off-chip read goes to DRAM, merging
    /// still applies). Default 256 KiB: 8 UltraRAMs (32 KiB of 64-bit words each) per copy of
    /// the data array, large against the working set of a frame's upper-middle levels.
    pub size_bytes: u64,
    /// Associativity (≥ 1). Default 4: the depth-first layout maps sibling subtrees to
    /// addresses a power of two apart often enough that a direct-mapped cache thrashes; four
    /// tag compares still fit one 300 MHz cycle.
    pub ways: u32,
    /// Line size in bytes (a power of two, 8 ..= 4096); also the size of every DRAM fill.
    /// Default 64: one DDR4 burst (BL8 × 64-bit bus) and 16 node words, i.e. one or two
    /// sibling groups, so a descent's next reads are often already in the line.
    pub line_bytes: u32,
    /// Hit latency in cycles (≥ 1). Default 4: UltraRAM read with its output and cascade
    /// registers (3 at 300 MHz) plus the way select after the tag compare.
    pub hit_latency: u32,
    /// Lookups per cycle (≥ 1). Default 2: one per read port of a true dual-port array.
    pub ports: u32,
    /// Whether attribute records go through the cache (true) or straight to DRAM (false;
    /// each then still moves a whole line, the DRAM burst). Default true: rays that hit
    /// neighbouring voxels read neighbouring records (the array is in Morton order), eight to a
    /// 64-byte line.
    pub attr_cached: bool,
}

impl Default for CacheConfig {
    fn default() -> Self {
        Self {
            size_bytes: 256 * 1024,
            ways: 4,
            line_bytes: 64,
            hit_latency: 4,
            ports: 2,
            attr_cached: true,
        }
    }
}

/// External DRAM behind the cache.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DramConfig {
    /// Cycles from a fill's issue to its first data (≥ 1). Default 60 at 300 MHz: DDR4's
    /// ~100 ns loaded access (30 cycles) plus about as much again for the memory controller,
    /// the AXI interconnect and clock-domain crossings.
    pub latency: u32,
    /// Peak bytes per cycle on the data bus (≥ 1). Default 64: one DDR4-2400 channel, 64 bits
    /// wide, gives 19.2 GB/s, which is 64 B per cycle at 300 MHz.
    pub bytes_per_cycle: u32,
    /// Outstanding line fills (MSHRs, ≥ 1). Default 32, a miss table a 300 MHz design can
    /// search in one cycle. By Little's law 32 fills of 64 B per (60 + 1) cycles cap miss
    /// bandwidth at about 33.6 B/cycle (52 % of peak): the walkers' scattered reads are bound
    /// by latency long before bandwidth, and the scaling benchmark sweeps this.
    pub mshrs: u32,
}

impl Default for DramConfig {
    fn default() -> Self {
        Self {
            latency: 60,
            bytes_per_cycle: 64,
            mshrs: 32,
        }
    }
}

/// The node-memory configuration: on-chip store, cache and external DRAM. Latencies are in
/// cycles of the pipeline clock; the defaults assume 300 MHz on an UltraScale+ part with one
/// DDR4 channel.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NodeMemoryConfig {
    /// The on-chip part.
    pub onchip: OnChipConfig,
    /// The cache.
    pub cache: CacheConfig,
    /// External DRAM.
    pub dram: DramConfig,
}

/// Why a configuration is not usable.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum ConfigError {
    /// A latency is 0 or above [`MAX_LATENCY`].
    #[error("{field} = {value} cycles is out of range (1 to {MAX_LATENCY})")]
    Latency {
        /// The field.
        field: &'static str,
        /// Its value.
        value: u32,
    },
    /// A count of banks, ports, ways or MSHRs is 0 or above [`MAX_PARALLEL`].
    #[error("{field} = {value} is out of range (1 to {MAX_PARALLEL})")]
    Count {
        /// The field.
        field: &'static str,
        /// Its value.
        value: u32,
    },
    /// The line size is not a power of two in 8 ..= 4096.
    #[error("cache.line_bytes = {0} must be a power of two from 8 to 4096")]
    LineBytes(u32),
    /// The cache size is above [`MAX_CACHE_BYTES`].
    #[error("cache.size_bytes = {0} is larger than {MAX_CACHE_BYTES}")]
    CacheTooLarge(u64),
    /// The cache size is not a power-of-two number of sets of `ways` lines.
    #[error("cache.size_bytes = {size} is not a power-of-two number of sets of {ways} ways × {line} bytes")]
    CacheGeometry {
        /// Size in bytes.
        size: u64,
        /// Ways.
        ways: u32,
        /// Line bytes.
        line: u32,
    },
    /// More on-chip levels than an image can have.
    #[error("onchip.levels = {0} is more than the deepest tree has (21)")]
    Levels(u8),
}

impl NodeMemoryConfig {
    /// Checks every field; the model is only built from a configuration that passes.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let lat = |field, value: u32| {
            if (1..=MAX_LATENCY).contains(&value) {
                Ok(())
            } else {
                Err(ConfigError::Latency { field, value })
            }
        };
        let count = |field, value: u32| {
            if (1..=MAX_PARALLEL).contains(&value) {
                Ok(())
            } else {
                Err(ConfigError::Count { field, value })
            }
        };
        let o = &self.onchip;
        if o.levels > crate::svo::MAX_DEPTH + 1 {
            return Err(ConfigError::Levels(o.levels));
        }
        lat("onchip.latency", o.latency)?;
        count("onchip.banks", o.banks)?;
        count("onchip.ports_per_bank", o.ports_per_bank)?;
        let c = &self.cache;
        if !c.line_bytes.is_power_of_two() || !(8..=4096).contains(&c.line_bytes) {
            return Err(ConfigError::LineBytes(c.line_bytes));
        }
        lat("cache.hit_latency", c.hit_latency)?;
        count("cache.ports", c.ports)?;
        count("cache.ways", c.ways)?;
        if c.size_bytes > MAX_CACHE_BYTES {
            return Err(ConfigError::CacheTooLarge(c.size_bytes));
        }
        if c.size_bytes > 0 {
            let set_bytes = u64::from(c.ways) * u64::from(c.line_bytes);
            let sets = c.size_bytes / set_bytes;
            if c.size_bytes % set_bytes != 0 || !sets.is_power_of_two() {
                return Err(ConfigError::CacheGeometry {
                    size: c.size_bytes,
                    ways: c.ways,
                    line: c.line_bytes,
                });
            }
        }
        let d = &self.dram;
        lat("dram.latency", d.latency)?;
        count("dram.bytes_per_cycle", d.bytes_per_cycle)?;
        count("dram.mshrs", d.mshrs)?;
        Ok(())
    }

    /// Cache sets (0 when the cache is disabled). Meaningful for a validated configuration.
    pub fn cache_sets(&self) -> u64 {
        let set_bytes = u64::from(self.cache.ways) * u64::from(self.cache.line_bytes);
        self.cache.size_bytes.checked_div(set_bytes).unwrap_or(0)
    }

    /// Memory blocks this configuration needs, for the resource report. `onchip_words` is
    /// the on-chip store's size ([`MemoryLayout::onchip_words`]).
    ///
    /// Counting rules: an on-chip bank is BRAM36 blocks of 1024 × 32-bit words; the cache data
    /// array is one UltraRAM copy (32 KiB as 4096 × 64 bits) per lookup port, each copy with
    /// one read port for lookups and one write port for refills; the tag array (tag, valid,
    /// LRU state, under 36 bits per way) is BRAM36 per lookup port, 1024 entries each.
    pub fn resources(&self, onchip_words: u64) -> MemoryResources {
        let banks = u64::from(self.onchip.banks.max(1));
        let onchip_bram36 = if onchip_words == 0 {
            0
        } else {
            banks * onchip_words.div_ceil(banks).div_ceil(1024)
        };
        let ports = u64::from(self.cache.ports);
        let cache_uram = ports * self.cache.size_bytes.div_ceil(32 * 1024);
        let tag_entries = self.cache_sets() * u64::from(self.cache.ways);
        let cache_tag_bram36 = ports * tag_entries.div_ceil(1024);
        MemoryResources {
            onchip_bram36,
            cache_uram,
            cache_tag_bram36,
        }
    }
}

/// Memory blocks of a node-memory configuration ([`NodeMemoryConfig::resources`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MemoryResources {
    /// BRAM36 blocks of the on-chip node store.
    pub onchip_bram36: u64,
    /// UltraRAM blocks of the cache data array (all copies).
    pub cache_uram: u64,
    /// BRAM36 blocks of the cache tag array (all copies).
    pub cache_tag_bram36: u64,
}

/// Why a memory layout could not be made.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum LayoutError {
    /// More node words or attribute records than 32-bit addresses reach.
    #[error("{what} = {value} is more than a 32-bit address reaches")]
    TooLarge {
        /// Which count.
        what: &'static str,
        /// Its value.
        value: u64,
    },
    /// An on-chip range is empty, unsorted, overlapping or outside the node memory.
    #[error(
        "on-chip range {start}..{end} is empty, out of order or outside the {words} node words"
    )]
    BadRange {
        /// Start word.
        start: u32,
        /// End word (exclusive).
        end: u32,
        /// Node words.
        words: u64,
    },
    /// A pointer in the image leads outside the node memory (never for images from
    /// `SvoImage::build`).
    #[error("node word {addr} points outside the image")]
    MalformedImage {
        /// The word whose pointer is bad.
        addr: u64,
    },
}

/// The address map the model serves: node-memory size, attribute count and the on-chip
/// whitelist (sorted, disjoint, half-open word ranges).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MemoryLayout {
    node_words: u64,
    attr_records: u64,
    onchip: Vec<(u32, u32)>,
    /// The same whitelist as one bit per word up to the last on-chip word, for the per-read
    /// test (a binary search over thousands of scattered groups costs a cache miss per
    /// probe); empty when that would exceed [`MAX_ONCHIP_BITMAP_WORDS`].
    onchip_bits: Vec<u64>,
    onchip_levels: u8,
    onchip_words: u64,
}

/// Largest word range the on-chip bitmap covers (2^28 words: a 32 MiB bitmap); beyond it
/// [`MemoryLayout::is_onchip`] searches the ranges instead.
pub const MAX_ONCHIP_BITMAP_WORDS: u64 = 1 << 28;

impl MemoryLayout {
    /// A layout without an on-chip part.
    pub fn flat(node_words: u64, attr_records: u64) -> Result<Self, LayoutError> {
        Self::with_onchip_ranges(node_words, attr_records, Vec::new())
    }

    /// A layout whose on-chip part is the given word ranges (half-open, sorted, disjoint,
    /// non-empty, inside the node memory). For synthetic tests and experiments; images use
    /// [`MemoryLayout::from_image`].
    pub fn with_onchip_ranges(
        node_words: u64,
        attr_records: u64,
        ranges: Vec<(u32, u32)>,
    ) -> Result<Self, LayoutError> {
        let limit = 1u64 << 32;
        if node_words > limit {
            return Err(LayoutError::TooLarge {
                what: "node words",
                value: node_words,
            });
        }
        if attr_records > limit {
            return Err(LayoutError::TooLarge {
                what: "attribute records",
                value: attr_records,
            });
        }
        let mut prev_end = 0u32;
        for (i, &(start, end)) in ranges.iter().enumerate() {
            if start >= end || u64::from(end) > node_words || (i > 0 && start < prev_end) {
                return Err(LayoutError::BadRange {
                    start,
                    end,
                    words: node_words,
                });
            }
            prev_end = end;
        }
        let onchip_words = ranges.iter().map(|&(s, e)| u64::from(e - s)).sum();
        let span = ranges.last().map_or(0, |&(_, e)| u64::from(e));
        let mut onchip_bits = Vec::new();
        if span <= MAX_ONCHIP_BITMAP_WORDS {
            onchip_bits = vec![0u64; span.div_ceil(64) as usize];
            for &(s, e) in &ranges {
                for a in s..e {
                    onchip_bits[(a / 64) as usize] |= 1 << (a % 64);
                }
            }
        }
        Ok(Self {
            node_words,
            attr_records,
            onchip: ranges,
            onchip_bits,
            onchip_levels: 0,
            onchip_words,
        })
    }

    /// The layout of an image: its sizes and the on-chip whitelist of its top
    /// `onchip.levels` levels, cut to whole levels that fit `onchip.max_bytes`.
    ///
    /// Level 0 is the root word; level `l ≥ 1` adds the groups of the internal nodes at level
    /// `l − 1` (their children's slots and the group's far words). A far word sits in the same
    /// group as the descriptor that points to it, so the far read that descends from an
    /// on-chip node is on chip too.
    pub fn from_image(img: &SvoImage, onchip: &OnChipConfig) -> Result<Self, LayoutError> {
        let nodes = img.nodes();
        let n = nodes.len() as u64;
        let attrs = img.attrs().len() as u64;
        if n > u64::from(u32::MAX) {
            // Built images stay below 2^32 words; range ends must fit u32.
            return Err(LayoutError::TooLarge {
                what: "node words",
                value: n,
            });
        }
        let max_words = onchip.max_bytes / 4;
        if onchip.levels == 0 || max_words == 0 || nodes.is_empty() {
            return Self::flat(n, attrs);
        }
        let word = |a: u64| -> Result<u32, LayoutError> {
            usize::try_from(a)
                .ok()
                .and_then(|i| nodes.get(i).copied())
                .ok_or(LayoutError::MalformedImage { addr: a })
        };
        let mut ranges: Vec<(u64, u64)> = vec![(0, 1)];
        let mut words = 1u64;
        let mut levels = 1u8;
        // Internal nodes at level `levels − 1`, whose groups make the next level.
        let mut frontier: Vec<u64> = vec![0];
        while levels < onchip.levels && !frontier.is_empty() {
            let mut level_ranges = Vec::new();
            let mut level_words = 0u64;
            let mut next = Vec::new();
            for &a in &frontier {
                let d = ChildDescriptor::unpack(word(a)?);
                if d.valid == 0 {
                    continue;
                }
                let ptr = u64::from(d.ptr);
                let off = if d.far {
                    u64::from(word(a + ptr)?)
                } else {
                    ptr
                };
                let base = a + off;
                let k = u64::from(d.valid.count_ones());
                let mut far_words = 0;
                let mut slot = base;
                for label in 0..8u8 {
                    let bit = 1u8 << label;
                    if d.valid & bit == 0 {
                        continue;
                    }
                    if d.leaf & bit == 0 {
                        if ChildDescriptor::unpack(word(slot)?).far {
                            far_words += 1;
                        }
                        next.push(slot);
                    }
                    slot += 1;
                }
                let end = base + k + far_words;
                if end > n {
                    return Err(LayoutError::MalformedImage { addr: a });
                }
                level_ranges.push((base, end));
                level_words += k + far_words;
            }
            if words + level_words > max_words {
                break;
            }
            words += level_words;
            ranges.extend(level_ranges);
            frontier = next;
            levels += 1;
        }
        if frontier.is_empty() {
            // The whole tree is on chip; deeper levels are trivially there.
            levels = onchip.levels;
        }
        ranges.sort_unstable();
        let mut merged: Vec<(u32, u32)> = Vec::with_capacity(ranges.len());
        for (s, e) in ranges {
            // e ≤ n ≤ 2^32 − 1 (checked above), so both ends fit u32.
            let (s, e) = (s as u32, e as u32);
            match merged.last_mut() {
                Some(last) if s <= last.1 => last.1 = last.1.max(e),
                _ => merged.push((s, e)),
            }
        }
        let mut layout = Self::with_onchip_ranges(n, attrs, merged)?;
        layout.onchip_levels = levels;
        Ok(layout)
    }

    /// Whether node word `addr` is in the on-chip store.
    #[inline]
    pub fn is_onchip(&self, addr: u32) -> bool {
        if !self.onchip_bits.is_empty() || self.onchip.is_empty() {
            return self
                .onchip_bits
                .get((addr / 64) as usize)
                .is_some_and(|w| w & (1 << (addr % 64)) != 0);
        }
        // Index of the first range starting after addr; the one before may contain it.
        let i = self.onchip.partition_point(|&(s, _)| s <= addr);
        i > 0 && addr < self.onchip[i - 1].1
    }

    /// Node-memory words.
    pub fn node_words(&self) -> u64 {
        self.node_words
    }

    /// Attribute records.
    pub fn attr_records(&self) -> u64 {
        self.attr_records
    }

    /// The on-chip ranges (half-open word ranges, sorted, disjoint).
    pub fn onchip_ranges(&self) -> &[(u32, u32)] {
        &self.onchip
    }

    /// Tree levels actually on chip (0 for layouts not made from an image).
    pub fn onchip_levels(&self) -> u8 {
        self.onchip_levels
    }

    /// Words in the on-chip store.
    pub fn onchip_words(&self) -> u64 {
        self.onchip_words
    }
}

/// Identifies one request; assigned in call order from 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct RequestId(pub u64);

/// Where a read was served.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Source {
    /// The on-chip store, in this bank.
    OnChip {
        /// Bank index (word address mod banks).
        bank: u32,
    },
    /// A cache hit.
    CacheHit,
    /// A miss that issued a line fill (also an uncached attribute read that did).
    Miss,
    /// A miss that joined a fill already in flight for its line.
    Merged,
}

/// A completed read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Completion {
    /// The request.
    pub id: RequestId,
    /// Who asked (walker context or any id the caller chose).
    pub requester: u32,
    /// What was read.
    pub kind: FetchKind,
    /// Node word address, or attribute index for [`FetchKind::Attr`].
    pub addr: u32,
    /// Cycle the request was made.
    pub cycle_requested: u64,
    /// Cycle it got its port (on-chip bank or cache lookup).
    pub cycle_served: u64,
    /// First cycle its data is valid.
    pub cycle_done: u64,
    /// Where it was served.
    pub source: Source,
}

/// Why a request was refused. Refused requests are not queued and get no completion.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum RequestError {
    /// The address is outside the node memory or the attribute array.
    #[error("{kind:?} read at {addr} is outside the {limit} entries of its memory")]
    OutOfRange {
        /// What was read.
        kind: FetchKind,
        /// The address.
        addr: u32,
        /// Words (node memory) or records (attributes) there are.
        limit: u64,
    },
    /// The cycle was already simulated (before the last `tick`).
    #[error("request for cycle {cycle}, but cycles before {now} are already simulated")]
    InPast {
        /// The request's cycle.
        cycle: u64,
        /// The first cycle still open.
        now: u64,
    },
    /// The cycle is above [`MAX_CYCLE`].
    #[error("request cycle {0} is above the model's limit of 2^62")]
    CycleTooLarge(u64),
}

/// Reads by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct KindCounts {
    /// Descriptor and leaf-slot reads.
    pub node: u64,
    /// Far-word reads.
    pub far: u64,
    /// Attribute-record reads.
    pub attr: u64,
}

impl KindCounts {
    /// All reads.
    pub fn total(&self) -> u64 {
        self.node + self.far + self.attr
    }

    fn add(&mut self, kind: FetchKind) {
        match kind {
            FetchKind::Node => self.node += 1,
            FetchKind::Far => self.far += 1,
            FetchKind::Attr => self.attr += 1,
        }
    }
}

/// Counters over a window of cycles (from construction or the last
/// [`NodeMemory::reset_stats`] to the last simulated cycle). Integers only, so two runs can
/// be compared exactly; the rates are methods.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NodeMemoryStats {
    /// First cycle of the window.
    pub window_start: u64,
    /// Cycles simulated in the window.
    pub window_cycles: u64,
    /// The DRAM's peak bytes per cycle (from the configuration, for the rates).
    pub dram_peak_bytes_per_cycle: u64,
    /// Accepted reads by kind (counted when requested).
    pub fetches: KindCounts,
    /// Words read (1 per node or far read, 2 per attribute read).
    pub words: u64,
    /// Bytes read by the walkers (4 per word); DRAM traffic is `dram_bytes`.
    pub bytes: u64,
    /// Requests refused for an out-of-range address.
    pub out_of_range: u64,
    /// Reads served by the on-chip store.
    pub onchip_reads: u64,
    /// Cached reads looked up (hits + misses + merged).
    pub cache_lookups: u64,
    /// Cache hits.
    pub cache_hits: u64,
    /// Cache misses that issued a fill.
    pub cache_misses: u64,
    /// Cache misses merged into a fill in flight.
    pub cache_merged: u64,
    /// Attribute reads that bypassed the cache (`attr_cached = false`).
    pub uncached_reads: u64,
    /// Of those, reads merged into a fill in flight.
    pub uncached_merged: u64,
    /// Line fills issued to DRAM.
    pub dram_fills: u64,
    /// Bytes moved on the DRAM bus in the window's cycles.
    pub dram_bytes: u64,
    /// Cycles in which the DRAM bus moved data.
    pub dram_busy_cycles: u64,
    /// Most bytes moved in one cycle (never above the peak).
    pub dram_max_bytes_in_cycle: u64,
    /// Cycles in which at least one read waited because its bank or the cache had no free port.
    pub port_conflict_cycles: u64,
    /// Request-cycles spent waiting for a port.
    pub port_wait: u64,
    /// Cycles in which the cache pipeline stalled on a miss with no free MSHR.
    pub mshr_full_cycles: u64,
    /// Request-cycles spent waiting behind such a stall.
    pub mshr_wait: u64,
    /// Most MSHRs in use at once.
    pub mshr_max_in_use: u64,
    /// Reads served (their completion cycle is fixed); each is returned once by `tick`.
    pub served: u64,
    /// Sum of (done − requested) over served reads.
    pub latency_sum: u64,
    /// Largest (done − requested).
    pub latency_max: u64,
}

impl NodeMemoryStats {
    /// Cache hits over lookups (merged misses count as misses); 0 without lookups.
    pub fn hit_rate(&self) -> f64 {
        ratio(self.cache_hits, self.cache_lookups)
    }

    /// DRAM bytes moved over the window's peak capacity, in percent.
    pub fn dram_bandwidth_pct(&self) -> f64 {
        100.0
            * ratio(
                self.dram_bytes,
                self.window_cycles
                    .saturating_mul(self.dram_peak_bytes_per_cycle),
            )
    }

    /// Cycles the DRAM bus was busy over the window, in percent.
    pub fn dram_busy_pct(&self) -> f64 {
        100.0 * ratio(self.dram_busy_cycles, self.window_cycles)
    }

    /// Average latency of served reads, cycles.
    pub fn avg_latency(&self) -> f64 {
        ratio(self.latency_sum, self.served)
    }
}

fn ratio(a: u64, b: u64) -> f64 {
    if b == 0 {
        0.0
    } else {
        a as f64 / b as f64
    }
}

/// A queued request; ordered by (cycle, requester, id), the service order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Req {
    cycle: u64,
    requester: u32,
    id: u64,
    addr: u32,
    kind: FetchKind,
}

/// A line fill on the DRAM bus. Byte slots count bus capacity: cycle `c` carries slots
/// `c·B .. (c+1)·B`, so fills serialised on slots never exceed the per-cycle budget.
#[derive(Clone, Copy, Debug)]
struct Fill {
    line: u64,
    start: u128,
    end: u128,
    done: u64,
}

/// The next free read port of an on-chip bank: `used` of its ports are taken in `cycle`.
#[derive(Clone, Copy, Debug, Default)]
struct BankSlot {
    cycle: u64,
    used: u32,
}

/// An MSHR: a line in flight.
#[derive(Clone, Copy, Debug)]
struct Mshr {
    done: u64,
    /// Install the line when it arrives (some cached read wants it).
    install: bool,
}

/// Tags of a set-associative cache with true LRU, each set kept in recency order (most
/// recent first), as an LRU stack in hardware would shift.
#[derive(Clone, Debug)]
struct Tags {
    sets: u64,
    ways: usize,
    tags: Vec<u64>,
}

const INVALID: u64 = u64::MAX;

impl Tags {
    fn new(sets: u64, ways: u32) -> Self {
        let ways = ways as usize;
        Self {
            sets,
            ways,
            tags: vec![INVALID; sets as usize * ways],
        }
    }

    fn set(&mut self, line: u64) -> &mut [u64] {
        // sets is a power of two; 0 (no cache) is handled by the callers.
        let s = (line & (self.sets - 1)) as usize;
        &mut self.tags[s * self.ways..(s + 1) * self.ways]
    }

    /// Looks up `line`; on a hit it becomes most recently used.
    fn touch(&mut self, line: u64) -> bool {
        if self.sets == 0 {
            return false;
        }
        let set = self.set(line);
        match set.iter().position(|&t| t == line) {
            Some(p) => {
                set[..=p].rotate_right(1);
                true
            }
            None => false,
        }
    }

    /// Installs `line` as most recently used, evicting the least recently used way.
    fn install(&mut self, line: u64) {
        if self.sets == 0 {
            return;
        }
        let set = self.set(line);
        let p = set.iter().position(|&t| t == line).unwrap_or(set.len() - 1);
        set[..=p].rotate_right(1);
        set[0] = line;
    }
}

/// The node-memory model. See the module documentation for the semantics.
///
/// ```
/// use rtl_model::cycle::memory::{FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, Source};
/// let cfg = NodeMemoryConfig::default();
/// let layout = MemoryLayout::with_onchip_ranges(1 << 20, 1 << 16, vec![(0, 64)]).unwrap();
/// let mut mem = NodeMemory::new(cfg, layout).unwrap();
/// let a = mem.request(10, 5, FetchKind::Node, 0).unwrap(); // on chip
/// let b = mem.request(10, 5000, FetchKind::Node, 1).unwrap(); // cold miss
/// let done = mem.drain();
/// assert_eq!((done[0].id, done[0].cycle_done), (a, 13)); // 3-cycle block RAM
/// assert_eq!((done[1].id, done[1].source), (b, Source::Miss));
/// assert_eq!(done[1].cycle_done, 10 + 60 + 1); // latency + one 64-byte beat
/// ```
#[derive(Clone, Debug)]
pub struct NodeMemory {
    cfg: NodeMemoryConfig,
    layout: MemoryLayout,
    /// First cycle not yet simulated.
    next: u64,
    next_id: u64,
    /// Requests made for a later cycle than `next`.
    future: BinaryHeap<Reverse<Req>>,
    /// Requests made for cycle `next` (the usual case: a walker asks in the cycle it is
    /// evaluated); sorted into service order when that cycle is simulated.
    arrivals: Vec<Req>,
    /// Per on-chip bank, its next free port. A bank serves its requests first come first
    /// served at a fixed rate, so a request's service cycle is known the moment it joins the
    /// bank's queue; it goes straight to `pending` instead of waiting in a queue of its own.
    bank_slots: Vec<BankSlot>,
    /// The last cycle, plus one, in which some bank still has a request waiting for a port
    /// (among the requests arbitrated so far).
    bank_busy_until: u64,
    /// Cycles before this one are counted in `port_conflict_cycles`.
    conflicts_counted: u64,
    /// Requests waiting for a cache lookup port, in service order.
    cache_q: VecDeque<Req>,
    /// Requests in `cache_q`.
    waiting: usize,
    tags: Tags,
    /// Lines in flight and their MSHRs; a handful (`dram.mshrs`), so a linear search beats
    /// a tree.
    mshrs: Vec<(u64, Mshr)>,
    fills: VecDeque<Fill>,
    /// First free byte slot of the DRAM bus.
    bus_next: u128,
    pending: CompletionWheel,
    stats: NodeMemoryStats,
}

impl NodeMemory {
    /// A model with empty caches at cycle 0.
    pub fn new(cfg: NodeMemoryConfig, layout: MemoryLayout) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let tags = Tags::new(cfg.cache_sets(), cfg.cache.ways);
        let stats = NodeMemoryStats {
            dram_peak_bytes_per_cycle: u64::from(cfg.dram.bytes_per_cycle),
            ..Default::default()
        };
        Ok(Self {
            bank_slots: vec![BankSlot::default(); cfg.onchip.banks as usize],
            bank_busy_until: 0,
            conflicts_counted: 0,
            cfg,
            layout,
            next: 0,
            next_id: 0,
            future: BinaryHeap::new(),
            arrivals: Vec::new(),
            cache_q: VecDeque::new(),
            waiting: 0,
            tags,
            mshrs: Vec::new(),
            fills: VecDeque::new(),
            bus_next: 0,
            pending: CompletionWheel::default(),
            stats,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &NodeMemoryConfig {
        &self.cfg
    }

    /// The address map.
    pub fn layout(&self) -> &MemoryLayout {
        &self.layout
    }

    /// First cycle not yet simulated: requests must be for this cycle or later.
    pub fn now(&self) -> u64 {
        self.next
    }

    /// Requests made and not yet returned by [`tick`](Self::tick) or [`drain`](Self::drain).
    pub fn outstanding(&self) -> usize {
        self.future.len() + self.arrivals.len() + self.waiting + self.pending.len()
    }

    /// Whether every request has been returned.
    pub fn is_idle(&self) -> bool {
        self.outstanding() == 0
    }

    /// Requests a read in `cycle` (this cycle or a later one) by `requester`. For
    /// [`FetchKind::Attr`], `addr` is the attribute index; otherwise a node word address.
    /// The read is arbitrated when the simulation reaches `cycle`, so requests of one cycle
    /// may be made in any order.
    pub fn request(
        &mut self,
        cycle: u64,
        addr: u32,
        kind: FetchKind,
        requester: u32,
    ) -> Result<RequestId, RequestError> {
        if cycle > MAX_CYCLE {
            return Err(RequestError::CycleTooLarge(cycle));
        }
        if cycle < self.next {
            return Err(RequestError::InPast {
                cycle,
                now: self.next,
            });
        }
        let limit = match kind {
            FetchKind::Node | FetchKind::Far => self.layout.node_words,
            FetchKind::Attr => self.layout.attr_records,
        };
        if u64::from(addr) >= limit {
            self.stats.out_of_range += 1;
            return Err(RequestError::OutOfRange { kind, addr, limit });
        }
        let id = self.next_id;
        self.next_id += 1;
        self.stats.fetches.add(kind);
        self.stats.words += kind.words();
        self.stats.bytes += 4 * kind.words();
        let req = Req {
            cycle,
            requester,
            id,
            addr,
            kind,
        };
        if cycle == self.next {
            self.arrivals.push(req);
        } else {
            self.future.push(Reverse(req));
        }
        Ok(RequestId(id))
    }

    /// Called at the start of `cycle`: simulates every cycle before it and returns the reads
    /// whose data is valid by `cycle` (`cycle_done ≤ cycle`) and were not returned before,
    /// ordered by (done, id).
    pub fn tick(&mut self, cycle: u64) -> Vec<Completion> {
        let mut out = Vec::new();
        self.tick_into(cycle, &mut out);
        out
    }

    /// Simulates every cycle before `cycle` without collecting completions (a later
    /// [`tick`](Self::tick) of the same cycle returns them). Requests for `cycle` made after
    /// this take the fast path of the current cycle instead of the heap of future requests.
    pub fn catch_up(&mut self, cycle: u64) {
        self.advance_to(cycle.min(MAX_CYCLE + 1));
    }

    /// [`tick`](Self::tick) appending to `out`, so a caller that ticks every cycle can reuse
    /// one buffer instead of allocating per cycle.
    pub fn tick_into(&mut self, cycle: u64, out: &mut Vec<Completion>) {
        self.advance_to(cycle.min(MAX_CYCLE + 1));
        self.pending.pop_due(cycle, out);
    }

    /// Simulates until every request has been served and returns all completions not yet
    /// returned, ordered by (done, id). `now` is then the cycle after the last one with any
    /// activity, which may be before the last `cycle_done`.
    pub fn drain(&mut self) -> Vec<Completion> {
        while !(self.future.is_empty()
            && self.arrivals.is_empty()
            && self.waiting == 0
            && self.fills.is_empty())
        {
            let k = self.next;
            if self.has_work(k) {
                self.step(k);
                self.next = k + 1;
            } else {
                // Not idle, so there is a next event after k.
                self.next = self.next_event().unwrap_or(k + 1);
            }
        }
        // The banks' last service (a read that waited) is activity too, though no step runs
        // for it: it happens in cycle `bank_busy_until`. (A read served as it arrived was
        // stepped in its own cycle, so `next` is past it already.)
        if self.bank_busy_until > 0 && self.bank_busy_until >= self.next {
            self.next = self.bank_busy_until + 1;
        }
        let mut out = Vec::new();
        self.pending.drain_all(&mut out);
        out
    }

    /// The statistics of the current window (up to the last simulated cycle).
    pub fn stats(&self) -> NodeMemoryStats {
        let mut s = self.stats.clone();
        s.window_cycles = self.next.saturating_sub(s.window_start);
        s.port_conflict_cycles += self.bank_conflicts_before(self.next);
        s
    }

    /// Cycles from `conflicts_counted` to `end` in which a bank had a request waiting; valid
    /// when no request arrives in between (every bank interval then starts before them).
    fn bank_conflicts_before(&self, end: u64) -> u64 {
        self.bank_busy_until
            .min(end)
            .saturating_sub(self.conflicts_counted)
    }

    /// Returns the current window's statistics and starts a new window at [`now`](Self::now)
    /// (e.g. per frame). Cache contents and requests in flight are kept.
    pub fn reset_stats(&mut self) -> NodeMemoryStats {
        let out = self.stats();
        self.conflicts_counted = self.conflicts_counted.max(self.next);
        self.stats = NodeMemoryStats {
            window_start: self.next,
            dram_peak_bytes_per_cycle: out.dram_peak_bytes_per_cycle,
            ..Default::default()
        };
        out
    }

    fn advance_to(&mut self, target: u64) {
        while self.next < target {
            let k = self.next;
            if self.has_work(k) {
                self.step(k);
                self.next = k + 1;
            } else {
                self.next = self.next_event().map_or(target, |e| e.min(target));
            }
        }
    }

    fn bus_rate(&self) -> u128 {
        u128::from(self.cfg.dram.bytes_per_cycle)
    }

    /// Whether cycle `k` changes anything: a request arrives or waits, a fill completes or
    /// moves bytes.
    fn has_work(&self, k: u64) -> bool {
        if self.waiting > 0 || !self.arrivals.is_empty() {
            return true;
        }
        if self.future.peek().is_some_and(|Reverse(r)| r.cycle <= k) {
            return true;
        }
        match self.fills.front() {
            // Fills complete in issue order, so the front one completes and transfers first.
            Some(f) => f.done <= k || f.start < (u128::from(k) + 1) * self.bus_rate(),
            None => false,
        }
    }

    /// The next cycle with work, given that the current one has none.
    fn next_event(&self) -> Option<u64> {
        let arrival = self.future.peek().map(|Reverse(r)| r.cycle);
        let transfer = self
            .fills
            .front()
            .map(|f| u64::try_from(f.start / self.bus_rate()).unwrap_or(u64::MAX));
        match (arrival, transfer) {
            (Some(a), Some(t)) => Some(a.min(t)),
            (a, t) => a.or(t),
        }
    }

    /// Simulates cycle `k`.
    fn step(&mut self, k: u64) {
        // 1. Fills that complete now install their line and free their MSHR, before this
        //    cycle's lookups (so a lookup in the completion cycle hits).
        while let Some(f) = self.fills.front().copied() {
            if f.done > k {
                break;
            }
            self.fills.pop_front();
            let freed = self.mshrs.iter().position(|&(l, _)| l == f.line);
            if let Some((_, m)) = freed.map(|i| self.mshrs.swap_remove(i)) {
                if m.install {
                    self.tags.install(f.line);
                }
            }
        }
        // 2. Requests of this cycle are arbitrated in (requester, id) order: all are of cycle k
        //    (`arrivals` holds those made for `next` = k, the heap any made earlier for k) and
        //    everything before them is from an earlier cycle, so taking them in this order
        //    keeps each bank and the cache queue in (cycle, requester, id) service order.
        //    An on-chip read is given its bank's next free port at once; a cached one joins
        //    the cache queue.
        while let Some(Reverse(r)) = self.future.peek().copied() {
            if r.cycle > k {
                break;
            }
            self.future.pop();
            self.arrivals.push(r);
        }
        if self.arrivals.len() > 1 {
            self.arrivals.sort_unstable_by_key(|r| (r.requester, r.id));
        }
        // Cycles skipped since the last step had no arrivals and no cache work: they were
        // conflict cycles exactly when a bank still had a request waiting.
        self.stats.port_conflict_cycles += self.bank_conflicts_before(k);
        self.conflicts_counted = k;
        let banks = self.cfg.onchip.banks;
        let ports = self.cfg.onchip.ports_per_bank.max(1);
        let latency = u64::from(self.cfg.onchip.latency);
        for i in 0..self.arrivals.len() {
            let r = self.arrivals[i];
            let onchip = r.kind != FetchKind::Attr && self.layout.is_onchip(r.addr);
            if onchip {
                // On-chip banks: `ports` reads per cycle each, in arrival order.
                let bank = (r.addr % banks) as usize;
                let slot = &mut self.bank_slots[bank];
                if slot.cycle < k {
                    *slot = BankSlot { cycle: k, used: 0 };
                }
                let served = slot.cycle;
                slot.used += 1;
                if slot.used == ports {
                    *slot = BankSlot {
                        cycle: served + 1,
                        used: 0,
                    };
                }
                // Waiting in cycles k .. served − 1.
                self.stats.port_wait += served - k;
                self.bank_busy_until = self.bank_busy_until.max(served);
                self.stats.onchip_reads += 1;
                self.complete(
                    r,
                    served,
                    served + latency,
                    Source::OnChip { bank: bank as u32 },
                );
            } else {
                self.cache_q.push_back(r);
                self.waiting += 1;
            }
        }
        self.arrivals.clear();
        // 3. Bytes on the DRAM bus in this cycle.
        let rate = self.bus_rate();
        let (lo, hi) = (u128::from(k) * rate, (u128::from(k) + 1) * rate);
        let mut bytes = 0u128;
        for f in &self.fills {
            if f.start >= hi {
                break;
            }
            let (s, e) = (f.start.max(lo), f.end.min(hi));
            bytes += e.saturating_sub(s);
        }
        if bytes > 0 {
            let bytes = bytes as u64; // at most bytes_per_cycle
            self.stats.dram_bytes += bytes;
            self.stats.dram_busy_cycles += 1;
            self.stats.dram_max_bytes_in_cycle = self.stats.dram_max_bytes_in_cycle.max(bytes);
        }
        // A bank has a request left waiting after this cycle's service.
        let mut port_conflict = self.bank_busy_until > k;
        // 4. The cache pipeline, in order.
        let mut blocked = false;
        for _ in 0..self.cfg.cache.ports {
            let Some(&r) = self.cache_q.front() else {
                break;
            };
            let Some(source_done) = self.lookup(r, k) else {
                blocked = true;
                break;
            };
            self.cache_q.pop_front();
            self.waiting -= 1;
            self.complete(r, k, source_done.1, source_done.0);
        }
        let left = self.cache_q.len() as u64;
        if left > 0 {
            if blocked {
                self.stats.mshr_full_cycles += 1;
                self.stats.mshr_wait += left;
            } else {
                port_conflict = true;
                self.stats.port_wait += left;
            }
        }
        if port_conflict {
            self.stats.port_conflict_cycles += 1;
        }
        self.conflicts_counted = k + 1;
    }

    /// The cache line holding a read: node words from byte 0, attribute records from
    /// [`ATTR_REGION_BASE`].
    fn line_of(&self, r: &Req) -> u64 {
        let byte = match r.kind {
            FetchKind::Node | FetchKind::Far => 4 * u64::from(r.addr),
            FetchKind::Attr => ATTR_REGION_BASE + 8 * u64::from(r.addr),
        };
        byte / u64::from(self.cfg.cache.line_bytes)
    }

    /// Looks up a read in cycle `k`: where it is served and when it completes, or `None` when
    /// it misses with every MSHR taken (nothing changes then).
    fn lookup(&mut self, r: Req, k: u64) -> Option<(Source, u64)> {
        let line = self.line_of(&r);
        let cached = r.kind != FetchKind::Attr || self.cfg.cache.attr_cached;
        if cached && self.tags.touch(line) {
            self.stats.cache_lookups += 1;
            self.stats.cache_hits += 1;
            return Some((Source::CacheHit, k + u64::from(self.cfg.cache.hit_latency)));
        }
        let in_flight = self.mshrs.iter_mut().find(|(l, _)| *l == line);
        let (source, done) = if let Some((_, m)) = in_flight {
            m.install |= cached;
            (Source::Merged, m.done)
        } else if self.mshrs.len() < self.cfg.dram.mshrs as usize {
            let rate = self.bus_rate();
            let earliest = (u128::from(k) + u128::from(self.cfg.dram.latency)) * rate;
            let start = earliest.max(self.bus_next);
            let end = start + u128::from(self.cfg.cache.line_bytes);
            let done = u64::try_from(end.div_ceil(rate)).unwrap_or(u64::MAX);
            self.bus_next = end;
            self.fills.push_back(Fill {
                line,
                start,
                end,
                done,
            });
            self.mshrs.push((
                line,
                Mshr {
                    done,
                    install: cached,
                },
            ));
            self.stats.dram_fills += 1;
            self.stats.mshr_max_in_use = self.stats.mshr_max_in_use.max(self.mshrs.len() as u64);
            (Source::Miss, done)
        } else {
            return None;
        };
        let merged = source == Source::Merged;
        if cached {
            self.stats.cache_lookups += 1;
            if merged {
                self.stats.cache_merged += 1;
            } else {
                self.stats.cache_misses += 1;
            }
        } else {
            self.stats.uncached_reads += 1;
            if merged {
                self.stats.uncached_merged += 1;
            }
        }
        Some((source, done))
    }

    fn complete(&mut self, r: Req, served: u64, done: u64, source: Source) {
        let latency = done - r.cycle;
        self.stats.served += 1;
        self.stats.latency_sum += latency;
        self.stats.latency_max = self.stats.latency_max.max(latency);
        self.pending.push(Completion {
            id: RequestId(r.id),
            requester: r.requester,
            kind: r.kind,
            addr: r.addr,
            cycle_requested: r.cycle,
            cycle_served: served,
            cycle_done: done,
            source,
        });
    }
}
