//! `--lift LIMIT`: the hardware with one limit of the bound line made ideal, so that a second
//! run says how much frame rate that limit alone costs (docs/cycle-model.md §2.2).
//!
//! Pipeline position: beside the cycle model, read once per run by `sim --lift`; it changes
//! the hardware configuration only, never the datapath, so images and hit dumps of the lifted
//! run are the same as the first run's. "Ideal" is the most the configuration schema allows
//! for that one limit, everything else unchanged.

use rtl_model::cycle::hw_config::HwConfig;

/// The limits `lift` knows, with what it sets for each.
pub const LIFTS: [(&str, &str); 8] = [
    (
        "walk_issue",
        "8 walk-issue lanes: transform_units and walker_root_units at least 8, reciprocal_units at least 24",
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
        }
        "write_port" => h.hit_buffer.write_ports = 2,
        "walkers" => h.walker_pool.walkers = (h.walker_pool.walkers * 4).min(4096),
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

fn names() -> String {
    LIFTS.map(|(n, _)| n).join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_lift_changes_the_hardware_and_stays_valid() {
        let hw = HwConfig::default();
        for (name, _) in LIFTS {
            let h = lift(&hw, name).unwrap_or_else(|e| panic!("{e}"));
            assert_ne!(h, hw, "{name} changed nothing");
        }
        let e = lift(&hw, "bogus").expect_err("unknown");
        assert!(
            e.contains("unknown limit") && e.contains("walk_issue"),
            "{e}"
        );
        assert!(lift(&hw, "clock").is_err());
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
