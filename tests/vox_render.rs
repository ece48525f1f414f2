//! Every MagicaVoxel model in `../shared/data/vox/` loads through a scene file and renders:
//! one instance per model, seen from a 3/4 view, must cover a fair share of the image, and
//! the example scene `scenes/vox_traffic.ron` renders.
//!
//! The models are shared data, not part of the repository: without them the test is skipped
//! with a printed reason, except under `CI=true`, where it fails.

use std::path::{Path, PathBuf};

mod common;
use svo_sim::models::reference::RenderOptions;
use svo_sim::run::{run, RunConfig};
use svo_sim::world::assets::Materialise;
use svo_sim::world::scene::Scene;

fn config(scene: Scene) -> RunConfig {
    RunConfig {
        scene,
        depth: None,
        materialise: Materialise::Auto,
        image_layout: Default::default(),
        options: RenderOptions::default(),
        out_dir: None,
        report_json: None,
        dump_hits: None,
        progress_every: None,
        model: svo_sim::run::Model::Reference,
        datapath: Default::default(),
        hardware: Default::default(),
        cross_check: false,
        sample: None,
        vcd: None,
        transaction_log: None,
        elaboration: None,
    }
}

#[test]
fn every_model_renders() {
    let Some(dir) = common::shared_vox_dir() else {
        return;
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
        .collect();
    files.sort();
    assert!(
        files.len() >= 10,
        "expected the shared model set, found {}",
        files.len()
    );
    for f in &files {
        // The octree cube is 2^depth voxels of 1/64 m; the camera stands back 3 cube sides.
        let ron = format!(
            r#"(resolution: (64, 48), frames: 1,
                camera: [(frame: 0, position: (2.6, 2.0, 3.0), look_at: (0, 0, 0), vfov_deg: 40)],
                assets: [(name: "m", depth: 1, source: Vox(path: "{}", voxel_size: 1.0))],
                instances: [(name: "m", asset: "m", keys: [(frame: 0)])])"#,
            f.display()
        );
        // depth 1 is raised to what the model needs by --depth below; size the cube to 2 m.
        let scene = Scene::from_ron(&ron, "vox test", Path::new("/")).unwrap();
        let needed =
            svo_sim::world::assets::vox::load_vox(f, None, svo_sim::input::DEFAULT_VOX_CAP_BYTES)
                .unwrap()
                .depth;
        let mut cfg = config(scene);
        cfg.depth = Some(needed);
        if let svo_sim::world::scene::AssetSource::Vox { voxel_size, .. } =
            &mut cfg.scene.file.assets[0].source
        {
            *voxel_size = 2.0 / f64::from(1u32 << needed);
        }
        let out = run(&cfg, |_, _| {}).unwrap_or_else(|e| panic!("{}: {e:#}", f.display()));
        let hits = out.frames[0].hits;
        let share = hits as f64 / out.frames[0].rays as f64;
        println!(
            "{:<24} depth {needed} leaves {:>7} hit pixels {:>5.1}%",
            f.file_name().unwrap().to_string_lossy(),
            out.assets[0].stats.leaves,
            100.0 * share
        );
        assert!(share > 0.02, "{}: only {hits} pixels hit", f.display());
    }
}

#[test]
fn vox_traffic_scene_renders() {
    let Some(path) = common::skip::vox_scene_path("scenes/vox_traffic.ron") else {
        return;
    };
    let mut scene = Scene::load(&path).unwrap();
    scene.set_resolution(96, 64).unwrap();
    scene.set_frames(4).unwrap();
    let out = run(&config(scene), |_, _| {}).unwrap();
    assert!(out.frames.iter().all(|f| f.hits > 0));
    assert_eq!(out.assets.len(), 5);
}
