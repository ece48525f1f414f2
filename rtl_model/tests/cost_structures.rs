//! The fabric estimate's structures (`cost::structures`, docs/cycle-model.md §1.5,
//! "Structures"): each item's formula pinned on a hand-computed configuration, with the
//! numbers worked out here from the formats' widths (no code shared with the estimate), and
//! each pin shown failing once when the configuration it was computed for is corrupted.

use rtl_model::cost::FabricItem;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;

/// The hand-computed configuration: 2 walkers of 4 contexts, a 64 × 64 frame, 16 MSHRs, a
/// 64 KiB two-way cache of 64-byte lines with two ports, the other fields at their defaults.
fn hand() -> HwConfig {
    let mut hw = HwConfig::default();
    hw.walker_pool.walkers = 2;
    hw.walker_pool.contexts_per_walker = 4;
    hw.frame.width = 64;
    hw.frame.height = 64;
    hw.node_memory.dram.mshrs = 16;
    hw.node_memory.cache.size_bytes = 64 * 1024;
    hw.node_memory.cache.ways = 2;
    hw.node_memory.cache.line_bytes = 64;
    hw.node_memory.cache.ports = 2;
    hw
}

/// The widths the numbers below assume (the default datapath's).
fn assumed_widths(dp: &DatapathConfig) {
    assert_eq!(dp.walker.t.width, 62, "walker.t");
    assert_eq!(dp.walker.pos.width, 40, "walker.pos");
    assert_eq!(dp.raygen.dir.width, 32, "raygen.dir");
    assert_eq!(dp.raygen.pos.width, 40, "raygen.pos");
    assert_eq!(dp.sorter.key.width, 32, "sorter.key");
    assert_eq!(dp.sorter.n, 16, "sorter lanes");
    assert_eq!(dp.hit_record.instance_bits, 8, "instance bits");
    assert_eq!(dp.hit_record.word_bits(), 72, "record word");
}

/// One pinned item: its name, instances, and one instance's LUTs and FFs.
type Pin = (&'static str, u64, u64, u64);

/// The pins of [`hand`], each worked out by hand. Shared: ray slots 2 × 4 + 64
/// (`fifos.root_to_dispatch`) = 72, so a slot tag is ⌈log₂ 72⌉ = 7 bits; a pixel of the
/// 4,096-pixel frame 12 bits.
fn pins() -> Vec<Pin> {
    // Walker contexts: each walker is svo_walker_barrel of R = 4 contexts with K = 2 take
    // ports (two transform units): its measured 11,663 CLB LUT and 4,308 FF at the default
    // widths, less the one-context walker's 5,181 and 2,503 (the walker's own row).
    let contexts = ("walker_contexts", 2, 11663 - 5181, 4308 - 2503);
    // record_to_write: 8 × (72 + 12) = 84 bits: RAM32M16 8 × ⌈84 / 14⌉ = 48 LUTs; pointers
    // 3 × (⌈log₂ 8⌉ + 1) = 12 LUTs and FFs; no output register (LUT-RAM is read as addressed).
    let record = ("fifo.record_to_write", 1, 48 + 12, 12);
    // check_to_transform: 1,024 entries of a ray 12 + 3·32 = 108 bits (its pixel and
    // direction) and its candidate list, 2 × 16 = 32 candidates of (32 + 8) bits and a count
    // of ⌈log₂ 33⌉ = 6 bits: 1,394 bits. Deeper than 64 entries, so in block RAM (its blocks
    // are pinned in `deep_fifos_are_block_ram_and_shallow_ones_lut_ram`): the output register
    // with a LUT per bit selecting its next value, 1,394; pointers 3 × (⌈log₂ 1024⌉ + 1) = 33.
    let check = ("fifo.check_to_transform", 1, 1394 + 33, 1394 + 33);
    // MSHR CAM: line address 34 − 6 = 28 bits; 16 × (1 + 28 + 7) FFs; compare(28) = 10 pairs
    // + ⌈10 / 6⌉ = 12 LUTs, for 2 ports × 16 entries, + 16 for the free-entry pick.
    let mshr = ("mshr_cam", 1, 2 * 16 * 12 + 16, 16 * 36);
    // Cache control per port: 65,536 / (2 × 64) = 512 sets, tag 34 − 6 − 9 = 19 (+ valid =
    // 20: compare 7 pairs + 2 = 9 LUTs per way); way select 64 × ⌈1 / 3⌉; LRU 2 × 1 bits per
    // set in RAM64M8 8 × ⌈2 / 7⌉ × ⌈512 / 64⌉ = 64, + 2 update LUTs. FFs 4 × (34 + 64) + 2 × 20.
    let cache = ("cache_control", 2, 2 * 9 + 64 + 64 + 2, 4 * 98 + 2 * 20);
    vec![contexts, record, check, mshr, cache]
}

/// Whether `items` hold the pin: the item is there with its instances, LUTs and FFs.
fn check(items: &[FabricItem], (name, n, lut, ff): Pin) -> Result<(), String> {
    let it = items
        .iter()
        .find(|it| it.name == name)
        .ok_or_else(|| format!("{name}: missing"))?;
    let got = (it.instances, it.per_instance.lut, it.per_instance.ff);
    // The walker contexts are calibrated on the barrel walker's synthesis; the rest are not.
    let calibrated = name == "walker_contexts";
    if got != (n, lut, ff) || it.calibrated != calibrated {
        return Err(format!(
            "{name}: (instances, LUT, FF) = {got:?}, calibrated {}; expected ({n}, {lut}, {ff}), calibrated {calibrated}",
            it.calibrated
        ));
    }
    Ok(())
}

#[test]
fn each_structure_matches_its_hand_computed_formula() {
    let dp = DatapathConfig::default();
    assumed_widths(&dp);
    let items = hand().fabric(&dp).unwrap();
    for pin in pins() {
        if let Err(m) = check(&items, pin) {
            panic!("{m}");
        }
    }
    // Every FIFO of the model is priced once, in pipeline order, after the contexts.
    let names: Vec<&str> = items.iter().map(|it| it.name).collect();
    let fifos: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| n.starts_with("fifo."))
        .collect();
    assert_eq!(fifos.len(), 9, "{names:?}");
    assert_eq!(fifos[3], "fifo.check_to_transform");
    // The loop-back is the ray-slot table (`cost::core_logic`), not a FIFO of rays.
    assert!(names.contains(&"ray_slots") && !names.contains(&"fifo.loop_back"));
}

#[test]
fn each_pin_fails_when_its_configuration_is_corrupted() {
    let dp = DatapathConfig::default();
    // One corruption per pin, and that pin fails with its own message (others that share
    // the field, e.g. the slot tag, may fail beside it).
    type Corrupt = fn(&mut HwConfig);
    let corruptions: [(&str, Corrupt); 5] = [
        ("walker_contexts", |hw| {
            hw.walker_pool.contexts_per_walker = 40
        }),
        ("fifo.record_to_write", |hw| hw.fifos.record_to_write = 40),
        ("fifo.check_to_transform", |hw| hw.sorter_lanes = 9),
        ("mshr_cam", |hw| hw.node_memory.dram.mshrs = 17),
        ("cache_control", |hw| hw.node_memory.cache.ways = 4),
    ];
    for (target, corrupt) in corruptions {
        let mut hw = hand();
        corrupt(&mut hw);
        // sorter_lanes must equal the datapath's lanes for `validate_for`, not for the
        // estimate, which prices it as configured.
        let items = hw.fabric(&dp).unwrap();
        let failed: Vec<&str> = pins()
            .into_iter()
            .filter(|&p| check(&items, p).is_err())
            .map(|p| p.0)
            .collect();
        assert!(
            failed.contains(&target),
            "corrupting for {target}: failed {failed:?}"
        );
        let m = check(&items, pins().into_iter().find(|p| p.0 == target).unwrap()).unwrap_err();
        assert!(m.starts_with(target), "{m}");
        eprintln!("corrupted for {target}: {m} (failed: {failed:?})");
    }
}

#[test]
fn one_context_and_no_cache_add_nothing() {
    let dp = DatapathConfig::default();
    let mut hw = hand();
    hw.walker_pool.contexts_per_walker = 1;
    hw.node_memory.cache.size_bytes = 0;
    let items = hw.fabric(&dp).unwrap();
    let ctx = items
        .iter()
        .find(|it| it.name == "walker_contexts")
        .unwrap();
    assert_eq!((ctx.per_instance.lut, ctx.per_instance.ff), (0, 0));
    assert!(items.iter().all(|it| it.name != "cache_control"));
    // The MSHRs still merge uncached reads.
    assert!(items.iter().any(|it| it.name == "mshr_cam"));
}

#[test]
fn more_contexts_cost_more_fabric_per_walker() {
    let dp = DatapathConfig::default();
    let total = |contexts: u32| {
        let mut hw = HwConfig::default();
        hw.walker_pool.contexts_per_walker = contexts;
        hw.fabric(&dp)
            .unwrap()
            .iter()
            .map(|it| it.total().lut)
            .sum::<u64>()
    };
    // 32 contexts fit a RAM32M16 column as 8 do; 64 take RAM64M8.
    assert!(total(2) > total(1));
    assert!(total(8) > total(2));
    assert!(total(64) > total(32) + 32 * 1000);
}

/// Where a FIFO is built: deeper than 64 entries in block RAM (Yosys maps `svo_fifo` of 128
/// entries and more to RAMB36E2, of 64 to RAM64M8), with its blocks in the resource
/// estimate; 64 entries and fewer in LUT-RAM with none.
#[test]
fn deep_fifos_are_block_ram_and_shallow_ones_lut_ram() {
    let dp = DatapathConfig::default();
    let hw = hand();
    let res = hw.resources(&dp).unwrap();
    let bram = |name: &str| {
        res.items
            .iter()
            .find(|it| it.name == name)
            .map(|it| it.used.bram36)
    };
    // check_to_transform, 1,024 × 1,394: 38 blocks of 1,024 × 36 hold 1,368 bits, one more
    // the last 26.
    assert_eq!(bram("fifo.check_to_transform"), Some(39));
    // root_to_dispatch, 64 entries: LUT-RAM, no resource line of its own.
    assert_eq!(bram("fifo.root_to_dispatch"), None);
    // Shown failing: at 64 entries check_to_transform is LUT-RAM and has no block.
    let mut shallow = hand();
    shallow.fifos.check_to_transform = 64;
    let res = shallow.resources(&dp).unwrap();
    assert!(
        res.items
            .iter()
            .all(|it| it.name != "fifo.check_to_transform"),
        "a 64-entry check_to_transform FIFO must be LUT-RAM"
    );
}

#[test]
fn the_barrel_walker_is_priced_between_its_measured_points() {
    use rtl_model::cost::fabric::barrel_fabric;
    let at = |r, k| barrel_fabric(r, k).map(|f| (f.lut, f.ff));
    // The measured points themselves (testbench/README.md, svo_walker_barrel's row).
    assert_eq!(at(16, 2), Some((18463, 6630)));
    assert_eq!(at(4, 1), Some((8795, 4304)));
    // R = 12, K = 2: halfway from R = 8 (14,256 LUT, 5,083 FF) to 16 (18,463, 6,630):
    // 14,256 + 4,207 / 2 = 16,359.5 → 16,360; 5,083 + 1,547 / 2 = 5,856.5 → 5,857.
    assert_eq!(at(12, 2), Some((16360, 5857)));
    // R = 32, K = 2: the 8 → 16 slope continued: 18,463 + 2 × 4,207, 6,630 + 2 × 1,547.
    assert_eq!(at(32, 2), Some((26877, 9724)));
    // K = 3 at R = 16: K = 2's figure plus K = 1 → 2's step (18,463 − 13,175 = 5,288 LUT,
    // 6,630 − 6,614 = 16 FF).
    assert_eq!(at(16, 3), Some((23751, 6646)));
    // One context is svo_walker, not a barrel.
    assert_eq!(at(1, 2), None);
}

/// The walker pool's own logic (`walker_pool`, `cost::core_logic`): its fit by hand, and the
/// fit against the synthesised pools it was made from (the Yosys figures written out here,
/// not read from the calibration), for both node memories: behind the cache every response on
/// its context's port (svo_top's `CTX_RESP` 2), with every node word on chip (`onchip.levels`
/// 21) the records on the walkers' ports (`CTX_RESP` 1).
#[test]
fn the_walker_pool_follows_its_synthesised_points() {
    let dp = DatapathConfig::default();
    let pool = |walkers: u32, contexts: u32, lanes: u32, levels: u8| {
        let mut hw = HwConfig::default();
        hw.walker_pool.walkers = walkers;
        hw.walker_pool.contexts_per_walker = contexts;
        // walk_lanes is the widest of the walk-issue units.
        hw.transform_units = lanes;
        hw.reciprocal_units = 3 * lanes;
        hw.walker_root_units = lanes;
        hw.node_memory.onchip.levels = levels;
        let items = hw.fabric(&dp).unwrap();
        let it = items.iter().find(|it| it.name == "walker_pool").unwrap();
        (it.instances, it.per_instance.lut, it.per_instance.ff)
    };
    // By hand, 2 walkers of 4 contexts, two lanes, behind the cache: N = 8, W² = 4; LUT
    // 8 · (167.944 + 11.013 · 4) + 42.214 · 4 = 1,864.824 → 1,865; FF 8 · (32.690 + 2.187 · 4)
    // + 1.591 · 4 = 337.868 → 338.
    assert_eq!(pool(2, 4, 2, 8), (1, 1865, 338));
    // One lane: 1,864.824 · 0.782 = 1,458.29 → 1,458.
    assert_eq!(pool(2, 4, 1, 8), (1, 1458, 338));
    // The records on the walker ports: 8 · (368.178 + 2.487 · 8) = 3,104.592 → 3,105.
    assert_eq!(pool(2, 4, 2, 21), (1, 3105, 338));
    // The default's 48 × 16: N = 768, W² = 2,304; 768 · (167.944 + 11.013 · 16) + 42.214 ·
    // 2,304 = 361,569.79 LUT (on the walker ports 768 · (368.178 + 2.487 · 768) =
    // 1,749,652.99), 768 · (32.690 + 2.187 · 16) + 1.591 · 2,304 = 55,645.44 FF.
    assert_eq!(pool(48, 16, 2, 8), (1, 361_570, 55_645));
    assert_eq!(pool(48, 16, 2, 21), (1, 1_749_653, 55_645));
    // One walker of one context schedules nothing.
    assert_eq!(pool(1, 1, 1, 8), (1, 0, 0));
    // Yosys 0.23 of svo_walker_pool at these points (W, R, K, CLB LUT behind the cache, on
    // the walker ports where measured, FF, the same for both response arrangements): each fit
    // within its stated spread of the LUTs (behind the cache −6.6 … +10.1 %, on the walker
    // ports −12.2 … +7.9 %) and 3 % of the FFs.
    let points = [
        (2, 16, 2, 11_229u64, Some(13_511u64), 2_111u64),
        (4, 16, 2, 22_719, Some(31_306), 4_320),
        (8, 16, 2, 47_802, Some(88_415), 8_865),
        (16, 16, 2, 100_721, Some(259_369), 18_210),
        (4, 4, 2, 4_348, Some(7_424), 686),
        (8, 8, 2, 17_348, Some(33_437), 3_360),
        (32, 8, 2, 109_423, None, 14_370),
        (4, 16, 1, 17_759, Some(26_427), 4_320),
    ];
    for (w, r, k, lut_ctx, lut_ports, ff) in points {
        let cases = [(8, Some(lut_ctx), -6.6, 10.1), (21, lut_ports, -12.2, 7.9)];
        for (levels, lut, lo, hi) in cases {
            let Some(lut) = lut else { continue };
            let (_, e_lut, e_ff) = pool(w, r, k, levels);
            let dl = 100.0 * (e_lut as f64 - lut as f64) / lut as f64;
            let df = 100.0 * (e_ff as f64 - ff as f64) / ff as f64;
            eprintln!(
                "pool {w} × {r}, K {k}, levels {levels}: LUT {e_lut} / {lut} ({dl:+.1} %), FF {e_ff} / {ff} ({df:+.1} %)"
            );
            assert!(
                (lo..=hi).contains(&dl),
                "pool {w} × {r}, K {k}, levels {levels}: LUT {dl:+.1} %"
            );
            assert!(df.abs() <= 3.0, "pool {w} × {r}, K {k}: FF {df:+.1} %");
        }
    }
    // The calibration's table of the synthesised pools is these figures (behind the cache).
    let written: Vec<(u64, u64, u64, u64, u64)> = points
        .iter()
        .map(|&(w, r, k, lut, _, ff)| (u64::from(w), u64::from(r), u64::from(k), lut, ff))
        .collect();
    assert_eq!(
        rtl_model::cost::core_logic::calibration::POOL_MEASURED.to_vec(),
        written
    );
    // Records on the context ports cost less, the more so the larger the pool.
    let saved = |w| 1.0 - pool(w, 16, 2, 8).1 as f64 / pool(w, 16, 2, 21).1 as f64;
    assert!(saved(48) > saved(16) && saved(16) > saved(4) && saved(4) > 0.0);
}
