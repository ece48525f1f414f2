//! Integration tests of the MagicaVoxel loader's conventions (`svo_sim::world::assets::vox`)
//! on tiny `.vox` files written by hand in memory: vox z-up becomes our y-up (vox +y our −z),
//! file colour indices select the documented palette entries (MagicaVoxel's default palette
//! without an `RGBA` chunk), and the scene graph translates, rotates, mirrors and hides
//! instances as MagicaVoxel does; broken scene graphs and instancing beyond the voxel budget
//! are errors naming the file.
//!
//! The sample models, corrupt input and depth handling are tested in `tests/vox_models.rs`.

use std::collections::HashMap;
use std::path::Path;

use rtl_model::svo::LeafAttr;
use svo_sim::world::assets::vox::{load_vox_bytes, VoxError};

mod common;
use common::vox::{
    assert_names_path, group_node, leaf_map, model, rgba, shape_node, test_palette, transform_node,
    vox_file,
};

/// `c` with alpha 255, as the loader makes every leaf.
fn opaque(c: [u8; 4]) -> [u8; 4] {
    [c[0], c[1], c[2], 255]
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
