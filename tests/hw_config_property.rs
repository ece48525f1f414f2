//! Validation of the hardware configuration closes (issue 26, finding 4): a property test over
//! random configurations — every field of `HwConfig`, drawn mostly inside its documented range
//! with its limits and, now and then, beyond them — run through the library as `sim` runs them
//! (`HwConfig::validate_for`, elaboration, `run::run`) on a tiny scene (the embedded car at
//! depth 5, 2×2 pixels, 1 frame: every latency may be at its limit of 2^20 cycles, which the model times event by event but not for free). For each configuration, either
//!
//! * validation refuses it (`validate_for`, or the run's own checks before any output exists:
//!   the image against the hardware frame, elaboration), or
//! * the run succeeds: it never fails later for a configuration reason (no derived FIFO depth,
//!   slot count or memory size is found wrong once frames run), and never panics.
//!
//! Seeded (`SVO_TEST_SEED`, printed), `SVO_PROPTEST_CASES` cases (default 40; a refused case
//! takes microseconds, a run mostly 0.01 s in the test profile; 200 cases of one seed took
//! 129 s, of which two runs with latencies at their 2^20-cycle limit took 117 s and 10 s).
//!
//! Found by this test and fixed: the cycle model's no-progress watchdog scaled with the DRAM
//! latency only, so a valid cache hit latency of 2^20 cycles stopped a run as "no progress";
//! it now scales with the longest wait of any part (`HwConfig::longest_wait_cycles`).

use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use rtl_model::cycle::hw_config::{
    FifoDepths, FrameSize, HitBuffer, HwConfig, Part, Placement, RayOrder, StackStorage,
    UnitTiming, UnitTimings, WalkerPool,
};
use rtl_model::cycle::memory::{CacheConfig, DramConfig, NodeMemoryConfig, OnChipConfig};
use std::sync::atomic::{AtomicU32, Ordering};

mod common;
use svo_sim::models::reference::RenderOptions;
use svo_sim::run::elaborate::elaborate;
use svo_sim::run::{run, Model, RunConfig};
use svo_sim::world::assets::Materialise;
use svo_sim::world::scene::Scene;

/// A value of a field whose documented range is `lo..=hi`: mostly small (where designs are),
/// often at either limit, sometimes anywhere in range. Values beyond the limits come from
/// [`beyond`], one field per configuration, so that the other fields can still pass.
fn field(lo: u32, hi: u32) -> BoxedStrategy<u32> {
    let small_hi = hi.min(lo.saturating_add(8));
    prop_oneof![
        60 => lo..=small_hi,
        10 => Just(lo),
        10 => Just(hi),
        15 => lo..=hi,
    ]
    .boxed()
}

/// Sets one field just beyond (or far beyond) its documented limit.
type Beyond = fn(&mut HwConfig);

/// Every field's step beyond its limits.
const BEYOND: [Beyond; 30] = [
    |h| h.part.name.clear(),
    |h| h.part.dsp48e2 = 0,
    |h| h.part.bram36 = 0,
    |h| h.part.luts = 0,
    |h| h.clock_mhz = 1001,
    |h| h.frame.width = 16385,
    |h| h.frame.height = u32::MAX,
    |h| h.units.sphere.latency_cycles = 100_001,
    |h| h.units.sorter.ii = 0,
    |h| h.sphere_units = 4097,
    |h| h.sorter_lanes = 256,
    |h| h.sorter_lanes = 300,
    |h| h.transform_units = 0,
    |h| h.walker_pool.walkers = 4097,
    |h| h.walker_pool.contexts_per_walker = 1025,
    |h| h.walker_pool.step_cycles = 100_001,
    |h| h.walker_pool.stack_depth = 65,
    |h| h.walker_pool.read_ports = h.walker_pool.contexts_per_walker + 1,
    |h| h.walker_pool.response_register_cycles = 2,
    |h| h.walker_pool.request_register_cycles = 2,
    |h| h.fifos.check_to_transform = 65_537,
    |h| h.fifos.root_to_dispatch = 65_536,
    |h| h.node_memory.onchip.levels = 22,
    |h| h.node_memory.cache.size_bytes = (1 << 26) + 64,
    |h| h.node_memory.dram.latency = (1 << 20) + 1,
    |h| h.hit_buffer.read_ports = 3,
    |h| h.hit_buffer.read_latency_cycles = 0,
    |h| h.node_memory.cache.banks = 3,
    |h| h.node_memory.cache.miss_queue = 4097,
    |h| h.ray_order = RayOrder::Tiles(0),
];

fn flag() -> BoxedStrategy<bool> {
    any::<bool>().boxed()
}

fn placement() -> BoxedStrategy<Placement> {
    prop_oneof![
        Just(Placement::Bram),
        Just(Placement::Uram),
        Just(Placement::External)
    ]
    .boxed()
}

fn part() -> impl Strategy<Value = Part> {
    (
        prop_oneof![Just("xcvu9p".to_string()), Just("xczu9eg".to_string())],
        1..=u32::MAX,
        1..=u32::MAX,
        any::<u32>(),
        1..=u32::MAX,
    )
        .prop_map(|(name, dsp48e2, bram36, uram288, luts)| Part {
            name,
            dsp48e2,
            bram36,
            uram288,
            luts,
        })
}

fn timing() -> impl Strategy<Value = UnitTiming> {
    // Documented: 1..=100,000 each; the floor is the datapath's stage count (validate_for).
    (field(1, 100_000), field(1, 100_000)).prop_map(|(l, ii)| UnitTiming {
        latency_cycles: l,
        ii,
    })
}

fn units() -> impl Strategy<Value = UnitTimings> {
    let d = UnitTimings::default();
    // Mostly the default's stage count plus a few registers, so that validate_for passes
    // often; sometimes anything `timing` draws.
    let near = move |t: UnitTiming| {
        prop_oneof![
            19 => (0u32..=4, 1u32..=3).prop_map(move |(extra, ii)| UnitTiming {
                latency_cycles: t.latency_cycles + extra,
                ii,
            }),
            1 => timing(),
        ]
    };
    (
        near(d.raygen),
        near(d.sphere),
        near(d.sqrt),
        near(d.sorter),
        near(d.transform),
        near(d.reciprocal),
        near(d.walker_root),
        near(d.hit_pack),
        near(d.hit_unpack),
    )
        .prop_map(
            |(
                raygen,
                sphere,
                sqrt,
                sorter,
                transform,
                reciprocal,
                walker_root,
                hit_pack,
                hit_unpack,
            )| {
                UnitTimings {
                    raygen,
                    sphere,
                    sqrt,
                    sorter,
                    transform,
                    reciprocal,
                    walker_root,
                    hit_pack,
                    hit_unpack,
                }
            },
        )
}

fn walker_pool() -> impl Strategy<Value = WalkerPool> {
    (
        field(1, 4096),
        field(1, 1024),
        field(1, 100_000),
        field(1, 100_000),
        prop_oneof![1u8..=64, Just(64u8)],
        prop_oneof![Just(StackStorage::FullT), Just(StackStorage::ExactPop)],
        // 0 (unlimited) to a few; above the contexts is refused, which `BEYOND` also reaches.
        prop_oneof![Just(0u32), Just(1u32), 0u32..=4],
        // The pool's response and request registers: 0 or 1 (2 is refused, in `BEYOND`).
        (0u32..=1, 0u32..=1),
    )
        .prop_map(
            |(
                walkers,
                contexts_per_walker,
                step_cycles,
                step_latency_cycles,
                stack_depth,
                stack,
                read_ports,
                (response_register_cycles, request_register_cycles),
            )| {
                WalkerPool {
                    walkers,
                    contexts_per_walker,
                    step_cycles,
                    step_latency_cycles,
                    stack_depth,
                    stack,
                    read_ports,
                    response_register_cycles,
                    request_register_cycles,
                }
            },
        )
}

fn fifos() -> impl Strategy<Value = FifoDepths> {
    let f = || field(1, 65_536);
    (f(), f(), f(), f(), f(), f(), f(), f(), f()).prop_map(|(a, b, c, d, e, g, h, i, j)| {
        FifoDepths {
            raygen_to_sphere: a,
            sphere_to_sorter: b,
            sorter_to_check: c,
            check_to_transform: d,
            transform_to_reciprocal: e,
            reciprocal_to_root: g,
            root_to_dispatch: h,
            walker_to_record: i,
            record_to_write: j,
        }
    })
}

fn node_memory() -> impl Strategy<Value = NodeMemoryConfig> {
    let onchip = (
        prop_oneof![0u8..=21, Just(21u8)],
        prop_oneof![any::<u64>(), 0u64..=1 << 20, Just(0u64)],
        field(1, 1 << 20),
        field(1, 4096),
        field(1, 2),
        flag(),
    )
        .prop_map(
            |(levels, max_bytes, latency, banks, ports_per_bank, combine)| OnChipConfig {
                levels,
                max_bytes,
                latency,
                banks,
                ports_per_bank,
                combine,
            },
        );
    // A cache of 2^s sets × ways × 2^k-byte lines (up to and past the 64 MiB limit), or none,
    // or any size (mostly an invalid geometry).
    let cache = (
        3u32..=12,
        field(1, 4096),
        0u32..=12,
        prop_oneof![20 => Just(None), 2 => Just(Some(0u64)), 1 => any::<u64>().prop_map(Some)],
        field(1, 1 << 20),
        field(1, 4096),
        flag(),
        prop_oneof![4 => (0u32..=6).prop_map(|b| 1 << b), 1 => field(0, 128)],
        field(0, 4096),
    )
        .prop_map(
            |(k, ways, s, size, hit_latency, ports, attr_cached, banks, miss_queue)| CacheConfig {
                size_bytes: size.unwrap_or_else(|| {
                    (1u64 << s)
                        .saturating_mul(u64::from(ways))
                        .saturating_mul(1 << k)
                }),
                ways,
                line_bytes: 1 << k,
                hit_latency,
                ports,
                attr_cached,
                banks,
                miss_queue,
            },
        );
    let dram = (field(1, 1 << 20), field(1, 4096), field(1, 4096)).prop_map(
        |(latency, bytes_per_cycle, mshrs)| DramConfig {
            latency,
            bytes_per_cycle,
            mshrs,
            ..DramConfig::default()
        },
    );
    (onchip, cache, dram).prop_map(|(onchip, cache, dram)| NodeMemoryConfig {
        onchip,
        cache,
        dram,
    })
}

fn hit_buffer() -> impl Strategy<Value = HitBuffer> {
    // One read port is the only value (2 is refused); 1 or 2 write paths anywhere.
    let ports =
        prop_oneof![4 => Just((1u8, 1u8)), 1 => Just((2, 1)), 1 => Just((1, 2)), 1 => Just((2, 2))];
    // Two record writes a cycle need the two banks: drawn 1 or 2 anywhere, so that the
    // refusal of 2 on one write path is drawn too.
    let record_writes = prop_oneof![3 => Just(1u8), 1 => Just(2u8)];
    (flag(), placement(), ports, record_writes, field(1, 100_000)).prop_map(
        |(present, placement, (read_ports, write_ports), record_writes, read_latency_cycles)| {
            HitBuffer {
                present,
                placement,
                read_ports,
                write_ports,
                record_writes,
                read_latency_cycles,
            }
        },
    )
}

fn hw_config() -> impl Strategy<Value = HwConfig> {
    let counts = (
        field(1, 1000),
        // The frame holds the test's 8×8 image (a smaller one is refused by the run's check).
        (field(8, 16384), field(8, 16384)),
        field(1, 4096),
        // Sorter lanes: mostly the default datapath's `sorter.n` (16), which validation
        // requires; sometimes any width, refused.
        prop_oneof![10 => Just(16u32), 2 => field(1, 255)],
        field(1, 4096),
        flag(),
        // Reciprocal units: 1, 2 or whole lanes of three (anything else is refused, and a
        // uniform draw would make most configurations that refusal).
        prop_oneof![1 => field(1, 2), 3 => field(1, 1365).prop_map(|k| 3 * k)],
        field(1, 4096),
    );
    let config = (
        part(),
        counts,
        units(),
        walker_pool(),
        fifos(),
        node_memory(),
        hit_buffer(),
        placement(),
        prop_oneof![
            Just(RayOrder::Scanline),
            Just(RayOrder::Morton),
            field(0, 64).prop_map(RayOrder::Tiles)
        ],
    )
        .prop_map(
            |(
                part,
                (
                    clock_mhz,
                    (w, h),
                    sphere_units,
                    sorter_lanes,
                    transform_units,
                    products,
                    recip,
                    roots,
                ),
                units,
                walker_pool,
                fifos,
                node_memory,
                hit_buffer,
                direction_table,
                ray_order,
            )| HwConfig {
                part,
                clock_mhz,
                frame: FrameSize {
                    width: w,
                    height: h,
                },
                units,
                sphere_units,
                sorter_lanes,
                transform_units,
                transform_products: products,
                reciprocal_units: recip,
                walker_root_units: roots,
                walker_pool,
                fifos,
                node_memory,
                hit_buffer,
                direction_table,
                ray_order,
            },
        );
    // One configuration in three has one field beyond its limit.
    (
        config,
        prop_oneof![2 => Just(None), 1 => (0..BEYOND.len()).prop_map(Some)],
    )
        .prop_map(|(mut hw, beyond)| {
            if let Some(k) = beyond {
                BEYOND[k](&mut hw);
            }
            hw
        })
}

/// What happened to one configuration.
enum Outcome {
    Refused,
    RefusedBeforeOutput,
    Ran,
}

fn judge(hw: &HwConfig, out: &std::path::Path) -> Result<Outcome, String> {
    let dp = rtl_model::datapath::DatapathConfig::default();
    if hw.validate_for(&dp).is_err() {
        return Ok(Outcome::Refused);
    }
    let mut scene = Scene::default_car().map_err(|e| e.to_string())?;
    scene.set_resolution(2, 2).map_err(|e| e.to_string())?;
    scene.set_frames(1).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(out);
    let cfg = RunConfig {
        scene,
        depth: Some(5),
        materialise: Materialise::Auto,
        image_layout: Default::default(),
        options: RenderOptions::default(),
        out_dir: Some(out.to_path_buf()),
        report_json: None,
        dump_hits: None,
        progress_every: None,
        model: Model::Cycle,
        datapath: dp.clone(),
        hardware: hw.clone(),
        cross_check: false,
        sample: None,
        vcd: None,
        transaction_log: None,
        elaboration: None,
    };
    // As `sim` does: elaborate the pipeline for the scene, then run.
    let cfg = match elaborate(&cfg.scene, cfg.depth, &cfg.hardware, &cfg.datapath, true) {
        Ok(e) => cfg.elaborated(e),
        Err(e) => return Err(format!("elaboration refused a valid configuration: {e}")),
    };
    match run(&cfg, |_, _| {}) {
        Ok(o) if o.report.summary.frames == 1 => Ok(Outcome::Ran),
        Ok(o) => Err(format!("{} frames instead of 1", o.report.summary.frames)),
        Err(e) if !out.exists() => {
            let text = format!("{e:#}");
            // The one run-level check of the hardware: the image against its frame.
            if text.contains("hardware frame") {
                Ok(Outcome::RefusedBeforeOutput)
            } else {
                Err(format!("refused before output, not by validation: {text}"))
            }
        }
        Err(e) => Err(format!("failed after the run started: {e:#}")),
    }
}

#[test]
fn a_configuration_is_refused_by_validation_or_runs() {
    let seed = common::test_seed();
    println!("seed = {seed} (set SVO_TEST_SEED to reproduce)");
    let cases = common::proptest_cases(40);
    let out = std::env::temp_dir().join(format!("svo_hw_property_{}", std::process::id()));
    let (refused, early, ran) = (AtomicU32::new(0), AtomicU32::new(0), AtomicU32::new(0));
    let mut runner = TestRunner::new_with_rng(
        common::proptest_config(cases),
        common::proptest_rng(seed, 26),
    );
    let result = runner.run(&hw_config(), |hw| {
        let outcome = std::panic::catch_unwind(|| judge(&hw, &out))
            .map_err(|_| TestCaseError::fail(format!("seed = {seed}: panicked on {hw:?}")))?;
        match outcome {
            Ok(Outcome::Refused) => refused.fetch_add(1, Ordering::Relaxed),
            Ok(Outcome::RefusedBeforeOutput) => early.fetch_add(1, Ordering::Relaxed),
            Ok(Outcome::Ran) => ran.fetch_add(1, Ordering::Relaxed),
            Err(m) => return Err(TestCaseError::fail(format!("seed = {seed}: {m}\n{hw:?}"))),
        };
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&out);
    if let Err(e) = result {
        panic!("failed with seed = {seed} (SVO_TEST_SEED={seed} reproduces it):\n{e}");
    }
    let (refused, early, ran) = (refused.into_inner(), early.into_inner(), ran.into_inner());
    println!(
        "{cases} configurations: {refused} refused by validate_for, {early} refused for the \
         image against the hardware frame, {ran} ran"
    );
    // The generator must exercise both sides, or the property says nothing.
    assert!(refused > 0 && ran > 0, "refused {refused}, ran {ran}");
}
