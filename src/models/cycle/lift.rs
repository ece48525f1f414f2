//! `--lift LIMIT`: the hardware with one limit of the bound line made ideal, so that a second
//! run says how much frame rate that limit alone costs (docs/cycle-model.md §2.2).
//!
//! Pipeline position: beside the cycle model, read once per run by `sim --lift`; it changes
//! the hardware configuration only, never the datapath's formats, so images and hit dumps of
//! the lifted run are the same as the first run's (`sorter` widens the datapath's sorting
//! network with the hardware's, [`lift_datapath`]: the order it gives is the same for every
//! width). "Ideal" is the most the configuration schema allows for that one limit, everything
//! else unchanged.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::sorter;

/// The limits `lift` knows, with what it sets for each.
pub const LIFTS: [(&str, &str); 12] = [
    (
        "record_write",
        "hit_buffer.write_ports and record_writes 2 and fifos.record_to_write 65536 (the most a FIFO may hold): two records a cycle, a packed record never waits for the write FIFO",
    ),
    (
        "sorter",
        "a 255-lane network (sorter_lanes and the datapath's sorter.n 255, its depth as the latency), units.sorter.ii 1: one issue for up to 255 candidates",
    ),
    (
        "sphere",
        "sphere_units at least 1024 and units.sphere.ii, units.sqrt.ii 1",
    ),
    (
        "walk_issue",
        "8 walk-issue lanes: transform_units and walker_root_units at least 8, reciprocal_units at least 24, and the walk section's FIFOs (transform_to_reciprocal, reciprocal_to_root, walker_to_record, record_to_write) at least 16 deep: a FIFO whose occupancy is registered passes at most half its depth a cycle",
    ),
    (
        "write_port",
        "hit_buffer.write_ports 2 (the check stage's own write path; the most the schema has)",
    ),
    (
        "walkers",
        "4 times the walkers (walker_pool.walkers, at most 4096)",
    ),
    (
        "walker_read_port",
        "walker_pool.read_ports 0: every context sends its read in the cycle it wants to",
    ),
    (
        "memory_ports",
        "node_memory.cache.ports and onchip.banks at least 64",
    ),
    ("mshr_full", "node_memory.dram.mshrs 4096"),
    (
        "hit_latency",
        "node_memory.onchip.latency and cache.hit_latency 1",
    ),
    ("dram_latency", "node_memory.dram.latency 1"),
    ("dram_bandwidth", "node_memory.dram.bytes_per_cycle 4096"),
];

/// `hw` with `limit` (one of [`LIFTS`]) made ideal; an error naming the limits it knows
/// otherwise, and for `clock` and `ray_generation`, which no hardware field lifts here.
pub fn lift(hw: &HwConfig, limit: &str) -> Result<HwConfig, String> {
    let mut h = hw.clone();
    let nm = &mut h.node_memory;
    match limit {
        "walk_issue" => {
            h.transform_units = h.transform_units.max(8);
            h.reciprocal_units = h.reciprocal_units.max(24);
            h.walker_root_units = h.walker_root_units.max(8);
            // A FIFO takes pushes against its registered occupancy, so it passes at most half
            // its depth a cycle: the default 4-deep FIFOs between the walk-issue units pass
            // two walks a cycle whatever the units (crowd_1000 gained nothing from 8 lanes
            // without this). Eight lanes need 16.
            let f = &mut h.fifos;
            for d in [
                &mut f.transform_to_reciprocal,
                &mut f.reciprocal_to_root,
                &mut f.walker_to_record,
                &mut f.record_to_write,
            ] {
                *d = (*d).max(16);
            }
        }
        "sorter" => {
            h.sorter_lanes = u32::from(LIFTED_SORTER_LANES);
            let depth = u32::try_from(sorter::depth(LIFTED_SORTER_LANES)).unwrap_or(u32::MAX);
            h.units.sorter.latency_cycles = h.units.sorter.latency_cycles.max(depth);
            h.units.sorter.ii = 1;
        }
        "sphere" => {
            h.sphere_units = h.sphere_units.max(1024);
            h.units.sphere.ii = 1;
            h.units.sqrt.ii = 1;
        }
        "record_write" => {
            h.hit_buffer.write_ports = 2;
            h.hit_buffer.record_writes = 2;
            h.fifos.record_to_write = LIFTED_FIFO_DEPTH;
        }
        "write_port" => h.hit_buffer.write_ports = 2,
        "walkers" => h.walker_pool.walkers = (h.walker_pool.walkers * 4).min(4096),
        "walker_read_port" => h.walker_pool.read_ports = 0,
        "memory_ports" => {
            nm.cache.ports = nm.cache.ports.max(64);
            nm.onchip.banks = nm.onchip.banks.max(64);
        }
        "mshr_full" => nm.dram.mshrs = 4096,
        "hit_latency" => {
            nm.onchip.latency = 1;
            nm.cache.hit_latency = 1;
        }
        "dram_latency" => nm.dram.latency = 1,
        "dram_bandwidth" => nm.dram.bytes_per_cycle = 4096,
        "clock" | "ray_generation" => {
            return Err(format!(
                "--lift {limit}: no hardware field lifts it (the front end generates one ray per \
                 clock); the limits that can be lifted are {}",
                names()
            ))
        }
        other => return Err(format!("--lift {other}: unknown limit; one of {}", names())),
    }
    h.validate()
        .map_err(|e| format!("--lift {limit}: the lifted hardware is refused: {e}"))?;
    // A lift that changes nothing would re-run the same hardware and report no gain as if the
    // limit had been lifted: say so instead (e.g. `write_port` on two write paths already,
    // where what stalls is the banks' conflicts, which no field of the schema widens).
    if h == *hw {
        let what = LIFTS
            .iter()
            .find(|(n, _)| *n == limit)
            .map_or("", |(_, w)| *w);
        return Err(format!(
            "--lift {limit}: the hardware already has what the lift sets ({what}); there is \
             nothing further to lift"
        ));
    }
    Ok(h)
}

/// What `--lift bound` says instead of a second run when the run's bound is one no hardware
/// field lifts: `clock` (the front end already generates about one ray per cycle, so the frame
/// is at the clock's limit) or `ray_generation`; `None` for a limit [`lift`] knows.
pub fn nothing_to_lift(bound: &str) -> Option<String> {
    match bound {
        "clock" => Some(
            "lift bound: the bound is clock: the frame is already at the clock's limit (about \
             one ray per cycle), nothing to lift; a faster clock (clock_mhz) is the only way on"
                .into(),
        ),
        "ray_generation" => Some(
            "lift bound: the bound is ray_generation: the front end's one ray per clock, which \
             no hardware field lifts; nothing to lift"
                .into(),
        ),
        _ => None,
    }
}

/// The depth of a lifted FIFO: the most `HwConfig::validate` allows (`cycle::fifo::MAX_DEPTH`).
const LIFTED_FIFO_DEPTH: u32 = 1 << 16;

/// The network width of the lifted sorter: the most the datapath's 8-bit `sorter.n` holds.
const LIFTED_SORTER_LANES: u8 = u8::MAX;

/// The datapath that goes with [`lift`]`(hw, limit)`: the same, except for `sorter`, whose
/// network width is the datapath's too (`HwConfig::validate_for`). The width changes no
/// image: the order is the total (t, id) order for any width (`units::sorter`), so only
/// cycles differ.
pub fn lift_datapath(dp: &DatapathConfig, limit: &str) -> DatapathConfig {
    let mut d = dp.clone();
    if limit == "sorter" {
        d.sorter.n = LIFTED_SORTER_LANES;
    }
    d
}

fn names() -> String {
    LIFTS.map(|(n, _)| n).join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_lift_changes_the_hardware_and_stays_valid() {
        // One write path (the default before issue 28), so that `write_port` and
        // `record_write` have something to lift.
        let mut hw = HwConfig::default();
        hw.hit_buffer.write_ports = 1;
        hw.hit_buffer.record_writes = 1;
        for (name, _) in LIFTS {
            let h = lift(&hw, name).unwrap_or_else(|e| panic!("{e}"));
            assert_ne!(h, hw, "{name} changed nothing");
        }
        let h = lift(&hw, "sorter").unwrap_or_else(|e| panic!("{e}"));
        h.validate_for(&lift_datapath(&DatapathConfig::default(), "sorter"))
            .unwrap_or_else(|e| panic!("the lifted sorter is refused: {e}"));
        let e = lift(&hw, "bogus").expect_err("unknown");
        assert!(
            e.contains("unknown limit") && e.contains("walk_issue"),
            "{e}"
        );
        assert!(lift(&hw, "clock").is_err());
        // Eight walk-issue lanes come with FIFOs deep enough to pass eight walks a cycle.
        let w = lift(&HwConfig::default(), "walk_issue").expect("walk_issue");
        assert_eq!(w.walk_lanes(), 8);
        assert!(w.fifos.transform_to_reciprocal >= 16 && w.fifos.reciprocal_to_root >= 16);
        // On the default's two write paths `write_port` has nothing left to set.
        let e = lift(&HwConfig::default(), "write_port").expect_err("nothing to lift");
        assert!(e.contains("already has what the lift sets"), "{e}");
    }

    #[test]
    fn a_clock_bound_has_nothing_to_lift_and_every_liftable_limit_has() {
        let says = nothing_to_lift("clock").expect("clock");
        assert!(says.contains("already at the clock's limit"), "{says}");
        assert!(nothing_to_lift("ray_generation").is_some());
        for (name, _) in LIFTS {
            assert_eq!(nothing_to_lift(name), None, "{name}");
        }
    }
}
