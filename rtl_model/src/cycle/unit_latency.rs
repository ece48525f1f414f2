//! Unit timing from the datapath: the latency and initiation interval each fixed unit needs
//! for the formats of a [`DatapathConfig`], as the hardware configuration's defaults and its
//! lower limits.
//!
//! Pipeline position: read once per run, with the configurations; in `cycle` (not `cost`)
//! because the hardware configuration's defaults are these timings, and `cycle` does not
//! import the layer above it. Each unit derives its own
//! stage count (`units::sphere::latency_cycles`, `units::sqrt::latency_cycles` of
//! `units::sphere::sqrt_config`, `units::sorter::network_latency`,
//! `units::transform::latency_cycles`, `units::reciprocal::latency_cycles`,
//! `units::walker::root_latency_cycles`, `units::raygen::LATENCY_CYCLES`, the hit record's
//! pack and unpack registers); this module only collects them into the
//! [`UnitTimings`] that `cycle::hw_config` declares, and answers the one timing question that
//! depends on where a memory lives ([`HwConfig::hit_buffer_read_cycles`]).

use crate::cycle::hw_config::{HwConfig, Placement, UnitTiming, UnitTimings};
use crate::datapath::DatapathConfig;
use crate::units::{hit_record, raygen, reciprocal, sorter, sphere, sqrt, transform, walker};

impl UnitTimings {
    /// The timings the stage counts of `dp`'s units give (the minimum latencies, II = 1
    /// except the sorter's network II).
    pub fn for_datapath(dp: &DatapathConfig) -> Self {
        let lanes = dp.sorter.n.max(1);
        Self {
            raygen: UnitTiming::pipelined(raygen::LATENCY_CYCLES),
            sphere: UnitTiming::pipelined(sphere::latency_cycles(&dp.sphere)),
            sqrt: UnitTiming::pipelined(sqrt::latency_cycles(&sphere::sqrt_config(&dp.sphere))),
            sorter: UnitTiming {
                // A one-lane network has no layer; its output register remains.
                latency_cycles: sat_u32(sorter::network_latency(lanes).max(1)),
                ii: sat_u32(sorter::network_ii(lanes)),
            },
            transform: UnitTiming::pipelined(transform::latency_cycles(&dp.transform)),
            reciprocal: UnitTiming::pipelined(reciprocal::latency_cycles(&dp.reciprocal)),
            walker_root: UnitTiming::pipelined(walker::root_latency_cycles(&dp.walker)),
            hit_pack: UnitTiming::pipelined(hit_record::PACK_LATENCY_CYCLES),
            hit_unpack: UnitTiming::pipelined(hit_record::UNPACK_LATENCY_CYCLES),
        }
    }
}

impl HwConfig {
    /// Cycles the hit-buffer check waits for its read, before the unpack register: the
    /// buffer's read latency on chip, the DRAM's latency when external, none when absent.
    pub fn hit_buffer_read_cycles(&self) -> u32 {
        match self.hit_buffer.placement {
            _ if !self.hit_buffer.present => 0,
            Placement::External => self.node_memory.dram.latency,
            _ => self.hit_buffer.read_latency_cycles,
        }
    }
}

fn sat_u32(x: u64) -> u32 {
    u32::try_from(x).unwrap_or(u32::MAX)
}
