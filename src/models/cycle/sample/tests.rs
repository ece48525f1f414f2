//! Tests of sampled timing's plan, warming and estimator (`super`).

use super::*;

#[test]
fn estimate_of_a_constant_sample_is_exact() {
    let e = Estimate::of(100.0, &[10.0, 10.0, 10.0, 10.0], 4);
    assert_eq!(e.total, 260.0);
    assert_eq!((e.low, e.high), (260.0, 260.0));
}

#[test]
fn estimate_by_hand() {
    // y = 1, 3, 2 with k = 2: T = 5 + 2·6 = 17; s² = (4 + 1)/(2·2) = 1.25;
    // v = 4·3·0.5·1.25 = 7.5; t(2) = 4.303.
    let e = Estimate::of(5.0, &[1.0, 3.0, 2.0], 2);
    assert_eq!(e.total, 17.0);
    assert!((e.std_error - 7.5f64.sqrt()).abs() < 1e-12);
    assert!((e.high - (17.0 + 4.303 * 7.5f64.sqrt())).abs() < 1e-9);
    assert_eq!(e.df, 2);
}

#[test]
fn t_quantile_is_continuous_past_the_table() {
    assert!((t_975(30) - 2.042).abs() < 1e-3);
    assert!((t_975(31) - 2.0395).abs() < 1e-3);
    assert!((t_975(1000) - 1.9623).abs() < 1e-3);
}

#[test]
fn plan_covers_first_and_last_band_and_every_kth() {
    let hw = HwConfig::default();
    let cfg = SampleConfig {
        period: 4,
        band_rows: 2,
        warm_rows: Some(1),
        seed: 7,
    };
    let s = Sampler::plan(cfg, &hw, 0, 10, 40);
    // 20 bands: 0, 19 and every 4th of 1..=18 from the start.
    let mid: Vec<u32> = s
        .bands
        .iter()
        .filter(|b| !b.certain)
        .map(|b| b.index)
        .collect();
    assert!(mid.windows(2).all(|w| w[1] - w[0] == 4));
    assert!(mid.len() >= 4);
    assert_eq!(s.bands.first().map(|b| b.index), Some(0));
    assert_eq!(s.bands.last().map(|b| b.index), Some(19));
    // Segments are ordered and disjoint, start at 0 and end at the last pixel.
    let mut s = s;
    while s.next_planned(&mut |_| Ok(10)).unwrap().is_some() {}
    assert_eq!(s.segments.first().map(|x| x.0), Some(0));
    assert_eq!(s.segments.last().map(|x| x.1), Some(400));
    assert!(s.segments.windows(2).all(|w| w[0].1 < w[1].0));
}

#[test]
fn warming_reaches_back_until_it_holds_the_walking_rays() {
    let hw = HwConfig::default();
    // Bands 60 rows apart: the default pipeline holds 32 rows' worth of one-in-ten walking
    // rays here, and warming never reaches past the previous band.
    let cfg = SampleConfig {
        period: 60,
        band_rows: 2,
        warm_rows: None,
        seed: 3,
    };
    let width = 1000;
    let wm = cfg.warming_for(&hw, width);
    assert!(wm.min_rows >= 1 && wm.walking > 0 && wm.max_rows > wm.min_rows);
    // Every pixel walks: the warming is the minimum rows.
    let mut s = Sampler::plan(cfg, &hw, 0, width, 600);
    while s
        .next_planned(&mut |_| Ok(u64::from(width)))
        .unwrap()
        .is_some()
    {}
    assert_eq!(s.warm_rows_max, wm.min_rows);
    // One pixel in ten walks: ten times the rows (up to the cap).
    let mut s = Sampler::plan(cfg, &hw, 0, width, 600);
    while s
        .next_planned(&mut |_| Ok(u64::from(width / 10)))
        .unwrap()
        .is_some()
    {}
    let want = wm.walking.div_ceil(u64::from(width / 10)) as u32;
    assert_eq!(s.warm_rows_max, want.clamp(wm.min_rows, wm.max_rows));
    assert!(s.warm_rows_max > wm.min_rows);
    // None walks: the cap.
    let mut s = Sampler::plan(cfg, &hw, 0, width, 600);
    while s.next_planned(&mut |_| Ok(0)).unwrap().is_some() {}
    assert_eq!(s.warm_rows_max, wm.max_rows);
    // `--sample-warm` fixes it in rows.
    let fixed = SampleConfig {
        warm_rows: Some(5),
        ..cfg
    };
    let mut s = Sampler::plan(fixed, &hw, 0, width, 600);
    while s.next_planned(&mut |_| Ok(0)).unwrap().is_some() {}
    assert_eq!(s.warm_rows_max, 5);
    assert!(s.segments.windows(2).all(|w| w[0].1 < w[1].0));
}
