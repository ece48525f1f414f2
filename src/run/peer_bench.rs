//! `sim bench peer`: the f64 reference walk's speed against the OpenVDB peer of
//! `tests/openvdb_peer/peer.cpp` on the 20 benchmark cameras (five shared models, four cameras
//! each), as ratios measured in one run (docs/render.md §7).
//!
//! Pipeline position: beside [`super::bench`], on the bare-model path of [`super::render`]. Both
//! programs run as child processes on the same rays with the same threads: `sim render` (this
//! very binary) and the peer, which is built here with g++ against Debian's OpenVDB 10 the way
//! the test builds it (same source, embedded; same flags). Each program times its traces
//! itself, after loading and after one untimed warm-up (the peer) or allocation (`sim render`),
//! so neither counts loading. Rounds alternate which program runs first, since the machines are
//! shared and the first of two runs is not always the luckier one. Nothing here is compared
//! with a fixed time: the table gives ratios, and the test (`tests/openvdb_peer.rs`) checks the
//! hits pixel by pixel.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::Command;

use thiserror::Error;

/// The peer's source, the one the test builds.
pub const PEER_SOURCE: &str = include_str!("../../tests/openvdb_peer/peer.cpp");
/// The peer's compiler flags: `-O3` as OpenVDB's own release builds (`-O2` made it 1.4× slower),
/// and no fused multiply-add, so its rays are bit-identical to `sim render`'s.
pub const PEER_FLAGS: &[&str] = &["-std=c++17", "-O3", "-DNDEBUG", "-ffp-contract=off"];
/// The peer's libraries.
pub const PEER_LIBS: &[&str] = &["-lopenvdb", "-ltbb", "-lpthread"];
/// The header whose absence means OpenVDB's development files are not installed.
pub const OPENVDB_HEADER: &str = "/usr/include/openvdb/openvdb.h";
/// The five shared models of the benchmark, in table order.
pub const MODELS: [&str; 5] = [
    "veh_bus.vox",
    "scene_store8.vox",
    "chr_mayor.vox",
    "alien_saucer2a.vox",
    "scene_park.vox",
];

/// Why the bench could not run.
#[derive(Debug, Error)]
pub enum PeerBenchError {
    /// g++ could not be started.
    #[error("g++ is needed to build the OpenVDB peer and could not be run ({0}); install g++, or give --peer PATH")]
    NoCompiler(std::io::Error),
    /// OpenVDB's headers are missing.
    #[error("OpenVDB's headers are missing ({OPENVDB_HEADER}): install libopenvdb-dev (Debian; it brings libboost-dev and libtbb-dev), or give --peer PATH")]
    NoOpenVdb,
    /// g++ failed.
    #[error("building the OpenVDB peer failed:\n{0}")]
    Build(String),
    /// A file or folder could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// A child process failed or printed something unexpected.
    #[error("{what}: {message}")]
    Child {
        /// The command and camera.
        what: String,
        /// Its error output, or what was missing from its output.
        message: String,
    },
    /// An option out of range.
    #[error("{0}")]
    Option(String),
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> PeerBenchError + '_ {
    move |source| PeerBenchError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Builds the peer into `cache` (or reuses the build of the same source and flags there) and
/// returns its path. The binary appears under its final name only once complete.
pub fn build_peer(cache: &Path) -> Result<PathBuf, PeerBenchError> {
    let mut h = DefaultHasher::new();
    (PEER_SOURCE, PEER_FLAGS, PEER_LIBS).hash(&mut h);
    let exe = cache.join(format!("peer-{:016x}", h.finish()));
    if exe.is_file() {
        return Ok(exe);
    }
    Command::new("g++")
        .arg("--version")
        .output()
        .map_err(PeerBenchError::NoCompiler)?;
    if !Path::new(OPENVDB_HEADER).is_file() {
        return Err(PeerBenchError::NoOpenVdb);
    }
    std::fs::create_dir_all(cache).map_err(io(cache))?;
    let src = cache.join(format!("peer-{}.cpp", std::process::id()));
    std::fs::write(&src, PEER_SOURCE).map_err(io(&src))?;
    let tmp = cache.join(format!("peer-build-{}", std::process::id()));
    let out = Command::new("g++")
        .args(PEER_FLAGS)
        .arg(&src)
        .arg("-o")
        .arg(&tmp)
        .args(PEER_LIBS)
        .output()
        .map_err(PeerBenchError::NoCompiler);
    let _ = std::fs::remove_file(&src);
    let out = out?;
    if !out.status.success() {
        let _ = std::fs::remove_file(&tmp);
        return Err(PeerBenchError::Build(
            String::from_utf8_lossy(&out.stderr).into_owned(),
        ));
    }
    std::fs::rename(&tmp, &exe).map_err(io(&exe))?;
    Ok(exe)
}

/// One benchmark camera, in the model's own voxel coordinates (`sim render`'s contract).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BenchCamera {
    /// Its name in the table.
    pub name: &'static str,
    /// Eye, or the centre of the orthographic view plane.
    pub eye: [f64; 3],
    /// A point on the view axis.
    pub look: [f64; 3],
    /// Up hint.
    pub up: [f64; 3],
    /// Orthographic (`value` is the view width) or pinhole (`value` is the vertical fov).
    pub ortho: bool,
    /// Field of view (degrees) or view width (voxels).
    pub value: f64,
    /// Image width.
    pub w: u32,
    /// Image height.
    pub h: u32,
}

/// The four cameras of a model with solid box [mn, mx] (inclusive voxel indices), the ones
/// `tests/openvdb_peer.rs` compares pixel by pixel; `scale` multiplies the image sides (1 in
/// the test, 8 for the benchmark's 1280×960, 1281×961 and 512–1024² images).
pub fn cameras(mn: [i64; 3], mx: [i64; 3], scale: u32) -> Vec<BenchCamera> {
    let c: [f64; 3] = std::array::from_fn(|k| (mn[k] + mx[k] + 1) as f64 * 0.5);
    let ext = (0..3).map(|k| mx[k] + 1 - mn[k]).max().unwrap_or(1) as f64;
    let side = (ext as u32).next_power_of_two().min(128);
    let pixels = side.max(64) * scale;
    let ortho_off = 1.0 - 0.5 / f64::from(pixels / side);
    let fl = |v: f64| v.floor();
    vec![
        BenchCamera {
            name: "oblique pinhole",
            eye: [
                c[0] + 1.3 * ext + 0.137,
                c[1] - 1.1 * ext + 0.291,
                c[2] + 0.9 * ext + 0.053,
            ],
            look: c,
            up: [0.0, 0.0, 1.0],
            ortho: false,
            value: 40.0,
            w: 160 * scale,
            h: 120 * scale,
        },
        // Odd size: the centre column and row have exact-zero direction components, and the
        // integer eye puts those rays exactly in the voxel planes x = eye.x and z = eye.z.
        BenchCamera {
            name: "axis pinhole, odd size",
            eye: [fl(c[0]), (mn[1] as f64 - 1.5 * ext).floor(), fl(c[2])],
            look: [fl(c[0]), c[1], fl(c[2])],
            up: [0.0, 0.0, 1.0],
            ortho: false,
            value: 50.0,
            w: 160 * scale + 1,
            h: 120 * scale + 1,
        },
        // A power-of-two view `side` voxels wide on `pixels` = p·side pixels (p a power of
        // two), so every origin is exact: (i + ½)/p − side/2 from the eye. With the eye at
        // 1 − 1/(2p) past an integer, every p-th row and column of rays runs exactly along
        // voxel edge lines (in the planes x = i and y = j).
        BenchCamera {
            name: "ortho along -z",
            eye: [
                fl(c[0]) + ortho_off,
                fl(c[1]) + ortho_off,
                mx[2] as f64 + 5.0,
            ],
            look: [fl(c[0]) + ortho_off, fl(c[1]) + ortho_off, mn[2] as f64],
            up: [0.0, 1.0, 0.0],
            ortho: true,
            value: f64::from(side),
            w: pixels,
            h: pixels,
        },
        BenchCamera {
            name: "inside the bounds",
            eye: [c[0] + 0.37, c[1] + 0.21, c[2] + 0.13],
            look: [c[0] + 10.37, c[1] + 6.21, c[2] - 2.37],
            up: [0.0, 0.0, 1.0],
            ortho: false,
            value: 90.0,
            w: 160 * scale,
            h: 120 * scale,
        },
    ]
}

/// What `sim bench peer` runs.
#[derive(Clone, Debug)]
pub struct PeerBenchOptions {
    /// The folder holding the five models.
    pub vox_dir: PathBuf,
    /// The `sim` binary whose `render` is timed (normally the running one).
    pub sim: PathBuf,
    /// The peer binary.
    pub peer: PathBuf,
    /// Runs of each program per camera, alternating which goes first (≥ 1).
    pub rounds: u32,
    /// Traces per run; each run reports its fastest (≥ 1).
    pub repeat: u32,
    /// Worker threads of both programs (≥ 1).
    pub threads: u32,
    /// Image sides multiplied by this (1 to 16).
    pub scale: u32,
    /// Only the cameras whose `model/camera` contains this text.
    pub only: Option<String>,
    /// Scratch folder for the peer's hit records (written by it, then removed).
    pub scratch: PathBuf,
}

/// One camera's measurement: speeds in Mrays/s.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraRow {
    /// Model name (file name without `.vox`).
    pub model: String,
    /// Camera name.
    pub camera: &'static str,
    /// Rays per trace.
    pub rays: u64,
    /// The reference's fastest trace.
    pub ref_best: f64,
    /// The median of the reference's runs (each run's fastest trace).
    pub ref_median: f64,
    /// The peer's fastest trace.
    pub peer_best: f64,
    /// The median of the peer's runs (each run's fastest trace).
    pub peer_median: f64,
}

impl CameraRow {
    /// Reference speed / peer speed, of the bests (≥ 1: the reference is faster).
    pub fn ratio(&self) -> f64 {
        self.ref_best / self.peer_best
    }

    /// The same of the medians.
    pub fn median_ratio(&self) -> f64 {
        self.ref_median / self.peer_median
    }
}

fn v3(v: [f64; 3]) -> String {
    format!("{},{},{}", v[0], v[1], v[2])
}

fn run(cmd: &mut Command, what: &str) -> Result<String, PeerBenchError> {
    let out = cmd.output().map_err(|e| PeerBenchError::Child {
        what: what.to_string(),
        message: e.to_string(),
    })?;
    if !out.status.success() {
        return Err(PeerBenchError::Child {
            what: what.to_string(),
            message: String::from_utf8_lossy(&out.stderr).trim().to_string(),
        });
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The number before `suffix` in `text` (`sim render`'s "… 12.3 Mrays/s").
fn number_before(text: &str, suffix: &str, what: &str) -> Result<f64, PeerBenchError> {
    text.find(suffix)
        .and_then(|at| text[..at].split_whitespace().last())
        .and_then(|w| w.trim_matches(|c| c == '(' || c == ',').parse().ok())
        .ok_or_else(|| PeerBenchError::Child {
            what: what.to_string(),
            message: format!("no number before {suffix:?} in its output"),
        })
}

/// The value after `key ` on a line of the peer's output.
fn peer_value(text: &str, key: &str, what: &str) -> Result<f64, PeerBenchError> {
    text.lines()
        .find_map(|l| l.strip_prefix(key))
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| PeerBenchError::Child {
            what: what.to_string(),
            message: format!("no {key:?} line in its output"),
        })
}

/// `x a..b, y a..b, z a..b` of `sim render`'s box line (the solid box the cameras are placed
/// by); `what` names the command in the error.
pub fn parse_box(text: &str, what: &str) -> Result<([i64; 3], [i64; 3]), PeerBenchError> {
    let bad = || PeerBenchError::Child {
        what: what.to_string(),
        message: "no solid bounding box line in its output".into(),
    };
    let line = text
        .lines()
        .find(|l| l.starts_with("solid bounding box"))
        .ok_or_else(bad)?;
    let body = line.split("): ").nth(1).ok_or_else(bad)?;
    let (mut mn, mut mx) = ([0; 3], [0; 3]);
    for (k, part) in body.split(", ").take(3).enumerate() {
        let range = part.split_whitespace().nth(1).ok_or_else(bad)?;
        let (a, b) = range.split_once("..").ok_or_else(bad)?;
        mn[k] = a.parse().map_err(|_| bad())?;
        mx[k] = b.parse().map_err(|_| bad())?;
    }
    Ok((mn, mx))
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Runs the benchmark, calling `row` after each camera (for a table printed as it goes).
pub fn run_peer_bench(
    o: &PeerBenchOptions,
    row: &mut dyn FnMut(&CameraRow),
) -> Result<Vec<CameraRow>, PeerBenchError> {
    for (v, name, lo, hi) in [
        (o.rounds, "--rounds", 1, 1000),
        (o.repeat, "--repeat", 1, 1000),
        (o.threads, "--threads", 1, 1024),
        (o.scale, "--scale", 1, 16),
    ] {
        if !(lo..=hi).contains(&v) {
            return Err(PeerBenchError::Option(format!(
                "{name} {v} is out of range ({lo} to {hi})"
            )));
        }
    }
    std::fs::create_dir_all(&o.scratch).map_err(io(&o.scratch))?;
    let out_bin = o
        .scratch
        .join(format!("peer-hits-{}.bin", std::process::id()));
    let (threads, repeat) = (o.threads.to_string(), o.repeat.to_string());
    let mut rows = Vec::new();
    for m in MODELS {
        let path = o.vox_dir.join(m);
        if !path.is_file() {
            return Err(PeerBenchError::Io {
                path,
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "benchmark model missing",
                ),
            });
        }
        let model = m.trim_end_matches(".vox").to_string();
        let what = format!("sim render {m}");
        let text = run(
            Command::new(&o.sim).arg("render").arg(&path).args([
                "--eye",
                "1000,1000,1000",
                "--look",
                "0,0,0",
                "--width",
                "1",
                "--height",
                "1",
            ]),
            &what,
        )?;
        let (mn, mx) = parse_box(&text, &what)?;
        for cam in cameras(mn, mx, o.scale) {
            let key = format!("{model}/{}", cam.name);
            if o.only.as_ref().is_some_and(|s| !key.contains(s.as_str())) {
                continue;
            }
            let (w, h) = (cam.w.to_string(), cam.h.to_string());
            let value = cam.value.to_string();
            let mut sim = Command::new(&o.sim);
            sim.arg("render").arg(&path).args([
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
                &threads,
                "--repeat",
                &repeat,
                if cam.ortho { "--ortho" } else { "--fov" },
                &value,
            ]);
            let mut peer = Command::new(&o.peer);
            peer.arg(&path).arg(&out_bin).args([&w, &h]);
            for v in [cam.eye, cam.look, cam.up] {
                peer.args(v.map(|x| x.to_string()));
            }
            peer.args([
                if cam.ortho { "ortho" } else { "pinhole" },
                &value,
                &threads,
                &repeat,
            ]);
            let rays = u64::from(cam.w) * u64::from(cam.h);
            let (mut refs, mut peers) = (Vec::new(), Vec::new());
            let (what_ref, what_peer) = (format!("sim render, {key}"), format!("peer, {key}"));
            for round in 0..o.rounds {
                // Even rounds: reference, then peer; odd rounds: peer, then reference.
                for first in [round % 2 == 0, round % 2 == 1] {
                    if first {
                        let s = run(&mut sim, &what_ref)?;
                        refs.push(number_before(&s, "Mrays/s", &what_ref)?);
                    } else {
                        let p = run(&mut peer, &what_peer)?;
                        let secs = peer_value(&p, "trace_seconds", &what_peer)?;
                        peers.push(rays as f64 / secs.max(1e-9) / 1e6);
                    }
                }
            }
            let _ = std::fs::remove_file(&out_bin);
            let r = CameraRow {
                model: model.clone(),
                camera: cam.name,
                rays,
                ref_best: refs.iter().copied().fold(0.0, f64::max),
                ref_median: median(&refs),
                peer_best: peers.iter().copied().fold(0.0, f64::max),
                peer_median: median(&peers),
            };
            row(&r);
            rows.push(r);
        }
    }
    Ok(rows)
}

/// The table's header line.
pub fn header_text() -> String {
    format!(
        "{:<15} {:<23} {:>8} {:>9} {:>9} {:>9} {:>9} {:>6} {:>6}",
        "model", "camera", "rays", "ref best", "ref med", "vdb best", "vdb med", "ratio", "r med"
    )
}

/// One row of the table (speeds in Mrays/s; ratio = reference / peer, of bests and medians).
pub fn row_text(r: &CameraRow) -> String {
    format!(
        "{:<15} {:<23} {:>8} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>6.2} {:>6.2}",
        r.model,
        r.camera,
        r.rays,
        r.ref_best,
        r.ref_median,
        r.peer_best,
        r.peer_median,
        r.ratio(),
        r.median_ratio()
    )
}

/// The summary under the table: the smallest ratios and how many cameras are below 1.
pub fn summary_text(rows: &[CameraRow]) -> String {
    let Some(min) = rows.iter().min_by(|a, b| a.ratio().total_cmp(&b.ratio())) else {
        return "no camera matched\n".into();
    };
    let below = rows.iter().filter(|r| r.ratio() < 1.0).count();
    let min_med = rows
        .iter()
        .map(CameraRow::median_ratio)
        .fold(f64::INFINITY, f64::min);
    format!(
        "minimum ratio (reference / OpenVDB, best of each): {:.2} ({}/{}); of medians: {:.2}; \
         {below} of {} cameras below 1.0\n",
        min.ratio(),
        min.model,
        min.camera,
        min_med,
        rows.len()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_line_of_sim_render_parses() {
        let t = "solid bounding box (model voxel indices, inclusive): x -63..62, y -63..62, z -16..3 (126x126x20 voxels)\n";
        assert_eq!(parse_box(t, "t").unwrap(), ([-63, -63, -16], [62, 62, 3]));
        assert!(parse_box("nothing", "t").is_err());
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
    }

    #[test]
    fn a_ratio_below_one_is_counted_in_the_summary() {
        let r = |m: &str, a: f64, b: f64| CameraRow {
            model: m.into(),
            camera: "ortho along -z",
            rays: 1,
            ref_best: a,
            ref_median: a,
            peer_best: b,
            peer_median: b,
        };
        let s = summary_text(&[r("a", 2.0, 1.0), r("b", 0.9, 1.0)]);
        assert!(
            s.starts_with(
                "minimum ratio (reference / OpenVDB, best of each): 0.90 (b/ortho along -z)"
            ),
            "{s}"
        );
        assert!(s.contains("1 of 2 cameras below 1.0"), "{s}");
    }
}
