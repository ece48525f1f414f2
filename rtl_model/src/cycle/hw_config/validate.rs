//! The hardware configuration's validation: the limits a buildable configuration keeps
//! ([`HwConfig::validate`]: ranges, FIFO depths, ray slots, the node memory, the hit buffer),
//! and its agreement with the datapath it times ([`HwConfig::validate_for`]). Each message
//! names the field by its path in the RON file.
//!
//! Pipeline position: run once per run on the configuration read (`super`, the schema),
//! before any stage, the walker pool or the memory model takes its part of it.

use super::{HwConfig, UnitTimings, MAX_SORTER_LANES};
use crate::cycle::fifo;
use crate::datapath::DatapathConfig;
use crate::units::transform;

/// Upper limits `validate` enforces: far above any sensible design, low enough that every
/// product of them in [`HwConfig::resources`] (`cost::estimate`) stays within `u64`.
const MAX_CLOCK_MHZ: u32 = 1000;
const MAX_LATENCY: u32 = 100_000;
const MAX_UNITS: u32 = 4096;
const MAX_CONTEXTS: u32 = 1024;
const MAX_STACK_DEPTH: u8 = 64;
/// Deepest FIFO the FIFO model builds.
const FIFO_MAX_DEPTH: u32 = fifo::MAX_DEPTH as u32;
const MAX_FRAME_SIDE: u32 = 16384;

impl HwConfig {
    /// Checks that the configuration describes buildable hardware; the message names the
    /// field (its path in the RON file) and says what is wrong. Whether it fits the part is
    /// [`resources`](Self::resources)' question; scene-dependent limits (stack depth against
    /// an image's depth, on-chip levels) are the model's to report.
    pub fn validate(&self) -> Result<(), String> {
        let p = &self.part;
        if p.name.trim().is_empty() {
            return Err("part.name must name the device".into());
        }
        for (field, v) in [
            ("part.dsp48e2", p.dsp48e2),
            ("part.bram36", p.bram36),
            ("part.luts", p.luts),
        ] {
            if v == 0 {
                return Err(format!(
                    "{field} must be positive (every UltraScale+ part has some)"
                ));
            }
        }
        in_range("clock_mhz", self.clock_mhz, 1, MAX_CLOCK_MHZ)?;
        in_range("frame.width", self.frame.width, 1, MAX_FRAME_SIDE)?;
        in_range("frame.height", self.frame.height, 1, MAX_FRAME_SIDE)?;
        for (name, t) in self.units.named() {
            in_range(
                &format!("units.{name}.latency_cycles"),
                t.latency_cycles,
                1,
                MAX_LATENCY,
            )?;
            in_range(&format!("units.{name}.ii"), t.ii, 1, MAX_LATENCY)?;
        }
        in_range("sphere_units", self.sphere_units, 1, MAX_UNITS)?;
        in_range("sorter_lanes", self.sorter_lanes, 1, MAX_SORTER_LANES)
            .map_err(|e| format!("{e} (it must equal the datapath's sorter.n, an 8-bit field)"))?;
        in_range("transform_units", self.transform_units, 1, MAX_UNITS)?;
        in_range("reciprocal_units", self.reciprocal_units, 1, MAX_UNITS)?;
        if self.reciprocal_units > 3 && self.reciprocal_units % 3 != 0 {
            return Err(format!(
                "reciprocal_units = {} must be 1, 2 or a multiple of 3: a walk issue lane takes \
                 one walk's three axes at once, so {} unit(s) would be priced and never used",
                self.reciprocal_units,
                self.reciprocal_units % 3
            ));
        }
        in_range("walker_root_units", self.walker_root_units, 1, MAX_UNITS)?;
        let w = &self.walker_pool;
        in_range("walker_pool.walkers", w.walkers, 1, MAX_UNITS)?;
        in_range(
            "walker_pool.contexts_per_walker",
            w.contexts_per_walker,
            1,
            MAX_CONTEXTS,
        )?;
        in_range("walker_pool.step_cycles", w.step_cycles, 1, MAX_LATENCY)?;
        in_range(
            "walker_pool.step_latency_cycles",
            w.step_latency_cycles,
            1,
            MAX_LATENCY,
        )?;
        in_range(
            "walker_pool.stack_depth",
            u32::from(w.stack_depth),
            1,
            u32::from(MAX_STACK_DEPTH),
        )?;
        // 0 is unlimited; above R a port could never be used (a context has one read out).
        if w.read_ports > w.contexts_per_walker {
            return Err(format!(
                "walker_pool.read_ports = {} exceeds walker_pool.contexts_per_walker = {}: a \
                 walker's contexts have at most one read out each, so the extra ports would never \
                 be used (0 = unlimited, every context sends in the cycle it wants to)",
                w.read_ports, w.contexts_per_walker
            ));
        }
        for (name, v) in [
            (
                "walker_pool.response_register_cycles",
                w.response_register_cycles,
            ),
            (
                "walker_pool.request_register_cycles",
                w.request_register_cycles,
            ),
        ] {
            if v > 1 {
                return Err(format!(
                    "{name} = {v} is not supported: 0 (the pool's input or output is not \
                     registered) or 1 (one register stage, walker_pool.rs)"
                ));
            }
        }
        for (name, depth) in self.fifos.named() {
            in_range(&format!("fifos.{name}"), depth, 1, FIFO_MAX_DEPTH)?;
        }
        // Derived: the loop-back FIFO holds one entry per ray slot (every context, plus the
        // walks that can wait for one), so its depth is W·R + root_to_dispatch.
        let slots = self.ray_slots_wide();
        if slots > u64::from(FIFO_MAX_DEPTH) {
            return Err(format!(
                "walker_pool.walkers × walker_pool.contexts_per_walker + fifos.root_to_dispatch \
                 = {} × {} + {} = {slots} ray slots exceeds the limit {FIFO_MAX_DEPTH}: the \
                 loop-back FIFO holds one entry per ray slot and the deepest FIFO is \
                 {FIFO_MAX_DEPTH} entries",
                w.walkers, w.contexts_per_walker, self.fifos.root_to_dispatch
            ));
        }
        self.validate_node_memory()?;
        self.ray_order.validate()?;
        let hb = &self.hit_buffer;
        // Every pixel is read once (reuse check) and written once (write-back) per frame; the
        // check stage reads one pixel per cycle, so a second read port would stay unused.
        if hb.read_ports != 1 {
            return Err(format!(
                "hit_buffer.read_ports = {} is not supported: the check stage reads one pixel \
                 per cycle (one ray per clock), so the buffer has exactly 1 read port",
                hb.read_ports
            ));
        }
        // 2 write paths are two banks of one read and one write port each (see the field).
        in_range("hit_buffer.write_ports", u32::from(hb.write_ports), 1, 2)?;
        in_range(
            "hit_buffer.record_writes",
            u32::from(hb.record_writes),
            1,
            2,
        )?;
        if hb.record_writes > hb.write_ports {
            return Err(format!(
                "hit_buffer.record_writes = {} needs as many banks: set hit_buffer.write_ports                  to {} (two records a cycle go to the two banks)",
                hb.record_writes, hb.record_writes
            ));
        }
        in_range(
            "hit_buffer.read_latency_cycles",
            hb.read_latency_cycles,
            1,
            MAX_LATENCY,
        )?;
        Ok(())
    }

    fn validate_node_memory(&self) -> Result<(), String> {
        let nm = &self.node_memory;
        // The memory model's messages start with the field's path below `node_memory`.
        nm.validate().map_err(|e| format!("node_memory.{e}"))?;
        if nm.onchip.ports_per_bank > 2 {
            return Err(format!(
                "node_memory.onchip.ports_per_bank = {} exceeds the 2 ports of a block RAM",
                nm.onchip.ports_per_bank
            ));
        }
        Ok(())
    }

    /// [`validate`](Self::validate), then that the configuration matches the datapath it
    /// times: `sorter_lanes` equals `dp.sorter.n`, and no unit's latency is below the stage
    /// count of `dp`'s formats ([`UnitTimings::for_datapath`]). A latency above it is allowed
    /// (extra pipeline registers for timing closure).
    pub fn validate_for(&self, dp: &DatapathConfig) -> Result<(), String> {
        self.validate()?;
        dp.validate().map_err(|m| format!("datapath: {m}"))?;
        if self.sorter_lanes != u32::from(dp.sorter.n) {
            return Err(format!(
                "sorter_lanes = {} must equal the datapath's sorter.n = {}",
                self.sorter_lanes, dp.sorter.n
            ));
        }
        let mut need = UnitTimings::for_datapath(dp);
        if !self.transform_products {
            need.transform.latency_cycles = transform::LATENCY_WITHOUT_PRODUCTS;
        }
        for ((name, have), (_, min)) in self.units.named().into_iter().zip(need.named()) {
            if have.latency_cycles < min.latency_cycles {
                return Err(format!(
                    "units.{name}.latency_cycles = {} is below the {} stages the datapath's \
                     {name} needs",
                    have.latency_cycles, min.latency_cycles
                ));
            }
        }
        Ok(())
    }
}

fn in_range(field: &str, v: u32, lo: u32, hi: u32) -> Result<(), String> {
    if v < lo {
        Err(format!("{field} must be at least {lo} (got {v})"))
    } else if v > hi {
        Err(format!("{field} = {v} exceeds the limit {hi}"))
    } else {
        Ok(())
    }
}
