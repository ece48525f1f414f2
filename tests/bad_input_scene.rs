//! Bad scene files given to the `sim` binary (and, where simpler, to
//! `svo_sim::world::scene::Scene::from_ron`): malformed RON (with its line and column);
//! unknown asset; NaN/inf/zero/negative instance transforms; a camera whose up is parallel to
//! its view; depth 0/21 and resolution 0 / too large in the file; zero frames, out-of-order
//! keyframes, vfov 0/180, empty/duplicate asset names, no instances.
//!
//! Each case edits `scenes/car.ron` in one place; what a failure must look like (exit code,
//! message, nothing half-written) is checked by `tests/common/bad_input.rs`. Command-line
//! and output-path cases are in `tests/bad_input_cli.rs`, `.vox` assets in
//! `tests/bad_input_vox.rs`.

use std::path::Path;

mod common;
use common::bad_input::{
    args, car, expect_failure, line_col, line_of, replace_once, scene_case, small_default, Tmp,
};

use svo_sim::world::scene::Scene;

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
// 5. Depth out of range in the file

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

// ---------------------------------------------------------------------------------------------
// 6. Resolution in the file

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
// 7. Frames, keyframes, field of view, asset names, instances

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
