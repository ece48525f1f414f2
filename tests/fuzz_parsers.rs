//! The parser fuzzer's short run (issue 14 part 5): at least 20,000 mutated inputs over the
//! `.vox` loader, the scene RON and the hardware and datapath RON, seeded with the shared
//! models and the example files. Every input must end in a result or an error: 0 panics,
//! 0 hangs (10 s per input, generous for a debug build), and the process's peak memory bounded.
//! The seed is `SVO_TEST_SEED` (printed); `sim fuzz --seed S --inputs N` runs the same inputs.

mod common;

use std::process::Command;
use std::time::Duration;
use svo_sim::studies::fuzz::{fuzz, FuzzCommand, Target};

/// Mutated inputs per target: 4 × 5,000 = 20,000, plus the seeds themselves.
const INPUTS_PER_TARGET: u64 = 5_000;

/// Peak resident memory allowed for the whole test process. The loaders cap what one input
/// may allocate (MAX_PLACED_VOXELS, MAX_UPSCALED_LEAVES); mutated seeds of at most 200 KB stay
/// far below, so exceeding this means a limit stopped working.
const MAX_PEAK_RSS: u64 = 2 << 30;

#[test]
fn twenty_thousand_mutated_inputs_end_in_a_result_or_an_error() {
    let seed = common::test_seed();
    println!("seed {seed} (SVO_TEST_SEED)");
    let vox_dir = common::skip::shared_vox_dir_for("the .vox seed corpus");
    let s = fuzz(&FuzzCommand {
        targets: Vec::new(),
        inputs: INPUTS_PER_TARGET,
        seed,
        time_limit: Duration::from_secs(10),
        vox_dir: vox_dir.clone().unwrap_or_default(),
        max_vox_bytes: 200_000,
        save: None,
        replay: None,
        quiet: true,
    })
    .expect("fuzz run");
    print!(
        "{}",
        svo_sim::studies::fuzz::command::summary_text(&s, seed)
    );
    assert!(s.inputs() >= 4 * INPUTS_PER_TARGET);
    assert_eq!(s.panics(), 0, "inputs panicked (see FOUND lines above)");
    assert_eq!(s.hangs(), 0, "an input hung (see FOUND lines above)");
    for (t, r) in &s.reports {
        assert!(
            r.seeds_rejected.is_empty(),
            "{}: {:?}",
            t.name(),
            r.seeds_rejected
        );
        // Both outcomes are reached: mutations that keep inputs valid and ones that break them.
        assert!(r.accepted > 0 && r.rejected > 0, "{}: {r:?}", t.name());
    }
    if vox_dir.is_some() {
        let vox = &s
            .reports
            .iter()
            .find(|(t, _)| *t == Target::Vox)
            .expect("vox")
            .1;
        assert!(
            vox.inputs > INPUTS_PER_TARGET + 5,
            "the shared models were seeds"
        );
    }
    if let Some(peak) = s.peak_rss {
        assert!(peak < MAX_PEAK_RSS, "peak resident memory {peak} bytes");
    }
}

fn sim(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(args)
        .output()
        .expect("run sim")
}

#[test]
fn the_command_rejects_bad_options_and_replays_an_input() {
    let bad = sim(&["fuzz", "--target", "pdf"]);
    assert!(!bad.status.success());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("--target pdf: no such parser"), "{err}");

    let dir = std::env::temp_dir().join(format!("svo_fuzz_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let input = dir.join("scene.ron");
    std::fs::write(&input, "(frames: NaN)").expect("write input");
    let p = input.to_string_lossy().into_owned();
    let two = sim(&["fuzz", "--replay", &p]);
    assert!(
        !two.status.success(),
        "--replay without one --target is an error"
    );
    let one = sim(&["fuzz", "--replay", &p, "--target", "scene"]);
    let out = String::from_utf8_lossy(&one.stdout);
    assert!(one.status.success(), "{out}");
    assert!(out.contains("rejected: <fuzz input>:1:"), "{out}");

    let small = sim(&[
        "fuzz", "--inputs", "200", "--target", "hardware", "--target", "datapath", "-q",
    ]);
    let out = String::from_utf8_lossy(&small.stdout);
    assert!(small.status.success(), "{out}");
    assert!(
        out.contains("404 inputs, 0 panics, 0 hangs, seed 1"),
        "{out}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
