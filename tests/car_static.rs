//! `scenes/car_static.ron` — the default car's eight parts at frame 0 in one SVO, the paper's
//! static case (docs/paper.md §3) — against the animated car's frame 0, rendered by the f64
//! reference at the scenes' 640×384.
//!
//! The static car's parts are resampled onto the body's grid (4.1 mm leaves) while the
//! animated parts keep their own grids (3.3–4.8 mm), so silhouettes and colour edges of the
//! wheels, doors and steering wheel can move by a leaf: the test caps the pixels whose hit or
//! miss differs and the pixels whose shaded colour differs at what was measured (with a little
//! room), and requires the body's pixels (instance 0 in the animated car) to be mostly
//! identical in colour. A control shows the check failing: the animated car's frame 12, with
//! the wheels turned and the doors moving, is refused with the count named (1,843 pixels hit in
//! one and miss in the other when measured).

use std::path::Path;
use svo_sim::models::reference::{render_frame, FrameInput, HitBuffer, HitRecord, RenderOptions};
use svo_sim::output::png::shade;
use svo_sim::world::assets::{build_assets, effective_depths, Materialise};
use svo_sim::world::scene::Scene;

/// Measured on the commit that added this test (640×384, frame 0): 28 pixels hit in one
/// scene and miss in the other and 4,318 differ in shaded colour, of 245,760 (1.8 %; the
/// resampled parts' leaf normals differ), and 99.97 % of the body's pixels keep their colour
/// (docs/paper.md §3). The caps leave about 10 % room (a few pixels for the hit/miss count).
const MAX_HIT_MISS: usize = 40;
const MAX_COLOUR: usize = 4_800;
const MIN_BODY_SAME: f64 = 0.999;

fn render(file: &str, frame: u32) -> (Vec<HitRecord>, image::RgbImage) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(file);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let depths = effective_depths(&scene, None).expect("depths");
    let assets = build_assets(&scene, &depths, Materialise::Auto).expect("assets");
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let state = scene.frame_state(frame, &half).expect("frame state");
    let (w, h) = scene.file.resolution;
    let mut buf = HitBuffer::new(w, h);
    let input = FrameInput {
        scene: &scene,
        assets: &assets,
        state: &state,
    };
    render_frame(&input, &mut buf, RenderOptions::default());
    let f = &scene.file;
    let img = shade(
        &buf.records,
        w,
        h,
        f.light.direction,
        f.light.ambient,
        f.background,
    );
    (buf.records, img)
}

/// Pixels whose hit differs, pixels whose colour differs, and of the animated car's body
/// pixels (instance 0) the share whose colour is the same.
fn differences(
    anim: &(Vec<HitRecord>, image::RgbImage),
    stat: &(Vec<HitRecord>, image::RgbImage),
) -> (usize, usize, f64) {
    let hit_miss = anim
        .0
        .iter()
        .zip(&stat.0)
        .filter(|(a, b)| a.hit != b.hit)
        .count();
    let colour = anim
        .1
        .pixels()
        .zip(stat.1.pixels())
        .filter(|(a, b)| a != b)
        .count();
    let body: Vec<usize> = (0..anim.0.len())
        .filter(|&k| anim.0[k].hit && anim.0[k].instance == 0)
        .collect();
    let (w, _) = anim.1.dimensions();
    let same = body
        .iter()
        .filter(|&&k| {
            let (x, y) = (k as u32 % w, k as u32 / w);
            anim.1.get_pixel(x, y) == stat.1.get_pixel(x, y)
        })
        .count();
    (hit_miss, colour, same as f64 / body.len().max(1) as f64)
}

fn check(
    anim: &(Vec<HitRecord>, image::RgbImage),
    stat: &(Vec<HitRecord>, image::RgbImage),
) -> Result<(), String> {
    let (hm, col, body_same) = differences(anim, stat);
    println!(
        "hit/miss differ: {hm} pixels (cap {MAX_HIT_MISS}); colour differs: {col} (cap {MAX_COLOUR}); body pixels with the same colour: {:.2} %",
        100.0 * body_same
    );
    if hm > MAX_HIT_MISS {
        return Err(format!("{hm} pixels hit in one car and miss in the other"));
    }
    if col > MAX_COLOUR {
        return Err(format!("{col} pixels differ in colour"));
    }
    if body_same < MIN_BODY_SAME {
        return Err(format!(
            "only {:.2} % of the body's pixels have the same colour",
            100.0 * body_same
        ));
    }
    Ok(())
}

#[test]
fn static_car_frame_0_matches_the_animated_car_within_the_measured_caps() {
    let stat = render("car_static.ron", 0);
    let anim = render("car.ron", 0);
    assert_eq!(stat.0.len(), 640 * 384);
    assert!(stat.0.iter().all(|r| !r.hit || r.instance == 0));
    check(&anim, &stat).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_later_frame_of_the_animated_car_is_refused() {
    let stat = render("car_static.ron", 0);
    let anim = render("car.ron", 12);
    let e = check(&anim, &stat).expect_err("frame 12 differs");
    assert!(
        e.ends_with("pixels hit in one car and miss in the other"),
        "{e}"
    );
}
