//! `sim vectors`: the committed golden set regenerates byte for byte; the same seed gives the
//! same files and another seed changes only the random rows; every manifest describes its
//! rows (contiguous fields, widths, one hex line of the stated digits per row, the model's
//! latencies in manifest and package); rows decode, through the manifests alone, to values an
//! independent oracle accepts (square roots, sorts, round-half-even transform outputs); the
//! adversarial cases the issue names are present; and the frame capture behind the vectors
//! reproduces the functional fixed-point model's pixels exactly; `--walk-lanes` gives the
//! transform, reciprocal and walker-root tables their unit counts and leaves their rows alone.

mod common;
mod vector_files;

use common::process::run_sim;
use rtl_model::cycle::hw_config::UnitTimings;
use rtl_model::datapath::DatapathConfig;
use std::collections::BTreeSet;
use std::path::Path;
use std::time::Duration;
use svo_sim::models::fixed::{render_frame_fixed, FixedBuffer};
use svo_sim::models::reference::FrameInput;
use svo_sim::world::assets::{build_assets, effective_depths, Materialise};
use svo_sim::world::scene::Scene;
use vector_files::{field, manifest, rows, value, Tmp, GOLDEN_ARGS};

const TIMEOUT: Duration = Duration::from_secs(300);

/// Runs `sim vectors --out DIR args` and requires success.
fn vectors(dir: &Path, args: &[&str]) {
    let mut a = vec!["vectors", "--out", dir.to_str().expect("UTF-8 path")];
    a.extend_from_slice(args);
    let r = run_sim(&a, None, TIMEOUT);
    assert!(
        r.status.success(),
        "sim {a:?} failed\nstdout:\n{}\nstderr:\n{}",
        r.stdout,
        r.stderr
    );
}

/// File name → bytes of a folder (no subfolders expected).
fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| {
            let e = e.expect("folder entry");
            let name = e.file_name().to_string_lossy().into_owned();
            let bytes = std::fs::read(e.path()).expect("read a vector file");
            (name, bytes)
        })
        .collect()
}

#[test]
fn golden_set_regenerates_byte_for_byte() {
    let t = Tmp::new("golden");
    vectors(&t.dir, &GOLDEN_ARGS);
    let fresh = files(&t.dir);
    let mut committed = files(&vector_files::repo().join("vectors"));
    committed.remove("README.md");
    let (a, b): (BTreeSet<_>, BTreeSet<_>) = (fresh.keys().collect(), committed.keys().collect());
    assert_eq!(
        a, b,
        "file lists differ: regenerate vectors/ as vectors/README.md says"
    );
    let mut total = 0;
    for (name, bytes) in &fresh {
        total += bytes.len();
        assert!(
            committed[name] == *bytes,
            "vectors/{name} differs from a fresh `sim vectors {}`",
            GOLDEN_ARGS.join(" ")
        );
    }
    println!(
        "golden set: {} files, {} bytes ({:.0} KB)",
        fresh.len(),
        total,
        total as f64 / 1024.0
    );
    // About 810 KB since issue 15: 440 KB of it are the sorter's rows of a whole ray (32 keys,
    // 650 digits a row), 256 of them the network's zero-one inputs; about 90 KB the walker's
    // concatenated memory (walker_nodes.hex, walker_attrs.hex) and per-row cycle predictions.
    assert!(
        total < 900 * 1024,
        "the golden set must stay small: {total} bytes"
    );
}

#[test]
fn same_seed_same_files_other_seed_other_random_rows() {
    let args = [
        "--count", "300", "--width", "12", "--height", "8", "--depth", "4",
    ];
    let (a, b, c) = (Tmp::new("seed_a"), Tmp::new("seed_b"), Tmp::new("seed_c"));
    vectors(&a.dir, &[&args[..], &["--seed", "5"]].concat());
    vectors(&b.dir, &[&args[..], &["--seed", "5"]].concat());
    vectors(&c.dir, &[&args[..], &["--seed", "6"]].concat());
    let (fa, fb, fc) = (files(&a.dir), files(&b.dir), files(&c.dir));
    assert_eq!(fa, fb, "two runs with the same seed differ");
    assert_ne!(fa, fc, "another seed gives the same files");
    for unit in [
        "sqrt",
        "reciprocal",
        "transform",
        "sphere",
        "sorter",
        "raygen",
    ] {
        let m = manifest(&a.dir, unit);
        let (ra, rc) = (rows(&a.dir, unit), rows(&c.dir, unit));
        let blocks = m["rows"].as_array().expect("rows[]");
        for b in blocks {
            let (first, count) = (
                b["first"].as_u64().unwrap() as usize,
                b["count"].as_u64().unwrap() as usize,
            );
            let same = ra[first..first + count] == rc[first..first + count];
            match b["origin"].as_str() {
                Some("random") => {
                    assert!(!same, "{unit}: the seed does not change its random rows")
                }
                _ => assert!(same, "{unit}: the seed changed {} rows", b["origin"]),
            }
        }
    }
}

#[test]
fn walk_lanes_give_the_units_side_by_side_and_the_same_rows() {
    // Two walk-issue lanes: two transforms, six reciprocals and two walker roots, the rows
    // unchanged.
    let args = [
        "--count", "40", "--width", "12", "--height", "8", "--depth", "4",
    ];
    let (one, two) = (Tmp::new("lanes_1"), Tmp::new("lanes_2"));
    vectors(&one.dir, &[&args[..], &["--walk-lanes", "1"]].concat());
    vectors(&two.dir, &[&args[..], &["--walk-lanes", "2"]].concat());
    for (unit, units) in [("transform", 2), ("reciprocal", 6), ("walker_root", 2)] {
        assert_eq!(rows(&one.dir, unit), rows(&two.dir, unit), "{unit}: rows");
        let m = manifest(&two.dir, unit);
        assert_eq!(m["parameters"]["units"], units, "{unit}");
        assert_eq!(manifest(&one.dir, unit)["parameters"]["units"], units / 2);
        let pkg = std::fs::read_to_string(two.dir.join(format!("{unit}_pkg.sv"))).unwrap();
        let want = format!("localparam int UNITS = {units};");
        assert!(pkg.contains(&want), "{unit}_pkg.sv lacks {want}");
    }
    // Other units are not walk-issue units: no unit count.
    assert!(manifest(&two.dir, "sphere")["parameters"]
        .get("units")
        .is_none());
    let index: serde_json::Value =
        serde_json::from_slice(&std::fs::read(two.dir.join("index.json")).unwrap()).unwrap();
    assert_eq!(index["walk_lanes"], 2);
    // index.json's table list says how many instances each walk-issue bench drives.
    let units: Vec<(String, u64)> = index["tables"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|t| Some((t["name"].as_str()?.to_string(), t["units"].as_u64()?)))
        .collect();
    assert_eq!(
        units,
        [("transform", 2), ("reciprocal", 6), ("walker_root", 2)]
            .map(|(n, u)| (n.to_string(), u))
            .to_vec(),
        "index.json tables' units"
    );
    // The car has 8 instances: its pipeline keeps both lanes.
    let lanes = index["elaboration"]["decisions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|d| d["unit"] == "walk_lanes")
        .expect("walk_lanes decision");
    assert_eq!(lanes["action"], "kept", "{lanes}");
    let bad = run_sim(
        &[
            "vectors",
            "--out",
            two.dir.to_str().unwrap(),
            "--walk-lanes",
            "0",
        ],
        None,
        TIMEOUT,
    );
    assert!(!bad.status.success());
    assert!(
        bad.stderr
            .contains("--walk-lanes 0 is out of range (1 to 64)"),
        "{}",
        bad.stderr
    );
}

/// A set made once for the checks below.
fn small_set(t: &Tmp) {
    vectors(
        &t.dir,
        &[
            "--count", "2000", "--seed", "11", "--width", "16", "--height", "12", "--depth", "5",
        ],
    );
}

#[test]
fn manifests_describe_their_rows() {
    let t = Tmp::new("manifests");
    small_set(&t);
    let index: serde_json::Value =
        serde_json::from_slice(&std::fs::read(t.dir.join("index.json")).expect("index.json"))
            .expect("index.json is JSON");
    let timings = UnitTimings::for_datapath(&DatapathConfig::default());
    let model_latency = [
        ("sqrt", timings.sqrt.latency_cycles),
        ("reciprocal", timings.reciprocal.latency_cycles),
        ("transform", timings.transform.latency_cycles),
        (
            "sphere",
            timings.sphere.latency_cycles + timings.sqrt.latency_cycles,
        ),
        ("sorter", timings.sorter.latency_cycles),
        ("raygen", timings.raygen.latency_cycles),
        // svo_hit_pack alone; units.hit_pack is the normal unit and the packer together.
        (
            "hit_record",
            timings.hit_pack.latency_cycles - rtl_model::units::normal::LATENCY_CYCLES,
        ),
        ("normal", rtl_model::units::normal::LATENCY_CYCLES),
        ("walker_root", timings.walker_root.latency_cycles),
    ];
    let tables = index["tables"].as_array().expect("tables[]");
    assert!(tables.len() >= 20);
    for tb in tables {
        let name = tb["name"].as_str().expect("name");
        let m = manifest(&t.dir, name);
        let bits = m["word_bits"].as_u64().expect("word_bits") as u32;
        let digits = bits.div_ceil(4) as usize;
        assert_eq!(m["hex_digits"].as_u64(), Some(digits as u64), "{name}");
        // Fields tile the word from bit 0 up.
        let mut next = 0;
        for f in m["fields"].as_array().expect("fields[]") {
            assert_eq!(f["offset"].as_u64(), Some(next), "{name}.{}", f["name"]);
            next += f["width"].as_u64().expect("width");
            if f["kind"] == "fixed" {
                for key in ["format", "quantisation", "overflow"] {
                    assert!(f[key].is_string(), "{name}.{}: no {key}", f["name"]);
                }
                assert!(f["quantisation"]
                    .as_str()
                    .is_some_and(|q| q.starts_with("AP_")));
            }
        }
        assert_eq!(next, u64::from(bits), "{name}: fields do not fill the word");
        let r = rows(&t.dir, name);
        assert_eq!(
            r.len() as u64,
            m["depth"].as_u64().expect("depth"),
            "{name}"
        );
        assert!(r
            .iter()
            .all(|l| l.len() == digits && l.chars().all(|c| c.is_ascii_hexdigit())));
        // The package states the same geometry (and latency) as the manifest.
        if let Some(p) = m["package_file"].as_str() {
            let pkg = std::fs::read_to_string(t.dir.join(p)).expect("package");
            assert!(
                pkg.contains(&format!("localparam int WORD_BITS = {bits};")),
                "{p}"
            );
            assert!(
                pkg.contains(&format!("localparam int DEPTH = {};", r.len())),
                "{p}"
            );
        }
    }
    for (unit, lat) in model_latency {
        let m = manifest(&t.dir, unit);
        assert_eq!(
            m["timing"]["latency_cycles"].as_u64(),
            Some(u64::from(lat)),
            "{unit}"
        );
        let pkg = std::fs::read_to_string(t.dir.join(format!("{unit}_pkg.sv"))).expect("package");
        assert!(
            pkg.contains(&format!("localparam int LATENCY = {lat};")),
            "{unit}"
        );
        let adversarial = m["rows"][0]["count"].as_u64().unwrap_or(0);
        assert_eq!(m["rows"][0]["origin"], "adversarial");
        assert!(
            adversarial > 0 && m["rows"][1]["origin"] == "captured",
            "{unit}"
        );
    }
}

#[test]
fn rows_decode_to_what_independent_oracles_expect() {
    let t = Tmp::new("oracles");
    small_set(&t);
    // Square root: root² ≤ x < (root + 1)² (48 fraction bits in, 24 out: no shift).
    let m = manifest(&t.dir, "sqrt");
    for r in rows(&t.dir, "sqrt") {
        let (x, root) = (value(&m, &r, "x") as u128, value(&m, &r, "root") as u128);
        assert!(
            root * root <= x && (root + 1) * (root + 1) > x,
            "sqrt row {r}"
        );
    }
    // Sorter: the outputs are the inputs sorted by (t, id).
    let m = manifest(&t.dir, "sorter");
    for r in rows(&t.dir, "sorter") {
        let n = value(&m, &r, "count") as usize;
        let mut keys: Vec<(i128, i128)> = (0..n)
            .map(|k| {
                (
                    value(&m, &r, &format!("in_t{k}")),
                    value(&m, &r, &format!("in_id{k}")),
                )
            })
            .collect();
        keys.sort();
        for (k, key) in keys.iter().enumerate() {
            let got = (
                value(&m, &r, &format!("out_t{k}")),
                value(&m, &r, &format!("out_id{k}")),
            );
            assert_eq!(got, *key, "sorter row {r}");
        }
        // The cycle model's timing, against docs/units/sorter.md §6 by hand (D = 10 at the
        // default N = 16; at most 4N keys, so P = ⌈log₂ C⌉ ≤ 2).
        let (lanes, depth) = sorter_network();
        let (c, n64) = (n.div_ceil(lanes).max(1) as i128, n as i128);
        let p = if c > 2 { 2 } else { c - 1 };
        let (cycles, busy) = if c == 1 {
            (depth, 1)
        } else {
            (c - 1 + depth + p * (n64 + 1), c + p * (n64 + 1))
        };
        assert_eq!(
            (value(&m, &r, "cycles"), value(&m, &r, "busy")),
            (cycles, busy),
            "sorter row {r} ({n} keys)"
        );
    }
    // Transform direction: Σ_j R_jk d_j rounded half to even by 30 bits, saturated.
    let m = manifest(&t.dir, "transform");
    let axes = ["x", "y", "z"];
    for r in rows(&t.dir, "transform") {
        for (k, ak) in axes.iter().enumerate() {
            let sum: i128 = (0..3)
                .map(|j| {
                    value(&m, &r, &format!("axis{k}_{}", axes[j]))
                        * value(&m, &r, &format!("d_{}", axes[j]))
                })
                .sum();
            let (fl, rem) = (sum >> 30, sum & ((1 << 30) - 1));
            let up = rem > 1 << 29 || (rem == 1 << 29 && fl & 1 == 1);
            let want = (fl + i128::from(up)).clamp(-(1 << 31), (1 << 31) - 1);
            assert_eq!(
                value(&m, &r, &format!("local_d_{ak}")),
                want,
                "transform row {r}"
            );
            assert_eq!(value(&m, &r, &format!("sign_{ak}")), i128::from(sum < 0));
        }
    }
    // Walker root, from the manifest's formats: o' = ∓o, t = ⌊(±e − o')·inv⌋ into t's
    // fraction bits, saturated to t (one bit narrower than the field), the field's extreme
    // codes on zero axes; it enters when no zero axis is outside its slab and
    // max t0 < min t1, min t1 > 0.
    let m = manifest(&t.dir, "walker_root");
    let frac = |name: &str| {
        m["fields"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["name"] == name)
            .unwrap()["frac"]
            .as_i64()
            .unwrap()
    };
    let shift = frac("o_x") + frac("inv_x") - frac("t0_x");
    let tw = field(&m, "t0_x").1 - 1;
    let (t_min, t_max) = (-(1i128 << (tw - 1)), (1i128 << (tw - 1)) - 1);
    let (neg_inf, pos_inf) = (-(1i128 << tw), (1i128 << tw) - 1);
    let (mut entered, mut zero_axes) = (0, 0);
    for r in rows(&t.dir, "walker_root") {
        let mut enter = true;
        let (mut t0, mut t1) = ([0i128; 3], [0i128; 3]);
        for (k, ak) in axes.iter().enumerate() {
            let v = |f: &str| value(&m, &r, &format!("{f}_{ak}"));
            let o = if v("negative") == 1 { -v("o") } else { v("o") };
            let e = v("half");
            if v("zero") == 1 {
                zero_axes += 1;
                enter &= -e <= o && o < e;
                (t0[k], t1[k]) = (neg_inf, pos_inf);
            } else {
                t0[k] = (((-e - o) * v("inv")) >> shift).clamp(t_min, t_max);
                t1[k] = (((e - o) * v("inv")) >> shift).clamp(t_min, t_max);
            }
            assert_eq!(v("om"), o, "walker_root row {r}: om_{ak}");
            assert_eq!(
                (v("t0"), v("t1")),
                (t0[k], t1[k]),
                "walker_root row {r}: axis {ak}"
            );
        }
        let (enter_t, exit_t) = (*t0.iter().max().unwrap(), *t1.iter().min().unwrap());
        enter &= enter_t < exit_t && exit_t > 0;
        assert_eq!(
            value(&m, &r, "enter"),
            i128::from(enter),
            "walker_root row {r}"
        );
        entered += i32::from(enter);
    }
    assert!(
        entered > 100 && zero_axes > 20,
        "walker_root: {entered} rows enter, {zero_axes} zero axes"
    );
}

#[test]
fn the_adversarial_cases_the_issue_names_are_present() {
    let t = Tmp::new("adversarial");
    small_set(&t);
    let find = |unit: &str, pred: &dyn Fn(&serde_json::Value, &str) -> bool| {
        let m = manifest(&t.dir, unit);
        rows(&t.dir, unit).iter().any(|r| pred(&m, r))
    };
    // 0 and −0: the reciprocal of code 0 with either sign bit; a transform output −0; an f64
    // −0.0 into the direction table.
    for neg in [0, 1] {
        assert!(find("reciprocal", &|m, r| value(m, r, "d") == 0
            && value(m, r, "sign_negative") == neg
            && value(m, r, "negative") == neg
            && value(m, r, "zero") == 1));
    }
    assert!(find("transform", &|m, r| value(m, r, "local_d_x") == 0
        && value(m, r, "sign_x") == 1));
    assert!(find("raygen", &|m, r| value(m, r, "dir_f64_x") as u64
        == (-0.0f64).to_bits()));
    // Saturation edges: saturated transform outputs, the largest square-root radicand.
    assert!(find("transform", &|m, r| value(m, r, "ov_origin") == 1));
    assert!(find("sqrt", &|m, r| value(m, r, "x") == i128::from(i64::MAX)));
    assert!(find("raygen", &|m, r| value(m, r, "ov_dir") == 1));
    // Sorter ties: equal entry distances, ids out of order on the way in, a full network.
    let lanes = sorter_network().0;
    assert!(find("sorter", &|m, r| value(m, r, "count")
        == lanes as i128
        && (0..lanes).all(
            |k| value(m, r, &format!("in_t{k}")) == value(m, r, "in_t0")
        )
        && value(m, r, "in_id0") > value(m, r, "in_id1")));
    // Grazing spheres: the same ray and centre, kept at threshold T and culled at T − 1.
    let m = manifest(&t.dir, "sphere");
    let rs = rows(&t.dir, "sphere");
    let key = |r: &str| {
        [
            "o_x", "o_y", "o_z", "d_x", "d_y", "d_z", "c_x", "c_y", "c_z",
        ]
        .map(|f| value(&m, r, f))
    };
    let grazing = rs.iter().any(|a| {
        value(&m, a, "hit") == 1
            && rs.iter().any(|b| {
                key(a) == key(b)
                    && value(&m, b, "threshold") == value(&m, a, "threshold") - 1
                    && value(&m, b, "hit") == 0
            })
    });
    assert!(grazing, "no grazing pair in sphere.hex");
    assert!(find("sphere", &|m, r| value(m, r, "ov_reach") == 1));
    // Axis-parallel rays: sphere rows with two zero direction codes, walks with two zero axes.
    assert!(find("sphere", &|m, r| value(m, r, "d_y") == 0
        && value(m, r, "d_z") == 0
        && value(m, r, "hit") == 1));
    assert!(find("walker", &|m, r| value(m, r, "zero_y") == 1
        && value(m, r, "zero_z") == 1
        && value(m, r, "negative_y") == 1
        && value(m, r, "outcome") == 1));
    let (off, w, _) = field(&manifest(&t.dir, "hit_record"), "word");
    assert_eq!((off > 0, w), (true, 72));
}

#[test]
fn capture_reproduces_the_functional_model() {
    let dp = DatapathConfig::default();
    let mut scene = Scene::default_car().expect("default scene");
    scene.set_resolution(40, 24).expect("resolution");
    let depths = effective_depths(&scene, Some(6)).expect("depths");
    let assets = build_assets(&scene, &depths, Materialise::Auto).expect("assets");
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    for frame in [0, 17] {
        let state = scene.frame_state(frame, &half).expect("state");
        let cap = svo_sim::studies::vectors::capture::capture_frame(&scene, &assets, &state, &dp)
            .expect("capture");
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &state,
        };
        let mut buffer = FixedBuffer::new(40, 24);
        render_frame_fixed(&input, &mut buffer, &dp, false).expect("fixed frame");
        assert_eq!(cap.pixels.len(), buffer.records.len());
        let mut hits = 0;
        for (k, (p, rec)) in cap.pixels.iter().zip(&buffer.records).enumerate() {
            assert_eq!(
                p.word, rec.word,
                "frame {frame} pixel {k}: packed words differ"
            );
            assert_eq!(
                (p.hit, p.t, p.voxel),
                (rec.hit, rec.t, rec.voxel),
                "pixel {k}"
            );
            hits += usize::from(p.hit);
        }
        assert!(hits > 50, "frame {frame}: only {hits} hits");
        assert_eq!(cap.captured.raygen.len(), 40 * 24);
        assert_eq!(
            cap.captured.sphere.len(),
            40 * 24 * scene.instance_asset.len()
        );
        assert_eq!(
            cap.captured.reciprocal.len(),
            3 * cap.captured.transform.len()
        );
    }
}

/// The default datapath's sorting network, by hand: (lanes, layers). Green's 16-lane network
/// has 10 layers, the 8-lane one 6 (docs/units/sorter.md); another width needs its own entry.
fn sorter_network() -> (usize, i128) {
    match DatapathConfig::default().sorter.n {
        8 => (8, 6),
        16 => (16, 10),
        n => panic!("no hand-counted network depth for {n} lanes"),
    }
}
