//! The layers of `docs/architecture.md` §1 hold: a layer uses only the layers below it.
//!
//! Every `.rs` file under `src/` (the library; `src/bin/` is the command line above every
//! layer) and `rtl_model/src/` is scanned for the module paths it names (`crate::…`,
//! `super::…`, `self::…`, use groups included; comments and strings ignored), and each path
//! is placed in the layer table below. A file that names a layer above its own fails the test
//! with its file, line and the path. A module that is in no layer fails too, so a new
//! top-level module has to be placed in the table (and in the document).
//!
//! The table is checked against the document's diagram as well: the order of the `svo_sim`
//! layers and of the three models, and `rtl_model`'s foundations. The scanner is
//! `tests/layering/scan.rs`; the tests at the end run it on small sources with a known
//! answer, one upward import each, so the check is seen to fail.

// The scanner sits in a folder of its own so that cargo does not build it as a test of its own.
#[path = "layering/scan.rs"]
mod scan;

use scan::{lines_naming, module_of, references};
use std::path::{Path, PathBuf};

/// One layer: its name and the module paths in it (a path belongs to the layer of its
/// longest listed prefix).
struct Layer {
    name: &'static str,
    modules: &'static [&'static str],
}

/// `svo_sim`'s layers, lowest first (docs/architecture.md §1): the world, the three models
/// each on the one before it, output, run, studies. `error` holds the world's errors
/// (`SceneError`, `AssetError`) and `input` is the bounded reader of every input file, both
/// with the world; `models` itself (its `mod.rs`) sits with its top model.
const SVO_SIM: &[Layer] = &[
    Layer {
        name: "world",
        modules: &["world", "error", "input"],
    },
    Layer {
        name: "models::reference",
        modules: &["models::reference"],
    },
    Layer {
        name: "models::fixed",
        modules: &["models::fixed"],
    },
    Layer {
        name: "models::cycle",
        modules: &["models::cycle", "models"],
    },
    Layer {
        name: "output",
        modules: &["output"],
    },
    Layer {
        name: "run",
        modules: &["run"],
    },
    Layer {
        name: "studies",
        modules: &["studies"],
    },
];

/// `rtl_model`'s layers, lowest first (docs/architecture.md §1 draws them highest first):
/// the fixed-point layer and the SVO memory image are the foundations, the resource estimate's
/// plain types sit below the units that price themselves with them, the datapath configuration
/// gathers the units' configurations, the cycle parts time them, `cost` prices the hardware
/// configuration and `vectors` packs everything into test-vector rows.
const RTL_MODEL: &[Layer] = &[
    Layer {
        name: "fixed",
        modules: &["fixed"],
    },
    Layer {
        name: "svo",
        modules: &["svo"],
    },
    Layer {
        name: "resources",
        modules: &["resources"],
    },
    Layer {
        name: "units",
        modules: &["units"],
    },
    Layer {
        name: "datapath",
        modules: &["datapath"],
    },
    Layer {
        name: "cycle",
        modules: &["cycle"],
    },
    Layer {
        name: "cost",
        modules: &["cost"],
    },
    Layer {
        name: "vectors",
        modules: &["vectors"],
    },
];

/// The index of the layer `path` is in, by its longest listed prefix; `None` for the crate
/// root itself and for a module in no layer.
fn layer_of(table: &[Layer], path: &[String]) -> Option<usize> {
    let mut best: Option<(usize, usize)> = None;
    for (rank, layer) in table.iter().enumerate() {
        for m in layer.modules {
            let segs: Vec<&str> = m.split("::").collect();
            let matches = segs.len() <= path.len() && segs.iter().zip(path).all(|(a, b)| a == b);
            if matches && best.is_none_or(|(len, _)| segs.len() > len) {
                best = Some((segs.len(), rank));
            }
        }
    }
    best.map(|(_, rank)| rank)
}

/// The violations in one file: `shown` is the path printed (relative to the repository),
/// `relative` its path under the crate's `src/`.
fn check_source(
    table: &[Layer],
    crate_name: &str,
    shown: &str,
    relative: &str,
    src: &str,
) -> Vec<String> {
    let module = module_of(relative);
    if module.is_empty() {
        // The crate root declares the layers.
        return Vec::new();
    }
    let Some(own) = layer_of(table, &module) else {
        return vec![format!(
            "{shown}: module {crate_name}::{} is in no layer of tests/layering.rs (place it there and in docs/architecture.md §1)",
            module.join("::")
        )];
    };
    let mut out = Vec::new();
    for r in references(src, &module) {
        if r.path.is_empty() {
            continue;
        }
        match layer_of(table, &r.path) {
            None => out.push(format!(
                "{shown}:{}: `{}` names {crate_name}::{}, which is in no layer of tests/layering.rs",
                r.line,
                r.written,
                r.path[0]
            )),
            Some(target) if target > own => out.push(format!(
                "{shown}:{}: {} (layer `{}`) imports `{}` from the layer above it, `{}`",
                r.line,
                module.join("::"),
                table[own].name,
                r.written,
                table[target].name
            )),
            Some(_) => {}
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()));
    for entry in entries {
        let path = entry
            .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
            .path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The violations of every file under `<crate_dir>/src`, skipping the folders in `skip`
/// (relative to `src/`); also the crate's own files, for the count.
fn check_crate(
    table: &[Layer],
    crate_name: &str,
    crate_dir: &str,
    skip: &[&str],
) -> (Vec<String>, usize) {
    let src = repository().join(crate_dir).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut out = Vec::new();
    let mut scanned = 0;
    for f in &files {
        let relative = f
            .strip_prefix(&src)
            .expect("under src")
            .to_string_lossy()
            .replace('\\', "/");
        if skip.iter().any(|s| relative.starts_with(s)) {
            continue;
        }
        let text = std::fs::read_to_string(f)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", f.display()));
        let shown = format!("{}/src/{relative}", crate_dir)
            .trim_start_matches("./")
            .to_string();
        out.extend(check_source(table, crate_name, &shown, &relative, &text));
        scanned += 1;
    }
    (out, scanned)
}

fn fail_with(what: &str, violations: &[String]) {
    assert!(
        violations.is_empty(),
        "{what} ({} found; docs/architecture.md §1: a layer uses only the layers below it):\n{}",
        violations.len(),
        violations.join("\n")
    );
}

#[test]
fn svo_sim_modules_import_only_their_own_layer_and_those_below() {
    let (v, scanned) = check_crate(SVO_SIM, "svo_sim", ".", &["bin/"]);
    println!("scanned {scanned} files of src/ (src/bin/ is the command line, above every layer)");
    assert!(scanned > 100, "only {scanned} files found under src/");
    fail_with("svo_sim modules import a layer above their own", &v);
}

#[test]
fn rtl_model_modules_import_only_their_own_layer_and_those_below() {
    let (v, scanned) = check_crate(RTL_MODEL, "rtl_model", "rtl_model", &[]);
    println!("scanned {scanned} files of rtl_model/src/");
    assert!(
        scanned > 50,
        "only {scanned} files found under rtl_model/src/"
    );
    fail_with("rtl_model modules import a layer above their own", &v);
}

#[test]
fn rtl_model_never_names_svo_sim() {
    let root = repository().join("rtl_model");
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("tests"), &mut files);
    files.sort();
    let mut v = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", f.display()));
        for line in lines_naming(&text, "svo_sim") {
            v.push(format!(
                "{}:{line}: names svo_sim",
                f.strip_prefix(repository()).unwrap_or(f).display()
            ));
        }
    }
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).expect("rtl_model/Cargo.toml");
    for (n, line) in manifest.lines().enumerate() {
        if line.trim_start().starts_with("svo_sim") || line.contains("path = \"..\"") {
            v.push(format!(
                "rtl_model/Cargo.toml:{}: depends on svo_sim",
                n + 1
            ));
        }
    }
    fail_with("rtl_model depends on svo_sim, the layer above it", &v);
}

/// The names of the layer lines between two lines of the §1 diagram: the word before the
/// first `/` of each line that starts (after the box's `│`) with a folder name.
fn diagram_layers(doc: &str, from: &str, to: &str) -> Vec<(String, String)> {
    let lines: Vec<&str> = doc.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.contains(from))
        .unwrap_or_else(|| panic!("docs/architecture.md: no line with {from:?}"));
    let end = start
        + lines[start..]
            .iter()
            .position(|l| l.contains(to))
            .unwrap_or_else(|| panic!("docs/architecture.md: no line with {to:?} after {from:?}"));
    lines[start + 1..end]
        .iter()
        .filter_map(|l| {
            let rest = l.trim_start().strip_prefix('│')?.trim_start();
            let (name, tail) = rest.split_once('/')?;
            let is_folder =
                !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c == '_');
            is_folder.then(|| (name.to_string(), tail.to_string()))
        })
        .collect()
}

#[test]
fn the_table_is_the_diagram_of_architecture_md() {
    let path = repository().join("docs/architecture.md");
    let doc = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    // svo_sim: the diagram lists the highest layer first.
    let drawn = diagram_layers(&doc, "svo_sim (src/)", "rtl_model (rtl_model/src/)");
    let drawn_names: Vec<&str> = drawn.iter().map(|(n, _)| n.as_str()).collect();
    let mut table_names: Vec<&str> = Vec::new();
    for l in SVO_SIM {
        let top = l.name.split("::").next().unwrap_or(l.name);
        if table_names.last() != Some(&top) {
            table_names.push(top);
        }
    }
    table_names.reverse();
    assert_eq!(drawn_names, table_names, "docs/architecture.md §1 draws the svo_sim layers in another order than tests/layering.rs's table");
    // The three models, in the order the models line names them.
    let (_, models_line) = drawn
        .iter()
        .find(|(n, _)| n == "models")
        .expect("a models line");
    let models: Vec<&str> = SVO_SIM
        .iter()
        .filter_map(|l| l.name.strip_prefix("models::"))
        .collect();
    let at: Vec<Option<usize>> = models.iter().map(|m| models_line.find(m)).collect();
    assert!(
        at.iter().all(Option::is_some) && at.windows(2).all(|w| w[0] < w[1]),
        "docs/architecture.md §1's models line {models_line:?} does not name {models:?} in this order"
    );
    // rtl_model: the diagram lists its layers highest first, as svo_sim's; the file modules
    // (`datapath`, `resources`) are drawn without a `/` and so are not read here.
    let drawn = diagram_layers(&doc, "rtl_model (rtl_model/src/)", "└");
    let mut drawn_names: Vec<&str> = drawn.iter().map(|(n, _)| n.as_str()).collect();
    drawn_names.reverse();
    let table: Vec<&str> = RTL_MODEL
        .iter()
        .map(|l| l.name)
        .filter(|n| drawn_names.contains(n))
        .collect();
    assert_eq!(drawn_names, table, "docs/architecture.md §1 draws the rtl_model layers in another order than tests/layering.rs's table (or a layer the table lacks)");
}

// The check on sources with a known answer: each of these would pass if the scanner missed
// the import.

fn check_svo_sim(relative: &str, src: &str) -> Vec<String> {
    check_source(
        SVO_SIM,
        "svo_sim",
        &format!("src/{relative}"),
        relative,
        src,
    )
}

#[test]
fn an_upward_use_is_named_with_its_file_and_line() {
    let src = "//! Text.\n\nuse super::report::Summary;\nuse crate::run::RunConfig;\n";
    assert_eq!(
        check_svo_sim("output/text.rs", src),
        ["src/output/text.rs:4: output::text (layer `output`) imports `crate::run::RunConfig` from the layer above it, `run`"]
    );
}

#[test]
fn the_imports_of_the_old_tree_each_fail() {
    // The debts of 1f329ce, as those files named them.
    assert_eq!(
        check_svo_sim("output/report.rs", "pub struct R { pub e: Option<crate::run::elaborate::Elaboration> }"),
        ["src/output/report.rs:1: output::report (layer `output`) imports `crate::run::elaborate::Elaboration` from the layer above it, `run`"]
    );
    assert_eq!(
        check_svo_sim("models/cycle/bench.rs", "fn f() {\n    crate::output::figure::register_font()?;\n}\n"),
        ["src/models/cycle/bench.rs:2: models::cycle::bench (layer `models::cycle`) imports `crate::output::figure::register_font` from the layer above it, `output`"]
    );
}

#[test]
fn groups_super_chains_and_inline_modules_are_resolved() {
    // A use group hiding an upward path.
    assert_eq!(
        check_svo_sim("models/fixed/plan.rs", "use crate::{world::scene::Scene, models::{reference::ray, cycle::CycleFrame as F}};"),
        ["src/models/fixed/plan.rs:1: models::fixed::plan (layer `models::fixed`) imports `crate::models::cycle::CycleFrame` from the layer above it, `models::cycle`"]
    );
    // super::super out of the layer.
    assert_eq!(
        check_svo_sim("models/reference/frame.rs", "use super::super::fixed::FramePlan;"),
        ["src/models/reference/frame.rs:1: models::reference::frame (layer `models::reference`) imports `super::super::fixed::FramePlan` from the layer above it, `models::fixed`"]
    );
    // Inside `mod tests`, `super` is the file's module: models::reference, not models.
    assert!(check_svo_sim(
        "models/reference/frame.rs",
        "mod tests {\n    use super::super::ray::primary_ray;\n}\n"
    )
    .is_empty());
    // The same path outside the inline module leaves the layer.
    assert_eq!(
        check_svo_sim(
            "models/reference/frame.rs",
            "mod tests {}\nuse super::super::cycle::X;\n"
        )
        .len(),
        1
    );
}

#[test]
fn comments_strings_and_macro_paths_are_not_imports() {
    let src = "//! See [`crate::run::run`].\n/* crate::studies::x */\nconst S: &str = \"crate::run::X\";\nconst R: &str = r#\"crate::run::Y\"#;\nconst C: char = '\"';\nmacro_rules! m { () => { $crate::run::z() } }\nfn f<'a>(x: &'a str) -> &'a str { x }\n";
    assert!(check_svo_sim("output/text.rs", src).is_empty());
    // After a char literal holding a quote, code is code again.
    assert_eq!(
        check_svo_sim(
            "output/text.rs",
            "const C: char = '\"';\nuse crate::run::X;\n"
        )
        .len(),
        1
    );
}

#[test]
fn a_module_in_no_layer_is_refused() {
    assert_eq!(
        check_svo_sim("output/text.rs", "use crate::extras::Thing;"),
        ["src/output/text.rs:1: `crate::extras::Thing` names svo_sim::extras, which is in no layer of tests/layering.rs"]
    );
    assert_eq!(
        check_svo_sim("extras/mod.rs", "use crate::world::scene::Scene;"),
        ["src/extras/mod.rs: module svo_sim::extras is in no layer of tests/layering.rs (place it there and in docs/architecture.md §1)"]
    );
}

#[test]
fn rtl_model_foundations_may_not_import_units() {
    assert_eq!(
        check_source(RTL_MODEL, "rtl_model", "rtl_model/src/fixed/ops.rs", "fixed/ops.rs", "use crate::units::sqrt;"),
        ["rtl_model/src/fixed/ops.rs:1: fixed::ops (layer `fixed`) imports `crate::units::sqrt` from the layer above it, `units`"]
    );
    assert!(check_source(
        RTL_MODEL,
        "rtl_model",
        "rtl_model/src/units/sqrt.rs",
        "units/sqrt.rs",
        "use crate::fixed::Format;"
    )
    .is_empty());
}
