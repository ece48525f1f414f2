//! Integration tests of the MagicaVoxel loader (`svo_sim::world::assets::vox`): the sample models in
//! `../shared/data/vox` ("Mini Mike's Metro Minis" by Mike Judge, CC BY 4.0; read in place,
//! never copied into the repository) and tiny `.vox` files written by hand in memory.

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use rtl_model::svo::LeafAttr;
use svo_sim::world::assets::vox::{load_vox, load_vox_bytes, VoxAsset, VoxError};

mod common;

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

/// One RIFF-style chunk.
fn chunk(id: &[u8; 4], content: &[u8], children: &[u8]) -> Vec<u8> {
    let mut out = id.to_vec();
    out.extend((content.len() as u32).to_le_bytes());
    out.extend((children.len() as u32).to_le_bytes());
    out.extend(content);
    out.extend(children);
    out
}

/// A whole `.vox` file: "VOX ", version 150, and a MAIN chunk holding `children`.
fn vox_file(children: &[Vec<u8>]) -> Vec<u8> {
    let mut out = b"VOX ".to_vec();
    out.extend(150u32.to_le_bytes());
    out.extend(chunk(b"MAIN", &[], &children.concat()));
    out
}

/// SIZE and XYZI chunks of one model; voxels are (x, y, z, file colour index 1..=255).
fn model(size: [u32; 3], voxels: &[[u8; 4]]) -> Vec<u8> {
    let size_content: Vec<u8> = size.iter().flat_map(|s| s.to_le_bytes()).collect();
    let mut xyzi = (voxels.len() as u32).to_le_bytes().to_vec();
    xyzi.extend(voxels.iter().flatten());
    [
        chunk(b"SIZE", &size_content, &[]),
        chunk(b"XYZI", &xyzi, &[]),
    ]
    .concat()
}

/// RGBA chunk; entry `j` is the colour of file index `j + 1`.
fn rgba(palette: &[[u8; 4]; 256]) -> Vec<u8> {
    chunk(b"RGBA", &palette.concat(), &[])
}

/// A palette whose every entry is distinct, with alpha ≠ 255 to see it forced opaque.
fn test_palette() -> [[u8; 4]; 256] {
    std::array::from_fn(|j| [j as u8, 255 - j as u8, (j as u8).wrapping_mul(7), 0x80])
}

fn dict(pairs: &[(&str, &str)]) -> Vec<u8> {
    let mut out = (pairs.len() as u32).to_le_bytes().to_vec();
    for s in pairs.iter().flat_map(|(k, v)| [k, v]) {
        out.extend((s.len() as u32).to_le_bytes());
        out.extend(s.as_bytes());
    }
    out
}

fn transform_node(id: u32, attrs: &[(&str, &str)], child: u32, frame: &[(&str, &str)]) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(dict(attrs));
    c.extend(child.to_le_bytes());
    c.extend((-1i32).to_le_bytes()); // reserved
    c.extend((-1i32).to_le_bytes()); // layer: none
    c.extend(1u32.to_le_bytes()); // one frame
    c.extend(dict(frame));
    chunk(b"nTRN", &c, &[])
}

fn group_node(id: u32, children: &[u32]) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(dict(&[]));
    c.extend((children.len() as u32).to_le_bytes());
    c.extend(children.iter().flat_map(|k| k.to_le_bytes()));
    chunk(b"nGRP", &c, &[])
}

fn shape_node(id: u32, model_id: u32) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(dict(&[]));
    c.extend(1u32.to_le_bytes());
    c.extend(model_id.to_le_bytes());
    c.extend(dict(&[]));
    chunk(b"nSHP", &c, &[])
}

fn leaf_map(asset: &VoxAsset) -> HashMap<[u32; 3], LeafAttr> {
    asset.leaves.coords().collect()
}

fn opaque(c: [u8; 4]) -> [u8; 4] {
    [c[0], c[1], c[2], 255]
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

fn assert_names_path(err: &VoxError, path: &Path) {
    let text = err.to_string();
    assert!(
        text.contains(&path.display().to_string()),
        "error message does not name {}: {text}",
        path.display()
    );
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
        let asset = load_vox(&path, None).unwrap();
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
    load_vox(&path, None).unwrap(); // warm the page cache
    let runs = 5;
    let t = Instant::now();
    for _ in 0..runs {
        load_vox(&path, None).unwrap();
    }
    let ms = t.elapsed().as_secs_f64() * 1e3 / f64::from(runs);
    println!("{}: {ms:.1} ms per load (mean of {runs})", path.display());
    // Generous bound: the target is well under a second in release; tests may share the machine.
    assert!(ms < 3000.0, "{} took {ms:.0} ms", path.display());
}

// ---------------------------------------------------------------------------------------------
// Axes and palette

#[test]
fn z_up_column_becomes_y_column_with_file_colours() {
    let palette = test_palette();
    // A 1x1x3 column along vox z; file colour indices 1, 2, 3 from bottom to top.
    let bytes = vox_file(&[
        model([1, 1, 3], &[[0, 0, 0, 1], [0, 0, 1, 2], [0, 0, 2, 3]]),
        rgba(&palette),
    ]);
    let asset = load_vox_bytes(&bytes, Path::new("column.vox"), None).unwrap();
    assert_eq!(asset.grid_dims, [1, 3, 1]);
    assert_eq!(asset.depth, 2);
    assert_eq!(asset.models, 1);
    let mut leaves: Vec<([u32; 3], LeafAttr)> = asset.leaves.coords().collect();
    assert_eq!(leaves.len(), 3);
    leaves.sort_by_key(|(c, _)| c[1]);
    let (x, z) = (leaves[0].0[0], leaves[0].0[2]);
    for (i, (c, attr)) in leaves.iter().enumerate() {
        assert_eq!([c[0], c[2]], [x, z], "column not along y: {leaves:?}");
        assert_eq!(
            c[1],
            leaves[0].0[1] + i as u32,
            "column not contiguous: {leaves:?}"
        );
        // File colour index i+1 is RGBA entry i (dot_vox's Voxel::i is 0-based).
        assert_eq!(attr.rgba(), opaque(palette[i]), "voxel {i} from the bottom");
    }
    // Centred in the 4-cube: x and z offset (4-1)/2 = 1, y offset (4-3)/2 = 0.
    assert_eq!(leaves[0].0, [1, 0, 1]);
    let bottom = leaves[0].1.normal();
    let top = leaves[2].1.normal();
    assert!(bottom[1] < -0.999, "bottom normal {bottom:?}");
    assert!(top[1] > 0.999, "top normal {top:?}");
}

#[test]
fn vox_y_becomes_our_minus_z() {
    let palette = test_palette();
    // A 1x3x1 row along vox +y; colour index 10 + y.
    let bytes = vox_file(&[
        model([1, 3, 1], &[[0, 0, 0, 10], [0, 1, 0, 11], [0, 2, 0, 12]]),
        rgba(&palette),
    ]);
    let asset = load_vox_bytes(&bytes, Path::new("row.vox"), None).unwrap();
    assert_eq!(asset.grid_dims, [1, 1, 3]);
    let mut leaves: Vec<([u32; 3], LeafAttr)> = asset.leaves.coords().collect();
    leaves.sort_by_key(|(c, _)| c[2]);
    // Right-handed y-up: vox +y points to our -z, so the vox y = 2 voxel has the smallest z.
    let colours: Vec<[u8; 4]> = leaves.iter().map(|(_, a)| a.rgba()).collect();
    assert_eq!(
        colours,
        vec![opaque(palette[11]), opaque(palette[10]), opaque(palette[9])]
    );
}

#[test]
fn file_without_palette_uses_magicavoxel_default() {
    let bytes = vox_file(&[model([1, 1, 1], &[[0, 0, 0, 1]])]);
    let asset = load_vox_bytes(&bytes, Path::new("nopalette.vox"), None).unwrap();
    let (_, attr) = asset.leaves.coords().next().unwrap();
    let c = dot_vox::DEFAULT_PALETTE[0];
    assert_eq!(attr.rgba(), [c.r, c.g, c.b, 255]);
}

// ---------------------------------------------------------------------------------------------
// Scene graph

#[test]
fn scene_graph_translates_rotates_and_hides_instances() {
    let palette = test_palette();
    let rot_z90 = (1 | (1 << 4)).to_string(); // rows: (0,-1,0), (1,0,0), (0,0,1)
    let bytes = vox_file(&[
        model([1, 1, 1], &[[0, 0, 0, 1]]),
        model([3, 1, 1], &[[0, 0, 0, 2], [1, 0, 0, 3], [2, 0, 0, 4]]),
        transform_node(0, &[], 1, &[]),
        group_node(1, &[2, 4, 6, 8]),
        transform_node(2, &[], 3, &[("_t", "0 0 0")]),
        shape_node(3, 0),
        transform_node(4, &[], 5, &[("_t", "10 0 0")]),
        shape_node(5, 1),
        transform_node(6, &[], 7, &[("_t", "0 0 5"), ("_r", &rot_z90)]),
        shape_node(7, 1),
        transform_node(8, &[("_hidden", "1")], 9, &[("_t", "-20 0 0")]),
        shape_node(9, 0),
        rgba(&palette),
    ]);
    let asset = load_vox_bytes(&bytes, Path::new("scene.vox"), None).unwrap();
    assert_eq!(asset.models, 3, "the hidden instance must be skipped");
    // World (vox axes): model 0 at (0,0,0); model 1 at x = 9..=11 (centred on x = 10);
    // rotated model 1 turned onto vox y = -1..=1 at x = -1, z = 5 (rotation about the grid
    // point floor(3/2) = 1, voxel centres floored). Ours = (x, z, -y-1).
    assert_eq!(asset.grid_dims, [13, 6, 3]);
    assert_eq!(asset.depth, 4);
    // Bounding box min (ours) = (-1, 0, -2); centring offset = (1, 5, 6).
    let expect: HashMap<[u32; 3], [u8; 4]> = [
        ([2, 5, 7], 0),
        ([11, 5, 7], 1),
        ([12, 5, 7], 2),
        ([13, 5, 7], 3),
        ([1, 10, 8], 1), // vox x = 0 of the rotated rod: vox y = -1
        ([1, 10, 7], 2),
        ([1, 10, 6], 3),
    ]
    .into_iter()
    .map(|(c, entry)| (c, opaque(palette[entry])))
    .collect();
    let got: HashMap<[u32; 3], [u8; 4]> =
        asset.leaves.coords().map(|(c, a)| (c, a.rgba())).collect();
    assert_eq!(got, expect);
}

#[test]
fn mirrored_even_model_keeps_its_footprint() {
    // A 2-wide model mirrored in x about its pivot floor(2/2) = 1 occupies the same cells with
    // its colours swapped (voxel centres 0.5 and 1.5 mirror to 1.5 and 0.5).
    let palette = test_palette();
    let mirror_x = ((1 << 2) | (1 << 4)).to_string(); // rows: (-1,0,0), (0,1,0), (0,0,1)
    let bytes = vox_file(&[
        model([2, 1, 1], &[[0, 0, 0, 1], [1, 0, 0, 2]]),
        transform_node(0, &[], 1, &[]),
        group_node(1, &[2, 4]),
        transform_node(2, &[], 3, &[("_t", "0 0 0")]),
        shape_node(3, 0),
        transform_node(4, &[], 5, &[("_t", "0 0 3"), ("_r", &mirror_x)]),
        shape_node(5, 0),
        rgba(&palette),
    ]);
    let asset = load_vox_bytes(&bytes, Path::new("mirror.vox"), None).unwrap();
    assert_eq!(asset.grid_dims, [2, 4, 1]);
    let leaves = leaf_map(&asset);
    let plain_y = leaves.keys().map(|c| c[1]).min().unwrap();
    let mirrored_y = leaves.keys().map(|c| c[1]).max().unwrap();
    let row = |y: u32| -> Vec<([u32; 3], [u8; 4])> {
        let mut r: Vec<_> = leaves
            .iter()
            .filter(|(c, _)| c[1] == y)
            .map(|(c, a)| (*c, a.rgba()))
            .collect();
        r.sort_by_key(|(c, _)| c[0]);
        r
    };
    let (plain, mirrored) = (row(plain_y), row(mirrored_y));
    let xs = |r: &[([u32; 3], [u8; 4])]| r.iter().map(|(c, _)| c[0]).collect::<Vec<_>>();
    assert_eq!(xs(&plain), xs(&mirrored), "mirroring moved the model");
    assert_eq!(
        plain.iter().map(|p| p.1).collect::<Vec<_>>(),
        vec![opaque(palette[0]), opaque(palette[1])]
    );
    assert_eq!(
        mirrored.iter().map(|p| p.1).collect::<Vec<_>>(),
        vec![opaque(palette[1]), opaque(palette[0])]
    );
}

#[test]
fn broken_scene_graphs_are_errors() {
    let path = Path::new("broken_scene.vox");
    let cases: Vec<(&str, Vec<Vec<u8>>)> = vec![
        (
            "dangling child",
            vec![
                model([1, 1, 1], &[[0, 0, 0, 1]]),
                transform_node(0, &[], 7, &[]),
            ],
        ),
        (
            "missing model",
            vec![
                model([1, 1, 1], &[[0, 0, 0, 1]]),
                transform_node(0, &[], 1, &[]),
                shape_node(1, 5),
            ],
        ),
        (
            "cycle",
            vec![
                model([1, 1, 1], &[[0, 0, 0, 1]]),
                transform_node(0, &[], 1, &[]),
                group_node(1, &[0]),
            ],
        ),
        (
            "invalid rotation",
            vec![
                model([1, 1, 1], &[[0, 0, 0, 1]]),
                transform_node(0, &[], 1, &[("_r", "0")]),
                shape_node(1, 0),
            ],
        ),
        (
            "invalid translation",
            vec![
                model([1, 1, 1], &[[0, 0, 0, 1]]),
                transform_node(0, &[], 1, &[("_t", "1 2")]),
                shape_node(1, 0),
            ],
        ),
    ];
    for (what, chunks) in cases {
        let err = load_vox_bytes(&vox_file(&chunks), path, None).expect_err(what);
        println!("{what}: {err}");
        assert!(matches!(err, VoxError::Scene { .. }), "{what}: {err:?}");
        assert_names_path(&err, path);
    }
}

#[test]
fn instancing_beyond_the_voxel_budget_is_an_error() {
    // One model of 2^20 voxels (a full 128 x 128 x 64 block), instanced 65 times: 2^26 + 2^20
    // placed voxels from a 4 MiB file.
    let voxels: Vec<[u8; 4]> = (0..1u32 << 20)
        .map(|i| [(i & 127) as u8, ((i >> 7) & 127) as u8, (i >> 14) as u8, 1])
        .collect();
    let instances = 65u32;
    let children: Vec<u32> = (0..instances).map(|i| 2 + 2 * i).collect();
    let mut chunks = vec![
        model([128, 128, 64], &voxels),
        transform_node(0, &[], 1, &[]),
        group_node(1, &children),
    ];
    for i in 0..instances {
        let t = format!("{} 0 0", 200 * i);
        chunks.push(transform_node(2 + 2 * i, &[], 3 + 2 * i, &[("_t", &t)]));
        chunks.push(shape_node(3 + 2 * i, 0));
    }
    let path = Path::new("instanced.vox");
    let err = load_vox_bytes(&vox_file(&chunks), path, None).expect_err("too many voxels");
    println!("{err}");
    assert!(
        matches!(err, VoxError::TooManyVoxels { voxels, .. } if voxels == 65 << 20),
        "{err:?}"
    );
    assert_names_path(&err, path);
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
        let err = load_vox(path, None).expect_err(what);
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
    let coarse = load_vox(&path, None).unwrap();
    let needed = coarse.depth;
    match load_vox(&path, Some(needed - 1)) {
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
        let err = load_vox(&path, Some(bad)).expect_err("out of range");
        assert!(
            matches!(err, VoxError::DepthOutOfRange { given, .. } if given == bad),
            "{err:?}"
        );
        assert_names_path(&err, &path);
    }
    // Depth 20 would turn each surface voxel into up to 6·(2^15)² leaves.
    let err = load_vox(&path, Some(20)).expect_err("too many leaves");
    assert!(
        matches!(err, VoxError::TooManyLeaves { depth: 20, .. }),
        "{err:?}"
    );
    println!("{err}");
    assert_names_path(&err, &path);
    let same = load_vox(&path, Some(needed)).unwrap();
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
        let coarse = load_vox(&path, None).unwrap();
        for extra in 1..=2u8 {
            let depth = coarse.depth + extra;
            let fine = load_vox(&path, Some(depth)).unwrap();
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
