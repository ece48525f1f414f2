//! Bad `.vox` assets named by a scene given to the `sim` binary: a missing file, seeded
//! random bytes, garbage after a valid header, and a real model truncated at several points.
//! The error must name the asset and the file's path; what a failure must look like otherwise
//! (exit code, message, nothing half-written) is checked by `tests/common/bad_input.rs`.
//!
//! Randomness: the corrupt `.vox` bytes come from a splitmix64 stream whose seed is printed
//! (override with the environment variable `SVO_SIM_TEST_SEED`).

use std::path::PathBuf;

mod common;
use common::bad_input::{args, expect_failure, Tmp};

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
