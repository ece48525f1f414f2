//! Node-memory model (`rtl_model::cycle::memory`) under random load, and what it refuses.
//!
//! - Random stress over random configurations: every request completes exactly once,
//!   `tick_into` returns each completion in its cycle, port and MSHR limits hold when
//!   recomputed from the completions, service order is (cycle, requester, id), statistics add
//!   up.
//! - Determinism: identical runs give identical completions and statistics, and the order in
//!   which one cycle's requests are made does not change anything.
//! - Errors and configuration: bad requests are refused and counted, configurations are
//!   validated field by field, configuration files reject unknown fields.
//!
//! What the memories hold is in `cycle_memory_contents.rs`, timing in
//! `cycle_memory_timing.rs`. Run with `-- --nocapture` to see seeds; `SVO_TEST_SEED` replays.

mod common;
mod memory_common;
use common::Rng;
use memory_common::{config, max_in_flight, seed};
use std::collections::{BTreeMap, HashMap, HashSet};

use rtl_model::cycle::memory::{
    Completion, ConfigError, DramConfig, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig,
    RequestError, Source,
};

// ---------------------------------------------------------------------------------------
// Random stress and determinism.

struct Issued {
    cycle: u64,
    addr: u32,
    kind: FetchKind,
    requester: u32,
}

fn random_config(rng: &mut Rng) -> NodeMemoryConfig {
    let line = 8u32 << rng.below(5); // 8 ..= 128
    let ways = 1u32 << rng.below(4);
    let sets = 1u64 << rng.below(6);
    let size = if rng.below(8) == 0 {
        0
    } else {
        sets * u64::from(ways) * u64::from(line)
    };
    let mut cfg = config(
        1 + rng.below(4) as u32,
        1 + rng.below(4) as u32,
        1 + rng.below(2) as u32,
        size,
        ways,
        line,
        1 + rng.below(5) as u32,
        1 + rng.below(3) as u32,
        1 + rng.below(80) as u32,
        1 + rng.below(80) as u32,
        1 + rng.below(12) as u32,
    );
    cfg.cache.attr_cached = rng.below(3) != 0;
    // Half the configurations use issue 28's mechanisms: combining at the on-chip banks, cache
    // banks (a power of two up to the sets), a miss queue.
    if rng.below(2) == 0 {
        cfg.onchip.combine = rng.below(2) == 0;
        let max_banks = if size == 0 { 8 } else { sets.min(8) };
        cfg.cache.banks = 1 << rng.below(u64::from(max_banks.trailing_zeros()) + 1);
        cfg.cache.miss_queue = rng.below(6) as u32;
    }
    cfg
}

fn random_requests(rng: &mut Rng, n: usize, node_words: u64, attrs: u64) -> Vec<Issued> {
    let mut v = Vec::with_capacity(n);
    let mut cycle = 0u64;
    let hot: Vec<u32> = (0..32).map(|_| rng.below(node_words) as u32).collect();
    for _ in 0..n {
        if rng.below(3) == 0 {
            let span = if rng.below(20) == 0 { 200 } else { 4 };
            cycle += rng.below(span);
        }
        let kind = match rng.below(6) {
            0 => FetchKind::Far,
            1 => FetchKind::Attr,
            _ => FetchKind::Node,
        };
        let addr = if kind == FetchKind::Attr {
            rng.below(attrs) as u32
        } else if rng.below(2) == 0 {
            hot[rng.below(32) as usize] + rng.below(8) as u32
        } else {
            rng.below(node_words) as u32
        };
        v.push(Issued {
            cycle,
            addr: addr.min(node_words as u32 - 1),
            kind,
            requester: rng.below(16) as u32,
        });
    }
    v
}

/// Runs the requests, calling `tick_into` at random cycles (skipping many); checks that each
/// tick returns exactly the completions due by its cycle.
fn run_ticked(
    cfg: &NodeMemoryConfig,
    layout: &MemoryLayout,
    reqs: &[Issued],
    rng: &mut Rng,
) -> (Vec<Completion>, rtl_model::cycle::memory::NodeMemoryStats) {
    let mut mem = NodeMemory::new(cfg.clone(), layout.clone()).unwrap();
    let mut out = Vec::new();
    let mut last_tick = 0u64;
    let mut i = 0;
    while i < reqs.len() {
        let c = reqs[i].cycle;
        if c > last_tick && rng.below(2) == 0 {
            let t = last_tick + 1 + rng.below(c - last_tick);
            let mut due = Vec::new();
            mem.tick_into(t, &mut due);
            for d in due {
                // Due by t, and not due at an earlier tick (those returned it already).
                assert!(d.cycle_done <= t && d.cycle_done > last_tick);
                out.push(d);
            }
            last_tick = t;
        }
        let r = &reqs[i];
        mem.request(r.cycle, r.addr, r.kind, r.requester).unwrap();
        i += 1;
    }
    for d in mem.drain() {
        assert!(d.cycle_done > last_tick);
        out.push(d);
    }
    (out, mem.stats())
}

#[test]
fn random_stress_invariants() {
    let mut rng = Rng::new(seed("random_stress", 0x5eed_3e30_0003));
    let node_words = 1u64 << 14;
    let attrs = 1u64 << 10;
    for round in 0..60 {
        let cfg = random_config(&mut rng);
        cfg.validate().unwrap();
        // Random on-chip ranges.
        let mut ranges = Vec::new();
        let mut at = 0u32;
        while at < node_words as u32 - 64 && ranges.len() < 12 {
            let s = at + rng.below(2000) as u32;
            let e = s + 1 + rng.below(300) as u32;
            if u64::from(e) > node_words {
                break;
            }
            ranges.push((s, e));
            at = e;
        }
        let onchip_set: HashSet<u32> = ranges.iter().flat_map(|&(s, e)| s..e).collect();
        let layout = MemoryLayout::with_onchip_ranges(node_words, attrs, ranges).unwrap();
        let reqs = random_requests(&mut rng, 3000, node_words, attrs);
        let (done, s) = run_ticked(&cfg, &layout, &reqs, &mut rng);
        let what = format!("round {round} cfg {cfg:?}");

        // Every request completes exactly once; ids are 0..n in call order.
        let mut ids: Vec<u64> = done.iter().map(|c| c.id.0).collect();
        ids.sort();
        assert_eq!(ids, (0..reqs.len() as u64).collect::<Vec<_>>(), "{what}");
        let by_id: BTreeMap<u64, &Completion> = done.iter().map(|c| (c.id.0, c)).collect();

        let line = u64::from(cfg.cache.line_bytes);
        let line_key = |c: &Completion| match c.kind {
            FetchKind::Attr => (1u8, 8 * u64::from(c.addr) / line),
            _ => (0u8, 4 * u64::from(c.addr) / line),
        };
        let beats = line.div_ceil(u64::from(cfg.dram.bytes_per_cycle));
        let mut ports_used: HashSet<(u32, u64, u32)> = HashSet::new();
        let cache_bank = |c: &Completion| line_key(c).1 % u64::from(cfg.cache.banks);
        let mut per_cache_cycle: HashMap<(u64, u64), u32> = HashMap::new();
        let mut fills: HashMap<(u8, u64), Vec<&Completion>> = HashMap::new();
        for (i, r) in reqs.iter().enumerate() {
            let c = by_id[&(i as u64)];
            assert_eq!(
                (c.addr, c.kind, c.requester, c.cycle_requested),
                (r.addr, r.kind, r.requester, r.cycle)
            );
            assert!(
                c.cycle_served >= c.cycle_requested && c.cycle_done > c.cycle_served,
                "{what}"
            );
            let onchip = r.kind != FetchKind::Attr && onchip_set.contains(&r.addr);
            match c.source {
                Source::OnChip { bank } => {
                    assert!(onchip, "{what}");
                    assert_eq!(bank, r.addr % cfg.onchip.banks);
                    assert_eq!(c.cycle_done - c.cycle_served, u64::from(cfg.onchip.latency));
                    // Combined reads of one word share a port read.
                    ports_used.insert((bank, c.cycle_served, c.addr));
                }
                src => {
                    assert!(!onchip, "{what}");
                    *per_cache_cycle
                        .entry((cache_bank(c), c.cycle_served))
                        .or_default() += 1;
                    match src {
                        Source::CacheHit => {
                            assert!(cfg.cache.size_bytes > 0);
                            assert!(r.kind != FetchKind::Attr || cfg.cache.attr_cached);
                            assert_eq!(
                                c.cycle_done - c.cycle_served,
                                u64::from(cfg.cache.hit_latency)
                            );
                        }
                        Source::Miss => {
                            assert!(
                                c.cycle_done
                                    >= c.cycle_served + u64::from(cfg.dram.latency) + beats
                            );
                            fills.entry(line_key(c)).or_default().push(c);
                        }
                        _ => {}
                    }
                }
            }
        }
        let bank_ports = cfg.onchip.ports_per_bank;
        let mut per_bank: HashMap<(u32, u64), u32> = HashMap::new();
        for &(bank, cycle, _) in &ports_used {
            *per_bank.entry((bank, cycle)).or_default() += 1;
        }
        assert!(per_bank.values().all(|&n| n <= bank_ports), "{what}");
        if !cfg.onchip.combine {
            assert_eq!(s.onchip_combined, 0, "{what}");
        }
        assert!(
            per_cache_cycle.values().all(|&n| n <= cfg.cache.ports),
            "{what}"
        );
        // A read from the miss queue holds its MSHR from a later cycle than its lookup, so the
        // fills' [served, done) intervals bound the MSHRs in use only without the queue.
        if s.miss_queued == 0 {
            assert!(max_in_flight(&done) <= cfg.dram.mshrs as usize, "{what}");
        }
        // A merged read joined a fill of its line that was in flight when it was served (or,
        // from the miss queue, when it left the queue: after its lookup).
        for c in done.iter().filter(|c| c.source == Source::Merged) {
            let queued = s.miss_queued > 0;
            let f = fills[&line_key(c)]
                .iter()
                .find(|f| {
                    (queued || f.cycle_served <= c.cycle_served)
                        && c.cycle_served < f.cycle_done
                        && f.cycle_done == c.cycle_done
                })
                .unwrap_or_else(|| panic!("{what}: merged read {c:?} without its fill"));
            assert_eq!(f.cycle_done, c.cycle_done);
        }
        // Service order: within one queue, (cycle, requester, id) order is never overtaken.
        let mut queues: BTreeMap<(bool, u32), Vec<&Completion>> = BTreeMap::new();
        for c in &done {
            let key = match c.source {
                Source::OnChip { bank } => (true, bank),
                _ => (false, cache_bank(c) as u32),
            };
            queues.entry(key).or_default().push(c);
        }
        for (key, q) in queues.iter_mut() {
            q.sort_by_key(|c| (c.cycle_requested, c.requester, c.id));
            if key.0 && cfg.onchip.combine {
                // A combined read joins the entry of its word wherever it is in the queue;
                // the entries themselves (each word's first read) keep the order.
                let mut seen = HashSet::new();
                q.retain(|c| seen.insert((c.cycle_served, c.addr)));
            }
            assert!(
                q.windows(2).all(|w| w[0].cycle_served <= w[1].cycle_served),
                "{what}"
            );
        }
        // Statistics add up.
        let n = reqs.len() as u64;
        assert_eq!(s.fetches.total(), n);
        assert_eq!(s.served, n);
        assert_eq!(
            s.cache_lookups,
            s.cache_hits + s.cache_misses + s.cache_merged
        );
        assert_eq!(s.onchip_reads + s.cache_lookups + s.uncached_reads, n);
        let misses = done.iter().filter(|c| c.source == Source::Miss).count() as u64;
        assert_eq!(s.dram_fills, misses);
        assert_eq!(s.dram_bytes, misses * line);
        assert!(s.dram_max_bytes_in_cycle <= u64::from(cfg.dram.bytes_per_cycle));
        assert!(s.mshr_max_in_use <= u64::from(cfg.dram.mshrs));
        let waited: u64 = done
            .iter()
            .map(|c| c.cycle_served - c.cycle_requested)
            .sum();
        assert_eq!(waited, s.port_wait + s.mshr_wait, "{what}");
        let lat: Vec<u64> = done
            .iter()
            .map(|c| c.cycle_done - c.cycle_requested)
            .collect();
        assert_eq!(s.latency_sum, lat.iter().sum::<u64>());
        assert_eq!(s.latency_max, *lat.iter().max().unwrap());
        let words: u64 = reqs.iter().map(|r| r.kind.words()).sum();
        assert_eq!((s.words, s.bytes), (words, 4 * words));
    }
}

#[test]
fn same_requests_give_same_completions() {
    let mut rng = Rng::new(seed("determinism", 0x5eed_3e30_0004));
    let node_words = 1u64 << 14;
    let attrs = 1u64 << 10;
    for _ in 0..10 {
        let cfg = random_config(&mut rng);
        let layout =
            MemoryLayout::with_onchip_ranges(node_words, attrs, vec![(0, 200), (5000, 5600)])
                .unwrap();
        let reqs = random_requests(&mut rng, 3000, node_words, attrs);
        let tick_seed = rng.next();
        let a = run_ticked(&cfg, &layout, &reqs, &mut Rng::new(tick_seed));
        let b = run_ticked(&cfg, &layout, &reqs, &mut Rng::new(tick_seed));
        assert_eq!(a, b);
        // Different tick points change nothing either (once sorted the same way).
        let mut c = run_ticked(&cfg, &layout, &reqs, &mut Rng::new(tick_seed ^ 1));
        let mut a0 = a.0.clone();
        a0.sort_by_key(|c| c.id);
        c.0.sort_by_key(|c| c.id);
        assert_eq!(a0, c.0);
        assert_eq!(a.1, c.1);

        // The order in which one cycle's requests are made does not matter: each requester
        // makes at most one request per cycle, made here in a shuffled order per cycle.
        let mut seen = HashSet::new();
        let unique: Vec<&Issued> = reqs
            .iter()
            .filter(|r| seen.insert((r.cycle, r.requester)))
            .collect();
        let outcome = |order: &[&Issued]| {
            let mut mem = NodeMemory::new(cfg.clone(), layout.clone()).unwrap();
            for r in order {
                mem.request(r.cycle, r.addr, r.kind, r.requester).unwrap();
            }
            let mut v: Vec<_> = mem
                .drain()
                .into_iter()
                .map(|c| {
                    (
                        c.cycle_requested,
                        c.requester,
                        c.cycle_served,
                        c.cycle_done,
                        c.source,
                    )
                })
                .collect();
            v.sort_by_key(|x| (x.0, x.1));
            (v, mem.stats())
        };
        let mut shuffled = unique.clone();
        let mut start = 0;
        while start < shuffled.len() {
            let mut end = start;
            while end < shuffled.len() && shuffled[end].cycle == shuffled[start].cycle {
                end += 1;
            }
            for i in (start + 1..end).rev() {
                let j = start + rng.below((i - start + 1) as u64) as usize;
                shuffled.swap(i, j);
            }
            start = end;
        }
        assert_eq!(outcome(&unique), outcome(&shuffled));
    }
}

// ---------------------------------------------------------------------------------------
// Errors and configuration.

#[test]
fn bad_requests_are_refused_and_counted() {
    let cfg = NodeMemoryConfig::default();
    let mut mem = NodeMemory::new(cfg, MemoryLayout::flat(100, 10).unwrap()).unwrap();
    assert!(matches!(
        mem.request(0, 100, FetchKind::Node, 0),
        Err(RequestError::OutOfRange { limit: 100, .. })
    ));
    assert!(matches!(
        mem.request(0, 10, FetchKind::Attr, 0),
        Err(RequestError::OutOfRange { limit: 10, .. })
    ));
    assert!(mem.request(0, u32::MAX, FetchKind::Far, 0).is_err());
    assert!(matches!(
        mem.request(1 << 63, 1, FetchKind::Node, 0),
        Err(RequestError::CycleTooLarge(_))
    ));
    mem.request(5, 1, FetchKind::Node, 0).unwrap();
    let mut due = Vec::new();
    mem.tick_into(3, &mut due);
    assert!(due.is_empty());
    assert!(matches!(
        mem.request(2, 1, FetchKind::Node, 0),
        Err(RequestError::InPast { cycle: 2, now: 3 })
    ));
    assert_eq!(mem.stats().out_of_range, 3);
    assert_eq!(mem.drain().len(), 1);
    assert!(mem.is_idle());
    // A huge tick after going idle is cheap and safe.
    mem.tick_into(u64::MAX, &mut due);
    assert!(due.is_empty());
    // Empty layouts refuse everything.
    let mut mem = NodeMemory::new(NodeMemoryConfig::default(), MemoryLayout::default()).unwrap();
    assert!(mem.request(0, 0, FetchKind::Node, 0).is_err());
}

#[test]
fn configurations_are_validated() {
    let d = NodeMemoryConfig::default();
    d.validate().unwrap();
    // The documented defaults (300 MHz, two DDR4-2400 channels' bandwidth; issue 28).
    assert_eq!(
        (
            d.onchip.levels,
            d.onchip.latency,
            d.onchip.banks,
            d.onchip.ports_per_bank
        ),
        (8, 3, 16, 2)
    );
    assert_eq!(
        (
            d.cache.size_bytes,
            d.cache.ways,
            d.cache.line_bytes,
            d.cache.hit_latency
        ),
        (256 * 1024, 4, 64, 4)
    );
    assert_eq!(
        (d.dram.latency, d.dram.bytes_per_cycle, d.dram.mshrs),
        (60, 128, 256)
    );
    assert_eq!(d.cache_sets(), 1024);
    let r = d.resources(37449);
    println!("default resources for 37449 on-chip words: {r:?}");
    // 16 banks of ⌈37449 / 16⌉ = 2341 words: 3 BRAM36 of 1024 words each.
    assert_eq!(r.onchip_bram36, 16 * 3);
    assert_eq!(r.cache_uram, 16);

    let bad: Vec<(NodeMemoryConfig, &str)> = vec![
        (
            {
                let mut c = d.clone();
                c.onchip.latency = 0;
                c
            },
            "onchip.latency",
        ),
        (
            {
                let mut c = d.clone();
                c.onchip.banks = 0;
                c
            },
            "onchip.banks",
        ),
        (
            {
                let mut c = d.clone();
                c.onchip.ports_per_bank = 0;
                c
            },
            "onchip.ports_per_bank",
        ),
        (
            {
                let mut c = d.clone();
                c.onchip.levels = 22;
                c
            },
            "levels",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.line_bytes = 48;
                c
            },
            "line_bytes",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.line_bytes = 4;
                c
            },
            "line_bytes",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.ways = 0;
                c
            },
            "cache.ways",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.ports = 0;
                c
            },
            "cache.ports",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.hit_latency = 0;
                c
            },
            "cache.hit_latency",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.size_bytes = 3 * 64 * 4;
                c
            },
            "power-of-two",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.size_bytes = 1000;
                c
            },
            "power-of-two",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.size_bytes = 1 << 40;
                c
            },
            "larger",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.banks = 3;
                c
            },
            "cache.banks = 3",
        ),
        (
            {
                // 1 KiB of 4 ways × 64 bytes is 4 sets: at most 4 banks.
                let mut c = d.clone();
                c.cache.size_bytes = 1024;
                c.cache.banks = 8;
                c
            },
            "cache.banks = 8 must be a power of two from 1 to 4",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.banks = 128;
                c
            },
            "cache.banks = 128",
        ),
        (
            {
                let mut c = d.clone();
                c.cache.miss_queue = 4097;
                c
            },
            "cache.miss_queue = 4097",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.latency = 0;
                c
            },
            "dram.latency",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.latency = u32::MAX;
                c
            },
            "dram.latency",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.bytes_per_cycle = 0;
                c
            },
            "dram.bytes_per_cycle",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.mshrs = 0;
                c
            },
            "dram.mshrs",
        ),
        (
            {
                let mut c = d.clone();
                c.dram.mshrs = 1 << 20;
                c
            },
            "dram.mshrs",
        ),
    ];
    for (c, field) in bad {
        let e = c.validate().unwrap_err();
        assert!(e.to_string().contains(field), "{e} should name {field}");
        assert_eq!(NodeMemory::new(c, MemoryLayout::default()).unwrap_err(), e);
    }
    // A disabled cache is valid, and three ways with a power-of-two set count too.
    let mut c = d.clone();
    c.cache.size_bytes = 0;
    c.validate().unwrap();
    c.cache.ways = 3;
    c.cache.size_bytes = 3 * 64 * 16;
    c.validate().unwrap();
    assert!(matches!(
        {
            let mut c = d.clone();
            c.cache.line_bytes = 3;
            c
        }
        .validate(),
        Err(ConfigError::LineBytes(3))
    ));

    // Layout errors.
    assert!(MemoryLayout::with_onchip_ranges(100, 0, vec![(5, 5)]).is_err());
    assert!(MemoryLayout::with_onchip_ranges(100, 0, vec![(50, 60), (55, 70)]).is_err());
    assert!(MemoryLayout::with_onchip_ranges(100, 0, vec![(90, 101)]).is_err());
    assert!(MemoryLayout::flat(1 << 33, 0).is_err());
}

#[test]
fn configuration_files_reject_unknown_fields() {
    use serde::de::value::{Error, MapDeserializer};
    use serde::Deserialize;
    let ok = DramConfig::deserialize(MapDeserializer::<_, Error>::new(
        vec![("latency", 90u32)].into_iter(),
    ))
    .unwrap();
    assert_eq!(
        ok,
        DramConfig {
            latency: 90,
            ..DramConfig::default()
        }
    );
    let typo = DramConfig::deserialize(MapDeserializer::<_, Error>::new(
        vec![("latency", 90u32), ("mshr", 8)].into_iter(),
    ));
    assert!(typo.unwrap_err().to_string().contains("mshr"));
}
