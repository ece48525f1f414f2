//! Every RTL unit of `testbench/synth/units.tsv` through Yosys (`synth_xilinx -family xcup`,
//! `svo_sim::studies::synthesis`), against the model's estimate: each unit's DSP48E2 count
//! equals the estimate's or differs by exactly the difference units.tsv records with its
//! reason; LUTs and flip-flops are within 10 % of the calibrated estimate (a changed RTL
//! needs its calibration in `rtl_model/src/cost/fabric.rs` updated); every unit has timed
//! stages. Results are cached in the target folder by a hash of the script, the unit's line,
//! its files and the Yosys version, so only changed units are synthesised again (all ten, two
//! workers, take about 115 s uncached on the 2-core machine since the sorter's rewrite for the
//! clock, 245 s before, when the sorter alone was one worker's whole run; about 1 s from the
//! cache).
//!
//! Without `yosys` the test skips with a `SKIPPED` line (tests/common/skip.rs); with `CI=true`
//! a missing `yosys` fails (`.ci/run` installs the Debian package yosys).

mod common;

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::path::Path;
use std::time::Instant;
use svo_sim::studies::synthesis::{self, text, SynthOptions};

/// Whether Yosys is on the PATH (else the test skips visibly, or fails under CI=true).
fn yosys() -> bool {
    common::skip::tools(&["yosys"], "yosys")
}

fn within(est: u64, got: u64, pct: u64) -> bool {
    est.abs_diff(got) * 100 <= got * pct
}

#[test]
fn every_unit_matches_the_estimate_or_its_recorded_reason() {
    if !yosys() {
        return;
    }
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("synth-cache");
    let o = SynthOptions::new(repo, &cache);
    let t0 = Instant::now();
    let units = synthesis::synthesise(&o).unwrap_or_else(|e| panic!("{e}"));
    let (hw, dp) = (HwConfig::default(), DatapathConfig::default());
    print!(
        "{}",
        text::synthesis_text(&hw, &dp, &units, &o.rule, hw.clock_mhz)
    );
    println!("wall time {:.1} s", t0.elapsed().as_secs_f64());
    assert!(units.len() >= 10, "units.tsv lists {} units", units.len());
    let bad = text::dsp_mismatches(&hw, &dp, &units);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    for u in &units {
        assert!(
            hw.unit_estimate(&u.spec.name, &dp).is_some(),
            "{}: no estimate for this unit",
            u.spec.name
        );
        // At the width synthesised (the sorter: units.tsv's N, 8 lanes; the 16-lane
        // calibration of the default is a recorded synthesis, rtl_model/src/cost/fabric.rs).
        let e = text::estimate(&hw, &dp, u);
        let c = &u.cells;
        assert!(
            within(e.fabric.lut, c.clb_luts(), 10) && within(e.fabric.ff, c.ff, 10),
            "{}: LUT {}/{} FF {}/{} (estimate/Yosys): update the calibration in \
             rtl_model/src/cost/fabric.rs",
            u.spec.name,
            e.fabric.lut,
            c.clb_luts(),
            e.fabric.ff,
            c.ff
        );
        assert!(!u.stages.is_empty(), "{}: no timed stage", u.spec.name);
    }
    // The check can fail: an unrecorded difference is reported, naming the unit.
    let mut changed = units.clone();
    changed[0].spec.dsp_vs_model += 1;
    let bad = text::dsp_mismatches(&hw, &dp, &changed);
    assert_eq!(bad.len(), 1);
    assert!(bad[0].starts_with(&changed[0].spec.name), "{}", bad[0]);
}
