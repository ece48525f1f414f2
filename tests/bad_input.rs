//! Bad inputs to the `sim` binary (and, where simpler, to `svo_sim::world::scene::Scene::from_ron`).
//!
//! Every test feeds one bad input to the real binary (`CARGO_BIN_EXE_sim`) in a fresh temporary
//! folder and checks that the program
//!
//! * exits with a non-zero code (and is not killed by a signal),
//! * prints a clear message on stderr that names the problem and where it is (the scene file
//!   with `line:column`, a path into the scene such as `instances[0](body).keys[0].scale`, the
//!   command-line option, or the asset and its file), without repeating itself,
//! * does not panic (stderr never contains "panicked"),
//! * leaves nothing half-written: no PNG anywhere in the folder, neither the `--report-json`
//!   nor the `--dump-hits` file, no `*.tmp` file, and no per-frame line on stdout.
//!
//! Cases: malformed RON; unknown asset; NaN/inf/zero/negative instance transforms; a camera
//! whose up is parallel to its view; depth 0/21 in the file and on the command line;
//! resolution 0 / too large on the command line and in the file; unreadable scene paths;
//! missing, corrupt (seeded random bytes) and truncated `.vox` assets; zero frames,
//! out-of-order keyframes, vfov 0/180, empty/duplicate asset names, no instances; output
//! paths in missing folders; and a depth too deep for memory (refused or rendered, never a
//! panic, never slow).
//!
//! Randomness: the corrupt `.vox` bytes come from a splitmix64 stream whose seed is printed
//! (override with the environment variable `SVO_SIM_TEST_SEED`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

mod common;
use common::process::run_sim;

use svo_sim::world::scene::Scene;

// ---------------------------------------------------------------------------------------------
// Helpers

/// Time after which a run of the binary is killed and the test fails.
const TIMEOUT: Duration = Duration::from_secs(120);

/// A scratch folder, unique per test and process, removed when dropped.
struct Tmp {
    dir: PathBuf,
}

impl Tmp {
    fn new(test: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("svo_sim_bad_input_{test}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the scratch folder");
        Self { dir }
    }

    /// A path inside the folder, as a string argument.
    fn p(&self, name: &str) -> String {
        path_str(&self.dir.join(name))
    }

    /// Writes a file into the folder and returns its path.
    fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> String {
        let p = self.dir.join(name);
        std::fs::write(&p, bytes).expect("write a scratch file");
        path_str(&p)
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn path_str(p: &Path) -> String {
    p.to_str().expect("temporary paths are UTF-8").to_string()
}

/// The value following `flag` in `args`.
fn flag_value<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.iter()
        .position(|a| a == flag)
        .and_then(|i| args.get(i + 1))
        .map(String::as_str)
}

/// Every file below `dir`.
fn files_below(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p);
            }
        }
    }
    out
}

/// Fails if a `": "`-separated clause of the error line occurs twice (an error chain printed
/// with its causes repeated).
fn assert_no_repetition(args: &[String], stderr: &str) {
    for line in stderr.lines().filter(|l| l.starts_with("error:")) {
        let clauses: Vec<&str> = line.split(": ").map(str::trim).collect();
        for (i, c) in clauses.iter().enumerate() {
            if c.len() >= 12 && clauses[..i].contains(c) {
                panic!(
                    "sim {args:?}: the error message repeats itself (\"{c}\" occurs more than once), \
                     which is not a clear message:\n{stderr}"
                );
            }
        }
    }
}

/// Runs `sim` with `args` (plus `--out`, `--report-json` and `--dump-hits` into `t` unless
/// `args` sets them), expects a clean failure whose stderr contains every string of `expect`,
/// and returns stderr.
fn expect_failure(t: &Tmp, args: &[String], expect: &[&str]) -> String {
    let mut full = args.to_vec();
    for (flag, name) in [
        ("--out", "out"),
        ("--report-json", "report.json"),
        ("--dump-hits", "hits.bin"),
    ] {
        if flag_value(args, flag).is_none() {
            full.push(flag.into());
            full.push(t.p(name));
        }
    }
    let r = run_sim(&full, None, TIMEOUT);
    let ctx = format!(
        "sim {full:?}\nexit: {:?}\nstdout:\n{}\nstderr:\n{}",
        r.status, r.stdout, r.stderr
    );
    assert!(
        r.status.code().is_some(),
        "sim was killed by a signal\n{ctx}"
    );
    assert!(!r.status.success(), "sim exited 0 on a bad input\n{ctx}");
    assert!(
        !r.stderr.contains("panicked"),
        "sim panicked instead of reporting an error\n{ctx}"
    );
    assert!(
        !r.stderr.trim().is_empty(),
        "sim failed without a message on stderr\n{ctx}"
    );
    for e in expect {
        assert!(
            r.stderr.contains(e),
            "the message does not contain {e:?}\n{ctx}"
        );
    }
    assert!(
        !r.stdout
            .lines()
            .any(|l| l.starts_with("frame ") || l.starts_with("summary:")),
        "frames were rendered before the error\n{ctx}"
    );
    for flag in ["--report-json", "--dump-hits"] {
        let p = flag_value(&full, flag).unwrap();
        assert!(
            !Path::new(p).exists(),
            "{flag} {p} exists after a failed run\n{ctx}"
        );
    }
    let left: Vec<PathBuf> = files_below(&t.dir)
        .into_iter()
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.ends_with(".png") || n.ends_with(".tmp")
        })
        .collect();
    assert!(
        left.is_empty(),
        "files left behind by a failed run: {left:?}\n{ctx}"
    );
    // Checked last, so a failure here means everything above passed.
    assert_no_repetition(&full, &r.stderr);
    r.stderr
}

/// String arguments.
fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// A small, fast run of the default scene.
fn small_default(extra: &[&str]) -> Vec<String> {
    let mut v = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "5",
    ]);
    v.extend(args(extra));
    v
}

/// The example scene's text.
fn car() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/car.ron"))
        .expect("read scenes/car.ron")
}

/// `text` with the first occurrence of `from` replaced; fails if `from` is absent (so the test
/// notices when `scenes/car.ron` changes under it).
fn replace_once(text: &str, from: &str, to: &str) -> String {
    assert!(
        text.contains(from),
        "scenes/car.ron no longer contains {from:?}; update the test"
    );
    text.replacen(from, to, 1)
}

/// Writes `text` as a scene into `t`, runs it and expects failure with the scene path and every
/// string of `expect`. The scene is loaded and checked before the command line's small
/// resolution, frame count and depth apply, so those only keep a wrongly accepted scene fast.
fn scene_case(t: &Tmp, text: &str, expect: &[&str]) -> String {
    let path = t.write("scene.ron", text);
    let mut want = vec![path.as_str()];
    want.extend_from_slice(expect);
    expect_failure(t, &small_default(&["--scene", &path]), &want)
}

/// The (line, column) of the `{path}:{line}:{column}:` prefix in `stderr`.
fn line_col(stderr: &str, path: &str) -> (usize, usize) {
    let at = stderr
        .find(&format!("{path}:"))
        .unwrap_or_else(|| panic!("no \"{path}:\" in\n{stderr}"));
    let rest = &stderr[at + path.len() + 1..];
    let mut it = rest.splitn(3, ':');
    let line = it.next().and_then(|s| s.parse().ok());
    let col = it.next().and_then(|s| s.parse().ok());
    match (line, col) {
        (Some(l), Some(c)) => (l, c),
        _ => panic!("no line:column after {path} in\n{stderr}"),
    }
}

/// 1-based number of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not in the text"))
        + 1
}

// ---------------------------------------------------------------------------------------------
// 1. Malformed RON

#[test]
fn malformed_missing_comma_inside_a_line() {
    let t = Tmp::new("malformed_missing_comma_inside_a_line");
    let text = replace_once(
        &car(),
        "(frame: 0, position: (4.6",
        "(frame: 0 position: (4.6",
    );
    let want_line = line_of(&text, "(frame: 0 position: (4.6");
    let err = scene_case(&t, &text, &["malformed scene"]);
    let (line, col) = line_col(&err, &t.p("scene.ron"));
    assert_eq!(line, want_line, "wrong line in\n{err}");
    let len = text.lines().nth(line - 1).unwrap().len();
    assert!(col >= 1 && col <= len + 1, "column {col} outside the line");
}

#[test]
fn malformed_missing_comma_at_end_of_line() {
    let t = Tmp::new("malformed_missing_comma_at_end_of_line");
    let text = replace_once(&car(), "frames: 48,", "frames: 48");
    let comma_line = line_of(&text, "frames: 48");
    let err = scene_case(&t, &text, &["malformed scene"]);
    let (line, _) = line_col(&err, &t.p("scene.ron"));
    // The parser notices at the next token, on the following line.
    assert!(
        line == comma_line || line == comma_line + 1,
        "line {line} is neither {comma_line} nor the next one\n{err}"
    );
}

#[test]
fn malformed_unclosed_paren() {
    let t = Tmp::new("malformed_unclosed_paren");
    let car = car();
    let body = car
        .trim_end()
        .strip_suffix(')')
        .expect("scenes/car.ron ends with ')'");
    let text = format!("{body}\n");
    let err = scene_case(&t, &text, &["malformed scene"]);
    let (line, _) = line_col(&err, &t.p("scene.ron"));
    // Detected at the end of the file.
    let eof_line = text.matches('\n').count() + 1;
    assert!(
        line == eof_line || line == eof_line - 1,
        "line {line} is not the end of the file ({eof_line})\n{err}"
    );
}

#[test]
fn malformed_unknown_field() {
    let t = Tmp::new("malformed_unknown_field");
    let text = replace_once(&car(), "frames: 48,", "frames: 48, colour: 3,");
    let want_line = line_of(&text, "colour: 3");
    let err = scene_case(&t, &text, &["malformed scene", "colour"]);
    let (line, _) = line_col(&err, &t.p("scene.ron"));
    assert_eq!(line, want_line, "wrong line in\n{err}");
}

#[test]
fn library_malformed_ron_names_line_and_column() {
    let text = replace_once(
        &car(),
        "(frame: 0, position: (4.6",
        "(frame: 0 position: (4.6",
    );
    let want_line = line_of(&text, "(frame: 0 position: (4.6");
    let err = Scene::from_ron(&text, "x", Path::new("."))
        .expect_err("malformed RON must be refused")
        .to_string();
    assert!(
        err.starts_with(&format!("x:{want_line}:")),
        "expected x:{want_line}:col: ..., got {err}"
    );
    assert!(err.contains("malformed scene"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// 2. Unknown asset

#[test]
fn unknown_asset_in_instance() {
    let t = Tmp::new("unknown_asset_in_instance");
    let text = replace_once(
        &car(),
        r#"(name: "body", asset: "body","#,
        r#"(name: "body", asset: "bodyy","#,
    );
    scene_case(
        &t,
        &text,
        &[
            "instances[0](body).asset",
            "\"bodyy\"",
            "body, wheel, door, steering_wheel",
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// 3. Non-finite and non-invertible transforms

#[test]
fn nan_translation() {
    let t = Tmp::new("nan_translation");
    let text = replace_once(
        &car(),
        "translation: (1.3, -0.45, -0.86)",
        "translation: (NaN, -0.45, -0.86)",
    );
    scene_case(
        &t,
        &text,
        &[
            "instances[1](wheel_front_left).keys[0].translation",
            "finite",
        ],
    );
}

#[test]
fn inf_rotation() {
    let t = Tmp::new("inf_rotation");
    let text = replace_once(
        &car(),
        "rotation_deg: (-300, 0, -30)",
        "rotation_deg: (-300, inf, -30)",
    );
    scene_case(
        &t,
        &text,
        &[
            "instances[7](steering_wheel).keys[1].rotation_deg",
            "finite",
        ],
    );
}

#[test]
fn zero_scale() {
    let t = Tmp::new("zero_scale");
    let text = replace_once(
        &car(),
        r#"(name: "body", asset: "body", keys: [(frame: 0)]),"#,
        r#"(name: "body", asset: "body", keys: [(frame: 0, scale: (1, 0, 1))]),"#,
    );
    scene_case(&t, &text, &["instances[0](body).keys[0].scale", "positive"]);
}

#[test]
fn negative_scale() {
    let t = Tmp::new("negative_scale");
    let text = replace_once(
        &car(),
        "(frame: 18, translation: (0.63, 0.05, -0.86), rotation_deg: (0, -65, 0)),",
        "(frame: 18, translation: (0.63, 0.05, -0.86), rotation_deg: (0, -65, 0), scale: (1, 1, -2)),",
    );
    scene_case(
        &t,
        &text,
        &["instances[5](door_left).keys[2].scale", "positive"],
    );
}

#[test]
fn library_bad_values_name_their_place_in_the_scene() {
    let car = car();
    let cases: &[(&str, &str, &str)] = &[
        (
            r#"(name: "body", asset: "body", keys: [(frame: 0)]),"#,
            r#"(name: "body", asset: "body", keys: [(frame: 0, scale: (0, 1, 1))]),"#,
            "x: invalid scene: instances[0](body).keys[0].scale",
        ),
        (
            "translation: (1.3, -0.45, -0.86)",
            "translation: (1.3, NaN, -0.86)",
            "x: invalid scene: instances[1](wheel_front_left).keys[0].translation",
        ),
        (
            "rotation_deg: (-300, 0, -30)",
            "rotation_deg: (-inf, 0, -30)",
            "x: invalid scene: instances[7](steering_wheel).keys[1].rotation_deg",
        ),
        (
            "depth: 8,",
            "depth: 0,",
            "x: invalid scene: assets[1](wheel).depth 0",
        ),
        (
            "vfov_deg: 36",
            "vfov_deg: 180",
            "x: invalid scene: camera[0].vfov_deg 180",
        ),
        (
            "resolution: (640, 384)",
            "resolution: (640, 0)",
            "x: invalid scene: resolution 640x0",
        ),
    ];
    for (from, to, want) in cases {
        let text = replace_once(&car, from, to);
        let err = Scene::from_ron(&text, "x", Path::new("."))
            .expect_err(&format!("{to} must be refused"))
            .to_string();
        assert!(err.contains(want), "{to}: expected {want:?} in {err:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Degenerate camera

#[test]
fn camera_up_parallel_to_view() {
    let t = Tmp::new("camera_up_parallel_to_view");
    // position (4.6, 2.2, -4.4), look_at (0, 0.05, 0): the view direction is
    // (-4.6, -2.15, 4.4); use exactly that as up.
    let text = replace_once(
        &car(),
        "look_at: (0.0, 0.05, 0.0), up: (0, 1, 0)",
        "look_at: (0.0, 0.05, 0.0), up: (-4.6, -2.15, 4.4)",
    );
    scene_case(&t, &text, &["parallel", "camera", "frame 0"]);
}

// ---------------------------------------------------------------------------------------------
// 5. Depth out of range

#[test]
fn depth_zero_in_scene_file() {
    let t = Tmp::new("depth_zero_in_scene_file");
    let text = replace_once(&car(), "depth: 8,", "depth: 0,");
    scene_case(&t, &text, &["assets[1](wheel).depth 0", "out of range"]);
}

#[test]
fn depth_21_in_scene_file() {
    let t = Tmp::new("depth_21_in_scene_file");
    let text = replace_once(&car(), "depth: 10,", "depth: 21,");
    scene_case(&t, &text, &["assets[0](body).depth 21", "out of range"]);
}

#[test]
fn depth_zero_on_command_line() {
    let t = Tmp::new("depth_zero_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "0",
    ]);
    expect_failure(&t, &a, &["--depth", "depth 0", "out of range"]);
}

#[test]
fn depth_21_on_command_line() {
    let t = Tmp::new("depth_21_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "21",
    ]);
    expect_failure(&t, &a, &["--depth", "depth 21", "out of range"]);
}

#[test]
fn depth_256_on_command_line() {
    let t = Tmp::new("depth_256_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "1", "--depth", "256",
    ]);
    expect_failure(&t, &a, &["--depth", "256"]);
}

// ---------------------------------------------------------------------------------------------
// 6. Resolution

#[test]
fn width_zero_on_command_line() {
    let t = Tmp::new("width_zero_on_command_line");
    let a = args(&[
        "--width", "0", "--height", "24", "--frames", "1", "--depth", "5",
    ]);
    expect_failure(&t, &a, &["command line", "resolution 0x24", "out of range"]);
}

#[test]
fn height_zero_on_command_line() {
    let t = Tmp::new("height_zero_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "0", "--frames", "1", "--depth", "5",
    ]);
    expect_failure(&t, &a, &["command line", "resolution 32x0", "out of range"]);
}

#[test]
fn huge_resolution_on_command_line() {
    let t = Tmp::new("huge_resolution_on_command_line");
    let a = args(&[
        "--width", "100000", "--height", "100000", "--frames", "1", "--depth", "5",
    ]);
    expect_failure(
        &t,
        &a,
        &["command line", "resolution 100000x100000", "out of range"],
    );
}

#[test]
fn zero_resolution_in_scene_file() {
    let t = Tmp::new("zero_resolution_in_scene_file");
    let text = replace_once(&car(), "resolution: (640, 384)", "resolution: (0, 384)");
    scene_case(&t, &text, &["resolution 0x384", "out of range"]);
}

#[test]
fn huge_resolution_in_scene_file() {
    let t = Tmp::new("huge_resolution_in_scene_file");
    let text = replace_once(
        &car(),
        "resolution: (640, 384)",
        "resolution: (100000, 100000)",
    );
    scene_case(&t, &text, &["resolution 100000x100000", "out of range"]);
}

// ---------------------------------------------------------------------------------------------
// 7. Unreadable scene paths

#[test]
fn scene_path_does_not_exist() {
    let t = Tmp::new("scene_path_does_not_exist");
    let missing = t.p("no_such_scene.ron");
    expect_failure(
        &t,
        &args(&["--scene", &missing]),
        &["cannot read scene file", &missing],
    );
}

#[test]
fn scene_path_is_a_directory() {
    let t = Tmp::new("scene_path_is_a_directory");
    let dir = t.p("a_folder.ron");
    std::fs::create_dir_all(&dir).unwrap();
    expect_failure(
        &t,
        &args(&["--scene", &dir]),
        &["cannot read scene file", &dir],
    );
}

// ---------------------------------------------------------------------------------------------
// 8. Bad .vox assets

/// A one-asset scene whose asset `hull_model` is the `.vox` file `file` (relative to the scene).
fn vox_scene(file: &str) -> String {
    format!(
        r#"(
    resolution: (32, 24),
    frames: 1,
    camera: [(frame: 0, position: (0, 1, -6), look_at: (0, 0, 0), vfov_deg: 40)],
    assets: [(name: "hull_model", depth: 8, source: Vox(path: "{file}", voxel_size: 0.05))],
    instances: [(name: "hull", asset: "hull_model", keys: [(frame: 0)])],
)
"#
    )
}

/// Runs the one-asset scene on `file` (already in `t`) and expects an error naming the asset
/// and the file's path.
fn vox_case(t: &Tmp, file: &str, expect: &[&str]) -> String {
    let scene = t.write("vox_scene.ron", vox_scene(file));
    let full = t.p(file);
    let mut want = vec!["hull_model", full.as_str()];
    want.extend_from_slice(expect);
    expect_failure(t, &args(&["--scene", &scene]), &want)
}

/// splitmix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.next() as u8).collect()
    }
}

fn seed(test: &str) -> u64 {
    let seed = std::env::var("SVO_SIM_TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5EED_2019_u64);
    println!("{test}: seed = {seed} (set SVO_SIM_TEST_SEED to change it)");
    seed
}

#[test]
fn vox_file_does_not_exist() {
    let t = Tmp::new("vox_file_does_not_exist");
    vox_case(&t, "missing.vox", &["cannot read"]);
}

#[test]
fn vox_file_is_random_garbage() {
    let t = Tmp::new("vox_file_is_random_garbage");
    let mut rng = Rng(seed("vox_file_is_random_garbage"));
    let n = 64 + (rng.next() % 4096) as usize;
    t.write("garbage.vox", rng.bytes(n));
    vox_case(&t, "garbage.vox", &["not a valid"]);
}

#[test]
fn vox_file_is_garbage_after_a_valid_header() {
    let t = Tmp::new("vox_file_is_garbage_after_a_valid_header");
    let mut rng = Rng(seed("vox_file_is_garbage_after_a_valid_header"));
    // "VOX " 150, a MAIN chunk whose children are a SIZE chunk and an XYZI chunk with a random
    // voxel count and random content.
    let len = 16 + (rng.next() % 2048) as usize;
    let payload = rng.bytes(len);
    let mut size = b"SIZE".to_vec();
    size.extend(12u32.to_le_bytes());
    size.extend(0u32.to_le_bytes());
    for _ in 0..3 {
        size.extend(((rng.next() % 300) as u32).to_le_bytes());
    }
    let mut xyzi = b"XYZI".to_vec();
    xyzi.extend(((payload.len() + 4) as u32).to_le_bytes());
    xyzi.extend(0u32.to_le_bytes());
    xyzi.extend((rng.next() as u32).to_le_bytes());
    xyzi.extend(&payload);
    let mut bytes = b"VOX ".to_vec();
    bytes.extend(150u32.to_le_bytes());
    bytes.extend(b"MAIN");
    bytes.extend(0u32.to_le_bytes());
    bytes.extend(((size.len() + xyzi.len()) as u32).to_le_bytes());
    bytes.extend(size);
    bytes.extend(xyzi);
    t.write("corrupt.vox", bytes);
    vox_case(&t, "corrupt.vox", &[]);
}

/// A real `.vox` file from `../shared/data/vox`, or `None` (skipped) when the folder is missing
/// outside CI; with `CI=true` a missing folder is a failure.
fn real_vox() -> Option<PathBuf> {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data/vox"));
    if !dir.is_dir() {
        if std::env::var("CI").as_deref() == Ok("true") {
            panic!(
                "the .vox sample folder {} is missing (CI=true, so this is a failure)",
                dir.display()
            );
        }
        eprintln!(
            "skipping the truncated-.vox case: the sample folder {} is missing",
            dir.display()
        );
        return None;
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
        .collect();
    files.sort();
    let pick = files
        .iter()
        .find(|p| p.file_name().is_some_and(|n| n == "veh_car1.vox"))
        .or(files.first())
        .cloned();
    assert!(pick.is_some(), "no .vox file in {}", dir.display());
    pick
}

#[test]
fn vox_file_is_truncated() {
    let Some(real) = real_vox() else { return };
    let bytes = std::fs::read(&real).unwrap();
    for cut in [20, bytes.len() / 2, bytes.len() - 1] {
        let t = Tmp::new(&format!("vox_file_is_truncated_{cut}"));
        t.write("truncated.vox", &bytes[..cut]);
        println!(
            "{} truncated to {cut} of {} bytes",
            real.display(),
            bytes.len()
        );
        vox_case(&t, "truncated.vox", &[]);
    }
}

// ---------------------------------------------------------------------------------------------
// 9. Frames, keyframes, field of view, asset names, instances

#[test]
fn frames_zero_on_command_line() {
    let t = Tmp::new("frames_zero_on_command_line");
    let a = args(&[
        "--width", "32", "--height", "24", "--frames", "0", "--depth", "5",
    ]);
    expect_failure(&t, &a, &["--frames 0", "out of range"]);
}

#[test]
fn frames_zero_in_scene_file() {
    let t = Tmp::new("frames_zero_in_scene_file");
    let text = replace_once(&car(), "frames: 48,", "frames: 0,");
    scene_case(&t, &text, &["frames: 0", "out of range"]);
}

#[test]
fn instance_keyframes_out_of_order() {
    let t = Tmp::new("instance_keyframes_out_of_order");
    let text = replace_once(
        &car(),
        "(frame: 18, translation: (0.63, 0.05, -0.86)",
        "(frame: 3, translation: (0.63, 0.05, -0.86)",
    );
    scene_case(
        &t,
        &text,
        &["instances[5](door_left).keys[2].frame 3", "increasing"],
    );
}

#[test]
fn camera_keyframes_out_of_order() {
    let t = Tmp::new("camera_keyframes_out_of_order");
    let text = replace_once(
        &car(),
        "        (frame: 0, position: (4.6, 2.2, -4.4),",
        "        (frame: 5, position: (4.6, 2.2, -4.4), look_at: (0, 0, 0), vfov_deg: 36),\n        (frame: 2, position: (4.6, 2.2, -4.4),",
    );
    scene_case(&t, &text, &["camera[1].frame 2", "increasing"]);
}

#[test]
fn vfov_zero() {
    let t = Tmp::new("vfov_zero");
    let text = replace_once(&car(), "vfov_deg: 36", "vfov_deg: 0");
    scene_case(&t, &text, &["camera[0].vfov_deg 0", "(0, 180)"]);
}

#[test]
fn vfov_180() {
    let t = Tmp::new("vfov_180");
    let text = replace_once(&car(), "vfov_deg: 36", "vfov_deg: 180");
    scene_case(&t, &text, &["camera[0].vfov_deg 180", "(0, 180)"]);
}

#[test]
fn empty_asset_name() {
    let t = Tmp::new("empty_asset_name");
    // Rename the steering wheel's asset to "" and point its instance at it, so the only
    // problem is the zero-length name.
    let text = replace_once(&car(), r#"name: "steering_wheel","#, r#"name: "","#);
    let text = replace_once(&text, r#"asset: "steering_wheel","#, r#"asset: "","#);
    let mut a = small_default(&[]);
    let path = t.write("scene.ron", &text);
    a.extend(args(&["--scene", &path]));
    expect_failure(&t, &a, &[&path, "assets[3]", "name"]);
}

#[test]
fn duplicate_asset_name() {
    let t = Tmp::new("duplicate_asset_name");
    let text = replace_once(&car(), r#"name: "door","#, r#"name: "wheel","#);
    scene_case(&t, &text, &["assets[2](wheel)", "twice"]);
}

#[test]
fn empty_instances_list() {
    let t = Tmp::new("empty_instances_list");
    let car = car();
    let start = car.find("    instances: [").expect("car.ron has instances");
    let text = format!("{}    instances: [],\n)\n", &car[..start]);
    scene_case(&t, &text, &["instances", "at least one"]);
}

// ---------------------------------------------------------------------------------------------
// 10. Output paths

#[test]
fn report_json_in_missing_folder() {
    let t = Tmp::new("report_json_in_missing_folder");
    let report = t.p("no_such_folder/report.json");
    let a = small_default(&["--report-json", &report]);
    expect_failure(&t, &a, &["--report-json", &report, "does not exist"]);
    assert!(!t.dir.join("out").exists() || files_below(&t.dir.join("out")).is_empty());
}

#[test]
fn dump_hits_in_missing_folder() {
    let t = Tmp::new("dump_hits_in_missing_folder");
    let dump = t.p("no_such_folder/hits.bin");
    let a = small_default(&["--dump-hits", &dump]);
    expect_failure(&t, &a, &["--dump-hits", &dump, "does not exist"]);
}

#[test]
fn out_is_an_existing_file() {
    let t = Tmp::new("out_is_an_existing_file");
    let out = t.write("out_file", "not a folder");
    let a = small_default(&["--out", &out]);
    expect_failure(&t, &a, &[&out]);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "not a folder");
}

#[test]
fn threads_zero() {
    let t = Tmp::new("threads_zero");
    let a = small_default(&["--threads", "0"]);
    expect_failure(&t, &a, &["--threads 0", "out of range"]);
}

// ---------------------------------------------------------------------------------------------
// 11. A depth too large for memory

#[test]
fn depth_too_large_for_memory_is_refused_or_rendered() {
    let t = Tmp::new("depth_too_large_for_memory");
    // The reference walks depth-16 SDF assets implicitly; the fixed-point and cycle models
    // refuse them (tests/cycle_cli.rs).
    let mut a = args(&[
        "--width",
        "32",
        "--height",
        "24",
        "--frames",
        "1",
        "--depth",
        "16",
        "--model",
        "reference",
    ]);
    for (flag, name) in [
        ("--out", "out"),
        ("--report-json", "report.json"),
        ("--dump-hits", "hits.bin"),
    ] {
        a.push(flag.into());
        a.push(t.p(name));
    }
    let start = Instant::now();
    let r = run_sim(&a, None, TIMEOUT);
    let ctx = format!(
        "sim {a:?}\nexit: {:?} after {:.1} s\nstdout:\n{}\nstderr:\n{}",
        r.status,
        start.elapsed().as_secs_f64(),
        r.stdout,
        r.stderr
    );
    assert!(
        r.status.code().is_some(),
        "sim was killed by a signal\n{ctx}"
    );
    assert!(!r.stderr.contains("panicked"), "sim panicked\n{ctx}");
    if r.status.success() {
        assert!(t.dir.join("out/frame_0000.png").is_file(), "no PNG\n{ctx}");
        assert!(t.dir.join("report.json").is_file(), "no report\n{ctx}");
        assert!(t.dir.join("hits.bin").is_file(), "no dump\n{ctx}");
    } else {
        assert!(
            r.stderr.contains("depth 16") && r.stderr.contains("GiB"),
            "the refusal does not say which depth and how much memory\n{ctx}"
        );
        assert!(!t.dir.join("report.json").exists(), "report left\n{ctx}");
        assert!(!t.dir.join("hits.bin").exists(), "dump left\n{ctx}");
        let left: Vec<PathBuf> = files_below(&t.dir)
            .into_iter()
            .filter(|p| {
                let n = p.file_name().unwrap().to_string_lossy();
                n.ends_with(".png") || n.ends_with(".tmp")
            })
            .collect();
        assert!(left.is_empty(), "files left behind: {left:?}\n{ctx}");
    }
}
