//! Bad `.vox` assets named by a scene given to the `sim` binary: a missing file, seeded
//! random bytes, garbage after a valid header, a real model truncated at several points, and
//! hand-built files with one broken model chunk each (SIZE above the deepest octree, a voxel
//! outside SIZE, an XYZI count beyond its chunk) or a model index out of range. The error must
//! name the asset and the file's path; what a failure must look like otherwise (exit code,
//! message, nothing half-written) is checked by `tests/common/bad_input.rs`.
//!
//! Files of several models without scene graph (animation frames) load their model 0 with one
//! warning line on stderr, in scenes and in `sim render`; `sim render --model-index` picks
//! another and refuses one out of range.
//!
//! Randomness: the corrupt `.vox` bytes come from a splitmix64 stream whose seed is printed
//! (override with the environment variable `SVO_SIM_TEST_SEED`).

use std::path::{Path, PathBuf};

mod common;
use common::bad_input::{args, expect_failure, files_below, Tmp, TIMEOUT};
use common::process::run_sim;
use common::vox::{chunk, model, vox_file};

/// A one-asset scene whose asset `hull_model` is the `.vox` file `file` (relative to the scene).
fn vox_scene(file: &str) -> String {
    vox_scene_with(file, "")
}

/// [`vox_scene`] with `extra` fields after the `Vox` source's `voxel_size`.
fn vox_scene_with(file: &str, extra: &str) -> String {
    format!(
        r#"(
    resolution: (32, 24),
    frames: 1,
    camera: [(frame: 0, position: (0, 1, -6), look_at: (0, 0, 0), vfov_deg: 40)],
    assets: [(name: "hull_model", depth: 8, source: Vox(path: "{file}", voxel_size: 0.05{extra}))],
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
    let mut rng = Rng::new(seed("vox_file_is_random_garbage"));
    let n = 64 + (rng.next() % 4096) as usize;
    t.write("garbage.vox", rng.bytes(n));
    vox_case(&t, "garbage.vox", &["not a valid"]);
}

#[test]
fn vox_file_is_garbage_after_a_valid_header() {
    let t = Tmp::new("vox_file_is_garbage_after_a_valid_header");
    let mut rng = Rng::new(seed("vox_file_is_garbage_after_a_valid_header"));
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
    let dir = common::shared_vox_dir()?;
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
// Broken model chunks, hand-built

#[test]
fn vox_size_above_the_deepest_octree() {
    let t = Tmp::new("vox_size_above_the_deepest_octree");
    t.write(
        "huge.vox",
        vox_file(&[model([0x7fff_ffff, 4, 4], &[[0, 0, 0, 1]])]),
    );
    vox_case(
        &t,
        "huge.vox",
        &["model 0", "x = 2147483647", "above 1048576 = 2^20"],
    );
}

#[test]
fn vox_voxel_outside_its_size() {
    let t = Tmp::new("vox_voxel_outside_its_size");
    t.write(
        "outside.vox",
        vox_file(&[model([4, 4, 4], &[[1, 1, 1, 1], [4, 0, 0, 1]])]),
    );
    vox_case(
        &t,
        "outside.vox",
        &[
            "model 0",
            "voxel 1",
            "(4, 0, 0)",
            "outside its SIZE 4 x 4 x 4",
        ],
    );
}

#[test]
fn vox_xyzi_count_beyond_its_chunk() {
    let t = Tmp::new("vox_xyzi_count_beyond_its_chunk");
    let size: Vec<u8> = [4u32, 4, 4].iter().flat_map(|v| v.to_le_bytes()).collect();
    let xyzi = [0x7fff_ffffu32.to_le_bytes(), [1, 1, 1, 1]].concat();
    t.write(
        "count.vox",
        vox_file(&[chunk(b"SIZE", &size, &[]), chunk(b"XYZI", &xyzi, &[])]),
    );
    let stderr = vox_case(
        &t,
        "count.vox",
        &[
            "model 0",
            "declares 2147483647 voxels",
            "truncated or inconsistent",
        ],
    );
    assert!(
        !stderr.contains("no visible voxels"),
        "wrong reason:\n{stderr}"
    );
}

// ---------------------------------------------------------------------------------------------
// Choice of model

/// Two models, no scene graph (animation frames): one voxel, then a row of three.
fn two_frames() -> Vec<u8> {
    vox_file(&[
        model([1, 1, 1], &[[0, 0, 0, 1]]),
        model([3, 1, 1], &[[0, 0, 0, 2], [1, 0, 0, 3], [2, 0, 0, 4]]),
    ])
}

#[test]
fn vox_model_index_out_of_range_in_a_scene() {
    let t = Tmp::new("vox_model_index_out_of_range_in_a_scene");
    t.write("frames.vox", two_frames());
    let scene = t.write(
        "vox_scene.ron",
        vox_scene_with("frames.vox", ", model: Some(5)"),
    );
    let full = t.p("frames.vox");
    expect_failure(
        &t,
        &args(&["--scene", &scene]),
        &[
            "hull_model",
            &full,
            "model index 5 is out of range",
            "the file has 2 model(s) (0 to 1)",
        ],
    );
}

/// Runs the one-asset scene with `extra` on the two-frame file; expects success and returns
/// stderr.
fn run_frames_scene(t: &Tmp, extra: &str) -> String {
    t.write("frames.vox", two_frames());
    let scene = t.write("vox_scene.ron", vox_scene_with("frames.vox", extra));
    let a = args(&["--scene", &scene, "--out", &t.p("out"), "-q"]);
    let r = run_sim(&a, None, TIMEOUT);
    assert!(
        r.status.success(),
        "sim {a:?}\nstdout:\n{}\nstderr:\n{}",
        r.stdout,
        r.stderr
    );
    r.stderr
}

#[test]
fn vox_animation_frames_in_a_scene_warn_once() {
    let t = Tmp::new("vox_animation_frames_in_a_scene_warn_once");
    let stderr = run_frames_scene(&t, "");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    let want = format!(
        "warning: asset \"hull_model\": {}: 2 models and no scene graph (animation frames): \
         loaded model 0 alone (1 voxels), not all 2 merged",
        t.p("frames.vox")
    );
    assert!(
        warnings.len() == 1 && warnings[0].starts_with(&want),
        "expected one line starting {want:?}, stderr:\n{stderr}"
    );
    // An explicit choice is not warned about.
    let t = Tmp::new("vox_animation_frames_in_a_scene_warn_once_chosen");
    let stderr = run_frames_scene(&t, ", model: Some(1)");
    assert!(!stderr.contains("warning:"), "stderr:\n{stderr}");
}

/// `sim render` of `file` with a 4x4 image and a dump into `t`, plus `extra`.
fn render(t: &Tmp, file: &str, extra: &[&str]) -> common::process::Run {
    let mut a = args(&[
        "render",
        file,
        "--eye",
        "20,-30,25",
        "--look",
        "1,0,0",
        "--width",
        "4",
        "--height",
        "4",
        "--out",
        &t.p("model.png"),
        "--dump-hits",
        &t.p("hits.bin"),
    ]);
    a.extend(args(extra));
    run_sim(&a, None, TIMEOUT)
}

#[test]
fn render_model_index_selects_and_refuses() {
    let t = Tmp::new("render_model_index_selects_and_refuses");
    let file = t.write("frames.vox", two_frames());

    let r = render(&t, &file, &["--model-index", "2"]);
    let ctx = format!("stdout:\n{}\nstderr:\n{}", r.stdout, r.stderr);
    assert!(r.status.code().is_some_and(|c| c != 0), "{ctx}");
    assert!(!r.stderr.contains("panicked"), "{ctx}");
    for want in [
        file.as_str(),
        "model index 2 is out of range",
        "the file has 2 model(s) (0 to 1)",
    ] {
        assert!(r.stderr.contains(want), "{want:?} missing\n{ctx}");
    }
    assert!(
        files_below(&t.dir)
            .iter()
            .all(|p| p.ends_with("frames.vox")),
        "{ctx}"
    );

    let r = render(&t, &file, &["--model-index", "1"]);
    let ctx = format!("stdout:\n{}\nstderr:\n{}", r.stdout, r.stderr);
    assert!(r.status.success(), "{ctx}");
    assert!(r.stdout.contains("(model index 1 of 2)"), "{ctx}");
    assert!(r.stdout.contains(" 3 solid voxels"), "{ctx}");
    assert!(!r.stderr.contains("warning:"), "{ctx}");
    assert!(Path::new(&t.p("model.png")).is_file(), "{ctx}");
}

#[test]
fn render_animation_frames_warns_and_draws_model_0() {
    let t = Tmp::new("render_animation_frames_warns_and_draws_model_0");
    let file = t.write("frames.vox", two_frames());
    let r = render(&t, &file, &[]);
    let ctx = format!("stdout:\n{}\nstderr:\n{}", r.stdout, r.stderr);
    assert!(r.status.success(), "{ctx}");
    let want = format!(
        "warning: {file}: 2 models and no scene graph (animation frames): loaded model 0 alone \
         (1 voxels)"
    );
    let warnings: Vec<&str> = r
        .stderr
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .collect();
    assert!(
        warnings.len() == 1 && warnings[0].starts_with(&want),
        "expected one line starting {want:?}\n{ctx}"
    );
    assert!(r.stdout.contains(" 1 solid voxels"), "{ctx}");
}

#[test]
fn render_colour_index_zero_is_empty() {
    let t = Tmp::new("render_colour_index_zero_is_empty");
    // A row of three voxels, the middle one with colour index 0 (MagicaVoxel: empty).
    let file = t.write(
        "index0.vox",
        vox_file(&[model(
            [3, 1, 1],
            &[[0, 0, 0, 1], [1, 0, 0, 0], [2, 0, 0, 2]],
        )]),
    );
    let r = render(&t, &file, &[]);
    let ctx = format!("stdout:\n{}\nstderr:\n{}", r.stdout, r.stderr);
    assert!(r.status.success(), "{ctx}");
    assert!(r.stdout.contains(" 2 solid voxels"), "{ctx}");
    assert!(r.stdout.contains("(3x1x1 voxels)"), "{ctx}");
}
