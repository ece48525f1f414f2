//! The space `sim explore` evaluates: a RON file of hardware fields, each by its path in the
//! hardware file with a list or a range of values, and the scenes to run every point on.
//!
//! Pipeline position: the input of `sim explore`, read once. A field is set by its path on
//! the JSON tree of the base hardware (`serde_json::to_value` of the `HwConfig`) and the tree
//! is read back into an `HwConfig`, so any field of the schema — those later branches add
//! included — can be explored without code per field; the schema's own deserialisation and
//! `HwConfig::validate_for` decide what a value may be. Every refusal names the field and its
//! line and column in the file. docs/explore.md documents the format.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use serde::de::{MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Default of `max_points`: the cap on the cross product.
pub const DEFAULT_MAX_POINTS: u64 = 1000;
/// The largest `max_points` a file may set.
pub const MAX_POINTS_LIMIT: u64 = 100_000;
/// Most values one range may produce.
const MAX_RANGE_VALUES: u64 = 100_000;

/// A scene of the space: a scene file (or `car` for the embedded car) at a resolution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Scene file, relative to the current folder, or `car` for the embedded animated car.
    pub path: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Frames (the first traces every pixel, later ones reuse the hit buffer).
    pub frames: u32,
    /// Octree depth of the deepest asset (the others keep their offset to it, as `sim
    /// --depth`); `None`: the scene's own depths.
    #[serde(default)]
    pub depth: Option<u8>,
}

/// Sampled timing (`sim --sample`): one band of rows in 1/rate is timed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    /// Sampling rate in (0, 1].
    pub rate: f64,
    /// Rows per band (default `models::cycle::sample::DEFAULT_BAND_ROWS`).
    #[serde(default)]
    pub band_rows: Option<u32>,
    /// Seed of the systematic sample's random start.
    #[serde(default)]
    pub seed: u64,
}

/// The fields in file order: `{ "path": values, ... }`.
#[derive(Clone, Debug, Default)]
struct OrderedFields(Vec<(String, Value)>);

impl<'de> Deserialize<'de> for OrderedFields {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = OrderedFields;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a map of \"field.path\": [values] or (from: a, to: b, step: c)")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<OrderedFields, A::Error> {
                let mut out = Vec::new();
                while let Some((k, v)) = m.next_entry::<String, Value>()? {
                    out.push((k, v));
                }
                Ok(OrderedFields(out))
            }
        }
        d.deserialize_map(V)
    }
}

/// The file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpaceFile {
    #[serde(default)]
    base: Option<String>,
    #[serde(default)]
    max_points: Option<u64>,
    #[serde(default)]
    sample: Option<SampleSpec>,
    scenes: Vec<SceneSpec>,
    fields: OrderedFields,
}

/// One explored field: its path, its values and where the file names it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Field {
    /// Path in the hardware file, e.g. `walker_pool.walkers`.
    pub path: String,
    /// Its values, in order.
    pub values: Vec<Value>,
    /// Line of the field's name in the file (1-based).
    pub line: usize,
    /// Column of the field's name (1-based).
    pub col: usize,
}

/// The space, read and checked.
#[derive(Clone, Debug)]
pub struct Space {
    /// The file.
    pub path: PathBuf,
    /// The hardware every point starts from (the base file's, or the default).
    pub base: HwConfig,
    /// The base file, if any.
    pub base_path: Option<PathBuf>,
    /// The fields, in file order.
    pub fields: Vec<Field>,
    /// The scenes, in file order.
    pub scenes: Vec<SceneSpec>,
    /// Sampled timing, if any.
    pub sample: Option<SampleSpec>,
    /// Cap on the points.
    pub max_points: u64,
}

/// One point of the space.
#[derive(Clone, Debug)]
pub struct Point {
    /// 1 … N in the cross product's order (the last field varying fastest); 0 for the base
    /// hardware, evaluated as well when no point of the cross product equals it.
    pub id: usize,
    /// Per field, its value as printed.
    pub values: Vec<String>,
    /// Whether this is the base hardware (the default, or the `base` file's).
    pub default: bool,
    /// The hardware.
    pub hw: HwConfig,
}

/// Why a space cannot be used.
#[derive(Debug, Error)]
pub enum SpaceError {
    /// The file cannot be read.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The base hardware file cannot be used.
    #[error("{path}: base: {source}")]
    Base {
        /// The space file.
        path: String,
        /// What is wrong with the base.
        #[source]
        source: crate::run::config_files::ConfigFileError,
    },
    /// Not RON of the space's schema.
    #[error("{path}:{line}:{col}: malformed space: {message}")]
    Malformed {
        /// The file.
        path: String,
        /// Line.
        line: usize,
        /// Column.
        col: usize,
        /// What the parser expected.
        message: String,
    },
    /// A field or its values are refused.
    #[error("{path}:{line}:{col}: field \"{field}\": {message}")]
    Field {
        /// The file.
        path: String,
        /// Line of the field's name.
        line: usize,
        /// Column of the field's name.
        col: usize,
        /// The field's path.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// Anything else about the file (its scenes, its cap, the point count).
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// Line and column (1-based) of byte offset `at` in `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before.len(), |k| before.len() - k - 1)
        + 1;
    (line, col)
}

/// Where the file names field `path` (its quoted name after `fields`; the first occurrence
/// after `from`), as a byte offset.
fn find_field(text: &str, path: &str, from: usize) -> Option<usize> {
    let quoted = format!("\"{path}\"");
    text.get(from..)?.find(&quoted).map(|k| from + k)
}

/// A value as printed in the outputs: strings bare, numbers as JSON prints them.
pub fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The (path, value) pairs one value of a field sets. A field whose name joins several paths
/// with `+` (`"transform_units+reciprocal_units+walker_root_units"`) is a linked field: each
/// of its values is a tuple with one value per path, set together (fields whose values only
/// make sense in step, such as the three unit counts of a walk-issue width).
pub fn sets_of<'a>(path: &'a str, v: &'a Value) -> Result<Vec<(&'a str, &'a Value)>, String> {
    if !path.contains('+') {
        return Ok(vec![(path, v)]);
    }
    let paths: Vec<&str> = path.split('+').map(str::trim).collect();
    if paths.iter().any(|p| p.is_empty()) {
        return Err(format!("the linked field {path:?} has an empty path"));
    }
    match v {
        Value::Array(parts) if parts.len() == paths.len() => {
            Ok(paths.into_iter().zip(parts.iter()).collect())
        }
        _ => Err(format!(
            "a value of a field linking {} paths is a tuple of {} values, (a, b, …); got {}",
            paths.len(),
            paths.len(),
            value_text(v)
        )),
    }
}

/// The values a field's entry declares: a list, or `(from: a, to: b, step: s)` (integers,
/// `to` included).
fn expand(v: &Value) -> Result<Vec<Value>, String> {
    match v {
        Value::Array(list) => {
            if list.is_empty() {
                return Err("the list of values is empty".into());
            }
            for x in list {
                if x.is_null() {
                    return Err("a value is a bare name or () (write an enum variant as a string, \"Uram\")".into());
                }
            }
            for (k, x) in list.iter().enumerate() {
                if list[..k].contains(x) {
                    return Err(format!("the value {} is listed twice", value_text(x)));
                }
            }
            Ok(list.clone())
        }
        Value::Object(m) => {
            let mut keys: Vec<&str> = m.keys().map(String::as_str).collect();
            keys.sort_unstable();
            if keys != ["from", "step", "to"] {
                return Err(format!(
                    "a range is (from: a, to: b, step: s); got the keys {}",
                    keys.join(", ")
                ));
            }
            let int = |k: &str| {
                m[k].as_i64()
                    .ok_or_else(|| format!("range {k}: {} is not an integer", m[k]))
            };
            let (from, to, step) = (int("from")?, int("to")?, int("step")?);
            if step <= 0 {
                return Err(format!("range step {step} must be positive"));
            }
            if to < from {
                return Err(format!("range to {to} is below from {from}"));
            }
            let n = (i128::from(to) - i128::from(from)) / i128::from(step) + 1;
            if n > i128::from(MAX_RANGE_VALUES) {
                return Err(format!(
                    "the range has {n} values, more than {MAX_RANGE_VALUES}"
                ));
            }
            Ok((0..n as i64)
                .map(|k| Value::from(from + k * step))
                .collect())
        }
        _ => Err(format!(
            "expected a list [a, b, ...] or a range (from: a, to: b, step: s), got {v}"
        )),
    }
}

/// Sets `path` (dot-separated) in the tree `root` to `v`; the error names the first segment
/// that does not exist and what exists there.
fn set_path(root: &mut Value, path: &str, v: &Value) -> Result<(), String> {
    let mut node = root;
    let mut walked = String::new();
    for seg in path.split('.') {
        let here = if walked.is_empty() {
            "the hardware file".to_string()
        } else {
            walked.clone()
        };
        let Value::Object(m) = node else {
            return Err(format!(
                "{here} has no fields (it is a value), so it has no {seg:?}"
            ));
        };
        if !m.contains_key(seg) {
            let known: Vec<&str> = m.keys().map(String::as_str).collect();
            return Err(format!(
                "no field {seg:?} in {here} (its fields: {})",
                known.join(", ")
            ));
        }
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(seg);
        node = m.get_mut(seg).ok_or_else(|| format!("no field {seg:?}"))?;
    }
    *node = v.clone();
    Ok(())
}

/// The base hardware with `sets` applied, read back through the schema.
pub fn hardware_with(base: &Value, sets: &[(&str, &Value)]) -> Result<HwConfig, (usize, String)> {
    let mut tree = base.clone();
    for (k, (path, v)) in sets.iter().enumerate() {
        set_path(&mut tree, path, v).map_err(|m| (k, m))?;
    }
    serde_json::from_value(tree).map_err(|e| {
        // The schema's message names no path; blame the last field whose value it shows,
        // else the first.
        let m = e.to_string();
        let k = sets
            .iter()
            .rposition(|(_, v)| m.contains(&value_text(v)))
            .unwrap_or(0);
        (k, m)
    })
}

impl Space {
    /// Reads and checks the space in `path`: its fields exist and each value is accepted by
    /// the schema on the base hardware, the cross product is within `max_points`, and every
    /// point is valid hardware for the datapath `dp` (the message names the field the
    /// model's rule names, with its position).
    pub fn load(path: &Path, dp: &DatapathConfig) -> Result<(Space, Vec<Point>), SpaceError> {
        let text = crate::input::read_text(path, crate::input::Cap::config("space"))?;
        Self::from_text(&text, path, dp)
    }

    /// [`Space::load`] of text already read; `path` names it in errors.
    pub fn from_text(
        text: &str,
        path: &Path,
        dp: &DatapathConfig,
    ) -> Result<(Space, Vec<Point>), SpaceError> {
        let shown = path.display().to_string();
        let invalid = |message: String| SpaceError::Invalid {
            path: shown.clone(),
            message,
        };
        // Implicit `Some`: `depth: 11` and `base: "hw.ron"` read as `Some(…)`.
        let file: SpaceFile = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
            .from_str(text)
            .map_err(|e| SpaceError::Malformed {
                path: shown.clone(),
                line: e.position.line,
                col: e.position.col,
                message: e.code.to_string(),
            })?;
        let base_path = file.base.as_ref().map(PathBuf::from);
        let base =
            crate::run::config_files::load_hardware(base_path.as_deref()).map_err(|source| {
                SpaceError::Base {
                    path: shown.clone(),
                    source,
                }
            })?;
        let max_points = file.max_points.unwrap_or(DEFAULT_MAX_POINTS);
        if !(1..=MAX_POINTS_LIMIT).contains(&max_points) {
            return Err(invalid(format!(
                "max_points = {max_points} is out of range (1 to {MAX_POINTS_LIMIT})"
            )));
        }
        if file.scenes.is_empty() {
            return Err(invalid("scenes: the list is empty".into()));
        }
        for (k, s) in file.scenes.iter().enumerate() {
            if file.scenes[..k].iter().any(|o| o.path == s.path) {
                return Err(invalid(format!("scenes: {:?} is listed twice", s.path)));
            }
            if s.frames == 0 || s.width == 0 || s.height == 0 {
                return Err(invalid(format!(
                    "scenes: {:?}: width, height and frames must be at least 1",
                    s.path
                )));
            }
        }
        if let Some(s) = &file.sample {
            crate::models::cycle::sample::SampleConfig::from_rate(
                s.rate,
                s.band_rows
                    .unwrap_or(crate::models::cycle::sample::DEFAULT_BAND_ROWS),
                None,
                s.seed,
            )
            .map_err(|m| invalid(format!("sample: {m}")))?;
        }
        let tree = serde_json::to_value(&base).map_err(|e| invalid(format!("base: {e}")))?;
        let after = text.find("fields").unwrap_or(0);
        let mut fields: Vec<Field> = Vec::new();
        for (name, v) in &file.fields.0 {
            let at = find_field(text, name, after).unwrap_or(after);
            let (line, col) = line_col(text, at);
            let err = |message: String| SpaceError::Field {
                path: shown.clone(),
                line,
                col,
                field: name.clone(),
                message,
            };
            if fields.iter().any(|f| &f.path == name) {
                return Err(err("named twice".into()));
            }
            let values = expand(v).map_err(err)?;
            // The paths first (their errors name no value), then each value through the schema.
            let mut probe = tree.clone();
            for (p, x) in sets_of(name, &values[0]).map_err(err)? {
                set_path(&mut probe, p, x).map_err(err)?;
            }
            for x in &values {
                let sets = sets_of(name, x).map_err(err)?;
                hardware_with(&tree, &sets)
                    .map_err(|(_, m)| err(format!("value {}: {m}", value_text(x))))?;
            }
            fields.push(Field {
                path: name.clone(),
                values,
                line,
                col,
            });
        }
        if fields.is_empty() {
            return Err(invalid("fields: no field to explore".into()));
        }
        let count = fields
            .iter()
            .try_fold(1u64, |a, f| a.checked_mul(f.values.len() as u64));
        let sizes: Vec<String> = fields.iter().map(|f| f.values.len().to_string()).collect();
        match count {
            Some(n) if n <= max_points => {}
            _ => {
                return Err(invalid(format!(
                    "the space has {} = {} points, more than max_points = {max_points}: narrow a field or raise max_points (at most {MAX_POINTS_LIMIT})",
                    sizes.join(" × "),
                    count.map_or_else(|| "too many".to_string(), |n| n.to_string())
                )))
            }
        }
        let space = Space {
            path: path.to_path_buf(),
            base,
            base_path,
            fields,
            scenes: file.scenes,
            sample: file.sample,
            max_points,
        };
        let points = space.points(&tree, dp)?;
        Ok((space, points))
    }

    /// The cross product, the last field varying fastest, each point checked.
    fn points(&self, tree: &Value, dp: &DatapathConfig) -> Result<Vec<Point>, SpaceError> {
        let n: usize = self.fields.iter().map(|f| f.values.len()).product();
        let mut out = Vec::with_capacity(n);
        for index in 0..n {
            let mut rest = index;
            let mut choice = vec![0; self.fields.len()];
            for (k, f) in self.fields.iter().enumerate().rev() {
                choice[k] = rest % f.values.len();
                rest /= f.values.len();
            }
            // Every (path, value) the point sets, and the field each comes from.
            let mut sets: Vec<(&str, &Value)> = Vec::new();
            let mut owner: Vec<usize> = Vec::new();
            for (k, (f, &c)) in self.fields.iter().zip(&choice).enumerate() {
                // `from_text` checked every value's shape.
                for set in sets_of(&f.path, &f.values[c]).unwrap_or_default() {
                    sets.push(set);
                    owner.push(k);
                }
            }
            let named = |k: usize, m: String| {
                let f = &self.fields[k];
                SpaceError::Field {
                    path: self.path.display().to_string(),
                    line: f.line,
                    col: f.col,
                    field: f.path.clone(),
                    message: format!("point {} ({}): {m}", index + 1, self.describe(&choice)),
                }
            };
            let hw = hardware_with(tree, &sets).map_err(|(k, m)| named(owner[k], m))?;
            if let Err(m) = hw.validate_for(dp) {
                // Blame the explored field the rule names (the longest path it contains).
                let k = (0..sets.len())
                    .filter(|&k| m.contains(sets[k].0))
                    .max_by_key(|&k| sets[k].0.len())
                    .map(|k| owner[k]);
                return Err(match k {
                    Some(k) => named(k, m),
                    None => SpaceError::Invalid {
                        path: self.path.display().to_string(),
                        message: format!(
                            "point {} ({}): the hardware is refused: {m}",
                            index + 1,
                            self.describe(&choice)
                        ),
                    },
                });
            }
            let values = self
                .fields
                .iter()
                .zip(&choice)
                .map(|(f, &c)| value_text(&f.values[c]))
                .collect();
            let default = hw == self.base;
            out.push(Point {
                id: index + 1,
                values,
                default,
                hw,
            });
        }
        if !out.iter().any(|p| p.default) {
            let values = self
                .fields
                .iter()
                .map(|f| {
                    let of = |path: &str| {
                        path.trim()
                            .split('.')
                            .try_fold(tree, |node, seg| node.get(seg))
                            .cloned()
                            .unwrap_or(Value::String("?".into()))
                    };
                    if f.path.contains('+') {
                        value_text(&Value::Array(f.path.split('+').map(of).collect()))
                    } else {
                        value_text(&of(&f.path))
                    }
                })
                .collect();
            out.insert(
                0,
                Point {
                    id: 0,
                    values,
                    default: true,
                    hw: self.base.clone(),
                },
            );
        }
        Ok(out)
    }

    /// `path = value, ...` of a point's chosen value indices.
    pub fn describe(&self, choice: &[usize]) -> String {
        let values: Vec<String> = self
            .fields
            .iter()
            .zip(choice)
            .map(|(f, &c)| value_text(&f.values[c]))
            .collect();
        self.describe_values(&values)
    }

    /// `path = value, ...` of a point's values as printed.
    pub fn describe_values(&self, values: &[String]) -> String {
        self.fields
            .iter()
            .zip(values)
            .map(|(f, v)| format!("{} = {v}", f.path))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_one_based() {
        assert_eq!(line_col("ab\ncd", 0), (1, 1));
        assert_eq!(line_col("ab\ncd", 4), (2, 2));
    }

    #[test]
    fn a_range_includes_its_end() {
        let r: Value = serde_json::json!({"from": 4, "to": 12, "step": 4});
        assert_eq!(
            expand(&r).unwrap(),
            vec![Value::from(4), Value::from(8), Value::from(12)]
        );
    }
}
