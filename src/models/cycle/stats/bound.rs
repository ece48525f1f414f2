//! Which limit holds a frame's rate: the limits the report's bound line can name
//! ([`LIMITS`], which `--lift` can lift) and the rule that names one from the frame's stage
//! cycles, stall counters and walker-pool cycles (docs/cycle-model.md §2.2).
//!
//! Pipeline position: applied by `super::CycleFrame::new` (and again for sampled estimates)
//! once a frame's counters are in; its answer is the report's `bound`.

use super::StallCounts;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::stage_stats::StageCycles;
use rtl_model::cycle::walker_pool::PoolCycles;
use serde::Serialize;

/// The limits the bound line names and `--lift` can lift (docs/cycle-model.md §2.2).
pub const LIMITS: [&str; 14] = [
    "clock",
    "walk_issue",
    "write_port",
    "sorter",
    "sphere",
    "ray_generation",
    "record_write",
    "walkers",
    "walker_read_port",
    "memory_ports",
    "mshr_full",
    "hit_latency",
    "dram_latency",
    "dram_bandwidth",
];

/// Which limit holds the frame rate.
#[derive(Clone, Debug, Serialize)]
pub struct Bound {
    /// One of [`LIMITS`] (`clock`: the front end at one ray per cycle), or `check`: the
    /// hit-buffer check passing a ray nearly every cycle.
    pub limit: String,
    /// Why, with the figures.
    pub reason: String,
}

/// The limit (docs/cycle-model.md §2.2): `clock` if the frame ran at 0.9 rays per cycle or more;
/// a front-end unit busy every cycle; otherwise the pipeline-level cause that held back the
/// most cycles — walks waiting for an issue unit (`walk_issue`), words waiting for the
/// hit-buffer write path (`write_port`), the walk section waiting for rays while the sorter
/// (`sorter`) or the sphere lanes (`sphere`) held a ray for its further passes, or for rays
/// otherwise (`ray_generation`), or walks waiting for a context (the pool full). A full pool is then
/// split by what its walker-cycles were spent on: holding finished walks while the record
/// stage held records for a full write FIFO (`record_write`), issuing or the step pipeline
/// (`walkers`), or waiting on node reads, named by the largest part of their latency (`memory_ports`,
/// `mshr_full`, `hit_latency`, `dram_latency`, `dram_bandwidth`).
pub(crate) fn bound_of(
    hw: &HwConfig,
    stages: &[StageCycles],
    w: &PoolCycles,
    st: &StallCounts,
    cycles: u64,
    pixels: u64,
) -> Bound {
    let c = cycles.max(1) as f64;
    let pct = |n: u64| 100.0 * n as f64 / c;
    let raygen = pixels as f64 / c;
    if raygen >= 0.9 {
        // What holds the rest of the clock's rate, when 1 % or more of it is lost: the
        // pipeline-level cause with the most stalled cycles, if any (the car's still frames:
        // the check stage's words waiting for their hit-buffer bank).
        let held = [
            ("walk_issue", st.walk_issue),
            ("write_port", st.write_port),
            ("sorter", st.sorter),
            ("sphere", st.sphere),
            ("walkers", st.walkers_full),
        ]
        .into_iter()
        .fold(("", 0), |top, c| if c.1 > top.1 { c } else { top });
        let rest = match held {
            // Nothing worth naming: under 1 % of the clock's rate is lost.
            _ if raygen >= 0.99 => String::new(),
            (_, 0) => String::new(),
            ("write_port", n) => format!(
                "; the rest is held by the hit-buffer write port: {:.1}% of cycles stalled (bank conflicts {:.1}%)",
                pct(n),
                pct(st.write_bank_conflicts)
            ),
            (name, n) => format!("; the rest is held by {name}: {:.1}% of cycles stalled", pct(n)),
        };
        return Bound {
            limit: "clock".into(),
            reason: format!(
                "the front end generates {:.2} rays per cycle of the ideal 1: the frame rate is the clock's ({} MHz){rest}",
                raygen, hw.clock_mhz
            ),
        };
    }
    // A front-end unit's throughput use: transactions per cycle.
    let share = |n: &str| {
        stages
            .iter()
            .find(|s| s.name == n)
            .map_or(0.0, |s| s.transactions as f64 / c)
    };
    // The check stage takes one ray per cycle at most: near that rate it is the limit. The
    // sorter and the sphere lanes take several cycles for some rays, so a transaction rate says
    // little about them: their causes are counted below (`StallCounts::sorter`, `sphere`).
    for unit in ["check"] {
        if share(unit) >= 0.95 {
            return Bound {
                limit: unit.into(),
                reason: format!(
                    "the {unit} stage is busy {:.0}% of cycles",
                    100.0 * share(unit)
                ),
            };
        }
    }
    let wc = (w.issuing + w.memory_wait + w.latency_wait + w.backpressured + w.empty).max(1) as f64;
    let stalls = format!(
        "stalled cycles: walk issue {:.0}%, write port {:.0}% (bank conflicts {:.0}%), waiting for the sorter {:.0}%, for the sphere lanes {:.0}%, for rays {:.0}%, contexts full {:.0}%, records held for the write FIFO {:.0}%",
        pct(st.walk_issue),
        pct(st.write_port),
        pct(st.write_bank_conflicts),
        pct(st.sorter),
        pct(st.sphere),
        pct(st.ray_generation),
        pct(st.walkers_full),
        pct(st.record_write)
    );
    let reads = st.walker_read_port
        + st.memory_ports
        + st.mshr_full
        + st.hit_latency
        + st.dram_latency
        + st.dram_bandwidth;
    let rp = |n: u64| 100.0 * n as f64 / reads.max(1) as f64;
    let pool = format!(
        "walker-cycles: {:.0}% issuing, {:.0}% waiting on node reads, {:.0}% on the step pipeline, {:.0}% holding finished walks, {:.0}% empty; read latency: walker request port {:.0}%, memory ports {:.0}%, MSHR full {:.0}%, hit latency {:.0}%, DRAM latency {:.0}%, DRAM bus and merges {:.0}%",
        100.0 * w.issuing as f64 / wc,
        100.0 * w.memory_wait as f64 / wc,
        100.0 * w.latency_wait as f64 / wc,
        100.0 * w.backpressured as f64 / wc,
        100.0 * w.empty as f64 / wc,
        rp(st.walker_read_port),
        rp(st.memory_ports),
        rp(st.mshr_full),
        rp(st.hit_latency),
        rp(st.dram_latency),
        rp(st.dram_bandwidth)
    );
    let reason = format!("{stalls}; {pool}");
    // The pipeline-level cause that held back the most cycles (ties: the order below).
    let causes = [
        ("walkers", st.walkers_full),
        ("walk_issue", st.walk_issue),
        ("write_port", st.write_port),
        ("sorter", st.sorter),
        ("sphere", st.sphere),
        ("ray_generation", st.ray_generation),
    ];
    let mut top = causes[0];
    for c in causes {
        if c.1 > top.1 {
            top = c;
        }
    }
    if top.0 != "walkers" {
        return Bound {
            limit: top.0.into(),
            reason,
        };
    }
    // The pool is full: what are its contexts doing? Holding finished walks the record stage
    // cannot take, more than waiting on reads and more than working, while the record stage
    // held records for the write FIFO: the record write path.
    let work = w.issuing + w.latency_wait;
    if w.backpressured > w.memory_wait
        && w.backpressured + w.memory_wait > work
        && st.record_write > 0
    {
        return Bound {
            limit: "record_write".into(),
            reason,
        };
    }
    if w.memory_wait > work {
        let parts = [
            ("walker_read_port", st.walker_read_port),
            ("memory_ports", st.memory_ports),
            ("mshr_full", st.mshr_full),
            ("hit_latency", st.hit_latency),
            ("dram_latency", st.dram_latency),
            ("dram_bandwidth", st.dram_bandwidth),
        ];
        let mut worst = parts[0];
        for p in parts {
            if p.1 > worst.1 {
                worst = p;
            }
        }
        return Bound {
            limit: worst.0.into(),
            reason,
        };
    }
    Bound {
        limit: "walkers".into(),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limit(w: &PoolCycles, st: &StallCounts, cycles: u64, pixels: u64) -> String {
        bound_of(&HwConfig::default(), &[], w, st, cycles, pixels).limit
    }

    #[test]
    fn the_rule_names_the_largest_cause_and_splits_a_full_pool() {
        let mut w = PoolCycles::default();
        let mut st = StallCounts {
            walk_issue: 600,
            write_port: 100,
            ray_generation: 50,
            ..StallCounts::default()
        };
        assert_eq!(limit(&w, &st, 1000, 500), "walk_issue");
        assert_eq!(limit(&w, &st, 1000, 950), "clock", "0.95 rays per cycle");
        // Corrupted: the write port's counter above the walk issue's names the write port.
        st.write_port = 700;
        assert_eq!(limit(&w, &st, 1000, 500), "write_port");
        // A full pool waiting on reads names the largest part of their latency...
        st.walkers_full = 900;
        w.memory_wait = 800;
        w.issuing = 100;
        st.dram_latency = 5000;
        st.memory_ports = 20_000;
        assert_eq!(limit(&w, &st, 1000, 500), "memory_ports");
        st.dram_latency = 30_000;
        assert_eq!(limit(&w, &st, 1000, 500), "dram_latency");
        // Reads waiting for their walker's request port the most (issue 29).
        st.walker_read_port = 40_000;
        assert_eq!(limit(&w, &st, 1000, 500), "walker_read_port");
        st.walker_read_port = 0;
        // ...and one that issues names the walkers.
        w.issuing = 900;
        assert_eq!(limit(&w, &st, 1000, 500), "walkers");
        // One holding finished walks, mostly, while records waited for the write FIFO, names
        // the record write path.
        w.issuing = 300;
        w.memory_wait = 200;
        w.backpressured = 400;
        st.record_write = 300;
        assert_eq!(limit(&w, &st, 1000, 500), "record_write");
        st.record_write = 0;
        assert_eq!(limit(&w, &st, 1000, 500), "walkers", "no record held");
    }

    #[test]
    fn at_the_clock_the_reason_names_what_holds_the_rest() {
        let reason = |st: &StallCounts, pixels: u64| {
            bound_of(
                &HwConfig::default(),
                &[],
                &PoolCycles::default(),
                st,
                1000,
                pixels,
            )
            .reason
        };
        let mut st = StallCounts {
            walk_issue: 30,
            write_port: 85,
            write_bank_conflicts: 89,
            ..StallCounts::default()
        };
        // 0.915 rays per cycle: 8.5 % of the cycles the check stage waited for a write port.
        let r = reason(&st, 915);
        assert!(
            r.ends_with(
                "; the rest is held by the hit-buffer write port: 8.5% of cycles stalled (bank conflicts 8.9%)"
            ),
            "{r}"
        );
        // The walk issue's counter above it names the walk issue.
        st.walk_issue = 120;
        let r = reason(&st, 915);
        assert!(
            r.ends_with("; the rest is held by walk_issue: 12.0% of cycles stalled"),
            "{r}"
        );
        // Under 1 % lost, or nothing stalled: no clause.
        assert!(!reason(&st, 995).contains("the rest"));
        assert!(!reason(&StallCounts::default(), 915).contains("the rest"));
    }
}
