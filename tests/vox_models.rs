//! Integration tests of the MagicaVoxel loader (`svo_sim::world::assets::vox`) on the sample
//! models in `../shared/data/vox` ("Mini Mike's Metro Minis" by Mike Judge, CC BY 4.0; read in
//! place, never copied into the repository): every sample loads and matches an independent
//! per-voxel reference, the biggest loads quickly, corrupt, truncated and mutated files are
//! errors naming the path (never panics), and depths that are too small, out of range or
//! upscaled behave as documented.
//!
//! Hand-built files check the model chunks (SIZE limits, voxels outside SIZE, colour index 0,
//! XYZI counts beyond their chunk, truncated chunks) and the choice of model (model index,
//! files of animation frames).
//!
//! The axis, palette and scene-graph conventions, on tiny `.vox` files written by hand in
//! memory, are in `tests/vox_conventions.rs`.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use svo_sim::world::assets::vox::{
    load_vox, load_vox_bytes, load_vox_bytes_model, load_vox_model, VoxError, MAX_SIZE,
};

mod common;
use common::vox::{
    assert_names_path, chunk, group_node, leaf_map, model, rgba, shape_node, test_palette,
    transform_node, vox_file,
};

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

    if let Some(dir) = common::skip::shared_vox_dir_for("the truncated real file case") {
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

// ---------------------------------------------------------------------------------------------
// Model chunks

/// `err` is a [`VoxError::Model`] naming `path` and containing every string of `want`.
fn expect_model_error(err: VoxError, path: &Path, want: &[&str]) {
    println!("{err}");
    assert!(matches!(err, VoxError::Model { .. }), "{err:?}");
    assert_names_path(&err, path);
    let text = err.to_string();
    for w in want {
        assert!(text.contains(w), "{w:?} missing from: {text}");
    }
}

#[test]
fn size_above_the_widest_octree_is_refused() {
    let path = Path::new("huge_size.vox");
    let huge = vox_file(&[
        model([1, 1, 1], &[[0, 0, 0, 1]]),
        model([1, 0x7fff_ffff, 1], &[[0, 0, 0, 1]]),
    ]);
    let err = load_vox_bytes(&huge, path, None).expect_err("SIZE 2^31 - 1");
    expect_model_error(
        err,
        path,
        &[
            "model 1",
            "y = 2147483647",
            "above 1048576",
            "SIZE chunk at byte 64",
        ],
    );
    // The limit itself is accepted: it only moves the pivot.
    let at_limit = vox_file(&[model([MAX_SIZE as u32, 1, 1], &[[0, 0, 0, 1]])]);
    let asset = load_vox_bytes(&at_limit, path, None).expect("SIZE at the limit");
    assert_eq!(asset.voxels, 1);
}

#[test]
fn voxel_outside_its_size_is_refused() {
    let path = Path::new("outside.vox");
    let bytes = vox_file(&[
        model([2, 2, 2], &[[1, 1, 1, 1]]),
        model(
            [2, 3, 2],
            &[[0, 0, 0, 1], [1, 2, 1, 1], [1, 3, 0, 1], [5, 5, 5, 1]],
        ),
    ]);
    let err = load_vox_bytes(&bytes, path, None).expect_err("voxel outside SIZE");
    // The first offending voxel of the model that holds it.
    expect_model_error(
        err,
        path,
        &[
            "model 1",
            "voxel 2",
            "(1, 3, 0)",
            "outside its SIZE 2 x 3 x 2",
        ],
    );
}

#[test]
fn colour_index_zero_is_empty() {
    let palette = test_palette();
    let path = Path::new("index0.vox");
    // A row of three voxels along vox x, the middle one with colour index 0.
    let bytes = vox_file(&[
        model([3, 1, 1], &[[0, 0, 0, 1], [1, 0, 0, 0], [2, 0, 0, 2]]),
        rgba(&palette),
    ]);
    let asset = load_vox_bytes(&bytes, path, None).unwrap();
    assert_eq!(asset.voxels, 2, "the index-0 voxel is not solid");
    assert_eq!(asset.grid_dims, [3, 1, 1], "the outer voxels still span 3");
    let mut row: Vec<([u32; 3], [u8; 4])> =
        asset.leaves.coords().map(|(c, a)| (c, a.rgba())).collect();
    row.sort_by_key(|(c, _)| c[0]);
    let xs: Vec<u32> = row.iter().map(|(c, _)| c[0]).collect();
    assert_eq!(
        xs,
        vec![xs[0], xs[0] + 2],
        "a leaf where the index-0 voxel was"
    );
    // File index 1 is RGBA entry 0, file index 2 entry 1: index 0 did not alias index 1.
    let rgb = |e: usize| [palette[e][0], palette[e][1], palette[e][2], 255];
    assert_eq!(row[0].1, rgb(0));
    assert_eq!(row[1].1, rgb(1));

    // A model of index-0 voxels only has nothing to show.
    let all_empty = vox_file(&[model([2, 1, 1], &[[0, 0, 0, 0], [1, 0, 0, 0]])]);
    let err = load_vox_bytes(&all_empty, path, None).expect_err("only index 0");
    assert!(matches!(err, VoxError::Empty { .. }), "{err:?}");
}

#[test]
fn xyzi_count_beyond_its_chunk_is_refused() {
    let path = Path::new("count.vox");
    let size: Vec<u8> = [2u32, 2, 2].iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut xyzi = 0x7fff_ffffu32.to_le_bytes().to_vec();
    xyzi.extend([0, 0, 0, 1, 1, 1, 1, 1]);
    let bytes = vox_file(&[chunk(b"SIZE", &size, &[]), chunk(b"XYZI", &xyzi, &[])]);
    let err = load_vox_bytes(&bytes, path, None).expect_err("count 0x7fffffff");
    expect_model_error(
        err,
        path,
        &[
            "model 0",
            "declares 2147483647 voxels",
            "holds 8 bytes of voxels, room for 2",
            "truncated or inconsistent",
        ],
    );
}

#[test]
fn xyzi_without_size_is_refused() {
    let path = Path::new("no_size.vox");
    let xyzi = [1u32.to_le_bytes(), [0, 0, 0, 1]].concat();
    let bytes = vox_file(&[chunk(b"XYZI", &xyzi, &[])]);
    let err = load_vox_bytes(&bytes, path, None).expect_err("XYZI before any SIZE");
    expect_model_error(err, path, &["XYZI chunk at byte 20", "model 0", "no SIZE"]);
}

#[test]
fn chunk_running_past_main_is_refused() {
    let path = Path::new("cut.vox");
    // MAIN's children: a model, then an RGBA header claiming 1024 bytes of which 8 are there.
    let mut cut = b"RGBA".to_vec();
    cut.extend(1024u32.to_le_bytes());
    cut.extend(0u32.to_le_bytes());
    cut.extend([7; 8]);
    let bytes = vox_file(&[model([1, 1, 1], &[[0, 0, 0, 1]]), cut]);
    let err = load_vox_bytes(&bytes, path, None).expect_err("cut chunk");
    expect_model_error(
        err,
        path,
        &[
            "\"RGBA\" chunk at byte 64",
            "declares 1036 bytes",
            "only 20",
            "truncated",
        ],
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
fn model_index_selects_one_model() {
    let path = Path::new("frames.vox");
    let bytes = two_frames();
    for (index, voxels, dims) in [(0, 1, [1, 1, 1]), (1, 3, [3, 1, 1])] {
        let asset = load_vox_bytes_model(&bytes, path, None, Some(index)).unwrap();
        assert_eq!(asset.voxels, voxels, "model {index}");
        assert_eq!(asset.grid_dims, dims, "model {index}");
        assert_eq!((asset.models, asset.file_models), (1, 2), "model {index}");
        assert_eq!(asset.notice, None, "an explicit choice needs no warning");
    }
    for index in [2, usize::MAX] {
        let err = load_vox_bytes_model(&bytes, path, None, Some(index)).expect_err("range");
        println!("{err}");
        assert!(
            matches!(err, VoxError::NoSuchModel { index: i, models: 2, .. } if i == index),
            "{err:?}"
        );
        assert_names_path(&err, path);
        let text = err.to_string();
        assert!(text.contains(&format!("model index {index}")), "{text}");
        assert!(text.contains("the file has 2 model(s) (0 to 1)"), "{text}");
    }
}

#[test]
fn animation_frames_load_the_first_frame_with_a_notice() {
    let path = Path::new("frames.vox");
    let asset = load_vox_bytes(&two_frames(), path, None).unwrap();
    // Merged, the frames would be 3 voxels; MagicaVoxel shows one frame at a time.
    assert_eq!(asset.voxels, 1);
    assert_eq!((asset.models, asset.file_models), (1, 2));
    let notice = asset.notice.expect("a notice naming what was not merged");
    println!("{notice}");
    assert!(
        notice.starts_with("frames.vox: 2 models and no scene graph"),
        "{notice}"
    );
    assert!(
        notice.contains("loaded model 0 alone (1 voxels)"),
        "{notice}"
    );
    assert!(!notice.contains('\n'), "one line: {notice}");
    // One model and no scene graph: nothing to say.
    let single = load_vox_bytes(&vox_file(&[model([1, 1, 1], &[[0, 0, 0, 1]])]), path, None);
    assert_eq!(single.unwrap().notice, None);
}

#[test]
fn scene_graph_files_merge_unless_a_model_is_chosen() {
    let path = Path::new("graph.vox");
    let bytes = vox_file(&[
        model([1, 1, 1], &[[0, 0, 0, 1]]),
        model([3, 1, 1], &[[0, 0, 0, 2], [1, 0, 0, 3], [2, 0, 0, 4]]),
        transform_node(0, &[], 1, &[]),
        group_node(1, &[2, 4]),
        transform_node(2, &[], 3, &[("_t", "0 0 0")]),
        shape_node(3, 0),
        transform_node(4, &[], 5, &[("_t", "10 0 0")]),
        shape_node(5, 1),
    ]);
    let merged = load_vox_bytes(&bytes, path, None).unwrap();
    assert_eq!(
        (merged.voxels, merged.models, merged.file_models),
        (4, 2, 2)
    );
    assert_eq!(merged.notice, None, "the scene graph says how to merge");
    // The chosen model alone, untransformed (its translation of 10 is the graph's).
    let one = load_vox_bytes_model(&bytes, path, None, Some(1)).unwrap();
    assert_eq!((one.voxels, one.models, one.grid_dims), (3, 1, [3, 1, 1]));
}

/// Distinct voxels with a colour index other than 0 of every XYZI chunk of a file, in file
/// order: an independent reading of the chunk list (no dot_vox, no loader code).
fn xyzi_voxel_counts(bytes: &[u8]) -> Vec<usize> {
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let main_end = 20 + u32_at(12) + u32_at(16);
    let mut pos = 20 + u32_at(12);
    let mut out = Vec::new();
    while pos < main_end {
        let (content, children) = (u32_at(pos + 4), u32_at(pos + 8));
        if &bytes[pos..pos + 4] == b"XYZI" {
            let n = u32_at(pos + 12);
            let cells: HashSet<[u8; 3]> = bytes[pos + 16..pos + 16 + 4 * n]
                .chunks_exact(4)
                .filter(|v| v[3] != 0)
                .map(|v| [v[0], v[1], v[2]])
                .collect();
            out.push(cells.len());
        }
        pos += 12 + content + children;
    }
    out
}

#[test]
fn every_model_of_the_samples_loads_by_index() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    // horse.vox (animation frames, no scene graph), when present, is the case of the issue:
    // merged it showed 1491 voxels with extra legs, its first model has 808.
    for path in vox_files(&dir) {
        let counts = xyzi_voxel_counts(&std::fs::read(&path).unwrap());
        println!("{}: XYZI voxel counts {counts:?}", path.display());
        for (index, &count) in counts.iter().enumerate() {
            let asset = load_vox_model(
                &path,
                None,
                Some(index),
                svo_sim::input::DEFAULT_VOX_CAP_BYTES,
            )
            .unwrap();
            assert_eq!(asset.voxels, count, "{} model {index}", path.display());
            assert_eq!(asset.file_models, counts.len());
        }
        let err = load_vox_model(
            &path,
            None,
            Some(counts.len()),
            svo_sim::input::DEFAULT_VOX_CAP_BYTES,
        )
        .expect_err("past the end");
        assert!(matches!(err, VoxError::NoSuchModel { .. }), "{err:?}");
    }
}
