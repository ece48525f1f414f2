//! The DRAMsim3 backend of the node memory's DRAM (docs/cycle-model.md, DRAM): isolated reads
//! against latencies computed by hand from the device's timing table, a row-buffer hit against
//! a row conflict, determinism of a seeded random stream, the device counters, and the
//! refusals of bad configurations.
//!
//! The hand values use the numbers of `rtl_model/dram_configs/DDR4_8Gb_x16_*.ini` (tRCD, CL,
//! tRP, BL) and DRAMsim3's own clock to move a transaction into its command queue; nothing
//! here calls the model's clock conversion.

mod common;
mod memory_common;
use common::Rng;
use memory_common::{config, seed};
use rtl_model::cycle::memory::{
    Completion, DramBackend, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, Source,
};

/// No cache (every off-chip read is a fill), 64-byte lines, 8 MSHRs, DRAMsim3 with `device`.
fn ds3(device: &str, channels: u32, controller_latency: u32) -> NodeMemoryConfig {
    let mut c = config(3, 1, 2, 0, 1, 64, 4, 1, 60, 64, 8);
    // DRAMsim3 refuses the built-in bus's fields set away from their defaults (it has its own
    // bus): the default `bytes_per_cycle`.
    c.dram.bytes_per_cycle = NodeMemoryConfig::default().dram.bytes_per_cycle;
    c.dram.backend = DramBackend::DramSim3 {
        config: device.to_string(),
        channels,
        controller_latency,
    };
    c
}

fn memory(cfg: NodeMemoryConfig, clock_mhz: u32) -> NodeMemory {
    let layout = MemoryLayout::with_onchip_ranges(1 << 22, 1 << 16, vec![]).unwrap();
    NodeMemory::with_clock(cfg, layout, clock_mhz).unwrap()
}

/// Reads made one at a time, each drained before the next: their completions.
fn reads(mem: &mut NodeMemory, at: &[(u64, u32)]) -> Vec<Completion> {
    at.iter()
        .map(|&(cycle, word)| {
            mem.request(cycle, word, FetchKind::Node, 0).unwrap();
            let done = mem.drain();
            assert_eq!(done.len(), 1);
            done[0]
        })
        .collect()
}

// DDR4-2400 (DDR4_8Gb_x16_2400.ini): tRCD = CL = tRP = 17, BL8 = 4 clocks of data, 1200 MHz:
// 4 DRAM clocks per 300 MHz cycle. DRAMsim3 issues the first command one clock after the
// transaction arrives. Mapping rochrababgco, 64-byte bursts: 7 column bits, then bank group
// (1), bank (2), rank (1), row, so bytes 128 KiB apart are the same bank, another row.
const TRCD: u64 = 17;
const CL: u64 = 17;
const TRP: u64 = 17;
const BURST: u64 = 4;
const QUEUE: u64 = 1;
const CTRL: u64 = 30;

#[test]
fn an_isolated_read_takes_trcd_cl_burst_and_the_controller_latency() {
    let mut mem = memory(ds3("DDR4_8Gb_x16_2400", 1, CTRL as u32), 300);
    let c = reads(&mut mem, &[(10, 5000)])[0];
    // Issued in cycle 10, it enters DRAMsim3 before the first DRAM clock of cycle 11:
    // clock 11 · 4 = 44. Its bank is closed: ACT at 45, READ at 45 + tRCD, data done at
    // READ + CL + burst = clock 83, which is in the pipeline's domain at ⌈83 / 4⌉ = 21.
    let dram_done = 11 * 4 + QUEUE + TRCD + CL + BURST;
    assert_eq!(dram_done, 83);
    assert_eq!(c.source, Source::Miss);
    assert_eq!(c.cycle_served, 10);
    assert_eq!(c.cycle_done, dram_done.div_ceil(4) + CTRL);
    assert_eq!(c.cycle_done, 51);
}

#[test]
fn the_clock_ratio_is_exact_when_it_is_not_an_integer() {
    // DDR4-2133: 1066.5 MHz against 300 MHz, 3.555 DRAM clocks per cycle; tRCD = CL = 16.
    let mut mem = memory(ds3("DDR4_8Gb_x16_2133", 1, 7), 300);
    let c = reads(&mut mem, &[(10, 5000)])[0];
    // First DRAM clock starting at or after cycle 11: ⌈11 · 1066.5 / 300⌉ = ⌈39.105⌉ = 40.
    let dram_done: u64 = 40 + 1 + 16 + 16 + 4;
    // In the pipeline's domain at ⌈77 · 300 / 1066.5⌉ = ⌈21.66⌉ = 22, then 7 cycles.
    assert_eq!(c.cycle_done, 22 + 7, "DRAM clock {dram_done}");
    // The same read at 250 MHz: ⌈11 · 1066.5 / 250⌉ = ⌈46.93⌉ = 47, done at clock 84,
    // ⌈84 · 250 / 1066.5⌉ = ⌈19.69⌉ = 20.
    let mut slow = memory(ds3("DDR4_8Gb_x16_2133", 1, 7), 250);
    assert_eq!(reads(&mut slow, &[(10, 5000)])[0].cycle_done, 20 + 7);
}

#[test]
fn a_row_hit_completes_before_a_row_conflict_and_both_are_counted() {
    // Word 5000 is byte 19 968 (bank 1, row 0); word 5016 the next burst of that row;
    // word 5000 + 32 768 is 128 KiB further: the same bank, row 1.
    let (same_row, other_row) = (5016, 5000 + (1 << 15));
    let mut hit = memory(ds3("DDR4_8Gb_x16_2400", 1, CTRL as u32), 300);
    let mut conflict = memory(ds3("DDR4_8Gb_x16_2400", 1, CTRL as u32), 300);
    // Each opens row 0 at cycle 10, reads again at cycle 200, and once more at 17 000 so
    // that DRAMsim3's first statistics epoch (65 536 clocks = 16 384 cycles) ends.
    let h = reads(&mut hit, &[(10, 5000), (200, same_row), (17_000, 9)]);
    let c = reads(&mut conflict, &[(10, 5000), (200, other_row), (17_000, 9)]);
    assert_eq!(h[0].cycle_done, 51);
    assert_eq!(c[0].cycle_done, 51);
    // Issued in cycle 200, they arrive at clock 201 · 4 = 804. Hit: READ at once; conflict:
    // PRE, then ACT after tRP, READ after tRCD.
    let hit_done = (201 * 4 + QUEUE + CL + BURST).div_ceil(4) + CTRL;
    let conflict_done = (201 * 4 + QUEUE + TRP + TRCD + CL + BURST).div_ceil(4) + CTRL;
    assert_eq!((hit_done, conflict_done), (237, 245));
    assert_eq!(h[1].cycle_done, hit_done);
    assert_eq!(c[1].cycle_done, conflict_done);
    assert!(h[1].cycle_done < c[1].cycle_done);
    let (hs, cs) = (
        hit.stats().dram_device.unwrap(),
        conflict.stats().dram_device.unwrap(),
    );
    assert_eq!(hs.device, "DDR4_8Gb_x16_2400");
    assert_eq!((hs.fills, hs.transactions, hs.bytes), (3, 3, 3 * 64));
    // The first epoch holds the first two reads.
    assert_eq!(hs.epochs, 1);
    assert_eq!((hs.read_cmds, hs.row_hits, hs.activates), (2, 1, 1));
    assert_eq!(hs.row_conflicts, 0);
    assert_eq!((cs.read_cmds, cs.row_hits, cs.activates), (2, 0, 2));
    assert_eq!(cs.row_conflicts, 1);
    assert!((hs.row_hit_rate() - 0.5).abs() < 1e-12);
    // A new window starts empty.
    hit.reset_stats();
    assert_eq!(hit.stats().dram_device.unwrap().fills, 0);
}

#[test]
fn the_peak_follows_the_device_channels_and_clock() {
    let peak = |d: &str, ch, mhz| ds3(d, ch, 1).dram.peak_bytes_per_cycle(mhz);
    // 2 × 16 bytes per clock × 1200 MHz / 300 MHz.
    assert_eq!(peak("DDR4_8Gb_x16_2400", 2, 300), 128);
    // 16 × 1066.5 / 300 = 56.88.
    assert_eq!(peak("DDR4_8Gb_x16_2133", 1, 300), 57);
    let mem = memory(ds3("DDR4_8Gb_x16_2400", 4, 1), 300);
    assert_eq!(mem.stats().dram_peak_bytes_per_cycle, 256);
}

/// A seeded stream of reads: every 0–3 cycles, up to four reads from four requesters, to
/// addresses in a few hot rows and the rest of a 4 MiB image.
fn random_run(seed: u64, cache_bytes: u64) -> (Vec<Completion>, String) {
    let mut cfg = ds3("DDR4_8Gb_x16_2400", 2, 20);
    cfg.cache.size_bytes = cache_bytes;
    cfg.cache.ways = 4;
    cfg.dram.mshrs = 16;
    let mut mem = memory(cfg, 300);
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    let mut cycle = 0;
    for _ in 0..1500 {
        cycle += rng.below(4);
        mem.tick_into(cycle, &mut out);
        for req in 0..=rng.below(4) {
            let word = if rng.below(2) == 0 {
                rng.below(4096) as u32
            } else {
                rng.below(1 << 20) as u32
            };
            let kind = if rng.below(8) == 0 {
                FetchKind::Attr
            } else {
                FetchKind::Node
            };
            let addr = if kind == FetchKind::Attr {
                word % (1 << 16)
            } else {
                word
            };
            mem.request(cycle, addr, kind, req as u32).unwrap();
        }
    }
    out.extend(mem.drain());
    let stats = serde_json::to_string(&mem.stats()).unwrap();
    (out, stats)
}

#[test]
fn the_same_reads_give_the_same_cycles_and_counters() {
    let s = seed("the_same_reads_give_the_same_cycles_and_counters", 0xd5a3);
    let (a, sa) = random_run(s, 16 * 1024);
    let (b, sb) = random_run(s, 16 * 1024);
    assert_eq!(a.len(), b.len());
    assert_eq!(a, b);
    assert_eq!(sa, sb);
    // Every read completes once, no earlier than the controller latency after its lookup
    // plus DRAMsim3's shortest read (1 + CL + burst clocks, 22 / 4 cycles), unless it hit.
    let mut ids: Vec<u64> = a.iter().map(|c| c.id.0).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), a.len());
    for c in &a {
        if c.source == Source::Miss {
            assert!(
                c.cycle_done >= c.cycle_served + 20 + 22 / 4,
                "{c:?} completes too early"
            );
        }
    }
    assert!(a.iter().any(|c| c.source == Source::Merged));
    assert!(sa.contains("\"row_hits\""));
}

#[test]
fn bad_dramsim3_configurations_are_refused_naming_the_field() {
    let base = ds3("DDR4_8Gb_x16_2400", 2, 30);
    assert_eq!(base.validate(), Ok(()));
    type Edit = fn(&mut NodeMemoryConfig);
    let set = |c: &mut NodeMemoryConfig, name: &str, ch: u32, lat: u32| {
        c.dram.backend = DramBackend::DramSim3 {
            config: name.to_string(),
            channels: ch,
            controller_latency: lat,
        }
    };
    let cases: [(Edit, &str); 6] = [
        (
            |c| {
                c.dram.backend = DramBackend::DramSim3 {
                    config: "DDR4_8Gb_x16_2401".into(),
                    channels: 2,
                    controller_latency: 30,
                }
            },
            "dram.backend.config = \"DDR4_8Gb_x16_2401\" is not a bundled DRAMsim3 device (one of DDR4_8Gb_x16_1866, ",
        ),
        (
            |c| {
                c.dram.backend = DramBackend::DramSim3 {
                    config: "DDR4_8Gb_x16_2400".into(),
                    channels: 3,
                    controller_latency: 30,
                }
            },
            "dram.backend.channels = 3 must be 1, 2, 4 or 8",
        ),
        (
            |c| {
                c.dram.backend = DramBackend::DramSim3 {
                    config: "DDR4_8Gb_x16_2400".into(),
                    channels: 0,
                    controller_latency: 30,
                }
            },
            "dram.backend.channels = 0 must be 1, 2, 4 or 8",
        ),
        (
            |c| {
                c.dram.backend = DramBackend::DramSim3 {
                    config: "DDR4_8Gb_x16_2400".into(),
                    channels: 2,
                    controller_latency: 0,
                }
            },
            "dram.backend.controller_latency = 0 cycles is out of range",
        ),
        (
            |c| c.dram.latency = 61,
            "dram.latency = 61 applies to the BuiltIn DRAM backend only; with DramSim3 leave it at its default 60",
        ),
        (
            |c| c.dram.bytes_per_cycle = 64,
            "dram.bytes_per_cycle = 64 applies to the BuiltIn DRAM backend only",
        ),
    ];
    for (edit, want) in cases {
        let mut c = base.clone();
        edit(&mut c);
        let err = c.validate().expect_err(want);
        assert!(err.to_string().starts_with(want), "{err} ≠ {want}");
        // The model is never built from it either.
        let layout = MemoryLayout::with_onchip_ranges(1 << 10, 1 << 10, vec![]).unwrap();
        assert!(NodeMemory::new(c, layout).is_err());
    }
    let mut ok = base.clone();
    set(&mut ok, "DDR4_4Gb_x8_2400", 8, 1);
    assert_eq!(ok.validate(), Ok(()));
}

#[test]
fn the_hardware_file_names_the_backend_as_the_issue_writes_it() {
    let text = r#"(dram: (mshrs: 16, backend: DramSim3(config: "DDR4_8Gb_x16_2400", channels: 2, controller_latency: 30)))"#;
    let c: NodeMemoryConfig = ron::from_str(text).unwrap();
    assert_eq!(
        c.dram.backend,
        DramBackend::DramSim3 {
            config: "DDR4_8Gb_x16_2400".into(),
            channels: 2,
            controller_latency: 30
        }
    );
    assert_eq!(c.dram.mshrs, 16);
    let back: NodeMemoryConfig = ron::from_str(&ron::to_string(&c).unwrap()).unwrap();
    assert_eq!(back, c);
    // A misspelt backend or a missing field is a parse error naming it.
    let typo = ron::from_str::<NodeMemoryConfig>(r#"(dram: (backend: DramSim(config: "x")))"#);
    assert!(typo.unwrap_err().to_string().contains("DramSim"));
    let missing = ron::from_str::<NodeMemoryConfig>(
        r#"(dram: (backend: DramSim3(config: "DDR4_8Gb_x16_2400", channels: 2)))"#,
    );
    assert!(missing
        .unwrap_err()
        .to_string()
        .contains("controller_latency"));
}
