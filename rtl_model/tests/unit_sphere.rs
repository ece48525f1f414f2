//! Sphere-test unit against exact f64: over random spheres and rays — grazing tangents,
//! origins inside, spheres behind the origin included — the fixed-point test never rejects a
//! sphere the exact test accepts, and its entry distance is never later than the exact one
//! and earlier by at most its named bound. The oracle is plain f64 written here.

mod common;
mod datapaths;
use common::Rng;
use rtl_model::fixed::{from_f64, to_f64, Overflows, SignalId};
use rtl_model::units::sphere::{
    sphere_radicand, sphere_test, SphereConfig, SphereRaw, SphereSignals,
};

/// A random unit vector.
fn unit(rng: &mut Rng) -> [f64; 3] {
    loop {
        let v = [rng.f(-1.0, 1.0), rng.f(-1.0, 1.0), rng.f(-1.0, 1.0)];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 {
            return v.map(|x| x / n);
        }
    }
}

/// Exact test: entry distance, or None if culled (miss, or entirely behind).
fn exact(o: [f64; 3], d: [f64; 3], c: [f64; 3], r: f64) -> Option<f64> {
    let l = [c[0] - o[0], c[1] - o[1], c[2] - o[2]];
    let tca = l[0] * d[0] + l[1] * d[1] + l[2] * d[2];
    let l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    let p2 = l2 - tca * tca;
    if p2 > r * r {
        return None;
    }
    if l2 <= r * r {
        return Some(0.0);
    }
    let t = tca - (r * r - p2).sqrt();
    (t >= 0.0).then_some(t)
}

fn sphere_seed() -> u64 {
    std::env::var("SVO_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5fe7e)
}

#[test]
fn conservative_and_within_bound() {
    let seed = sphere_seed();
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    within_bound(&SphereConfig::default(), seed, &mut rng);
}

/// The entry bound is tight within a documented factor on the default datapath's sphere
/// stage and the two non-default ones (`datapaths/mod.rs`): over 20,000 rays (two in five
/// grazing) the worst entry error is at least 1/2 of `t_enter_error_bound`. Measured (the
/// default seed, 1 and 2): 0.71–0.73 of it on all three (the grazing rays reach the √(2W)
/// term of the widening W).
#[test]
fn sphere_entry_bound_is_tight() {
    let seed = sphere_seed();
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed ^ 0x7167);
    for (name, dp) in datapaths::all() {
        let w = within_bound(&dp.sphere, seed, &mut rng);
        println!("{name}: worst entry error {w:.4} of its bound");
        assert!(w >= 0.5, "{name}: entry bound loose: worst {w:.4} of it");
    }
}

/// 20,000 random rays against random spheres of `cfg`: conservative and within the entry
/// bound; returns the worst entry error as a fraction of its bound.
fn within_bound(cfg: &SphereConfig, seed: u64, rng: &mut Rng) -> f64 {
    let cfg = *cfg;
    cfg.validate().unwrap();
    let mut ov = Overflows::new(&["in", "tca", "sq", "t_enter", "reach"]);
    let sig = SphereSignals {
        tca: SignalId(1),
        sq: SignalId(2),
        t_enter: SignalId(3),
        reach: SignalId(4),
    };
    let (mut accepted, mut extra, mut grazing_kept, mut worst_ratio) = (0u64, 0u64, 0u64, 0f64);
    for case in 0..20_000 {
        let c = [rng.f(-30.0, 30.0), rng.f(-30.0, 30.0), rng.f(-30.0, 30.0)];
        let r = rng.f(0.05, 5.0);
        let d = unit(rng);
        let o = match case % 5 {
            // Grazing: the ray passes at distance r·(1 ± 1e-9) from the centre.
            0 | 1 => {
                let side = unit(rng);
                // Component of `side` perpendicular to d.
                let s = side[0] * d[0] + side[1] * d[1] + side[2] * d[2];
                let mut p = [side[0] - s * d[0], side[1] - s * d[1], side[2] - s * d[2]];
                let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt().max(1e-9);
                p = p.map(|x| x / n);
                let scale = r * if case % 5 == 0 {
                    1.0 - 1e-9
                } else {
                    1.0 + 1e-9
                };
                let back = rng.f(1.0, 40.0);
                [0, 1, 2].map(|k| c[k] + p[k] * scale - d[k] * back)
            }
            // Origin inside the sphere.
            2 => [0, 1, 2].map(|k| c[k] + rng.f(-0.5, 0.5) * r),
            _ => [rng.f(-30.0, 30.0), rng.f(-30.0, 30.0), rng.f(-30.0, 30.0)],
        };
        let q = |v: [f64; 3], f, ov: &mut Overflows| v.map(|x| from_f64(x, f, ov, SignalId(0)));
        let (oq, dq, cq) = (
            q(o, cfg.pos, &mut ov),
            q(d, cfg.dir, &mut ov),
            q(c, cfg.pos, &mut ov),
        );
        let got = sphere_test(oq, dq, &SphereRaw::new(cq, r, &cfg), &cfg, &mut ov, sig);
        match (exact(o, d, c, r), got) {
            (Some(t), Some(h)) => {
                accepted += 1;
                let tf = to_f64(h.t_enter, cfg.t_enter);
                assert!(tf <= t + 1e-12, "seed {seed} case {case}: entry {tf} later than exact {t}");
                let bound = cfg.t_enter_error_bound(r);
                assert!(t - tf <= bound, "seed {seed} case {case}: entry {tf} earlier than exact {t} by more than {bound:e}");
                worst_ratio = worst_ratio.max((t - tf) / bound);
            }
            (Some(t), None) => panic!("seed {seed} case {case}: rejected a sphere the exact test accepts (t = {t})\n o {o:?} d {d:?} c {c:?} r {r}"),
            (None, Some(_)) if case % 5 == 1 => grazing_kept += 1,
            (None, Some(_)) => extra += 1,
            (None, None) => {}
        }
    }
    assert_eq!(ov.total(), 0);
    println!(
        "accepted by both: {accepted}; kept although the exact test culls: {grazing_kept} grazing (1e-9 outside, within the widening), {extra} others; worst entry error / bound: {worst_ratio:.3}"
    );
    // Ordinary rays (not constructed to graze) are culled exactly as f64 culls them, but for
    // the rare one that passes within the widening of a sphere. How rare, by hand: the unit
    // keeps a sphere the exact test culls only if the exact p² lies in (r², r² + 2W] (its own
    // p² is at most W below the exact one, and it keeps p² ≤ r² + W). For an origin at
    // distance L from the centre and a uniformly random direction, P(p² ≤ x) ≈ x/(4L²) per
    // cone, so the band has probability ≤ 2·2W/(4L²) = W/L² (both cones). With W = 4.2·10⁻⁵ m² (the default, `sim datapath`)
    // and the 12,000 ordinary rays' L distributed as the distance of two uniform points in a
    // 60 m cube (E[1/L²] ≈ 4π·30/60³ ≈ 1.7·10⁻³ m⁻²), the expected count is about
    // 12,000 · 4.2·10⁻⁵ · 1.7·10⁻³ ≈ 9·10⁻⁴: P(extra ≥ 2) ≈ 4·10⁻⁷. Measured: 0 for seeds 1 to
    // 5 and the default. (It was `extra < 12` before it was derived.)
    assert!(
        extra <= 1,
        "the widening should keep (almost) no extra spheres: {extra}"
    );
    worst_ratio
}

/// Regression (found by `sim stress`, case `far_diagonal`): the conservative analysis holds
/// for |l| ≤ reach, but the unit used to check the reach per component, so a sphere up to
/// √3·reach away along a diagonal passed the guard unflagged and could be rejected although
/// the exact test accepts it. Every grazing ray here is 205 m from the sphere along the
/// diagonal (each component of l about 118 m, below the 128 m reach): the unit must keep the
/// sphere or count it on the reach signal, never reject it silently. Where it counts, it takes
/// no square root ([`sphere_radicand`], which the vectors capture the root's inputs with).
#[test]
fn beyond_reach_along_a_diagonal_is_never_silently_rejected() {
    let seed: u64 = std::env::var("SVO_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0xd1a9);
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    let cfg = SphereConfig::default();
    let mut ov = Overflows::new(&["in", "tca", "sq", "t_enter", "reach"]);
    let sig = SphereSignals {
        tca: SignalId(1),
        sq: SignalId(2),
        t_enter: SignalId(3),
        reach: SignalId(4),
    };
    let (mut kept, mut counted) = (0u64, 0u64);
    for case in 0..20_000 {
        let c = [
            60.0 + rng.f(-1.0, 1.0),
            60.0 + rng.f(-1.0, 1.0),
            60.0 + rng.f(-1.0, 1.0),
        ];
        let r = rng.f(0.5, 3.0);
        let k = 3f64.sqrt().recip();
        // The spread of ±0.02 keeps every origin in range for every seed: the largest
        // component of the normalised direction is at most (k + 0.02) / |(k + 0.02, k − 0.02,
        // k − 0.02)| < 0.604, so |c − o| ≤ 205 · 0.604 + 3 < 127 on each axis (±0.03 reached
        // 129.6 and failed the precondition below for seeds 1 and 2).
        let d = {
            let v = [
                k + rng.f(-0.02, 0.02),
                k + rng.f(-0.02, 0.02),
                k + rng.f(-0.02, 0.02),
            ];
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            v.map(|x| x / n)
        };
        let side = unit(&mut rng);
        let s = side[0] * d[0] + side[1] * d[1] + side[2] * d[2];
        let mut p = [side[0] - s * d[0], side[1] - s * d[1], side[2] - s * d[2]];
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt().max(1e-9);
        p = p.map(|x| x / n * r * (1.0 - 1e-9));
        let o = [0, 1, 2].map(|i| c[i] + p[i] - d[i] * 205.0);
        assert!(
            (0..3).all(|i| (c[i] - o[i]).abs() < 128.0),
            "case {case}: the generator left the origin's range"
        );
        let q = |v: [f64; 3], f, ov: &mut Overflows| v.map(|x| from_f64(x, f, ov, SignalId(0)));
        let (oq, dq, cq) = (
            q(o, cfg.pos, &mut ov),
            q(d, cfg.dir, &mut ov),
            q(c, cfg.pos, &mut ov),
        );
        let before = ov.count(sig.reach);
        let sphere = SphereRaw::new(cq, r, &cfg);
        let got = sphere_test(oq, dq, &sphere, &cfg, &mut ov, sig);
        let flagged = ov.count(sig.reach) > before;
        if flagged {
            assert_eq!(
                sphere_radicand(oq, dq, &sphere, &cfg, &mut ov, sig),
                None,
                "seed {seed} case {case}: a root beyond the reach"
            );
        }
        if exact(o, d, c, r).is_some() {
            assert!(
                got.is_some() || flagged,
                "seed {seed} case {case}: rejected silently beyond the reach (o {o:?} d {d:?} c {c:?} r {r})"
            );
            kept += u64::from(got.is_some());
            counted += u64::from(flagged);
        }
    }
    println!("exact hits kept: {kept}, counted on sphere/reach: {counted}");
}
