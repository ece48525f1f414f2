//! The stiff and extreme cases of `docs/stability.md`, as tests: every case runs through both
//! models without a panic and ends with its documented verdict (pass, or flagged where the
//! default formats cannot represent it), never FAIL; each case really exercises what it
//! claims (exact −0 components, flushed tiny components, grazing rays, the camera inside
//! spheres, boxes and a leaf, a 10^4 scale ratio, 1000:1 anisotropy, a 16-deep walk,
//! saturation beyond the range, ≥ 64 candidates past the sorter's N). And the judge itself can
//! fail: a frame with one corrupted pixel is caught.

mod common;
use common::process::run_sim;
use std::time::Duration;
use svo_sim::models::fixed::explain::{judge, JudgeCtx};
use svo_sim::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use svo_sim::studies::stress::cases::all;
use svo_sim::studies::stress::command::run_cases;
use svo_sim::studies::stress::{CaseResult, Verdict};

fn by_name<'a>(r: &'a [CaseResult], name: &str) -> &'a CaseResult {
    r.iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("case {name} missing"))
}

#[test]
fn every_case_meets_its_verdict_and_exercises_its_extreme() {
    let results = run_cases(&[]).unwrap();
    assert_eq!(results.len(), all().len());
    for r in &results {
        println!(
            "{:<18} {:<8} mismatches {}/{}/{} beyond {} t/bound {:.3} saturations {:?}",
            r.name,
            r.verdict.word(),
            r.hit_mismatches,
            r.instance_mismatches,
            r.voxel_mismatches,
            r.beyond_bound,
            r.t_err_over_bound,
            r.saturated_signals
        );
        assert_ne!(
            r.verdict,
            Verdict::Fail,
            "{}: silently wrong pixels: {r:?}",
            r.name
        );
        assert_eq!(r.verdict, r.expected, "{}: {r:?}", r.name);
        if r.verdict == Verdict::Pass {
            assert_eq!(
                (r.beyond_bound, r.saturations, r.step_limit_hits),
                (0, 0, 0),
                "{r:?}"
            );
            assert!(r.t_err_over_bound <= 1.0, "{r:?}");
        }
    }
    let c = |n: &str| by_name(&results, n);
    assert!(c("axis_zero").census.negative_zero_components > 0);
    assert!(c("axis_zero").census.zero_components > 0);
    assert!(c("near_axis").census.tiny_components > 0 && c("near_axis").zero_flushes > 0);
    assert!(c("grazing_sphere").census.grazing > 100);
    assert!(c("camera_in_sphere").census.camera_in_spheres >= 2);
    assert_eq!(c("camera_in_sphere").census.camera_in_boxes, 0);
    assert!(c("camera_in_svo").census.camera_in_boxes >= 1);
    let leaf = c("camera_in_leaf");
    assert_eq!((leaf.reference_hits, leaf.t_err_max), (33 * 33, 0.0));
    assert_eq!((c("depth16").depth_max, c("depth16").max_stack), (16, 16));
    let range = c("range_beyond");
    assert!(range
        .saturated_signals
        .iter()
        .any(|(n, _)| n == "raygen/pos"));
    for n in ["far_beyond_reach", "far_diagonal"] {
        assert!(
            c(n).saturated_signals
                .iter()
                .any(|(s, _)| s == "sphere/reach"),
            "{n}"
        );
    }
    let many = c("overlap_72");
    assert!(many.census.candidates_max >= 64 && many.sorter_overflow_batches > 0);
    assert!(many.reference_hits > 0);
    // The scale cases: ratios from the built frames.
    let specs = all();
    let build = |n: &str| (specs.iter().find(|s| s.name == n).unwrap().build)().unwrap();
    let scale = build("scale_1e4");
    let sizes: Vec<f64> = scale
        .state
        .poses
        .iter()
        .map(|p| p.half_extent.max_element())
        .collect();
    assert!(sizes[1] / sizes[0] >= 1e4);
    let aniso = build("anisotropic_1000").state.poses[0].half_extent;
    assert!(aniso.max_element() / aniso.min_element() >= 1000.0);
}

#[test]
fn the_judge_catches_a_silently_wrong_pixel() {
    let spec = all()
        .into_iter()
        .find(|s| s.name == "camera_in_svo")
        .unwrap();
    let input = (spec.build)().unwrap();
    let (w, h) = input.scene.file.resolution;
    let mut reference = HitBuffer::new(w, h);
    let frame = FrameInput {
        scene: &input.scene,
        assets: &input.assets,
        state: &input.state,
    };
    render_frame(&frame, &mut reference, RenderOptions::default());
    let cfg = rtl_model::datapath::DatapathConfig::default();
    let depths = [input.assets[0].depth()];
    let ctx = JudgeCtx {
        cfg: &cfg,
        camera: &input.state.camera,
        size: (w, h),
        poses: &input.state.poses,
        depths: &depths,
        mat_err: 0.0,
    };
    assert_eq!(
        judge(&ctx, &reference.records, &reference.records).all_beyond_bound(),
        0
    );
    // The centre pixel: its t off by 1 mm, then its hit dropped, then its leaf moved.
    let k = (h / 2 * w + w / 2) as usize;
    let mut bad = reference.records.clone();
    bad[k].t += 1e-3;
    assert_eq!(judge(&ctx, &reference.records, &bad).t_beyond_bound, 1);
    let mut bad = reference.records.clone();
    bad[k] = svo_sim::models::reference::HitRecord::MISS;
    assert_eq!(
        judge(&ctx, &reference.records, &bad).hit_mismatches_beyond_bound,
        1
    );
    let mut bad = reference.records.clone();
    bad[k].voxel[0] ^= 8;
    assert_eq!(
        judge(&ctx, &reference.records, &bad)
            .accuracy
            .voxel_mismatches_beyond_bound,
        1
    );
}

#[test]
fn cli_writes_the_table_and_refuses_unknown_cases() {
    let dir = std::env::temp_dir().join(format!("svo_stress_cli_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.display().to_string();
    let run = run_sim(
        &[
            "stress",
            "--case",
            "depth16",
            "--case",
            "range_beyond",
            "--out",
            &out,
        ],
        None,
        Duration::from_secs(120),
    );
    assert!(run.status.success(), "{}", run.stderr);
    assert!(
        run.stdout.contains("2 cases: 1 pass, 1 flagged, 0 FAIL"),
        "{}",
        run.stdout
    );
    let csv = std::fs::read_to_string(dir.join("stress.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3);
    assert!(std::fs::read_to_string(dir.join("stress.md"))
        .unwrap()
        .contains("`depth16`"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("stress.json")).unwrap()).unwrap();
    assert_eq!(json[1]["verdict"], "flagged");
    let run = run_sim(&["stress", "--case", "nope"], None, Duration::from_secs(60));
    assert!(!run.status.success());
    assert!(
        run.stderr.contains("no such case") && run.stderr.contains("axis_zero"),
        "{}",
        run.stderr
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn coincident_instances_go_to_the_lower_id_in_both_models() {
    let spec = all().into_iter().find(|s| s.name == "coincident").unwrap();
    let mut input = (spec.build)().unwrap();
    // Keep the two instances at the very same pose; drop the one 10^-9 m beside them.
    input.state.poses.truncate(2);
    input.scene.instance_asset.truncate(2);
    input.scene.file.instances.truncate(2);
    let (w, h) = input.scene.file.resolution;
    let frame = FrameInput {
        scene: &input.scene,
        assets: &input.assets,
        state: &input.state,
    };
    let mut reference = HitBuffer::new(w, h);
    render_frame(&frame, &mut reference, RenderOptions::default());
    let cfg = rtl_model::datapath::DatapathConfig::default();
    let mut fixed = svo_sim::models::fixed::FixedBuffer::new(w, h);
    svo_sim::models::fixed::render_frame_fixed(&frame, &mut fixed, &cfg, false).unwrap();
    let fixed = svo_sim::models::fixed::to_hit_records(&fixed, &cfg);
    let hits = reference.records.iter().filter(|r| r.hit).count();
    assert!(hits > 100);
    for (r, f) in reference.records.iter().zip(&fixed) {
        assert_eq!(r.hit, f.hit);
        if r.hit {
            assert_eq!((r.instance, f.instance), (0, 0));
        }
    }
}

/// The Markdown table of docs/stability.md §2: the first block of `|` lines after its heading.
fn documented_table(doc: &str) -> Vec<&str> {
    doc.lines()
        .skip_while(|l| !l.starts_with("## 2."))
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .collect()
}

/// The rows of `doc` that are not `want`'s row at the same place (by case, or by position),
/// and any row one has and the other not.
fn table_differences(doc: &[&str], want: &[&str]) -> Vec<String> {
    let mut d = Vec::new();
    for (i, (a, b)) in doc.iter().zip(want).enumerate() {
        if a != b {
            d.push(format!("row {i}:\n  doc:     {a}\n  command: {b}"));
        }
    }
    if doc.len() != want.len() {
        d.push(format!(
            "the doc has {} rows, the command {}",
            doc.len(),
            want.len()
        ));
    }
    d
}

/// docs/stability.md §2 is today's `sim stress` table, row for row: the doc names the command
/// that regenerates it, and this test stops it drifting from the code again.
#[test]
fn the_documented_table_is_the_commands_output() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/stability.md"))
        .expect("docs/stability.md");
    let want = svo_sim::studies::stress::report::markdown(&run_cases(&[]).unwrap());
    let want: Vec<&str> = want.lines().collect();
    let bad = table_differences(&documented_table(&doc), &want);
    assert!(
        bad.is_empty(),
        "docs/stability.md §2 differs from `sim stress` (regenerate it with \
         `cargo run --release --bin sim -- stress | grep '^|'`):\n{}",
        bad.join("\n")
    );
}

/// The comparison catches one changed figure, naming its row, and a row too many.
#[test]
fn a_changed_figure_in_the_documented_table_is_caught() {
    let doc =
        "# x\n## 2. The table\n\n| case | a |\n|---|---|\n| `one` | 1 |\n| `two` | 2 |\n\ntext\n";
    let table = documented_table(doc);
    assert_eq!(table.len(), 4);
    let want = [
        "| case | a |",
        "|---|---|",
        "| `one` | 1 |",
        "| `two` | 2 |",
    ];
    assert!(table_differences(&table, &want).is_empty());
    let changed = [
        "| case | a |",
        "|---|---|",
        "| `one` | 1 |",
        "| `two` | 3 |",
    ];
    assert_eq!(
        table_differences(&table, &changed),
        ["row 3:\n  doc:     | `two` | 2 |\n  command: | `two` | 3 |"]
    );
    let fewer = &want[..3];
    assert_eq!(
        table_differences(&table, fewer),
        ["the doc has 4 rows, the command 3"]
    );
}
