//! The node memory's counters over a window of cycles: reads by kind, where they were
//! served, DRAM traffic, port and MSHR waits, latency; integers only, with the rates as
//! methods.
//!
//! Pipeline position: kept by [`super::NodeMemory`] as it simulates, read per frame
//! ([`super::NodeMemory::reset_stats`]) into the run report.

use crate::svo::FetchKind;
use serde::{Deserialize, Serialize};

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

    pub(super) fn add(&mut self, kind: FetchKind) {
        match kind {
            FetchKind::Node => self.node += 1,
            FetchKind::Far => self.far += 1,
            FetchKind::Attr => self.attr += 1,
        }
    }
}

/// Counters over a window of cycles (from construction or the last
/// [`NodeMemory::reset_stats`](super::NodeMemory::reset_stats) to the last simulated cycle). Integers only, so two runs can
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
    /// Request-cycles spent waiting for a port (on-chip bank or cache bank).
    pub port_wait: u64,
    /// Of `port_wait`, the request-cycles spent in a cache bank's queue.
    pub cache_port_wait: u64,
    /// On-chip reads that shared the port read of the same word queued at their bank
    /// (`onchip.combine`).
    pub onchip_combined: u64,
    /// Misses that found every MSHR taken and waited in the miss queue (hit under miss).
    pub miss_queued: u64,
    /// Request-cycles spent in the miss queue (counted when a read leaves it).
    pub miss_queue_wait: u64,
    /// Most reads in the miss queue at once.
    pub miss_queue_max: u64,
    /// Cycles in which a cache bank's pipeline stalled on a miss with no free MSHR and no
    /// room in the miss queue.
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
    /// The DRAMsim3 device's own counters, when it times the fills (`None` with the built-in
    /// DRAM model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dram_device: Option<DramDeviceStats>,
}

/// Counters of the DRAMsim3 backend over a window. Fills, transactions and bytes are counted
/// by the model; the command counters come from DRAMsim3's epoch statistics and cover the
/// epochs that ended in the window (docs/cycle-model.md, DRAM).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct DramDeviceStats {
    /// The device (a bundled DRAMsim3 configuration name).
    pub device: String,
    /// Line fills issued.
    pub fills: u64,
    /// Read transactions (bursts) they made.
    pub transactions: u64,
    /// Bytes of the transactions that completed.
    pub bytes: u64,
    /// DRAM clocks at which a transaction waited because DRAMsim3's queue was full.
    pub queue_full_clocks: u64,
    /// DRAMsim3 epochs (per channel) counted below.
    pub epochs: u64,
    /// READ commands issued.
    pub read_cmds: u64,
    /// Of those, reads to the open row (row-buffer hits).
    pub row_hits: u64,
    /// ACTIVATE commands (row opens).
    pub activates: u64,
    /// Precharges forced by a request to another row of an open bank (row conflicts).
    pub row_conflicts: u64,
    /// REFRESH commands.
    pub refreshes: u64,
}

impl DramDeviceStats {
    /// Row-buffer hits over read commands; 0 without reads.
    pub fn row_hit_rate(&self) -> f64 {
        ratio(self.row_hits, self.read_cmds)
    }

    /// Adds one epoch record of one channel (DRAMsim3's JSON object).
    pub(super) fn add_epoch(&mut self, v: &serde_json::Value) {
        let get = |k: &str| v.get(k).and_then(serde_json::Value::as_u64).unwrap_or(0);
        self.epochs += 1;
        self.read_cmds += get("num_read_cmds");
        self.row_hits += get("num_read_row_hits");
        self.activates += get("num_act_cmds");
        self.row_conflicts += get("num_ondemand_pres");
        self.refreshes += get("num_ref_cmds");
    }
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
