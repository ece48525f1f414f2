//! A check that the stages stay below the model in the import graph (issue 30): no stage file
//! names the model's file (`cycle::model`, `super::model`) or the pipeline in a `use`, so
//! `model.rs` → `pipeline.rs` → `stages/` is a line, not a circle. What a stage needs from
//! above (the error type) lives in its own file, `cycle/error.rs`.
//!
//! Pipeline position: none; a unit test reading the stage sources as they are compiled
//! (`include_str!`), so it checks the real files.

/// Every stage file, with its name.
const STAGE_SOURCES: [(&str, &str); 12] = [
    ("mod.rs", include_str!("mod.rs")),
    ("io.rs", include_str!("io.rs")),
    ("check.rs", include_str!("check.rs")),
    ("passthrough.rs", include_str!("passthrough.rs")),
    ("raygen.rs", include_str!("raygen.rs")),
    ("record.rs", include_str!("record.rs")),
    ("sorter.rs", include_str!("sorter.rs")),
    ("sphere.rs", include_str!("sphere.rs")),
    ("tile_list.rs", include_str!("tile_list.rs")),
    ("transform.rs", include_str!("transform.rs")),
    ("walkers.rs", include_str!("walkers.rs")),
    ("write.rs", include_str!("write.rs")),
];

/// Paths a stage may not import from: the model's file and the pipeline.
const FORBIDDEN: [&str; 4] = [
    "cycle::model",
    "super::model",
    "super::super::model",
    "pipeline",
];

/// The `use` declarations of `src` (each from `use` to its `;`, over several lines if need be),
/// with their first line number.
fn uses(src: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut open: Option<(usize, String)> = None;
    for (n, line) in src.lines().enumerate() {
        let t = line.trim_start();
        if open.is_none() && (t.starts_with("use ") || t.starts_with("pub use ")) {
            open = Some((n + 1, String::new()));
        }
        if let Some((_, text)) = open.as_mut() {
            text.push_str(t);
            if t.contains(';') {
                out.extend(open.take());
            }
        }
    }
    out
}

/// The forbidden imports of every stage file: (file, line, declaration).
fn violations() -> Vec<(&'static str, usize, String)> {
    let mut v = Vec::new();
    for (file, src) in STAGE_SOURCES {
        for (line, decl) in uses(src) {
            if FORBIDDEN.iter().any(|f| decl.contains(f)) {
                v.push((file, line, decl));
            }
        }
    }
    v
}

#[test]
fn no_stage_imports_the_model_or_the_pipeline() {
    let v = violations();
    assert!(
        v.is_empty(),
        "stage files import the model or the pipeline (an import circle): {v:?}"
    );
}

#[test]
fn the_check_sees_a_multi_line_use() {
    // The reader must catch a forbidden path inside a grouped, multi-line `use`.
    let src = "use super::{\n    id,\n    super::pipeline::Fifos,\n};\nuse rtl_model::cycle::fifo::Fifo;\n";
    let u = uses(src);
    assert_eq!(u.len(), 2, "{u:?}");
    assert!(FORBIDDEN.iter().any(|f| u[0].1.contains(f)));
    assert!(!FORBIDDEN.iter().any(|f| u[1].1.contains(f)));
}
