//! The layers of `rtl_model` (docs/architecture.md §1) hold in the source: a module imports
//! only modules of its own layer or below. Bottom to top:
//!
//! `fixed` · `svo` · `resources` · `units` · `datapath` · `cycle` · `cost` · `vectors`
//!
//! The check reads every `.rs` file of each layer and refuses, outside comments, any path
//! `crate::X` where X is a layer above it. It shares no code with the crate: it is a text scan.

use std::path::{Path, PathBuf};

/// The layers, bottom first: a module name and the source path it covers.
const LAYERS: [(&str, &str); 8] = [
    ("fixed", "src/fixed"),
    ("svo", "src/svo"),
    ("resources", "src/resources.rs"),
    ("units", "src/units"),
    ("datapath", "src/datapath.rs"),
    ("cycle", "src/cycle"),
    ("cost", "src/cost"),
    ("vectors", "src/vectors"),
];

fn rs_files(p: &Path) -> Vec<PathBuf> {
    if p.is_file() {
        return vec![p.to_path_buf()];
    }
    let mut out = Vec::new();
    let mut stack = vec![p.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("a source folder").flatten() {
            let q = e.path();
            if q.is_dir() {
                stack.push(q);
            } else if q.extension().is_some_and(|x| x == "rs") {
                out.push(q);
            }
        }
    }
    out.sort();
    out
}

/// `crate::NAME` paths in the code (not the comments) of `text` that name one of `above`,
/// as "file:line: text".
fn upward_imports(file: &Path, text: &str, above: &[&str]) -> Vec<String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        for name in above {
            if code.contains(&format!("crate::{name}::"))
                || code.contains(&format!("crate::{name};"))
                || code.contains(&format!("crate::{name} "))
            {
                out.push(format!("{}:{}: {}", file.display(), i + 1, line.trim()));
            }
        }
    }
    out
}

#[test]
fn no_layer_imports_a_layer_above_it() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut bad = Vec::new();
    for (k, (name, path)) in LAYERS.iter().enumerate() {
        let above: Vec<&str> = LAYERS[k + 1..].iter().map(|(n, _)| *n).collect();
        let files = rs_files(&root.join(path));
        assert!(!files.is_empty(), "layer {name}: no source at {path}");
        for f in files {
            let text = std::fs::read_to_string(&f).expect("a source file");
            bad.extend(upward_imports(&f, &text, &above));
        }
    }
    assert!(
        bad.is_empty(),
        "imports of a layer above (docs/architecture.md §1):\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_scan_sees_an_upward_import() {
    // The check itself: a unit file importing `cost` is caught, a comment naming it is not.
    let text = "//! priced by `crate::cost::estimate`\nuse crate::cost::report::Resources;\n";
    let found = upward_imports(Path::new("units/x.rs"), text, &["cost"]);
    assert_eq!(
        found,
        vec!["units/x.rs:2: use crate::cost::report::Resources;"]
    );
}
