//! Independent oracles for the vector rows of the reciprocal (with its seed ROM), the
//! transform's origin path, the sphere test and the hit-record packer (issue 14 part 4; the square root, the
//! sorter and the transform's direction path are checked in `tests/vectors.rs`).
//!
//! Every check reads the rows through the manifests alone (`tests/vector_files`, plain JSON and
//! hex) and computes the expected value from the documents — `docs/units/reciprocal.md` §3, §4
//! and §6, `docs/number-formats.md`, `docs/units/hit-record.md` — in exact integer arithmetic,
//! sharing no code with `rtl_model`. Formats come from each manifest, so the checks follow a
//! change of the default datapath without edits.

mod common;
mod vector_files;

use common::process::run_sim;
use std::time::Duration;
use vector_files::{manifest, rows, value, Tmp};

const TIMEOUT: Duration = Duration::from_secs(300);

fn make_set(t: &Tmp) {
    let out = t.dir.to_str().expect("UTF-8 path");
    let a = [
        "vectors", "--out", out, "--count", "3000", "--seed", "77", "--width", "16", "--height",
        "12", "--depth", "5",
    ];
    let r = run_sim(&a, None, TIMEOUT);
    assert!(r.status.success(), "sim {a:?}: {}", r.stderr);
}

fn param(m: &serde_json::Value, path: &[&str]) -> i64 {
    let mut v = &m["parameters"];
    for k in path {
        v = &v[*k];
    }
    v.as_i64()
        .unwrap_or_else(|| panic!("{}: parameter {path:?} missing", m["name"]))
}

/// Round half to even of n / 2^s (s ≥ 0), exactly.
fn rne_shift(n: i128, s: u32) -> i128 {
    if s == 0 {
        return n;
    }
    let fl = n >> s;
    let rem = n - (fl << s);
    let half = 1i128 << (s - 1);
    fl + i128::from(rem > half || (rem == half && fl & 1 == 1))
}

#[test]
fn reciprocal_seed_rom_is_the_documented_table() {
    // docs/units/reciprocal.md §4: entry i = round(2^(t+2)·2^(t+1) / (2^(t+1) + 2i + 1)); the
    // divisor is odd, so there is no tie; entries lie in [1/2, 1) and do not increase.
    let dir = vector_files::repo().join("vectors");
    let m = manifest(&dir, "reciprocal_seed");
    let t = param(&m, &["table_bits"]) as u32;
    let r = rows(&dir, "reciprocal_seed");
    assert_eq!(r.len(), 1 << t);
    let mut previous = i128::MAX;
    for (i, row) in r.iter().enumerate() {
        let num = 1i128 << (2 * t + 3);
        let den = (1i128 << (t + 1)) + 2 * i as i128 + 1;
        let want = (2 * num + den) / (2 * den); // nearest: ⌊num/den + ½⌋
        let got = value(&m, row, "seed");
        assert_eq!(got, want, "seed ROM entry {i}");
        assert!((1 << (t + 1)..1 << (t + 2)).contains(&got) && got <= previous);
        previous = got;
    }
}

/// The worst relative error of the seed over every mantissa interval, exactly: |1 − m·y0| at
/// the ends of [a_i, b_i − 2^−G], in units of 2^−2G.
fn seed_error(seeds: &[i128], t: u32, g: u32) -> f64 {
    let one = 1i128 << (2 * g);
    let step = 1i128 << (g - t);
    let mut worst = 0i128;
    for (i, &s) in seeds.iter().enumerate() {
        let y0 = s << (g - t - 2); // uQ0.(t+2) placed in uQ1.G
        let lo = ((1i128 << t) + i as i128) * step;
        for m in [lo, lo + step - 1] {
            worst = worst.max((one - m * y0).abs());
        }
    }
    worst as f64 / 2f64.powi(2 * g as i32)
}

#[test]
fn reciprocal_rows_are_within_the_documented_bound_of_the_exact_quotient() {
    let t = Tmp::new("recip_oracle");
    make_set(&t);
    let m = manifest(&t.dir, "reciprocal");
    let f_in = param(&m, &["config", "input", "frac"]) as u32;
    let f_out = param(&m, &["config", "output", "frac"]) as u32;
    let w_out = param(&m, &["config", "output", "width"]) as u32;
    let tb = param(&m, &["config", "table_bits"]) as u32;
    let iters = param(&m, &["config", "iterations"]) as u32;
    // §3: k magnitude integer bits; |d| ≤ 2^−k, i.e. a code ≤ 2^(F_in − k), is flagged zero.
    let k = w_out - f_out - 1;
    let threshold = 1i128 << (f_in - k);
    assert_eq!(i128::from(param(&m, &["zero_threshold_code"])), threshold);
    // §6, derived again here: R0 from the ROM itself, R(i+1) = R(i)² + 2^(1−G), then the
    // mantissa truncation: rel = R(n)(1 + 2^−G) + 2^−G; plus half an output LSB (RndConv).
    let g = f_out + 2;
    let rom_dir = &t.dir;
    let rom_m = manifest(rom_dir, "reciprocal_seed");
    let seeds: Vec<i128> = rows(rom_dir, "reciprocal_seed")
        .iter()
        .map(|r| value(&rom_m, r, "seed"))
        .collect();
    let ulp = 2f64.powi(-(g as i32));
    let mut rel = seed_error(&seeds, tb, g);
    assert!(rel < 2f64.powi(-8), "seed error {rel}");
    for _ in 0..iters {
        rel = rel * rel + 2.0 * ulp;
    }
    let rel = rel * (1.0 + ulp) + ulp;
    let max = (1i128 << (w_out - 1)) - 1;
    let (mut finite, mut worst_lsb, mut zeros) = (0, 0f64, 0);
    for r in rows(&t.dir, "reciprocal") {
        let d = value(&m, &r, "d");
        let neg = d < 0 || (d == 0 && value(&m, &r, "sign_negative") == 1);
        let inv = value(&m, &r, "inv");
        assert_eq!(value(&m, &r, "negative"), i128::from(neg), "row {r}");
        let zero = d.abs() <= threshold;
        assert_eq!(value(&m, &r, "zero"), i128::from(zero), "row {r}");
        assert_eq!(
            value(&m, &r, "flushed"),
            i128::from(zero && d != 0),
            "row {r}"
        );
        if zero {
            zeros += 1;
            assert_eq!(inv, if neg { -max } else { max }, "zero row {r}");
            continue;
        }
        finite += 1;
        // The quotient in output codes, 2^(F_in + F_out) / d, in f64: its own error (≤ |q|·2^−53)
        // is far below the bound's half LSB, and the margin below covers it.
        let q = (1i128 << (f_in + f_out)) as f64 / d as f64;
        let err_lsb = (inv as f64 - q).abs();
        let bound_lsb = rel * q.abs() + 0.5;
        assert!(
            err_lsb <= bound_lsb * (1.0 + 1e-12),
            "row {r}: 1/d code {inv}, exact {q}, error {err_lsb} LSB > bound {bound_lsb}"
        );
        // No saturation above the threshold (§4): ov only where the code reached ±max.
        assert_eq!(value(&m, &r, "ov"), 0, "row {r}");
        worst_lsb = worst_lsb.max(err_lsb / bound_lsb);
    }
    println!(
        "reciprocal: {finite} finite rows within the bound (worst at {:.2} of it), {zeros} zero rows; rel bound {rel:.3e}",
        worst_lsb
    );
    assert!(finite > 1000 && zeros > 5);
}

#[test]
fn transform_origin_rows_are_the_exactly_rounded_rotation() {
    let t = Tmp::new("transform_origin_oracle");
    make_set(&t);
    let m = manifest(&t.dir, "transform");
    let f_pos = param(&m, &["config", "pos", "frac"]) as u32;
    let f_mat = param(&m, &["config", "mat", "frac"]) as u32;
    let f_loc = param(&m, &["config", "local_pos", "frac"]) as u32;
    let w_loc = param(&m, &["config", "local_pos", "width"]) as u32;
    let (lo, hi) = (-(1i128 << (w_loc - 1)), (1i128 << (w_loc - 1)) - 1);
    let axes = ["x", "y", "z"];
    let (mut n, mut saturated) = (0, 0);
    for r in rows(&t.dir, "transform") {
        // o' = Rᵀ(o − c): component k = Σ_j R_jk (o_j − c_j), exact, then one rounding (half
        // to even) from F_mat + F_pos to F_loc fraction bits and saturation.
        let mut any_sat = false;
        for (k, ak) in axes.iter().enumerate() {
            let sum: i128 = (0..3)
                .map(|j| {
                    let oj = value(&m, &r, &format!("o_{}", axes[j]));
                    let cj = value(&m, &r, &format!("c_{}", axes[j]));
                    value(&m, &r, &format!("axis{k}_{}", axes[j])) * (oj - cj)
                })
                .sum();
            let rounded = rne_shift(sum, f_mat + f_pos - f_loc);
            let want = rounded.clamp(lo, hi);
            any_sat |= want != rounded;
            assert_eq!(
                value(&m, &r, &format!("local_o_{ak}")),
                want,
                "transform row {r}, axis {ak}"
            );
        }
        assert_eq!(value(&m, &r, "ov_origin"), i128::from(any_sat), "row {r}");
        saturated += usize::from(any_sat);
        n += 1;
    }
    println!("transform origin: {n} rows, {saturated} saturating");
    assert!(n > 1000 && saturated > 0);
}

/// A layout field of the hit-record word: (offset, width, signed).
fn layout(m: &serde_json::Value, name: &str) -> (u32, u32, bool) {
    let f = m["parameters"]["record_layout"]
        .as_array()
        .expect("record_layout")
        .iter()
        .find(|f| f["name"] == name)
        .unwrap_or_else(|| panic!("no {name} in record_layout"));
    (
        f["offset"].as_u64().expect("offset") as u32,
        f["width"].as_u64().expect("width") as u32,
        f["signed"].as_bool().expect("signed"),
    )
}

#[test]
fn hit_record_words_pack_the_saturated_fields_at_their_documented_places() {
    let t = Tmp::new("hit_record_oracle");
    make_set(&t);
    let m = manifest(&t.dir, "hit_record");
    let (mut n, mut saturated, mut misses) = (0, 0, 0);
    for r in rows(&t.dir, "hit_record") {
        // docs/units/hit-record.md: each field saturates into its width (counted in ov);
        // instance all ones = none (a miss), an id at or above it becomes none and counts.
        let mut sat = false;
        let mut word = 0u128;
        let mut put = |name: &str, v: i128| {
            let (off, w, signed) = layout(&m, name);
            let (lo, hi) = if signed {
                (-(1i128 << (w - 1)), (1i128 << (w - 1)) - 1)
            } else {
                (0, (1i128 << w) - 1)
            };
            let c = v.clamp(lo, hi);
            word |= ((c as u128) & ((1u128 << w) - 1)) << off;
            c != v
        };
        let hit = value(&m, &r, "instance_valid") == 1;
        let (_, iw, _) = layout(&m, "instance");
        let none = (1i128 << iw) - 1;
        sat |= put("kind", value(&m, &r, "kind"));
        if hit {
            let id = value(&m, &r, "instance");
            sat |= id >= none;
            put("instance", id.min(none));
        } else {
            misses += 1;
            put("instance", none);
        }
        // The row's t is already a raw code (a miss's far code included, docs/vectors.md §3),
        // so it saturates like every other field, hit or miss.
        sat |= put("t", value(&m, &r, "t"));
        for f in ["normal_u", "normal_v", "colour_r", "colour_g", "colour_b"] {
            sat |= put(f, value(&m, &r, f));
        }
        assert_eq!(value(&m, &r, "word") as u128, word, "hit_record row {r}");
        assert_eq!(value(&m, &r, "ov"), i128::from(sat), "hit_record row {r}");
        saturated += usize::from(sat);
        n += 1;
    }
    println!("hit_record: {n} rows, {misses} misses, {saturated} saturating");
    assert!(n > 1000 && misses > 0 && saturated > 0);
}

#[test]
fn sphere_rows_follow_the_documented_test_within_rounding() {
    // rtl_model/src/units/sphere.rs's module documentation (and docs/number-formats.md):
    // l = c − o exact; beyond the reach (a component or the length) → kept, entry 0, ov_reach;
    // origin may be inside (l·l ≤ the inside threshold) → kept, entry 0; otherwise p² =
    // l·l − t_ca² against T: culled iff p² > T; culled as behind iff t_ca + Δt + √(T − p²) < 0;
    // else entry = max(0, t_ca − Δt − √(T − p²)). Computed here in f64 from the row's codes;
    // where the unit's roundings (t_ca down to its LSB, squares and root truncated) could
    // decide differently, the row is counted as in the band and its decision not judged.
    let t = Tmp::new("sphere_oracle");
    make_set(&t);
    let m = manifest(&t.dir, "sphere");
    let fr = |k: &str| param(&m, &["config", k, "frac"]) as i32;
    let (fp, fd, ftca, fsq, fte) = (fr("pos"), fr("dir"), fr("tca"), fr("sq"), fr("t_enter"));
    let lsb = |f: i32| 2f64.powi(-f);
    let axes = ["x", "y", "z"];
    let (mut judged, mut band, mut culled, mut inside, mut beyond) = (0, 0, 0, 0, 0);
    for r in rows(&t.dir, "sphere") {
        let v = |n: &str| value(&m, &r, n);
        let l: Vec<i128> = axes
            .iter()
            .map(|a| v(&format!("c_{a}")) - v(&format!("o_{a}")))
            .collect();
        let reach = v("reach");
        let l2_code: i128 = l.iter().map(|x| x * x).sum(); // 2·F_pos fraction bits
        let (hit, te, ov_reach) = (v("hit"), v("t_enter"), v("ov_reach"));
        if l.iter().any(|x| x.abs() > reach) || l2_code > reach * reach {
            beyond += 1;
            assert_eq!((hit, te, ov_reach), (1, 0, 1), "beyond the reach, row {r}");
            continue;
        }
        assert_eq!(ov_reach, 0, "within the reach, row {r}");
        // Inside: l·l against the inside code (F_sq); the unit may truncate l·l to F_sq first.
        let inside_code = v("inside") << (2 * fp - fsq);
        let step = 1i128 << (2 * fp - fsq);
        if l2_code <= inside_code {
            inside += 1;
            assert_eq!((hit, te), (1, 0), "origin may be inside, row {r}");
            continue;
        }
        if l2_code < inside_code + step {
            band += 1;
            continue;
        }
        let lf: Vec<f64> = l.iter().map(|&x| x as f64 * lsb(fp)).collect();
        let df: Vec<f64> = axes
            .iter()
            .map(|a| v(&format!("d_{a}")) as f64 * lsb(fd))
            .collect();
        let tca: f64 = (0..3).map(|k| lf[k] * df[k]).sum();
        let l2 = l2_code as f64 * lsb(2 * fp);
        // p² lives in the unsigned squares' format: a direction longer than 1 (adversarial
        // rows) can make l·l − t_ca² negative, which the format holds as 0.
        let p2 = (l2 - tca * tca).max(0.0);
        let thr = v("threshold") as f64 * lsb(fsq);
        let dt = v("delta_t") as f64 * lsb(ftca);
        // How far the unit's roundings can move p²: t_ca down by < 1 LSB moves t_ca² by
        // ≤ 2|t_ca|·lsb + lsb²; two truncations of squares; f64's own error on values ≤ 3·128².
        let slack = 2.0 * tca.abs() * lsb(ftca) + lsb(ftca).powi(2) + 2.0 * lsb(fsq) + 1e-10;
        if (p2 - thr).abs() <= slack {
            band += 1;
            continue;
        }
        if p2 > thr {
            culled += 1;
            assert_eq!((hit, te), (0, 0), "p² {p2} > T {thr}, row {r}");
            continue;
        }
        let s = (thr - p2).sqrt();
        // The root's own error: t_ca's rounding, √ of the p² slack, the root's floor.
        let tol = lsb(ftca) + slack.sqrt() + lsb(fsq / 2) + 2.0 * lsb(fte) + 1e-9;
        let far = tca + dt + s;
        if far.abs() <= tol {
            band += 1;
            continue;
        }
        judged += 1;
        if far < 0.0 {
            culled += 1;
            assert_eq!(
                (hit, te),
                (0, 0),
                "behind: t_ca + Δt + √(T − p²) = {far}, row {r}"
            );
            continue;
        }
        assert_eq!(hit, 1, "kept sphere culled, row {r}");
        let want = (tca - dt - s).max(0.0);
        let got = te as f64 * lsb(fte);
        assert!(
            (got - want).abs() <= tol,
            "entry {got} vs {want} (tolerance {tol:e}), row {r}"
        );
        assert_eq!(v("ov_t_enter"), 0, "row {r}");
    }
    println!(
        "sphere: {judged} entries judged, {culled} culled, {inside} inside, {beyond} beyond the reach, {band} in a rounding band"
    );
    assert!(judged > 500 && culled > 100 && inside > 10 && beyond > 0);
    assert!(band * 20 < judged, "too many rows undecided: {band}");
}
