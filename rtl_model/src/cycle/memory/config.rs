//! The node memory's configuration: on-chip store, cache and external DRAM, with their
//! defaults and the reason for each, the checks a configuration must pass, and the memory
//! blocks it needs for the resource report.
//!
//! Pipeline position: part of the hardware configuration (`HwConfig::node_memory`), read once
//! per run; [`super::NodeMemory::new`] is built only from a configuration that passes
//! [`NodeMemoryConfig::validate`].

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Largest cache accepted by [`NodeMemoryConfig::validate`] (64 MiB): far above the on-chip
/// memory of any part, and small enough that the tag array the model allocates (8 bytes per
/// line) stays reasonable.
pub const MAX_CACHE_BYTES: u64 = 1 << 26;

/// Largest latency accepted (cycles); anything larger is a typo in a configuration.
pub const MAX_LATENCY: u32 = 1 << 20;

/// Largest number of banks, ports or MSHRs accepted.
pub const MAX_PARALLEL: u32 = 4096;

/// On-chip node store: the top levels of the tree in block RAM.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OnChipConfig {
    /// Tree levels held on chip, counting the root as level 0: descriptors of nodes at levels
    /// `0 .. levels` (and their far words) are on chip. 0 disables the on-chip store.
    ///
    /// Default 8 (issue 28; 6 before, `configs/baseline.ron`): levels 0..7 are the reads
    /// nearly every ray makes, and at one ray per cycle the cache could not serve them; a
    /// sparse surface tree's eight levels fit the 2 MiB cap, while a completely dense tree
    /// keeps fewer (whole levels are kept while they fit, see `max_bytes`).
    pub levels: u8,
    /// Capacity cap in bytes: whole levels are kept while their words fit. Default 2 MiB
    /// (512 BRAM36 of 1024 × 32-bit words, 24 % of the part), 256 KiB before issue 28.
    pub max_bytes: u64,
    /// Read latency in cycles (≥ 1). Default 3: an address register, the block RAM with its
    /// output register (needed to reach 300 MHz) and one mux stage across the cascaded
    /// BRAM36 blocks.
    pub latency: u32,
    /// Word-interleaved banks (bank = word address mod banks). Default 16 (issue 28; 4
    /// before): the walkers' reads of one group's consecutive slots land in different banks,
    /// and 16 × 2 ports serve the reads of 64 walkers on two walk lanes near the root.
    pub banks: u32,
    /// Ports per bank per cycle (2 = true dual port, the BRAM36 maximum). Reads beyond this in
    /// a cycle wait. Default 2.
    pub ports_per_bank: u32,
    /// Whether reads of a word already queued at its bank join that entry and share its port
    /// read (a CAM on the bank queue's word addresses; the return crossbar broadcasts the
    /// word). Default true: every walk reads its asset's root word and the few words below
    /// it, so without combining those words' banks serve every walk `ports_per_bank` at a
    /// time. The car at 1280×768, frame 0, 4 cache banks: 158.1 fps and 14.7 cycles of port
    /// wait per node read without, 183.3 fps and 2.2 with (docs/cycle-model.md §3.6). False is
    /// the arrangement before issue 28 (a baseline configuration keeps it).
    pub combine: bool,
}

impl Default for OnChipConfig {
    fn default() -> Self {
        Self {
            levels: 8,
            max_bytes: 2 * 1024 * 1024,
            latency: 3,
            banks: 16,
            ports_per_bank: 2,
            combine: true,
        }
    }
}

/// The set-associative LRU cache in front of DRAM (node image and attribute array).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CacheConfig {
    /// Capacity in bytes; 0 disables the cache (every off-chip read goes to DRAM, merging
    /// still applies). Default 256 KiB: 8 UltraRAMs (32 KiB of 64-bit words each) per copy of
    /// the data array, large against the working set of a frame's upper-middle levels once the
    /// top 8 levels are on chip: `sim explore` (docs/explore.md §5) found 1 MiB worth no fps
    /// on the car or crowd_1000.
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
    /// Lookups per cycle (≥ 1). Default 2: one per read port of a true dual-port array; per
    /// bank, so the default's 4 banks take 8 lookups a cycle (4 ports were worth no fps in
    /// `sim explore`, docs/explore.md §5).
    pub ports: u32,
    /// Whether attribute records go through the cache (true) or straight to DRAM (false;
    /// each then still moves a whole line, the DRAM burst). Default true: rays that hit
    /// neighbouring voxels read neighbouring records (the array is in Morton order), eight to a
    /// 64-byte line.
    pub attr_cached: bool,
    /// Line-interleaved banks (bank = line mod banks; a power of two, at most the number of
    /// sets), each with its own request queue, tag and data arrays of `size_bytes / banks`
    /// and `ports` lookup ports, behind the walker-to-bank crossbar. Default 4: the car at
    /// 1280×768 (32 walkers) asks ~1.3 lookups per cycle on average but in bursts, and with one
    /// 2-port array a node read waited 16 of its 23 cycles for a lookup port; 4 banks bring
    /// that to 2 (+20 % fps, docs/cycle-model.md §3.6). A bank of 64 KiB is still two
    /// UltraRAMs per copy, so the blocks are those of one array; the crossbar costs LUTs
    /// ([`NodeMemoryConfig::fabric_items`]). 1 is the arrangement before issue 28.
    pub banks: u32,
    /// Entries of the miss queue (hit under miss): a miss that finds every MSHR taken and
    /// no fill of its line in flight leaves its bank's lookup pipeline for this queue, in
    /// order, and takes the next MSHR that frees, so the lookups behind it go on. 0: no
    /// queue, the bank's pipeline stalls in order until an MSHR frees (the cache before
    /// issue 28; a baseline configuration keeps it); when the queue is full it stalls too.
    /// Default 32,
    /// as many as the MSHRs: a queued miss then waits at most one round of fills.
    pub miss_queue: u32,
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
            banks: 4,
            miss_queue: 32,
        }
    }
}

/// External DRAM behind the cache: the MSHRs in front of it and the model of the DRAM itself.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DramConfig {
    /// Cycles from a fill's issue to its first data (≥ 1), for the [`DramBackend::BuiltIn`]
    /// model. Default 60 at 300 MHz: DDR4's ~100 ns loaded access (30 cycles) plus about as
    /// much again for the memory controller, the AXI interconnect and clock-domain crossings.
    /// With [`DramBackend::DramSim3`] the fills take the device's timing instead and this field
    /// must stay at its default (it still gives the nominal DRAM latency of an external hit
    /// buffer and of the watchdog).
    pub latency: u32,
    /// Peak bytes per cycle on the data bus (≥ 1), for the [`DramBackend::BuiltIn`] model.
    /// Default 128 (issue 28; 64 before): two DDR4-2400 channels, 64 bits wide, give 38.4 GB/s,
    /// which is 128 B per cycle at 300 MHz, as boards with this part carry. With [`DramBackend::DramSim3`] the peak follows from the device and
    /// the channel count, and this field must stay at its default.
    pub bytes_per_cycle: u32,
    /// Outstanding line fills (MSHRs, ≥ 1). Default 256 (issue 28; 32 before): by Little's law
    /// 32 fills of 64 B per (60 + 1) cycles capped miss bandwidth at about 33.6 B/cycle, which
    /// bound the walkers at one ray per cycle; 256 entries are searched through the CAM the
    /// fabric estimate prices (`cost::structures`).
    pub mshrs: u32,
    /// What times the line fills: the built-in fixed-latency bus (default) or DRAMsim3.
    pub backend: DramBackend,
}

impl Default for DramConfig {
    fn default() -> Self {
        Self {
            latency: 60,
            bytes_per_cycle: 128,
            mshrs: 256,
            backend: DramBackend::BuiltIn,
        }
    }
}

impl DramConfig {
    /// Peak bytes per pipeline cycle at `clock_mhz`: `bytes_per_cycle` for the built-in
    /// model; for DRAMsim3, 16 bytes per DRAM clock per channel (a 64-bit DDR bus) converted
    /// to pipeline cycles and rounded to the nearest byte (128 for two DDR4-2400 channels at
    /// 300 MHz). Meaningful for a validated configuration.
    pub fn peak_bytes_per_cycle(&self, clock_mhz: u32) -> u64 {
        match &self.backend {
            DramBackend::BuiltIn => u64::from(self.bytes_per_cycle),
            DramBackend::DramSim3 {
                config, channels, ..
            } => super::dramsim3::device(config).map_or(0, |d| {
                super::dramsim3::peak_bytes_per_cycle(&d, *channels, clock_mhz)
            }),
        }
    }
}

/// The model that times the line fills behind the MSHRs (docs/cycle-model.md, DRAM).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DramBackend {
    /// A fixed latency and one data bus of `bytes_per_cycle` (fast; an approximation with no
    /// banks, rows, refresh or scheduling).
    #[default]
    BuiltIn,
    /// DRAMsim3 (the `dramsim3` crate): banks, bank groups, row buffers, refresh and the
    /// controller's scheduling of a JEDEC device, clocked at its own rate against the
    /// pipeline clock.
    DramSim3 {
        /// The device: one of [`super::dramsim3::CONFIG_NAMES`], e.g. `"DDR4_8Gb_x16_2400"`.
        config: String,
        /// Independent channels (1, 2, 4 or 8), each with its own 64-bit bus and controller.
        channels: u32,
        /// Cycles of the pipeline clock added to every fill for the memory controller's
        /// front end, the AXI interconnect and the clock-domain crossings (≥ 1).
        controller_latency: u32,
    },
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
    /// A DRAMsim3 device name that is not bundled.
    #[error("dram.backend.config = {name:?} is not a bundled DRAMsim3 device (one of {known})")]
    DramDevice {
        /// The name given.
        name: String,
        /// The names there are.
        known: String,
    },
    /// A DRAMsim3 channel count that is not 1, 2, 4 or 8.
    #[error("dram.backend.channels = {0} must be 1, 2, 4 or 8")]
    DramChannels(u32),
    /// A field of the built-in DRAM model set while another backend times the fills.
    #[error("dram.{field} = {value} applies to the BuiltIn DRAM backend only; with DramSim3 leave it at its default {default}")]
    BuiltInOnly {
        /// The field.
        field: &'static str,
        /// Its value.
        value: u32,
        /// Its default.
        default: u32,
    },
    /// DRAMsim3 could not be started (its scratch directory or configuration file).
    #[error("dram.backend: DRAMsim3 could not be started: {0}")]
    DramSim3Start(String),
    /// More on-chip levels than an image can have.
    #[error("onchip.levels = {0} is more than the deepest tree has (21)")]
    Levels(u8),
    /// The cache banks are not a power of two up to [`MAX_CACHE_BANKS`] and the sets.
    #[error("cache.banks = {banks} must be a power of two from 1 to {max} (the cache's sets, at most {MAX_CACHE_BANKS})")]
    CacheBanks {
        /// Banks asked for.
        banks: u32,
        /// The most there can be.
        max: u64,
    },
    /// The miss queue is longer than [`MAX_PARALLEL`].
    #[error("cache.miss_queue = {0} is above {MAX_PARALLEL}")]
    MissQueue(u32),
}

/// Most cache banks: a 64 × W crossbar is already far larger than the cache's control.
pub const MAX_CACHE_BANKS: u32 = 64;

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
        let max_banks = if c.size_bytes == 0 {
            u64::from(MAX_CACHE_BANKS)
        } else {
            self.cache_sets().min(u64::from(MAX_CACHE_BANKS))
        };
        if !c.banks.is_power_of_two() || u64::from(c.banks) > max_banks {
            return Err(ConfigError::CacheBanks {
                banks: c.banks,
                max: max_banks,
            });
        }
        if c.miss_queue > MAX_PARALLEL {
            return Err(ConfigError::MissQueue(c.miss_queue));
        }
        let d = &self.dram;
        lat("dram.latency", d.latency)?;
        count("dram.bytes_per_cycle", d.bytes_per_cycle)?;
        count("dram.mshrs", d.mshrs)?;
        if let DramBackend::DramSim3 {
            config,
            channels,
            controller_latency,
        } = &d.backend
        {
            let base = DramConfig::default();
            for (field, value, default) in [
                ("latency", d.latency, base.latency),
                ("bytes_per_cycle", d.bytes_per_cycle, base.bytes_per_cycle),
            ] {
                if value != default {
                    return Err(ConfigError::BuiltInOnly {
                        field,
                        value,
                        default,
                    });
                }
            }
            if super::dramsim3::device(config).is_none() {
                return Err(ConfigError::DramDevice {
                    name: config.clone(),
                    known: super::dramsim3::CONFIG_NAMES.join(", "),
                });
            }
            if !matches!(channels, 1 | 2 | 4 | 8) {
                return Err(ConfigError::DramChannels(*channels));
            }
            lat("dram.backend.controller_latency", *controller_latency)?;
        }
        Ok(())
    }

    /// Cache sets (0 when the cache is disabled). Meaningful for a validated configuration.
    pub fn cache_sets(&self) -> u64 {
        let set_bytes = u64::from(self.cache.ways) * u64::from(self.cache.line_bytes);
        self.cache.size_bytes.checked_div(set_bytes).unwrap_or(0)
    }

    /// Memory blocks this configuration needs, for the resource report. `onchip_words` is
    /// the on-chip store's size ([`MemoryLayout::onchip_words`](super::MemoryLayout::onchip_words)).
    ///
    /// Counting rules: an on-chip bank is BRAM36 blocks of 1024 × 32-bit words; each cache
    /// bank's data array (`size_bytes / banks`) is one UltraRAM copy (32 KiB as 4096 × 64
    /// bits) per lookup port, each copy with one read port for lookups and one write port
    /// for refills; each bank's tag array (tag, valid, LRU state, under 36 bits per way) is
    /// BRAM36 per lookup port, 1024 entries each. Banking is free in blocks while a bank
    /// holds at least 32 KiB; below that each bank still takes a whole UltraRAM.
    pub fn resources(&self, onchip_words: u64) -> MemoryResources {
        let banks = u64::from(self.onchip.banks.max(1));
        let onchip_bram36 = if onchip_words == 0 {
            0
        } else {
            banks * onchip_words.div_ceil(banks).div_ceil(1024)
        };
        let copies = u64::from(self.cache.ports) * u64::from(self.cache.banks.max(1));
        let per_bank = |total: u64| total / u64::from(self.cache.banks.max(1));
        let cache_uram = copies * per_bank(self.cache.size_bytes).div_ceil(32 * 1024);
        let tag_entries = self.cache_sets() * u64::from(self.cache.ways);
        let cache_tag_bram36 = copies * per_bank(tag_entries).div_ceil(1024);
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
