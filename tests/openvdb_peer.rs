//! OpenVDB as a peer of the reference walk: `sim render` and the C++ program of
//! `tests/openvdb_peer/peer.cpp` (its own `.vox` reader, OpenVDB 10's VolumeRayIntersector and
//! voxel DDA; no code shared with the project) render the same shared models with the same
//! cameras, and every pixel is compared: hit or miss, voxel (model indices), t.
//!
//! Each difference is classified in exact rational arithmetic on the pixel's f64 ray (both
//! programs must produce the same ray bit for bit, which is checked first):
//! - **tie**: the exact ray only touches one of the reported voxels at an edge or a corner
//!   (its segment in the closed cube has length 0), or enters both at the same exact point;
//! - **sliver**: the exact ray passes through the voxel one side missed for a length of at
//!   most [`SLIVER`] voxels, misses the voxel one side reported by at most that much, or
//!   enters the two voxels less than that apart, so f64 rounding decides;
//! - **real**: anything else, including a ray lying in a voxel plane that goes to another
//!   cell than the plane rule's (`docs/render.md` §3). Required: 0.
//!
//! Ties and slivers are capped per camera at the counts measured ([`CAPS`]), so a regression in
//! either walk that does not yet make a real difference still fails.
//!
//! The 20 cameras (five models, four cameras each) and the peer's g++ build are the library's
//! (`svo_sim::run::peer_bench`, which `sim bench peer` times): the test checks the very images
//! the benchmark times. The peer is built once with g++ against Debian's libopenvdb-dev 10 (plus
//! libboost-dev and libtbb-dev, which it pulls in) into Cargo's test temp folder, keyed by its
//! source and flags. Without
//! g++ or the OpenVDB headers, or without `../shared/data/vox`, the test skips with a `SKIPPED`
//! line (tests/common/skip.rs); under `CI=true` it fails instead. The Mrays/s it prints are indicative only (small
//! images, the test profile); `docs/render.md` §7 gives the benchmark command.

use std::path::{Path, PathBuf};
use std::process::Command;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::ToPrimitive;
use svo_sim::run::peer_bench;

mod common;

/// Largest exact length (voxels) of a segment, gap or entry separation that f64 rounding may
/// decide: the t of both programs are within 1e-12 voxels of each other on these scenes (at
/// most a few hundred voxels from the camera), and OpenVDB's VolumeRayIntersector restarts a
/// ray 1e-9 after each span of leaf nodes without a hit.
const SLIVER: f64 = 1e-8;

/// Ties and slivers allowed per camera, at what was measured (docs/render.md §7): `model/camera`,
/// then `[ties, slivers]` in the test's images and in benchmark mode's 8× larger ones. Every
/// camera not listed allows none. Both programs are deterministic (same rays, f64 without
/// fused multiply-add), so the counts are exact and any more is a regression of one of the
/// two walks (e.g. an edge or plane rule changed) that does not yet reach a real difference.
const CAPS: &[(&str, [usize; 2], [usize; 2])] = &[
    ("scene_store8/axis pinhole, odd size", [0, 2], [6, 14]),
    ("chr_mayor/axis pinhole, odd size", [0, 0], [10, 2]),
    ("alien_saucer2a/axis pinhole, odd size", [0, 0], [1, 7]),
    ("scene_park/axis pinhole, odd size", [0, 14], [3, 20]),
];

/// The caps of camera `key` (`model/camera`): `[ties, slivers]`.
fn cap_of(key: &str, bench: bool) -> [usize; 2] {
    CAPS.iter()
        .find(|(k, _, _)| *k == key)
        .map_or([0, 0], |&(_, test, big)| if bench { big } else { test })
}

/// Names each of ties and slivers over its cap, for the final assertion.
fn over_cap(key: &str, ties: usize, slivers: usize, cap: [usize; 2]) -> Vec<String> {
    let mut out = Vec::new();
    if ties > cap[0] {
        out.push(format!(
            "{key}: {ties} ties, more than its cap of {}",
            cap[0]
        ));
    }
    if slivers > cap[1] {
        out.push(format!(
            "{key}: {slivers} slivers, more than its cap of {}",
            cap[1]
        ));
    }
    out
}

/// Builds the peer with the library's recipe (`svo_sim::run::peer_bench::build_peer`: the same
/// embedded source and flags as `sim bench peer`) into Cargo's test temp folder, or reuses the
/// build of the same source there, and returns its path; `None` after a visible skip (a failure
/// under CI=true) when g++ or the OpenVDB headers are missing.
fn build_peer() -> Option<PathBuf> {
    if !common::skip::tools(&["g++"], "g++")
        || !common::skip::header(peer_bench::OPENVDB_HEADER, "libopenvdb-dev libboost-dev")
        || !common::skip::header("/usr/include/boost/version.hpp", "libboost-dev")
    {
        return None;
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("openvdb_peer");
    Some(peer_bench::build_peer(&dir).unwrap_or_else(|e| panic!("{e}")))
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Rec {
    origin: [f64; 3],
    dir: [f64; 3],
    t: f64,
    voxel: [i32; 3],
    hit: bool,
}

fn read_dump(path: &Path, w: u32, h: u32) -> Vec<Rec> {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&b[..8], b"SVOMHIT1", "{}", path.display());
    let u32_at = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    assert_eq!(
        (u32_at(8), u32_at(12), u32_at(16), u32_at(20)),
        (1, w, h, 80)
    );
    assert_eq!(b.len(), 32 + 80 * (w * h) as usize, "{}", path.display());
    let f = |o: usize| f64::from_le_bytes(b[o..o + 8].try_into().unwrap());
    let i = |o: usize| i32::from_le_bytes(b[o..o + 4].try_into().unwrap());
    (0..(w * h) as usize)
        .map(|k| {
            let r = 32 + 80 * k;
            let rec = Rec {
                origin: [f(r), f(r + 8), f(r + 16)],
                dir: [f(r + 24), f(r + 32), f(r + 40)],
                t: f(r + 48),
                voxel: [i(r + 56), i(r + 60), i(r + 64)],
                hit: b[r + 68] == 1,
            };
            let (px, py) = (
                u16::from_le_bytes([b[r + 76], b[r + 77]]),
                u16::from_le_bytes([b[r + 78], b[r + 79]]),
            );
            assert_eq!((u32::from(px), u32::from(py)), (k as u32 % w, k as u32 / w));
            assert!(rec.hit || rec.t == -1.0, "a miss has t = -1");
            rec
        })
        .collect()
}

fn q(v: f64) -> BigRational {
    BigRational::from_float(v).expect("finite")
}

fn qi(v: i64) -> BigRational {
    BigRational::from_integer(BigInt::from(v))
}

/// The exact ray's part in the cube of voxel `v`, for t ≥ 0.
enum Seg {
    /// The ray misses the cube; by this much (t units, or distance for a ray parallel to
    /// the cube's faces).
    Empty(BigRational),
    /// The ray lies in the cube's upper plane on an axis it does not move along: the plane
    /// rule gives it to the next cell, so reporting this voxel breaks the contract.
    UpperPlane,
    /// The ray touches the closed cube at one point (an edge or a corner).
    Touch,
    /// The ray runs through the cube from `enter` for `len`.
    Len {
        enter: BigRational,
        len: BigRational,
    },
}

fn segment(o: [f64; 3], d: [f64; 3], v: [i32; 3]) -> Seg {
    let mut lo = qi(0);
    let mut hi: Option<BigRational> = None;
    for k in 0..3 {
        let (a, b) = (qi(i64::from(v[k])), qi(i64::from(v[k]) + 1));
        let ok = q(o[k]);
        if d[k] == 0.0 {
            // Half-open [v, v + 1): the plane rule (floor).
            if ok == b {
                return Seg::UpperPlane;
            }
            if ok < a {
                return Seg::Empty(a - ok);
            }
            if ok > b {
                return Seg::Empty(ok - b);
            }
            continue;
        }
        let dk = q(d[k]);
        let (mut ta, mut tb) = ((&a - &ok) / &dk, (&b - &ok) / &dk);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        if ta > lo {
            lo = ta;
        }
        hi = Some(match hi {
            Some(h) if h < tb => h,
            _ => tb,
        });
    }
    let hi = hi.expect("a unit direction has a non-zero component");
    if hi < lo {
        Seg::Empty(lo - hi)
    } else if hi == lo {
        Seg::Touch
    } else {
        Seg::Len {
            len: &hi - &lo,
            enter: lo,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Agree,
    Tie,
    Sliver,
    Real,
}

thread_local! {
    /// Largest measure (voxels) that classified a pixel as a sliver, for the table.
    static MAX_SLIVER: std::cell::Cell<f64> = const { std::cell::Cell::new(0.0) };
}

fn small(x: &BigRational) -> bool {
    let is = *x <= q(SLIVER);
    if is {
        let v = x.to_f64().unwrap_or(f64::NAN);
        MAX_SLIVER.with(|m| m.set(m.get().max(v)));
    }
    is
}

/// One side reports voxel `v`, the other a miss.
fn classify_hit_miss(o: [f64; 3], d: [f64; 3], v: [i32; 3]) -> Class {
    match segment(o, d, v) {
        Seg::Touch => Class::Tie,
        Seg::UpperPlane => Class::Real,
        Seg::Empty(gap) => {
            if small(&gap) {
                Class::Sliver
            } else {
                Class::Real
            }
        }
        Seg::Len { len, .. } => {
            if small(&len) {
                Class::Sliver
            } else {
                Class::Real
            }
        }
    }
}

fn classify(r: &Rec, p: &Rec) -> Class {
    let (o, d) = (r.origin, r.dir);
    match (r.hit, p.hit) {
        (false, false) => Class::Agree,
        (true, false) => classify_hit_miss(o, d, r.voxel),
        (false, true) => classify_hit_miss(o, d, p.voxel),
        (true, true) if r.voxel == p.voxel => {
            if (r.t - p.t).abs() <= 1e-9 * r.t.abs().max(1.0) {
                Class::Agree
            } else {
                Class::Real
            }
        }
        (true, true) => {
            let (sr, sp) = (segment(o, d, r.voxel), segment(o, d, p.voxel));
            match (&sr, &sp) {
                (Seg::UpperPlane, _) | (_, Seg::UpperPlane) => Class::Real,
                (Seg::Empty(g), _) | (_, Seg::Empty(g)) => {
                    let other_small = match (&sr, &sp) {
                        (Seg::Empty(a), Seg::Empty(b)) => small(a) && small(b),
                        _ => true,
                    };
                    if small(g) && other_small {
                        Class::Sliver
                    } else {
                        Class::Real
                    }
                }
                (Seg::Touch, _) | (_, Seg::Touch) => Class::Tie,
                (Seg::Len { enter: er, len: lr }, Seg::Len { enter: ep, len: lp }) => {
                    if er == ep {
                        return Class::Tie;
                    }
                    // The side that reported the later voxel skipped the earlier one.
                    let (first_len, sep) = if er < ep {
                        (lr, ep - er)
                    } else {
                        (lp, er - ep)
                    };
                    if small(first_len) || small(&sep) {
                        Class::Sliver
                    } else {
                        Class::Real
                    }
                }
            }
        }
    }
}

fn peer_value<'a>(stdout: &'a str, key: &str) -> Vec<&'a str> {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix(key).map(|r| r.split_whitespace().collect()))
        .unwrap_or_else(|| panic!("peer printed no {key}"))
}

fn number_before(text: &str, suffix: &str) -> f64 {
    let at = text
        .find(suffix)
        .unwrap_or_else(|| panic!("no {suffix:?} in {text}"));
    text[..at]
        .split_whitespace()
        .last()
        .and_then(|w| w.trim_matches(|c| c == '(' || c == ',').parse().ok())
        .unwrap_or_else(|| panic!("no number before {suffix:?}"))
}

fn run_ok(cmd: &mut Command, what: &str) -> String {
    let out = cmd.output().unwrap_or_else(|e| panic!("{what}: {e}"));
    assert!(
        out.status.success(),
        "{what} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8")
}

fn v3(v: [f64; 3]) -> String {
    format!("{},{},{}", v[0], v[1], v[2])
}

#[test]
fn reference_walk_agrees_with_openvdb() {
    let Some(vox_dir) = common::shared_vox_dir() else {
        return;
    };
    let Some(peer) = build_peer() else {
        return;
    };
    // Benchmark mode (docs/render.md §7): larger images, best of 3 trace times for both
    // tracers, and the sim binary of SVO_SIM_BIN (e.g. target/release/sim) if given.
    let bench = std::env::var("SVO_PEER_BENCH").as_deref() == Ok("1");
    let sim_bin = std::env::var("SVO_SIM_BIN").unwrap_or_else(|_| env!("CARGO_BIN_EXE_sim").into());
    let sim = sim_bin.as_str();
    let repeat = if bench { "3" } else { "1" };
    // SVO_PEER_ONLY=veh_bus/oblique: only the cameras whose `model/camera` contains this text
    // (one camera of the 20-camera benchmark takes seconds; all of them, minutes).
    let only = std::env::var("SVO_PEER_ONLY").ok();
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("openvdb_peer_run_{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    println!(
        "{:<15} {:<23} {:>6} {:>6} {:>5} {:>7} {:>5} {:>9} {:>10} {:>8} {:>8} {:>8} {:>6}",
        "model",
        "camera",
        "pixels",
        "agree",
        "ties",
        "slivers",
        "real",
        "max |dt|",
        "max sliver",
        "ref Mr/s",
        "vdb Mr/s",
        "vdb med",
        "ratio"
    );
    let mut total_real = 0;
    let mut over: Vec<String> = Vec::new();
    let mut first_real: Vec<String> = Vec::new();
    for m in peer_bench::MODELS {
        let path = vox_dir.join(m);
        // The box first (a one-pixel render), to place the cameras.
        let s = run_ok(
            Command::new(sim).args(["render"]).arg(&path).args([
                "--eye",
                "1000,1000,1000",
                "--look",
                "0,0,0",
                "--width",
                "1",
                "--height",
                "1",
            ]),
            "sim render",
        );
        let (mn, mx) = peer_bench::parse_box(&s, "sim render").unwrap_or_else(|e| panic!("{e}"));
        for cam in peer_bench::cameras(mn, mx, if bench { 8 } else { 1 }) {
            let key = format!("{}/{}", m.trim_end_matches(".vox"), cam.name);
            if only.as_ref().is_some_and(|o| !key.contains(o.as_str())) {
                continue;
            }
            let ours = tmp.join("ours.bin");
            let theirs = tmp.join("peer.bin");
            let (w, h) = (cam.w.to_string(), cam.h.to_string());
            let mut c_ref = Command::new(sim);
            let c = &mut c_ref;
            c.arg("render").arg(&path).args([
                "--eye",
                &v3(cam.eye),
                "--look",
                &v3(cam.look),
                "--up",
                &v3(cam.up),
                "--width",
                &w,
                "--height",
                &h,
                "--threads",
                "2",
                "--repeat",
                repeat,
            ]);
            if cam.ortho {
                c.args(["--ortho", &cam.value.to_string()]);
            } else {
                c.args(["--fov", &cam.value.to_string()]);
            }
            c.arg("--dump-hits").arg(&ours);
            let s = run_ok(c, "sim render");
            let mut c_peer = Command::new(&peer);
            let c = &mut c_peer;
            c.arg(&path).arg(&theirs).args([&w, &h]);
            for v in [cam.eye, cam.look, cam.up] {
                c.args(v.map(|x| x.to_string()));
            }
            c.args([
                if cam.ortho { "ortho" } else { "pinhole" },
                &cam.value.to_string(),
                "2",
                repeat,
            ]);
            let p = run_ok(c, "OpenVDB peer");
            // Speeds: in benchmark mode a second run of each in the other order (peer, then
            // reference), so neither always runs first on a loaded machine; the best of both.
            let mut ref_speed = number_before(&s, "Mrays/s");
            let mut vdb_best: f64 = peer_value(&p, "trace_seconds")[0].parse().unwrap();
            let mut vdb_median: f64 = peer_value(&p, "trace_median_seconds")[0].parse().unwrap();
            if bench {
                let p2 = run_ok(&mut c_peer, "OpenVDB peer");
                let s2 = run_ok(&mut c_ref, "sim render");
                ref_speed = ref_speed.max(number_before(&s2, "Mrays/s"));
                let best2: f64 = peer_value(&p2, "trace_seconds")[0].parse().unwrap();
                let median2: f64 = peer_value(&p2, "trace_median_seconds")[0].parse().unwrap();
                vdb_best = vdb_best.min(best2);
                vdb_median = vdb_median.min(median2);
            }
            // Both read the model the same way: the same solid box, voxels and surface.
            let (pmn, pmx) = (peer_value(&p, "solid_min"), peer_value(&p, "solid_max"));
            let parse3 =
                |v: Vec<&str>| -> Vec<i64> { v.iter().map(|x| x.parse().unwrap()).collect() };
            assert_eq!(
                (parse3(pmn), parse3(pmx)),
                (mn.to_vec(), mx.to_vec()),
                "{m}: solid box"
            );
            assert_eq!(
                peer_value(&p, "voxels")[0].parse::<f64>().unwrap(),
                number_before(&s, "solid voxels"),
                "{m}: solid voxel count"
            );
            assert_eq!(
                peer_value(&p, "surface")[0].parse::<f64>().unwrap(),
                number_before(&s, "surface leaves"),
                "{m}: surface voxel count"
            );
            let a = read_dump(&ours, cam.w, cam.h);
            let b = read_dump(&theirs, cam.w, cam.h);
            let mut counts = [0usize; 4];
            MAX_SLIVER.with(|m| m.set(0.0));
            let mut max_dt = 0f64;
            for (k, (r, pr)) in a.iter().zip(&b).enumerate() {
                let bits = |v: [f64; 3]| v.map(f64::to_bits);
                assert!(
                    bits(r.origin) == bits(pr.origin) && bits(r.dir) == bits(pr.dir),
                    "{m} {}: pixel {k}: the rays differ ({:?} {:?} against {:?} {:?}): the camera contracts disagree",
                    cam.name, r.origin, r.dir, pr.origin, pr.dir
                );
                let class = classify(r, pr);
                if class == Class::Agree && r.hit {
                    max_dt = max_dt.max((r.t - pr.t).abs());
                }
                if class == Class::Real && first_real.len() < 10 {
                    first_real.push(format!(
                        "{m} {} pixel ({}, {}): reference {r:?}, OpenVDB {pr:?}",
                        cam.name,
                        k as u32 % cam.w,
                        k as u32 / cam.w
                    ));
                }
                counts[class as usize] += 1;
            }
            let pixels = a.len();
            let vdb_speed = pixels as f64 / vdb_best.max(1e-9) / 1e6;
            let vdb_median_speed = pixels as f64 / vdb_median.max(1e-9) / 1e6;
            println!(
                "{:<15} {:<23} {:>6} {:>6} {:>5} {:>7} {:>5} {:>9.1e} {:>10.1e} {:>8.2} {:>8.2} {:>8.2} {:>6.2}",
                m.trim_end_matches(".vox"),
                cam.name,
                pixels,
                counts[0],
                counts[1],
                counts[2],
                counts[3],
                max_dt,
                MAX_SLIVER.with(|m| m.get()),
                ref_speed,
                vdb_speed,
                vdb_median_speed,
                ref_speed / vdb_speed
            );
            total_real += counts[3];
            over.extend(over_cap(&key, counts[1], counts[2], cap_of(&key, bench)));
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    assert!(
        over.is_empty(),
        "ties or slivers over their caps (a regression of one of the walks):\n{}",
        over.join("\n")
    );
    assert!(
        total_real == 0,
        "{total_real} real differences between the reference walk and OpenVDB; first:\n{}",
        first_real.join("\n")
    );
}

/// The classifier itself, on hand-made rays: a test that it can fail.
#[test]
fn classifier_separates_ties_slivers_and_real_differences() {
    let rec = |hit: bool, voxel: [i32; 3], t: f64, o: [f64; 3], d: [f64; 3]| Rec {
        origin: o,
        dir: d,
        t,
        voxel,
        hit,
    };
    let s = 0.5f64.sqrt();
    // Diagonal through the edge x = 1, y = 1 (z inside): voxels (0,1,0) and (1,0,0) are
    // touched at one point only.
    let (o, d) = ([0.0, 0.0, 0.5], [s, s, 0.0]);
    let r = rec(true, [1, 1, 0], s * 2.0, o, d);
    let p = rec(true, [0, 1, 0], s * 2.0, o, d);
    assert_eq!(classify(&r, &p), Class::Tie);
    // A ray in the plane x = 1 moving along y: the plane rule gives it to x = 1, so
    // reporting x = 0 is a real difference.
    let (o, d) = ([1.0, -3.0, 0.5], [0.0, 1.0, 0.0]);
    let r = rec(true, [1, 0, 0], 3.0, o, d);
    let p = rec(true, [0, 0, 0], 3.0, o, d);
    assert_eq!(classify(&r, &p), Class::Real);
    assert_eq!(classify(&r, &rec(false, [0; 3], -1.0, o, d)), Class::Real);
    // Clipping a corner of voxel (0,0,0) by 1e-12: a sliver.
    let eps = 1e-12;
    let (o, d) = ([-1.0, 1.0 - eps - 1.0, 0.5], [s, s, 0.0]);
    let p = rec(true, [0, 0, 0], 1.0, o, d);
    assert_eq!(classify(&rec(false, [0; 3], -1.0, o, d), &p), Class::Sliver);
    // Missing voxel (0,0,0) by a clear margin while the other side hits it: real.
    let (o, d) = ([-1.0, 0.5, 0.5], [1.0, 0.0, 0.0]);
    assert_eq!(
        classify(
            &rec(false, [0; 3], -1.0, o, d),
            &rec(true, [0, 0, 0], 1.0, o, d)
        ),
        Class::Real
    );
    assert_eq!(
        classify(
            &rec(true, [0, 0, 0], 1.0, o, d),
            &rec(true, [0, 0, 0], 1.0, o, d)
        ),
        Class::Agree
    );
}

/// The caps: a count at its cap passes, one more fails with exactly that message, and a
/// camera without an entry allows none.
#[test]
fn ties_and_slivers_over_their_caps_fail() {
    let key = "scene_park/axis pinhole, odd size";
    assert_eq!(cap_of(key, false), [0, 14]);
    assert_eq!(cap_of(key, true), [3, 20]);
    assert!(over_cap(key, 0, 14, cap_of(key, false)).is_empty());
    assert_eq!(
        over_cap(key, 0, 15, cap_of(key, false)),
        ["scene_park/axis pinhole, odd size: 15 slivers, more than its cap of 14"]
    );
    assert_eq!(
        over_cap(key, 4, 20, cap_of(key, true)),
        ["scene_park/axis pinhole, odd size: 4 ties, more than its cap of 3"]
    );
    assert_eq!(cap_of("veh_bus/oblique pinhole", true), [0, 0]);
    assert_eq!(
        over_cap("veh_bus/oblique pinhole", 1, 0, [0, 0]),
        ["veh_bus/oblique pinhole: 1 ties, more than its cap of 0"]
    );
}
