//! The hardware packages the RTL reads (`testbench/hw/*_pkg.sv`): each committed package is
//! what `sim hardware --sv-package` writes from its hardware file today, and a package field
//! the frame top cannot build stops it with the field named.
//!
//! Pipeline position: the bridge from the model's hardware configuration (`HwConfig`) to the
//! RTL's parameters.

use super::common::process::run_sim;
use super::frame::{frame_hw, hw_package};
use super::vector_files::{repo, Tmp};
use super::{run_sh, simulators};
use std::path::Path;
use std::time::Duration;

/// The committed hardware packages are what `sim hardware --sv-package` writes from their
/// files today: testbench/hw/svo_hw_pkg.sv from the default hardware, frame_hw_pkg.sv from
/// frame_hw.ron. A change of the default or of the schema that is not regenerated fails here,
/// naming the file and the first line that differs.
#[test]
fn committed_hardware_packages_are_generated_from_their_files() {
    let t = Tmp::new("hw_packages");
    let dir = repo().join("testbench/hw");
    let ron = |name: &str| dir.join(name).display().to_string();
    let (frame_ron, p14, p24, p42, p42r) = (
        ron("frame_hw.ron"),
        ron("pool_1x4.ron"),
        ron("pool_2x4.ron"),
        ron("pool_4x2.ron"),
        ron("pool_4x2_reg.ron"),
    );
    for (committed, hw) in [
        ("svo_hw_pkg.sv", None),
        ("frame_hw_pkg.sv", Some(frame_ron.as_str())),
        ("pool_1x4_pkg.sv", Some(p14.as_str())),
        ("pool_2x4_pkg.sv", Some(p24.as_str())),
        ("pool_4x2_pkg.sv", Some(p42.as_str())),
        ("pool_4x2_reg_pkg.sv", Some(p42r.as_str())),
    ] {
        let out = t.p(committed);
        let mut args = vec!["hardware", "--sv-package", &out];
        if let Some(h) = hw {
            args.extend(["--hw", h]);
        }
        let regen = match hw {
            Some(h) => format!(
                "sim hardware --hw testbench/hw/{} --sv-package testbench/hw/{committed}",
                Path::new(h)
                    .file_name()
                    .map_or(h.into(), |f| f.to_string_lossy())
            ),
            None => format!("sim hardware --sv-package testbench/hw/{committed}"),
        };
        let r = run_sim(&args, None, Duration::from_secs(120));
        assert!(r.status.success(), "sim {args:?}: {}", r.stderr);
        let fresh = std::fs::read_to_string(&out).expect("read the fresh package");
        let have =
            std::fs::read_to_string(dir.join(committed)).expect("read the committed package");
        if let Some((i, (a, b))) = have
            .lines()
            .zip(fresh.lines())
            .enumerate()
            .find(|(_, (a, b))| a != b)
        {
            panic!(
                "testbench/hw/{committed} is stale at line {}: committed {a:?}, generated {b:?} (regenerate: {regen})",
                i + 1
            );
        }
        assert_eq!(
            have, fresh,
            "testbench/hw/{committed} differs in length (regenerate it)"
        );
        println!(
            "testbench/hw/{committed}: equal to `sim {}`",
            args.join(" ")
        );
    }
}

/// A hardware package the frame top cannot build stops it with the field named: two walkers
/// (tb_frame builds one walker with one context), never run as if it were one.
#[test]
fn a_package_field_the_frame_cannot_build_stops_it() {
    let Some(&sim) = simulators().first() else {
        return;
    };
    let t = Tmp::new("frame_refuses");
    let one = "walker_pool: (walkers: 1, contexts_per_walker: 1)";
    let hw = frame_hw();
    assert!(hw.contains(one), "frame_hw.ron no longer names {one}");
    let pkg = hw_package(
        &t,
        "two_walkers",
        &hw.replace(one, "walker_pool: (walkers: 2, contexts_per_walker: 1)"),
    );
    let golden = repo().join("vectors").display().to_string();
    let p = pkg.display().to_string();
    let (_, text) = run_sh(
        &["--sim", sim, &golden, "frame"],
        &[
            ("FRAME_ARGS", "+model_cycles=1 +latency=3"),
            ("FRAME_HW_PKG", &p),
        ],
    );
    let want = "tb_frame: the hardware package has walker_pool.walkers = 2; this top builds 1";
    println!(
        "frame on a two-walker package ({sim}): {}",
        text.lines()
            .find(|l| l.contains("tb_frame:"))
            .unwrap_or("(no line)")
    );
    assert!(text.contains(want), "no \"{want}\":\n{text}");
    assert!(!text.contains(" passed, 0 failed\n== "), "{text}");
}
