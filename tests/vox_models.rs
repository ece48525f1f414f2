//! Integration tests of the MagicaVoxel loader (`svo_sim::world::assets::vox`) on the sample
//! models in `../shared/data/vox` ("Mini Mike's Metro Minis" by Mike Judge, CC BY 4.0; read in
//! place, never copied into the repository): every sample loads and matches an independent
//! per-voxel reference, the biggest loads quickly, corrupt, truncated and mutated files are
//! errors naming the path (never panics), and depths that are too small, out of range or
//! upscaled behave as documented.
//!
//! The axis, palette and scene-graph conventions, on tiny `.vox` files written by hand in
//! memory, are in `tests/vox_conventions.rs`.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use svo_sim::world::assets::vox::{load_vox, load_vox_bytes, VoxError};

mod common;
use common::vox::{assert_names_path, leaf_map};

// ---------------------------------------------------------------------------------------------
// Helpers

fn vox_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no .vox files in {}", dir.display());
    files
}

/// A scratch directory for files the tests write, unique per process and test.
fn scratch_dir(test: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("svo_sim_vox_models_{}_{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const FACES: [[i64; 3]; 6] = [
    [-1, 0, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [0, 0, -1],
    [0, 0, 1],
];

/// Independent reference for a file without scene graph: every voxel mapped to y-up by hand,
/// shifted and centred, scaled by `k`, surface cells only (a cell with an empty face neighbour),
/// as coordinate → opaque colour.
fn reference_leaves(bytes: &[u8], depth: u8, k: i64) -> HashMap<[u32; 3], [u8; 4]> {
    let data = dot_vox::load_bytes(bytes).unwrap();
    assert!(
        data.scenes.is_empty(),
        "reference only handles files without scene graph"
    );
    let mut solid: HashMap<[i64; 3], [u8; 4]> = HashMap::new();
    for m in &data.models {
        for v in &m.voxels {
            let c = data.palette[usize::from(v.i)];
            // vox (x, y, z) -> ours (x, z, -y); the -1 only moves everything by one cell
            let ours = [i64::from(v.x), i64::from(v.z), -i64::from(v.y)];
            for dx in 0..k {
                for dy in 0..k {
                    for dz in 0..k {
                        let f = [ours[0] * k + dx, ours[1] * k + dy, ours[2] * k + dz];
                        solid.entry(f).or_insert([c.r, c.g, c.b, 255]);
                    }
                }
            }
        }
    }
    let lo: [i64; 3] = std::array::from_fn(|a| solid.keys().map(|c| c[a]).min().unwrap());
    let hi: [i64; 3] = std::array::from_fn(|a| solid.keys().map(|c| c[a]).max().unwrap());
    let side = 1i64 << depth;
    let off: [i64; 3] = std::array::from_fn(|a| (side - (hi[a] - lo[a] + 1)) / 2);
    solid
        .iter()
        .filter(|(c, _)| {
            FACES
                .iter()
                .any(|d| !solid.contains_key(&[c[0] + d[0], c[1] + d[1], c[2] + d[2]]))
        })
        .map(|(c, &col)| {
            let p: [u32; 3] = std::array::from_fn(|a| (c[a] - lo[a] + off[a]) as u32);
            (p, col)
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Sample files

#[test]
fn every_sample_file_loads() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    for path in vox_files(&dir) {
        let bytes = std::fs::read(&path).unwrap();
        let data = dot_vox::load_bytes(&bytes).unwrap();
        let file_voxels: usize = data.models.iter().map(|m| m.voxels.len()).sum();

        let t = Instant::now();
        let asset = load_vox(&path, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap();
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let name = path.file_name().unwrap().to_string_lossy();
        println!(
            "{name:<20} models {:>2}  grid {:>3}x{:>3}x{:>3}  depth {}  voxels {:>7}  leaves {:>7}  {ms:>7.1} ms",
            asset.models,
            asset.grid_dims[0],
            asset.grid_dims[1],
            asset.grid_dims[2],
            asset.depth,
            asset.voxels,
            asset.leaves.len(),
        );

        assert!(asset.models >= 1, "{name}");
        assert!(!asset.leaves.is_empty(), "{name}");
        assert!(asset.grid_dims.iter().all(|&d| d > 0), "{name}");
        assert_eq!(asset.leaves.depth(), asset.depth, "{name}");
        let extent = *asset.grid_dims.iter().max().unwrap();
        assert!(1u32 << asset.depth >= extent, "{name}: depth too small");
        assert!(
            asset.depth == 1 || 1u32 << (asset.depth - 1) < extent,
            "{name}: depth not minimal"
        );
        assert!(asset.voxels <= file_voxels, "{name}");
        assert!(
            asset.leaves.len() <= file_voxels,
            "{name}: more leaves than voxels"
        );
        assert!(asset.leaves.len() <= asset.voxels, "{name}");

        // Leaves fill exactly the centred bounding box (extreme voxels are always surface).
        let side = 1u32 << asset.depth;
        for a in 0..3 {
            let lo = asset.leaves.coords().map(|(c, _)| c[a]).min().unwrap();
            let hi = asset.leaves.coords().map(|(c, _)| c[a]).max().unwrap();
            let off = (side - asset.grid_dims[a]) / 2;
            assert_eq!(
                (lo, hi),
                (off, off + asset.grid_dims[a] - 1),
                "{name}: axis {a}"
            );
        }
        for (c, attr) in asset.leaves.coords() {
            assert!(
                c.iter().all(|&v| v < side),
                "{name}: {c:?} outside the cube"
            );
            assert_eq!(attr.rgba()[3], 255, "{name}: alpha");
            let n = attr.normal();
            assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-6);
        }

        // Same leaves and colours as an independent per-voxel reference.
        let expect = reference_leaves(&bytes, asset.depth, 1);
        let got: HashMap<[u32; 3], [u8; 4]> =
            asset.leaves.coords().map(|(c, a)| (c, a.rgba())).collect();
        assert_eq!(
            got.len(),
            expect.len(),
            "{name}: leaf count differs from the reference"
        );
        assert!(got == expect, "{name}: leaves differ from the reference");
    }
}

#[test]
fn biggest_sample_loads_quickly() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    let path = vox_files(&dir)
        .into_iter()
        .max_by_key(|p| std::fs::metadata(p).unwrap().len())
        .unwrap();
    load_vox(&path, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap(); // warm the page cache
    let runs = 5;
    let t = Instant::now();
    for _ in 0..runs {
        load_vox(&path, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap();
    }
    let ms = t.elapsed().as_secs_f64() * 1e3 / f64::from(runs);
    // Printed, not asserted: these machines are shared and noisy, so load speed is a figure
    // to read (and `sim bench` territory), never a pass/fail condition.
    println!("{}: {ms:.1} ms per load (mean of {runs})", path.display());
}

// ---------------------------------------------------------------------------------------------
// Corrupt input

#[test]
fn corrupt_input_is_an_error_naming_the_path() {
    let scratch = scratch_dir("corrupt");
    let mut cases: Vec<(String, PathBuf)> = Vec::new();

    if let Some(dir) = common::shared_vox_dir() {
        let real = std::fs::read(vox_files(&dir)[0].clone()).unwrap();
        let truncated = scratch.join("truncated.vox");
        std::fs::write(&truncated, &real[..100]).unwrap();
        cases.push(("first 100 bytes of a real file".into(), truncated));
    }

    let seed = 0x5eed_0fb0_0005_u64;
    println!("garbage seed {seed:#x}");
    let mut s = seed;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    let garbage: Vec<u8> = (0..4096).map(|_| next() as u8).collect();
    let garbage_path = scratch.join("garbage.vox");
    std::fs::write(&garbage_path, &garbage).unwrap();
    cases.push(("random garbage".into(), garbage_path));

    let mut headed = b"VOX ".to_vec();
    headed.extend(150u32.to_le_bytes());
    headed.extend((0..4096).map(|_| next() as u8));
    let headed_path = scratch.join("garbage_with_header.vox");
    std::fs::write(&headed_path, &headed).unwrap();
    cases.push(("garbage after a valid header".into(), headed_path));

    let empty = scratch.join("empty.vox");
    std::fs::write(&empty, b"").unwrap();
    cases.push(("empty file".into(), empty));
    cases.push((
        "nonexistent path".into(),
        scratch.join("does_not_exist.vox"),
    ));
    cases.push(("directory".into(), scratch.clone()));

    for (what, path) in &cases {
        let err = load_vox(path, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES).expect_err(what);
        println!("{what}: {err}");
        assert_names_path(&err, path);
    }
    std::fs::remove_dir_all(&scratch).unwrap();
}

#[test]
fn truncations_and_mutations_never_panic() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    let path = Path::new("mutated.vox");
    let files = vox_files(&dir);
    let small = files
        .iter()
        .min_by_key(|p| std::fs::metadata(p).unwrap().len())
        .unwrap();
    let real = std::fs::read(small).unwrap();
    // Every proper prefix cuts the MAIN chunk short, which must be an error.
    for len in 0..real.len() {
        let err = load_vox_bytes(&real[..len], path, None).expect_err("prefix");
        assert_names_path(&err, path);
    }
    let seed = 0xc0ff_ee11u64;
    println!("mutation seed {seed:#x}, base file {}", small.display());
    let mut s = seed;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    let (mut ok, mut err) = (0, 0);
    for _ in 0..2000 {
        let mut b = real.clone();
        for _ in 0..1 + next() % 8 {
            let i = (next() % b.len() as u64) as usize;
            b[i] = next() as u8;
        }
        match load_vox_bytes(&b, path, None) {
            Ok(asset) => {
                ok += 1;
                assert!(!asset.leaves.is_empty());
            }
            Err(e) => {
                err += 1;
                assert_names_path(&e, path);
            }
        }
    }
    println!("mutations: {ok} loaded, {err} rejected");
}

// ---------------------------------------------------------------------------------------------
// Depth

#[test]
fn depth_too_small_and_out_of_range_are_errors() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    let path = dir.join("veh_car1.vox");
    let coarse = load_vox(&path, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap();
    let needed = coarse.depth;
    match load_vox(
        &path,
        Some(needed - 1),
        svo_sim::input::DEFAULT_VOX_CAP_BYTES,
    ) {
        Err(
            err @ VoxError::DepthTooSmall {
                needed: n,
                given: g,
                ..
            },
        ) => {
            assert_eq!((n, g), (needed, needed - 1));
            println!("{err}");
            assert_names_path(&err, &path);
        }
        other => panic!("expected DepthTooSmall, got {other:?}"),
    }
    for bad in [0u8, 21, 255] {
        let err = load_vox(&path, Some(bad), svo_sim::input::DEFAULT_VOX_CAP_BYTES)
            .expect_err("out of range");
        assert!(
            matches!(err, VoxError::DepthOutOfRange { given, .. } if given == bad),
            "{err:?}"
        );
        assert_names_path(&err, &path);
    }
    // Depth 20 would turn each surface voxel into up to 6·(2^15)² leaves.
    let err = load_vox(&path, Some(20), svo_sim::input::DEFAULT_VOX_CAP_BYTES)
        .expect_err("too many leaves");
    assert!(
        matches!(err, VoxError::TooManyLeaves { depth: 20, .. }),
        "{err:?}"
    );
    println!("{err}");
    assert_names_path(&err, &path);
    let same = load_vox(&path, Some(needed), svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap();
    assert_eq!(same.leaves, coarse.leaves);
}

#[test]
fn deeper_depth_upscales_the_surface() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    for name in ["veh_car1.vox", "chr_mayor.vox"] {
        let path = dir.join(name);
        let bytes = std::fs::read(&path).unwrap();
        let coarse = load_vox(&path, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap();
        for extra in 1..=2u8 {
            let depth = coarse.depth + extra;
            let fine = load_vox(&path, Some(depth), svo_sim::input::DEFAULT_VOX_CAP_BYTES).unwrap();
            println!(
                "{name}: depth {} -> {depth}: {} -> {} leaves",
                coarse.depth,
                coarse.leaves.len(),
                fine.leaves.len()
            );
            assert_eq!(fine.depth, depth);
            assert_eq!(fine.grid_dims, coarse.grid_dims);
            assert!(fine.leaves.len() > coarse.leaves.len());
            // Exactly the surface of the fully upscaled solid, with the source colours.
            let k = 1i64 << extra;
            let expect = reference_leaves(&bytes, depth, k);
            let fine_map = leaf_map(&fine);
            let got: HashMap<[u32; 3], [u8; 4]> =
                fine_map.iter().map(|(c, a)| (*c, a.rgba())).collect();
            assert!(
                got == expect,
                "{name} at depth {depth}: leaves differ from the upscaled reference"
            );
            // Every leaf is on the surface (some face neighbour is not a leaf) and carries the
            // attributes of the coarse voxel it was cut from.
            let keys: HashSet<[u32; 3]> = fine_map.keys().copied().collect();
            let coarse_map = leaf_map(&coarse);
            let k = k as u32;
            let off_fine: [u32; 3] =
                std::array::from_fn(|a| ((1u32 << depth) - fine.grid_dims[a] * k) / 2);
            let off_coarse: [u32; 3] =
                std::array::from_fn(|a| ((1u32 << coarse.depth) - coarse.grid_dims[a]) / 2);
            for (c, a) in &fine_map {
                let open = FACES.iter().any(|d| {
                    let n: [i64; 3] = std::array::from_fn(|i| i64::from(c[i]) + d[i]);
                    n.iter().any(|&v| v < 0)
                        || !keys.contains(&[n[0] as u32, n[1] as u32, n[2] as u32])
                });
                assert!(open, "{name}: interior leaf {c:?}");
                let parent: [u32; 3] =
                    std::array::from_fn(|i| (c[i] - off_fine[i]) / k + off_coarse[i]);
                assert_eq!(
                    coarse_map.get(&parent),
                    Some(a),
                    "{name}: leaf {c:?} vs its voxel {parent:?}"
                );
            }
        }
    }
}
