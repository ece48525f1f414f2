//! The datapath configurations a sweep runs: a built-in named list derived from the documented
//! default, or a user's list read from a RON file (`--configs`).
//!
//! Pipeline position: the first input of `sim sweep`. Every variant changes one signal family
//! through every unit it passes, so the interfaces `DatapathConfig::validate` checks stay
//! consistent: the direction family is raygen → sphere → transform in and out → reciprocal in;
//! the position family raygen → sphere → transform in and out → walker; the matrix family
//! raygen → transform; t is the walker's; the sphere's t_ca = l·d is its own (it is not in the
//! position family: narrowing it with positions would force the squared distances, and with
//! them the square root, narrower too); the square root's digits follow the sphere's squared
//! distances (`units::sphere::sqrt_config`); the reciprocal's iterations, seed table and output
//! (with the walker's matching input) are its own.

use rtl_model::datapath::DatapathConfig;
use rtl_model::fixed::Format;
use serde::Deserialize;
use std::path::Path;
use thiserror::Error;

/// A datapath configuration with the name the sweep reports it under.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedConfig {
    /// Short name: letters, digits, `_`, `-`, `.` (a CSV field without quoting).
    pub name: String,
    /// The validated configuration.
    pub datapath: DatapathConfig,
}

/// Name of the documented default in every built-in list.
pub const DEFAULT_NAME: &str = "default";

/// Why a configuration list cannot be used.
#[derive(Debug, Error)]
pub enum ConfigsError {
    /// The file cannot be read, or is larger than its cap.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The file is not a RON list of `(name: "...", datapath: (...))`.
    #[error("{path}:{line}:{col}: malformed configuration list (expected [(name: \"...\", datapath: (...)), ...]): {message}")]
    Parse {
        /// The file.
        path: String,
        /// Line of the error.
        line: usize,
        /// Column of the error.
        col: usize,
        /// What the parser found.
        message: String,
    },
    /// The list is empty.
    #[error("{0}: the configuration list is empty")]
    Empty(String),
    /// A name is empty or has characters a CSV field or a plot label cannot carry plainly.
    #[error("{path}: configuration {index} has the name {name:?}: names must be 1 to 40 letters, digits, '_', '-' or '.'")]
    BadName {
        /// The file.
        path: String,
        /// Position in the list (from 0).
        index: usize,
        /// The name.
        name: String,
    },
    /// Two configurations share a name.
    #[error("{path}: the name {name:?} appears twice")]
    Duplicate {
        /// The file.
        path: String,
        /// The name.
        name: String,
    },
    /// A configuration fails `DatapathConfig::validate`.
    #[error("{path}: configuration {name:?} is invalid: {message}")]
    Invalid {
        /// The file (or `built-in`).
        path: String,
        /// The configuration.
        name: String,
        /// What is wrong.
        message: String,
    },
}

/// One entry of a `--configs` file. The datapath names only what it changes (every field of
/// `DatapathConfig` has a default).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    name: String,
    #[serde(default)]
    datapath: DatapathConfig,
}

fn name_ok(name: &str) -> bool {
    (1..=40).contains(&name.len())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// Checks names (well-formed, unique) and every configuration; `path` names the source in
/// messages.
pub fn check(list: &[NamedConfig], path: &str) -> Result<(), ConfigsError> {
    if list.is_empty() {
        return Err(ConfigsError::Empty(path.into()));
    }
    for (index, c) in list.iter().enumerate() {
        if !name_ok(&c.name) {
            return Err(ConfigsError::BadName {
                path: path.into(),
                index,
                name: c.name.clone(),
            });
        }
        if list[..index].iter().any(|o| o.name == c.name) {
            return Err(ConfigsError::Duplicate {
                path: path.into(),
                name: c.name.clone(),
            });
        }
        c.datapath
            .validate()
            .map_err(|message| ConfigsError::Invalid {
                path: path.into(),
                name: c.name.clone(),
                message,
            })?;
    }
    Ok(())
}

/// Parses a `--configs` list from text (`path` for messages) and checks it.
pub fn parse(text: &str, path: &str) -> Result<Vec<NamedConfig>, ConfigsError> {
    let entries: Vec<Entry> = ron::from_str(text).map_err(|e| ConfigsError::Parse {
        path: path.into(),
        line: e.position.line,
        col: e.position.col,
        message: e.code.to_string(),
    })?;
    let list: Vec<NamedConfig> = entries
        .into_iter()
        .map(|e| NamedConfig {
            name: e.name,
            datapath: e.datapath,
        })
        .collect();
    check(&list, path)?;
    Ok(list)
}

/// Reads and checks a `--configs` file.
pub fn load(path: &Path) -> Result<Vec<NamedConfig>, ConfigsError> {
    let shown = path.display().to_string();
    let text = crate::input::read_text(path, crate::input::Cap::config("--configs"))?;
    parse(&text, &shown)
}

/// Keeps a format's integer bits and signedness and sets its fraction bits (at most 62, the
/// layer's limit; a width beyond 64 is clamped and left for `validate` to refuse).
fn with_frac(f: Format, frac: u8) -> Format {
    let frac = frac.min(62);
    let int = i32::from(f.width) - i32::from(f.frac);
    Format {
        width: (int + i32::from(frac)).clamp(1, 64) as u8,
        frac: frac as i8,
        ..f
    }
}

/// Direction components (unit vectors) with `frac` fraction bits, through every unit.
pub fn set_dir_frac(dp: &mut DatapathConfig, frac: u8) {
    let d = with_frac(dp.raygen.dir, frac);
    dp.raygen.dir = d;
    dp.sphere.dir = d;
    dp.transform.dir = d;
    dp.transform.local_dir = d;
    dp.reciprocal.input = d;
}

/// Positions (metres) with `frac` fraction bits, through every unit.
pub fn set_pos_frac(dp: &mut DatapathConfig, frac: u8) {
    let p = with_frac(dp.raygen.pos, frac);
    dp.raygen.pos = p;
    dp.sphere.pos = p;
    dp.transform.pos = p;
    dp.transform.local_pos = p;
    dp.walker.pos = p;
}

/// Rotation matrix entries with `frac` fraction bits.
pub fn set_mat_frac(dp: &mut DatapathConfig, frac: u8) {
    let m = with_frac(dp.raygen.mat, frac);
    dp.raygen.mat = m;
    dp.transform.mat = m;
}

/// The walker's t with `frac` fraction bits.
pub fn set_t_frac(dp: &mut DatapathConfig, frac: u8) {
    dp.walker.t = with_frac(dp.walker.t, frac);
}

/// Squared distances of the sphere test sized so that its square root
/// (`units::sphere::sqrt_config`) computes `digits` (≥ 8) root digits: the radicand keeps the
/// default's 16 integer bits and gets 2·`digits` − 16 fraction bits, so it is 2·`digits` bits
/// wide and needs no alignment shift.
pub fn set_sqrt_digits(dp: &mut DatapathConfig, digits: u8) {
    let int = 16u8;
    dp.sphere.sq = Format::uq(int, (2 * digits).saturating_sub(int));
}

/// The reciprocal's output (and the walker's matching input) with `frac` fraction bits.
pub fn set_recip_frac(dp: &mut DatapathConfig, frac: u8) {
    let o = with_frac(dp.reciprocal.output, frac);
    dp.reciprocal.output = o;
    dp.walker.inv = o;
}

fn variant(name: &str, edit: impl FnOnce(&mut DatapathConfig)) -> NamedConfig {
    let mut datapath = DatapathConfig::default();
    edit(&mut datapath);
    NamedConfig {
        name: name.into(),
        datapath,
    }
}

/// The built-in list: the default, then one signal family at a time made coarser (and in
/// places finer) than the default, then two combinations. `docs/accuracy.md` lists them.
pub fn builtin() -> Vec<NamedConfig> {
    vec![
        variant(DEFAULT_NAME, |_| {}),
        variant("t_frac24", |d| set_t_frac(d, 24)),
        variant("t_frac16", |d| set_t_frac(d, 16)),
        variant("dir_frac34", |d| set_dir_frac(d, 34)),
        variant("dir_frac24", |d| set_dir_frac(d, 24)),
        variant("dir_frac17", |d| set_dir_frac(d, 17)),
        variant("mat_frac24", |d| set_mat_frac(d, 24)),
        variant("mat_frac17", |d| set_mat_frac(d, 17)),
        variant("pos_frac24", |d| set_pos_frac(d, 24)),
        variant("pos_frac16", |d| set_pos_frac(d, 16)),
        variant("tca_frac32", |d| d.sphere.tca = Format::sq(10, 32)),
        variant("sqrt_digits24", |d| set_sqrt_digits(d, 24)),
        variant("sqrt_digits16", |d| set_sqrt_digits(d, 16)),
        variant("recip_iter1", |d| d.reciprocal.iterations = 1),
        variant("recip_iter3", |d| d.reciprocal.iterations = 3),
        variant("recip_table12_iter1", |d| {
            d.reciprocal.table_bits = 12;
            d.reciprocal.iterations = 1;
        }),
        variant("recip_frac26", |d| set_recip_frac(d, 26)),
        variant("lean", |d| {
            set_dir_frac(d, 24);
            set_mat_frac(d, 24);
            set_pos_frac(d, 24);
            set_t_frac(d, 24);
            set_sqrt_digits(d, 24);
            d.reciprocal.iterations = 1;
        }),
        variant("coarse", |d| {
            set_dir_frac(d, 14);
            set_mat_frac(d, 14);
            set_pos_frac(d, 14);
            set_t_frac(d, 12);
            set_sqrt_digits(d, 16);
            set_recip_frac(d, 16);
            d.reciprocal.iterations = 1;
        }),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use rtl_model::cycle::hw_config::HwConfig;
    use rtl_model::fixed::Quant;
    use rtl_model::units::sphere::sqrt_config;
    use rtl_model::units::sqrt;

    #[test]
    fn builtin_list_is_valid_and_starts_with_the_default() {
        let list = builtin();
        assert!(list.len() >= 12);
        check(&list, "built-in").unwrap();
        assert_eq!(list[0].name, DEFAULT_NAME);
        assert_eq!(list[0].datapath, DatapathConfig::default());
        for c in &list {
            // The hardware derived from each variant accepts it (its latencies follow).
            HwConfig::for_datapath(&c.datapath)
                .validate_for(&c.datapath)
                .unwrap();
            // Variants keep the default's rounding modes: only widths change.
            assert_eq!(c.datapath.raygen.dir.quant, Quant::RndConv, "{}", c.name);
        }
    }

    #[test]
    fn sqrt_variants_have_the_digits_their_names_say() {
        for (digits, name) in [
            (32, DEFAULT_NAME),
            (24, "sqrt_digits24"),
            (16, "sqrt_digits16"),
        ] {
            let c = builtin().into_iter().find(|c| c.name == name).unwrap();
            let cfg = sqrt_config(&c.datapath.sphere);
            assert_eq!(sqrt::radicand_bits(&cfg) / 2, digits, "{name}");
        }
    }

    #[test]
    fn setters_change_only_the_fraction_bits() {
        let mut d = DatapathConfig::default();
        set_pos_frac(&mut d, 20);
        assert_eq!(d.walker.pos, Format::sq(8, 20).with_quant(Quant::RndConv));
        set_t_frac(&mut d, 16);
        assert_eq!(d.walker.t, Format::sq(31, 16));
    }

    #[test]
    fn bad_lists_are_refused_with_the_reason() {
        let e = parse("[]", "f.ron").unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
        let e = parse("[(name: \"a b\")]", "f.ron").unwrap_err().to_string();
        assert!(e.contains("\"a b\""), "{e}");
        let e = parse("[(name: \"a\"), (name: \"a\")]", "f.ron")
            .unwrap_err()
            .to_string();
        assert!(e.contains("twice"), "{e}");
        let e = parse("[(name: \"a\", nope: 1)]", "f.ron")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.ron:1:"), "{e}");
        let bad = "[(name: \"w\", datapath: (walker: (pos: (signed: true, width: 41, frac: 33), inv: (signed: true, width: 52, frac: 30), t: (signed: true, width: 62, frac: 31), max_steps: 100000)))]";
        let e = parse(bad, "f.ron").unwrap_err().to_string();
        assert!(
            e.contains("\"w\" is invalid") && e.contains("walker.pos"),
            "{e}"
        );
        let ok = parse("[(name: \"d\"), (name: \"t20\", datapath: (walker: (pos: (signed: true, width: 40, frac: 32, quant: RndConv), inv: (signed: true, width: 52, frac: 30, quant: RndConv), t: (signed: true, width: 51, frac: 20), max_steps: 100000)))]", "f.ron").unwrap();
        assert_eq!(ok.len(), 2);
        assert_eq!(ok[1].datapath.walker.t.frac, 20);
    }
}
