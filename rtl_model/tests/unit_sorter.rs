//! Sorter: networks checked exhaustively by the 0-1 principle, and the whole sorter (chunks,
//! merges, clamping, statistics) against `std`'s sort by (t, id) on seeded random and
//! adversarial inputs. Set `SORTER_SEED` to replay a failing run; the seed is printed.

use rtl_model::fixed::Format;
use rtl_model::units::sorter::{
    apply_network, comparator_count, depth, network, network_stages, pipe_cost, resources,
    sort_timing, SortKey, Sorter, SorterConfig, SorterStats,
};

/// `rtl_model`'s splitmix64 (`rtl_model::vectors::rng::Rng`, not a copy: it only picks test
/// inputs) with the draws this test needs.
struct Rng(rtl_model::vectors::rng::Rng);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(rtl_model::vectors::rng::Rng::new(seed))
    }
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// Uniform in lo..=hi.
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        let span = (hi as i128 - lo as i128 + 1) as u128;
        (lo as i128 + (u128::from(self.next()) % span) as i128) as i64
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn seed(test: &str) -> u64 {
    let s = std::env::var("SORTER_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0000_0000_0001);
    println!("{test}: SORTER_SEED={s}");
    s
}

fn std_sorted(keys: &[SortKey]) -> Vec<SortKey> {
    let mut v = keys.to_vec();
    v.sort(); // tuples: t first, then id
    v
}

/// The 0-1 principle: a comparator network sorts every input iff it sorts every 0/1 input.
fn sorts_all_zero_one(net: &[(usize, usize)], n: usize) -> bool {
    let mut keys = vec![(0i64, 0u16); n];
    for x in 0u32..(1 << n) {
        for (i, k) in keys.iter_mut().enumerate() {
            *k = (i64::from((x >> i) & 1), 0);
        }
        apply_network(net, &mut keys);
        if keys.windows(2).any(|w| w[0] > w[1]) {
            return false;
        }
    }
    true
}

#[test]
fn every_network_up_to_16_sorts_all_zero_one_inputs() {
    for n in 1..=16u8 {
        let net = network(n);
        assert!(
            sorts_all_zero_one(&net, usize::from(n)),
            "network for {n} lanes fails the 0-1 principle"
        );
    }
}

#[test]
fn network_shapes_are_hardware_layers() {
    for n in 0..=255u8 {
        let stages = network_stages(n);
        assert_eq!(depth(n), stages.len());
        assert_eq!(
            comparator_count(n),
            stages.iter().map(Vec::len).sum::<usize>()
        );
        for s in &stages {
            assert!(!s.is_empty(), "n = {n}: empty layer");
            let mut used = vec![false; usize::from(n)];
            for &(i, j) in s {
                assert!(i < j && j < usize::from(n), "n = {n}: bad pair ({i}, {j})");
                assert!(!used[i] && !used[j], "n = {n}: lane used twice in a layer");
                used[i] = true;
                used[j] = true;
            }
        }
        assert_eq!(network(n), stages.concat());
    }
}

#[test]
fn comparator_counts_and_depths() {
    // Fewest comparators known for 2, 4, 8, 16.
    for (n, c, d) in [(2u8, 1usize, 1usize), (4, 5, 3), (8, 19, 6), (16, 60, 10)] {
        assert_eq!((comparator_count(n), depth(n)), (c, d), "n = {n}");
    }
    // Batcher for 2^k: (k² − k + 4)·2^(k−2) − 1 comparators, depth k(k+1)/2.
    for k in 5..=7u32 {
        let n = 1u8 << k;
        let c = ((k * k - k + 4) << (k - 2)) as usize - 1;
        let d = (k * (k + 1) / 2) as usize;
        assert_eq!((comparator_count(n), depth(n)), (c, d), "Batcher n = {n}");
    }
    assert_eq!((comparator_count(0), depth(0)), (0, 0));
    assert_eq!((comparator_count(1), depth(1)), (0, 0));
    // Print the table the docs quote.
    for n in 2..=16u8 {
        println!(
            "n = {n:2}: {:3} comparators, depth {:2}",
            comparator_count(n),
            depth(n)
        );
    }
}

#[test]
fn wide_batcher_networks_sort_random_inputs() {
    let mut rng = Rng::new(seed("wide_batcher_networks_sort_random_inputs"));
    for n in (17..=255u8).step_by(7).chain([32, 64, 128, 255]) {
        let net = network(n);
        for _ in 0..40 {
            let mut keys: Vec<SortKey> = (0..usize::from(n))
                .map(|_| (rng.range(0, 3), rng.next() as u16))
                .collect();
            let want = std_sorted(&keys);
            apply_network(&net, &mut keys);
            assert_eq!(keys, want, "n = {n}");
        }
    }
}

#[test]
fn partially_filled_networks_sort() {
    // Fewer keys than lanes: the comparators on empty lanes are skipped, as +∞ padding.
    let mut rng = Rng::new(seed("partially_filled_networks_sort"));
    for n in 2..=16u8 {
        let net = network(n);
        for m in 0..=usize::from(n) {
            for _ in 0..50 {
                let mut keys: Vec<SortKey> = (0..m).map(|_| (rng.range(0, 4), 0)).collect();
                let want = std_sorted(&keys);
                apply_network(&net, &mut keys);
                assert_eq!(keys, want, "n = {n}, m = {m}");
            }
        }
    }
}

/// Input shapes, most of them adversarial on purpose.
#[derive(Clone, Copy, Debug)]
enum Shape {
    Uniform,
    ManyTies,
    AllEqual,
    Sorted,
    Reversed,
    Extremes,
}

const SHAPES: [Shape; 6] = [
    Shape::Uniform,
    Shape::ManyTies,
    Shape::AllEqual,
    Shape::Sorted,
    Shape::Reversed,
    Shape::Extremes,
];

/// Formats of t_enter to sort in: the default, a narrow unsigned one, signed ones, and the
/// widest of each kind.
fn formats() -> [Format; 5] {
    [
        SorterConfig::default().key,
        Format::uq(4, 4),
        Format::sq(8, 8),
        Format::sq(32, 32),
        Format::uq(40, 23),
    ]
}

fn gen_keys(rng: &mut Rng, shape: Shape, count: usize, f: Format) -> Vec<SortKey> {
    let (lo, hi) = (f.min_raw(), f.max_raw());
    // Ids are distinct per ray in the pipeline, but the sorter must not rely on that.
    let id = |rng: &mut Rng| rng.next() as u16 % 300;
    let mut keys: Vec<SortKey> = match shape {
        Shape::Uniform => (0..count).map(|_| (rng.range(lo, hi), id(rng))).collect(),
        Shape::ManyTies => {
            let base = rng.range(lo, hi.saturating_sub(2).max(lo));
            (0..count)
                .map(|_| (base.saturating_add(rng.range(0, 2)).min(hi), id(rng)))
                .collect()
        }
        Shape::AllEqual => {
            let t = rng.range(lo, hi);
            let same_id = rng.next() % 2 == 0;
            let i0 = id(rng);
            (0..count)
                .map(|_| (t, if same_id { i0 } else { id(rng) }))
                .collect()
        }
        Shape::Sorted | Shape::Reversed => {
            let mut v: Vec<SortKey> = (0..count).map(|_| (rng.range(lo, hi), id(rng))).collect();
            v.sort();
            if matches!(shape, Shape::Reversed) {
                v.reverse();
            }
            v
        }
        Shape::Extremes => {
            let pick = [lo, hi, lo.saturating_add(1), hi.saturating_sub(1), 0];
            (0..count)
                .map(|_| (pick[rng.below(pick.len())].clamp(lo, hi), id(rng)))
                .collect()
        }
    };
    if matches!(shape, Shape::Uniform | Shape::Extremes) && rng.next() % 4 == 0 {
        // Force the id extremes too.
        for k in keys.iter_mut().take(2) {
            k.1 = if rng.next() % 2 == 0 { 0 } else { u16::MAX };
        }
    }
    keys
}

fn check_case(rng: &mut Rng, shape: Shape, case: usize) {
    let f = formats()[rng.below(5)];
    let n = [1u8, 2, 3, 4, 5, 7, 8, 8, 8, 9, 16, 16, 31][rng.below(13)];
    let count = rng.below(101);
    let keys = gen_keys(rng, shape, count, f);
    let cfg = SorterConfig { n, key: f };
    let mut st = SorterStats::default();
    let out = Sorter::new(&cfg).sort(&keys, &mut st);
    let ctx = || {
        format!(
            "case {case} {shape:?} n = {n} count = {count} key {}",
            f.name()
        )
    };
    // Same multiset and in (t, id) order: a permutation of the input, nothing dropped or
    // duplicated, in exactly std's order.
    assert_eq!(out.len(), keys.len(), "{}", ctx());
    assert_eq!(out, std_sorted(&keys), "{}", ctx());
    assert!(out.windows(2).all(|w| w[0] <= w[1]), "{}", ctx());
    let mut ids_in: Vec<u16> = keys.iter().map(|k| k.1).collect();
    let mut ids_out: Vec<u16> = out.iter().map(|k| k.1).collect();
    ids_in.sort();
    ids_out.sort();
    assert_eq!(ids_in, ids_out, "{}", ctx());
    // Statistics follow the documented timing model.
    let t = sort_timing(count, n);
    assert_eq!(st.networks_run, t.chunks, "{}", ctx());
    assert_eq!(st.overflow_batches, t.chunks.saturating_sub(1), "{}", ctx());
    assert_eq!(st.merge_steps, t.merge_steps, "{}", ctx());
    assert_eq!(st.merge_passes, t.merge_passes, "{}", ctx());
    assert_eq!(st.cycles, t.latency, "{}", ctx());
    assert_eq!((st.keys_clamped, st.config_errors), (0, 0), "{}", ctx());
    assert_eq!(st.keys, count as u64, "{}", ctx());
    // A reused sorter gives the same keys and counts.
    let mut st2 = SorterStats::default();
    assert_eq!(Sorter::new(&cfg).sort(&keys, &mut st2), out, "{}", ctx());
    assert_eq!(st2, st, "{}", ctx());
    if count > usize::from(n) {
        assert!(
            st.extra_cycles > 0 && st.merge_steps >= count as u64,
            "{}",
            ctx()
        );
    } else {
        assert_eq!((st.extra_cycles, st.merge_steps), (0, 0), "{}", ctx());
    }
}

#[test]
fn sorter_matches_std_sort_for_every_input_shape() {
    let mut rng = Rng::new(seed("sorter_matches_std_sort_for_every_input_shape"));
    const CASES: usize = 10_000;
    for shape in SHAPES {
        for case in 0..CASES {
            check_case(&mut rng, shape, case);
        }
    }
}

#[test]
fn sorter_matches_std_sort_on_mixed_shapes() {
    // Two in three cases adversarial (not uniform), as the style guide asks.
    let mut rng = Rng::new(seed("sorter_matches_std_sort_on_mixed_shapes"));
    for case in 0..20_000 {
        let shape = if rng.below(3) == 0 {
            Shape::Uniform
        } else {
            SHAPES[1 + rng.below(5)]
        };
        check_case(&mut rng, shape, case);
    }
}

#[test]
fn out_of_range_keys_are_clamped_and_counted() {
    let mut rng = Rng::new(seed("out_of_range_keys_are_clamped_and_counted"));
    let f = Format::uq(4, 4); // raw 0..=255
    let cfg = SorterConfig { n: 4, key: f };
    for _ in 0..2_000 {
        let count = rng.below(30);
        let keys: Vec<SortKey> = (0..count)
            .map(|_| (rng.range(-1000, 1000), rng.next() as u16))
            .collect();
        let outside = keys.iter().filter(|k| k.0 < 0 || k.0 > 255).count() as u64;
        let clamped: Vec<SortKey> = keys.iter().map(|&(t, i)| (t.clamp(0, 255), i)).collect();
        let mut st = SorterStats::default();
        let out = Sorter::new(&cfg).sort(&keys, &mut st);
        assert_eq!(out, std_sorted(&clamped));
        assert_eq!(st.keys_clamped, outside);
    }
    // i64 extremes in the widest signed format need no clamping.
    let mut st = SorterStats::default();
    let wide = SorterConfig {
        n: 8,
        key: Format::sq(32, 32),
    };
    let keys = [(i64::MAX, 1), (i64::MIN, 2), (0, 3), (i64::MIN, 1)];
    assert_eq!(
        Sorter::new(&wide).sort(&keys, &mut st),
        vec![(i64::MIN, 1), (i64::MIN, 2), (0, 3), (i64::MAX, 1)]
    );
    assert_eq!(st.keys_clamped, 0);
}

#[test]
fn invalid_configurations_sort_and_are_counted() {
    let keys = [(5, 1), (3, 2), (5, 0), (-7, 9), (1, 1), (2, 2), (0, 0)];
    let bad_format = Format {
        width: 0,
        ..Format::uq(8, 8)
    };
    for cfg in [
        SorterConfig {
            n: 0,
            ..SorterConfig::default()
        },
        SorterConfig {
            n: 3,
            key: bad_format,
        },
    ] {
        assert!(cfg.validate().is_err());
        let mut st = SorterStats::default();
        let out = Sorter::new(&cfg).sort(&keys, &mut st);
        assert_eq!(st.config_errors, 1, "{cfg:?}");
        assert_eq!(out.len(), keys.len());
        assert!(out.windows(2).all(|w| w[0] <= w[1]));
    }
    // n = 0 runs as one lane: nothing but merges.
    let mut st = SorterStats::default();
    let out = Sorter::new(&SorterConfig {
        n: 0,
        ..SorterConfig::default()
    })
    .sort(&keys, &mut st);
    // uQ10.22 clamps −7 to 0 (counted), then sorts as usual.
    assert_eq!(out, std_sorted(&keys.map(|(t, i)| (t.max(0), i))));
    assert_eq!(st.keys_clamped, 1);
    assert_eq!(st.networks_run, keys.len() as u64);
}

#[test]
fn the_largest_count_is_sorted_in_full() {
    let mut rng = Rng::new(seed("the_largest_count_is_sorted_in_full"));
    let cfg = SorterConfig::default();
    let keys: Vec<SortKey> = (0..=u16::MAX - 1)
        .map(|id| (rng.range(0, 1 << 12), id))
        .collect();
    assert_eq!(keys.len(), 65_535);
    let mut st = SorterStats::default();
    let out = Sorter::new(&cfg).sort(&keys, &mut st);
    assert_eq!(out, std_sorted(&keys));
    // The default 16 lanes: ⌈65535 / 16⌉ = 4096 chunks, merged pairwise in log₂ 4096 = 12
    // passes over every key.
    assert_eq!(st.networks_run, 4096);
    assert_eq!(st.merge_passes, 12);
    assert_eq!(st.merge_steps, 12 * 65_535);
}

#[test]
fn timing_model_examples() {
    let t = sort_timing(0, 8);
    assert_eq!((t.chunks, t.latency), (0, 0));
    let t = sort_timing(8, 8);
    assert_eq!(
        (t.chunks, t.merge_passes, t.latency, t.network_busy),
        (1, 0, 6, 1)
    );
    // 17 keys on 8 lanes: 3 chunks (issued on 3 cycles), 2 merge passes of 17 keys each.
    let t = sort_timing(17, 8);
    assert_eq!(
        (t.chunks, t.merge_passes, t.merge_steps, t.latency),
        (3, 2, 34, 2 + 6 + 2 * 18)
    );
    // It holds the input until its merges are done: 2 + 2 * 18 + 1 cycles.
    assert_eq!(t.occupancy, 2 + 2 * 18 + 1);
    assert_eq!(pipe_cost(17, 8, 6), (39, 2 + 2 * 18));
    assert_eq!(pipe_cost(8, 8, 6), (1, 0));
    assert_eq!(
        pipe_cost(0, 8, 6),
        (1, 0),
        "an empty issue passes the network"
    );
    let t = sort_timing(16, 16);
    assert_eq!((t.chunks, t.latency, t.occupancy), (1, 10, 1));
}

#[test]
fn resources_of_the_default_sorter() {
    // 16 lanes (issue 28): Green's 60 comparators in 10 layers; keys of 32 bits with 8-bit ids.
    let r = resources(&SorterConfig::default(), 8);
    assert_eq!((r.comparators, r.depth, r.compare_bits), (60, 10, 40));
    assert_eq!(r.comparator_bits, 60 * 40);
    assert_eq!(r.register_bits, 10 * 16 * 41);
    // 8 lanes, the default before: 19 comparators in 6 layers.
    let eight = SorterConfig {
        n: 8,
        ..SorterConfig::default()
    };
    let r = resources(&eight, 8);
    assert_eq!((r.comparators, r.depth, r.compare_bits), (19, 6, 40));
    assert_eq!(r.register_bits, 6 * 8 * 41);
}

#[test]
fn default_config() {
    let cfg = SorterConfig::default();
    assert_eq!(cfg.n, 16);
    assert_eq!(cfg.key, Format::uq(10, 22));
    assert!(cfg.validate().is_ok());
}

/// `Sorter::sort_in_place` (the model's fast path) gives the same order and the same
/// statistics as `Sorter::sort` (the whole unit, any count), for counts below, at and above N.
#[test]
fn in_place_sort_matches_sort() {
    use rtl_model::units::sorter::{Sorter, SorterConfig, SorterStats};
    let cfg = SorterConfig::default();
    let sorter = Sorter::new(&cfg);
    let mut s = 0x1234_5678_9abc_def1u64;
    println!("seed = {s:#x}");
    for case in 0..10_000 {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let count = (s % 20) as usize;
        let keys: Vec<(i64, u16)> = (0..count)
            .map(|i| {
                (
                    (s.rotate_left(i as u32 * 7) % 64) as i64
                        - if case % 50 == 0 { 100 } else { 0 },
                    (i * 3 % 17) as u16,
                )
            })
            .collect();
        let (mut a, mut b) = (SorterStats::default(), SorterStats::default());
        let want = sorter.sort(&keys, &mut a);
        let mut got = keys.clone();
        sorter.sort_in_place(&mut got, &mut b);
        assert_eq!(got, want, "case {case}");
        assert_eq!(a, b, "case {case}: statistics differ");
    }
}
