//! Ray-generation table entries against f64: for random unit directions (axis-aligned,
//! diagonal and exactly-halfway components included), every component is within the named
//! bound and the entry's length within √3 times it of 1; nothing saturates.

use rtl_model::datapath::RaygenConfig;
use rtl_model::fixed::{to_f64, Overflows, SignalId};
use rtl_model::units::raygen::{direction_entry, error_bound, table_bits};

#[test]
fn entries_within_bound() {
    let seed: u64 = std::env::var("SVO_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x7a6e_0001);
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut s = seed | 1;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let cfg = RaygenConfig::default();
    let b = error_bound(&cfg);
    let mut ov = Overflows::new(&["dir"]);
    let mut worst = 0f64;
    for case in 0..10_000 {
        let mut d = [next(), next(), next()];
        match case % 10 {
            0 => d = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]][case / 10 % 3],
            1 => d = [1.0, 1.0, 1.0],
            _ => {}
        }
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-9);
        let d = d.map(|v| v / n);
        let e = direction_entry(d, &cfg, &mut ov, SignalId(0));
        let v = e.map(|c| to_f64(c, cfg.dir));
        for k in 0..3 {
            let err = (v[k] - d[k]).abs();
            worst = worst.max(err);
            assert!(
                err <= b,
                "seed {seed} case {case}: component {k} error {err:e} > {b:e}"
            );
        }
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        assert!(
            (len - 1.0).abs() <= 3f64.sqrt() * b + b * b + 1e-15,
            "seed {seed} case {case}: length {len}"
        );
    }
    assert_eq!(ov.total(), 0);
    println!(
        "worst component error {worst:e}, bound {b:e}; table for 1280x768: {} bits",
        table_bits(&cfg, 1280, 768)
    );
}
