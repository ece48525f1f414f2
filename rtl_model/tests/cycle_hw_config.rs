//! Tests of the cycle model's hardware configuration (`rtl_model::cycle::hw_config`) and what
//! it costs (`rtl_model::cost`): the default validates and fits its part, the unit latencies
//! are the units' own stage counts, the resource estimate of the default is what
//! `docs/cycle-model.md` states, serde rejects unknown fields and fills missing ones, and
//! invalid configurations are rejected with the field named. Deterministic: no randomness is needed.

use rtl_model::cost::FabricTotals;
use rtl_model::cycle::hw_config::{
    HwConfig, Part, Placement, ResourceReport, StackStorage, UnitTimings, WalkerPool,
};
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::sqrt::SqrtConfig;
use rtl_model::units::{reciprocal, sorter, sphere, sqrt, transform, walker};
use serde::de::value::{Error as ValueError, MapDeserializer};
use serde::Deserialize;

fn default_report() -> ResourceReport {
    HwConfig::default()
        .resources(&DatapathConfig::default())
        .expect("the default configuration is valid")
}

fn item(r: &ResourceReport, name: &str) -> (u64, u64, u64, u64) {
    let it = r
        .items
        .iter()
        .find(|i| i.name == name)
        .unwrap_or_else(|| panic!("no item {name}"));
    (
        it.instances,
        it.used.dsp48e2,
        it.used.bram36,
        it.used.uram288,
    )
}

#[test]
fn default_validates_and_fits_the_part() {
    let cfg = HwConfig::default();
    let dp = DatapathConfig::default();
    cfg.validate().unwrap();
    cfg.validate_for(&dp).unwrap();
    assert_eq!(cfg.part, Part::xcvu9p());
    assert_eq!(cfg, HwConfig::for_datapath(&dp));
    let r = default_report();
    println!("{r}");
    assert!(r.fits(), "{:?}", r.over_budget());
    assert!(r.over_budget().is_empty());
    assert!(r.to_string().contains("fits"));
    // The logic fits too (issue 29: the 32 × 8 pool, 67.2 % of the LUTs by the estimate
    // calibrated on the RTL's synthesis), where issue 28's 48 × 16 pool does not (135.9 %).
    let fabric =
        |cfg: &HwConfig| FabricTotals::of(&cfg.fabric(&dp).unwrap(), u64::from(cfg.part.luts));
    let t = fabric(&cfg);
    println!("{t}");
    assert!(t.fits(), "{t}");
    assert_eq!((t.lut, t.ff), (794_120, 269_899));
    let mut old = cfg.clone();
    old.walker_pool.walkers = 48;
    old.walker_pool.contexts_per_walker = 16;
    let t = fabric(&old);
    assert!(!t.fits(), "{t}");
    assert_eq!((t.lut, t.ff), (1_606_115, 547_658));
}

#[test]
fn resource_estimate_of_the_default() {
    let r = default_report();
    println!("{r}");
    // (instances, DSP48E2, BRAM36, URAM288) per component; docs/cycle-model.md §2.4.
    assert_eq!(item(&r, "sphere"), (8, 272, 0, 0));
    assert_eq!(item(&r, "sqrt"), (8, 0, 0, 0));
    assert_eq!(item(&r, "sorter"), (1, 0, 0, 0));
    // Two walk-issue lanes (issue 28): two transforms, two lanes of three reciprocals, two
    // roots.
    assert_eq!(item(&r, "transform"), (2, 144, 0, 0));
    assert_eq!(item(&r, "reciprocal"), (6, 72, 0, 0));
    assert_eq!(item(&r, "walker_root"), (2, 72, 0, 0));
    // The record's normal unit: 9 products.
    assert_eq!(item(&r, "normal"), (1, 9, 0, 0));
    // 32 walkers: 8 contexts × 20 frames (the top frame is in registers) = 160 entries of
    // the RTL's 700-bit frame, ⌈700 / 72⌉ = 10 BRAM36 side by side (issue 29: the barrel's
    // synthesis has 10 RAMB36 at 16 contexts, 320 entries, as at 8).
    assert_eq!(item(&r, "walker_stacks"), (32, 0, 320, 0));
    // Two banks on pixel parity (two write paths), 240 URAM288 in all.
    assert_eq!(item(&r, "hit_buffer"), (2, 0, 0, 240));
    assert_eq!(item(&r, "direction_table"), (1, 0, 0, 480));
    // 2 MiB of on-chip words in 16 banks: 512 BRAM36 of 1024 × 32 bits.
    assert_eq!(item(&r, "node_onchip"), (16, 0, 512, 0));
    // 4 banks × 2 lookup ports: eight copies of 64 KiB (2 URAM288 each), eight tag copies.
    assert_eq!(item(&r, "cache_data"), (8, 0, 0, 16));
    assert_eq!(item(&r, "cache_tags"), (8, 0, 8, 0));
    // svo_front's candidate gathering, a decoder per key slot (issue 29), maps to no DSP48E2
    // (its running-index version took one per sphere lane): no resource row.
    assert!(r.items.iter().all(|i| i.name != "front_gather"));
    // The one FIFO deeper than 64 entries is block RAM: check_to_transform, 1,024 entries of
    // a ray (pixel 20 + direction 3·32 bits) and its candidate list (a 6-bit count and 2 × 16
    // candidates of 32 + 8 bits): 1,402 bits. 38 blocks of 1,024 × 36 hold 1,368 bits, a 39th
    // the last 34. The loop-back is the ray-slot table, in LUT-RAM (`cost::core_logic`).
    assert_eq!(item(&r, "fifo.check_to_transform"), (1, 0, 39, 0));
    assert!(r.items.iter().all(|i| i.name != "fifo.loop_back"));
    assert_eq!(
        (r.used.dsp48e2, r.used.bram36, r.used.uram288),
        (569, 879, 736)
    );
    assert_eq!(
        (r.available.dsp48e2, r.available.bram36, r.available.uram288),
        (6840, 2160, 960)
    );
    let p = r.percent();
    assert!((p[0] - 8.3).abs() < 0.05 && (p[1] - 40.7).abs() < 0.05 && (p[2] - 76.7).abs() < 0.05);
    // The used line is the sum of the items.
    let sum = r.items.iter().fold((0, 0, 0), |a, i| {
        (
            a.0 + i.used.dsp48e2,
            a.1 + i.used.bram36,
            a.2 + i.used.uram288,
        )
    });
    assert_eq!(sum, (r.used.dsp48e2, r.used.bram36, r.used.uram288));
}

#[test]
fn unit_latencies_equal_the_unit_functions() {
    let dp = DatapathConfig::default();
    let u = HwConfig::default().units;
    // Units that expose their latency: the default must be exactly theirs.
    assert_eq!(sphere::sqrt_config(&dp.sphere), SqrtConfig::default());
    assert_eq!(
        u.sqrt.latency_cycles,
        sqrt::latency_cycles(&SqrtConfig::default())
    );
    assert_eq!(u.sqrt.latency_cycles, 32);
    assert_eq!(
        u64::from(u.sorter.latency_cycles),
        sorter::network_latency(dp.sorter.n)
    );
    assert_eq!(u64::from(u.sorter.ii), sorter::network_ii(dp.sorter.n));
    // The default 16-lane network: depth 10 (issue 28; 6 at 8 lanes).
    assert_eq!((u.sorter.latency_cycles, u.sorter.ii), (10, 1));
    assert_eq!(
        u.reciprocal.latency_cycles,
        reciprocal::latency_cycles(&dp.reciprocal)
    );
    assert_eq!(u.reciprocal.latency_cycles, 26);
    // Units whose stage count is built from their products (`fixed::Products`).
    assert_eq!(u.sphere.latency_cycles, sphere::latency_cycles(&dp.sphere));
    assert_eq!(u.sphere.latency_cycles, 16);
    assert_eq!(
        u.transform.latency_cycles,
        transform::latency_cycles(&dp.transform)
    );
    assert_eq!(u.transform.latency_cycles, 9);
    assert_eq!(
        u.walker_root.latency_cycles,
        walker::root_latency_cycles(&dp.walker)
    );
    assert_eq!(u.walker_root.latency_cycles, 8);
    assert_eq!(
        (
            u.raygen.latency_cycles,
            u.hit_pack.latency_cycles,
            u.hit_unpack.latency_cycles
        ),
        // hit_pack: the normal unit (13) and the word packer (1).
        (4, 14, 1)
    );
    for (name, t) in u.named() {
        assert_eq!(t.ii, 1, "{name} is fully pipelined");
    }
}

#[test]
fn dsp_counts_are_those_sim_datapath_prints() {
    let dp = DatapathConfig::default();
    assert_eq!(sphere::dsp48e2_count(&dp.sphere), 34);
    assert_eq!(transform::dsp48e2_count(&dp.transform), 72);
    assert_eq!(reciprocal::dsp48e2_count(&dp.reciprocal), 12);
    assert_eq!(walker::root_dsp48e2_count(&dp.walker), 36);
    assert_eq!(sqrt::dsp48e2_count(&sphere::sqrt_config(&dp.sphere)), 0);
}

#[test]
fn timings_follow_the_datapath() {
    let mut dp = DatapathConfig::default();
    // 8 lanes, the default before issue 28 (16 now): the 19-comparator network of depth 6.
    dp.sorter.n = 8;
    dp.reciprocal.iterations = 1;
    dp.reciprocal.table_bits = 12;
    dp.validate().unwrap();
    let cfg = HwConfig::for_datapath(&dp);
    assert_eq!(cfg.sorter_lanes, 8);
    assert_eq!(cfg.units.sorter.latency_cycles, 6);
    assert_eq!(
        cfg.units.reciprocal.latency_cycles,
        reciprocal::latency_cycles(&dp.reciprocal)
    );
    assert!(cfg.units.reciprocal.latency_cycles < 26);
    cfg.validate_for(&dp).unwrap();
    // The default hardware no longer matches this datapath: the sorter lanes differ.
    let e = HwConfig::default().validate_for(&dp).unwrap_err();
    assert!(e.contains("sorter_lanes"), "{e}");
}

#[test]
fn latency_below_the_stage_count_is_rejected_above_it_allowed() {
    let dp = DatapathConfig::default();
    let mut cfg = HwConfig::default();
    cfg.units.sqrt.latency_cycles = 31;
    cfg.validate().unwrap(); // structurally fine …
    let e = cfg.validate_for(&dp).unwrap_err(); // … but faster than the circuit
    assert!(e.contains("units.sqrt.latency_cycles"), "{e}");
    cfg.units.sqrt.latency_cycles = 40; // extra pipeline registers
    cfg.validate_for(&dp).unwrap();
    let mut bad = dp.clone();
    bad.sphere.pos.width = 0;
    let e = HwConfig::default().validate_for(&bad).unwrap_err();
    assert!(e.starts_with("datapath:"), "{e}");
}

#[test]
fn invalid_configurations_are_rejected_with_the_field_named() {
    type Mutation = fn(&mut HwConfig);
    let cases: &[(&str, Mutation)] = &[
        ("part.name", |c| c.part.name = " ".into()),
        ("part.dsp48e2", |c| c.part.dsp48e2 = 0),
        ("part.bram36", |c| c.part.bram36 = 0),
        ("clock_mhz", |c| c.clock_mhz = 0),
        ("clock_mhz", |c| c.clock_mhz = 5000),
        ("frame.width", |c| c.frame.width = 0),
        ("frame.height", |c| c.frame.height = 100_000),
        ("units.sqrt.ii", |c| c.units.sqrt.ii = 0),
        ("units.sphere.latency_cycles", |c| {
            c.units.sphere.latency_cycles = 0
        }),
        ("sphere_units", |c| c.sphere_units = 0),
        ("sorter_lanes", |c| c.sorter_lanes = 0),
        ("transform_units", |c| c.transform_units = 0),
        ("reciprocal_units", |c| c.reciprocal_units = 0),
        ("walker_root_units", |c| c.walker_root_units = 0),
        ("walker_pool.walkers", |c| c.walker_pool.walkers = 0),
        ("walker_pool.contexts_per_walker", |c| {
            c.walker_pool.contexts_per_walker = 0
        }),
        ("walker_pool.step_cycles", |c| c.walker_pool.step_cycles = 0),
        ("walker_pool.step_latency_cycles", |c| {
            c.walker_pool.step_latency_cycles = 0
        }),
        ("walker_pool.stack_depth", |c| c.walker_pool.stack_depth = 0),
        // More request ports than contexts could never be used (0 is unlimited, 16 the most).
        ("walker_pool.read_ports = 17", |c| {
            c.walker_pool.read_ports = 17
        }),
        // The pool's registers are 0 or 1 cycles (issue 29).
        ("walker_pool.response_register_cycles = 2", |c| {
            c.walker_pool.response_register_cycles = 2
        }),
        ("walker_pool.request_register_cycles = 2", |c| {
            c.walker_pool.request_register_cycles = 2
        }),
        ("fifos.root_to_dispatch", |c| c.fifos.root_to_dispatch = 0),
        ("fifos.raygen_to_sphere", |c| {
            c.fifos.raygen_to_sphere = 1 << 20
        }),
        // 256 KiB is not a whole number of sets of 3 × 64 bytes.
        ("node_memory.cache.size_bytes", |c| {
            c.node_memory.cache.ways = 3
        }),
        ("node_memory.cache.ways", |c| c.node_memory.cache.ways = 0),
        ("node_memory.cache.line_bytes", |c| {
            c.node_memory.cache.line_bytes = 48
        }),
        ("node_memory.dram.latency", |c| {
            c.node_memory.dram.latency = 0
        }),
        ("node_memory.dram.bytes_per_cycle", |c| {
            c.node_memory.dram.bytes_per_cycle = 0
        }),
        ("node_memory.dram.mshrs", |c| c.node_memory.dram.mshrs = 0),
        ("node_memory.onchip.banks", |c| {
            c.node_memory.onchip.banks = 0
        }),
        ("node_memory.onchip.ports_per_bank", |c| {
            c.node_memory.onchip.ports_per_bank = 3
        }),
        ("node_memory.onchip.levels", |c| {
            c.node_memory.onchip.levels = 30
        }),
        ("hit_buffer.read_ports", |c| c.hit_buffer.read_ports = 0),
        ("hit_buffer.write_ports", |c| c.hit_buffer.write_ports = 0),
        ("hit_buffer.read_ports = 2", |c| c.hit_buffer.read_ports = 2),
        ("hit_buffer.read_latency_cycles", |c| {
            c.hit_buffer.read_latency_cycles = 0
        }),
    ];
    let dp = DatapathConfig::default();
    for (field, mutate) in cases {
        let mut cfg = HwConfig::default();
        mutate(&mut cfg);
        let e = cfg.validate().expect_err(field);
        assert!(e.starts_with(field), "expected {field}: {e}");
        // Nothing downstream panics on it either.
        let r = cfg.resources(&dp).expect_err(field);
        assert_eq!(r, e);
    }
    // Unlimited and one port per context are valid.
    for ports in [0, 8] {
        let mut cfg = HwConfig::default();
        cfg.walker_pool.read_ports = ports;
        cfg.validate()
            .unwrap_or_else(|e| panic!("read_ports {ports}: {e}"));
    }
    // The check stage reads one pixel per cycle wherever the buffer is: a second read port
    // would never be used, so it is refused off chip too.
    let mut cfg = HwConfig::default();
    cfg.hit_buffer.placement = Placement::External;
    cfg.hit_buffer.read_ports = 2;
    let e = cfg.validate().expect_err("two read ports off chip");
    assert!(e.starts_with("hit_buffer.read_ports = 2"), "{e}");
}

#[test]
fn zu9eg_needs_the_per_pixel_tables_off_chip() {
    let dp = DatapathConfig::default();
    let mut cfg = HwConfig {
        part: Part::xczu9eg(),
        ..HwConfig::default()
    };
    cfg.validate().unwrap();
    let r = cfg.resources(&dp).unwrap();
    println!("{r}");
    assert!(!r.fits());
    let over = r.over_budget();
    // The per-pixel tables' UltraRAM; the block RAM fits, just (879 of 912 BRAM36 with the
    // stacks as the RTL builds them, 320).
    assert_eq!(over.len(), 1, "{over:?}");
    assert!(
        over[0].starts_with("URAM288: 736 used, 0 available"),
        "{over:?}"
    );
    assert_eq!(r.used.bram36, 879);
    // In block RAM the hit buffer alone is 1,920 BRAM36, more than the part's 912.
    cfg.hit_buffer.placement = Placement::Bram;
    cfg.direction_table = Placement::External;
    cfg.node_memory.cache.size_bytes = 0;
    let r = cfg.resources(&dp).unwrap();
    assert_eq!(item(&r, "hit_buffer"), (2, 0, 1920, 0));
    // With the stacks (320), the on-chip node store (512) and the deep FIFO (39), no cache
    // tags.
    assert_eq!(
        (r.used.dsp48e2, r.used.bram36, r.used.uram288),
        (569, 2791, 0)
    );
    assert!(
        r.over_budget()[0].starts_with("BRAM36"),
        "{:?}",
        r.over_budget()
    );
    // Both tables in DRAM and no UltraRAM cache: it fits with the default's 32 walkers (320
    // BRAM36 of stacks); 48 walkers' stacks (480) take the block RAM over (1,031).
    cfg.hit_buffer.placement = Placement::External;
    let r = cfg.resources(&dp).unwrap();
    println!("{r}");
    assert!(r.fits(), "{:?}", r.over_budget());
    assert_eq!(
        (r.used.dsp48e2, r.used.bram36, r.used.uram288),
        (569, 871, 0)
    );
    cfg.walker_pool.walkers = 48;
    let r = cfg.resources(&dp).unwrap();
    assert_eq!(r.used.bram36, 1031);
    assert!(!r.fits());
}

#[test]
fn exact_pop_stacks_fit_one_bram_per_walker() {
    let dp = DatapathConfig::default();
    let mut cfg = HwConfig::default();
    // The RTL's frame: 9 × 63 t bits + 32 + 32 + 4 + 5 (level) + 60 (coordinates).
    assert_eq!(cfg.stack_frame_bits(&dp), 700);
    cfg.walker_pool.stack = StackStorage::ExactPop;
    assert_eq!(cfg.stack_frame_bits(&dp), 71);
    let r = cfg.resources(&dp).unwrap();
    // 8 contexts × 20 frames = 160 entries of 71 bits: one BRAM36 (512 × 72) a walker.
    assert_eq!(item(&r, "walker_stacks"), (32, 0, 32, 0));
    assert_eq!(
        (r.used.dsp48e2, r.used.bram36, r.used.uram288),
        (569, 591, 736)
    );
    assert!(r.fits());
}

#[test]
fn serde_rejects_unknown_fields_and_fills_missing_ones() {
    // A format-free check of the serde attributes (the RON files go through the same derive):
    // maps of field name → value, deserialised by serde's own value deserializer.
    let map = |kv: Vec<(&'static str, u32)>| MapDeserializer::<_, ValueError>::new(kv.into_iter());
    let w = WalkerPool::deserialize(map(vec![("walkers", 32)])).unwrap();
    assert_eq!(
        w,
        WalkerPool {
            walkers: 32,
            ..WalkerPool::default()
        }
    );
    let e = WalkerPool::deserialize(map(vec![("walker", 32)])).unwrap_err();
    assert!(e.to_string().contains("unknown field `walker`"), "{e}");
    let e = HwConfig::deserialize(map(vec![("clock_mhz", 250), ("walkers", 4)])).unwrap_err();
    assert!(e.to_string().contains("unknown field `walkers`"), "{e}");
    let c = HwConfig::deserialize(map(vec![("clock_mhz", 250)])).unwrap();
    assert_eq!(
        c,
        HwConfig {
            clock_mhz: 250,
            ..HwConfig::default()
        }
    );
    let e = UnitTimings::deserialize(map(vec![("sqrtt", 1)])).unwrap_err();
    assert!(e.to_string().contains("unknown field `sqrtt`"), "{e}");
}

#[test]
fn odd_datapaths_do_not_panic() {
    let mut dp = DatapathConfig::default();
    dp.sphere.pos.width = 0;
    dp.sphere.tca.width = 255;
    dp.walker.pos.width = 0;
    dp.sorter.n = 0;
    let cfg = HwConfig::for_datapath(&dp);
    assert!(cfg.validate().is_err()); // sorter_lanes 0
    let e = HwConfig::default().resources(&dp).unwrap_err();
    assert!(e.starts_with("datapath:"), "{e}");
}

#[test]
fn ron_round_trip() {
    let pretty = ron::ser::PrettyConfig::new().struct_names(false);
    let mut other = HwConfig {
        part: Part::xczu9eg(),
        ..HwConfig::default()
    };
    other.hit_buffer.placement = Placement::External;
    other.direction_table = Placement::Bram;
    other.walker_pool.stack = StackStorage::ExactPop;
    other.node_memory.cache.size_bytes = 0;
    for cfg in [HwConfig::default(), other] {
        let text = ron::ser::to_string_pretty(&cfg, pretty.clone()).unwrap();
        let back: HwConfig = ron::from_str(&text).unwrap();
        assert_eq!(back, cfg, "{text}");
    }
    // A file names only what it changes; the rest is the default.
    let partial: HwConfig = ron::from_str(
        "(clock_mhz: 250, walker_pool: (walkers: 32), hit_buffer: (placement: External))",
    )
    .unwrap();
    let mut want = HwConfig {
        clock_mhz: 250,
        ..HwConfig::default()
    };
    want.walker_pool.walkers = 32;
    want.hit_buffer.placement = Placement::External;
    assert_eq!(partial, want);
    // Unknown fields and variants are errors that name them.
    for (text, name) in [
        ("(walker_pool: (walker: 32))", "`walker`"),
        ("(clock: 300)", "`clock`"),
        ("(hit_buffer: (placement: Dram))", "`Dram`"),
        ("(node_memory: (cache: (size: 1)))", "`size`"),
    ] {
        let e = ron::from_str::<HwConfig>(text).unwrap_err().to_string();
        assert!(e.contains(name), "{text}: {e}");
    }
}

/// The elaboration knobs: a transform without products costs no DSP48E2 and may be as short
/// as its subtract and round, but no shorter; with products the datapath's stage count holds.
/// An absent hit buffer costs no memory and no read cycles; the other items do not move.
#[test]
fn transform_without_products_and_absent_hit_buffer() {
    let dp = DatapathConfig::default();
    let full = default_report();
    let mut cfg = HwConfig {
        transform_products: false,
        ..HwConfig::default()
    };
    cfg.units.transform.latency_cycles = transform::LATENCY_WITHOUT_PRODUCTS;
    cfg.validate_for(&dp)
        .expect("2 stages suffice without products");
    let r = cfg.resources(&dp).unwrap();
    assert_eq!(item(&r, "transform").1, 0);
    assert_eq!(
        full.used.dsp48e2 - r.used.dsp48e2,
        item(&full, "transform").1
    );
    // Two transform units of 72 each (two walk-issue lanes).
    assert_eq!(item(&full, "transform").1, 144);
    cfg.units.transform.latency_cycles = transform::LATENCY_WITHOUT_PRODUCTS - 1;
    let e = cfg.validate_for(&dp).unwrap_err();
    assert!(e.contains("units.transform.latency_cycles"), "{e}");
    cfg.transform_products = true;
    cfg.units.transform.latency_cycles = transform::LATENCY_WITHOUT_PRODUCTS;
    assert!(cfg.validate_for(&dp).is_err(), "products need their stages");

    let mut cfg = HwConfig::default();
    assert_eq!(cfg.hit_buffer_read_cycles(), 4);
    cfg.hit_buffer.placement = Placement::External;
    assert_eq!(cfg.hit_buffer_read_cycles(), cfg.node_memory.dram.latency);
    cfg.hit_buffer.present = false;
    assert_eq!(cfg.hit_buffer_read_cycles(), 0);
    cfg.hit_buffer.placement = Placement::Uram;
    let r = cfg.resources(&dp).unwrap();
    assert_eq!(item(&r, "hit_buffer"), (0, 0, 0, 0));
    assert_eq!(item(&full, "hit_buffer").3, 240);
    assert_eq!(full.used.uram288 - r.used.uram288, 240);
    assert_eq!(r.used.dsp48e2, full.used.dsp48e2);
}
