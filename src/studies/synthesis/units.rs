//! The unit list of the synthesis, `testbench/synth/units.tsv`: one RTL unit a line — name,
//! top module, files, parameters, the DSP48E2 difference from the model's estimate the unit
//! is allowed, and the recorded reason for it (the rest of the line).
//!
//! Pipeline position: read by the synthesis study (`studies::synthesis`) before it runs
//! `testbench/synth/synth.sh`, which reads the same file's first four columns.

use super::SynthError;
use std::path::{Path, PathBuf};

/// One line of units.tsv.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnitSpec {
    /// Unit name (the estimate's component name; `sphere` includes its square root).
    pub name: String,
    /// Top module.
    pub top: String,
    /// RTL files, relative to `testbench/rtl`.
    pub files: Vec<String>,
    /// Parameters as written (`NAME=VALUE`; `{vectors}` is the golden vector folder).
    pub params: Vec<String>,
    /// Yosys's DSP48E2 count minus the estimate's, as recorded (0: they must agree).
    pub dsp_vs_model: i64,
    /// Why they differ (empty when they agree).
    pub reason: String,
    /// The whole line (part of the cache key).
    pub line: String,
}

impl UnitSpec {
    /// Every file the synthesis of this unit reads: its RTL and the files its parameters
    /// name under `{vectors}`.
    pub fn input_files(&self, repo: &Path) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self
            .files
            .iter()
            .map(|f| repo.join("testbench/rtl").join(f))
            .collect();
        for p in &self.params {
            if let Some(rest) = p
                .split_once('=')
                .and_then(|(_, v)| v.strip_prefix("{vectors}"))
            {
                v.push(repo.join("vectors").join(rest.trim_start_matches('/')));
            }
        }
        v
    }
}

/// Parses units.tsv (`path` names it in errors).
pub fn parse_units(text: &str, path: &Path) -> Result<Vec<UnitSpec>, SynthError> {
    let mut out: Vec<UnitSpec> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let err = |message: String| SynthError::Units {
            path: path.to_path_buf(),
            line: i + 1,
            message,
        };
        let mut f = line.split_whitespace();
        let (Some(name), Some(top), Some(files), Some(params), Some(delta)) =
            (f.next(), f.next(), f.next(), f.next(), f.next())
        else {
            return Err(err(
                "expected: unit top files parameters dsp_vs_model [reason]".into(),
            ));
        };
        let reason = f.collect::<Vec<_>>().join(" ");
        let dsp_vs_model: i64 = delta
            .parse()
            .map_err(|_| err(format!("dsp_vs_model `{delta}` is not an integer")))?;
        if dsp_vs_model != 0 && reason.is_empty() {
            return Err(err(format!(
                "`{name}`: a DSP48E2 difference of {dsp_vs_model} needs a recorded reason"
            )));
        }
        if out.iter().any(|u| u.name == name) {
            return Err(err(format!("unit `{name}` listed twice")));
        }
        let params = match params {
            "-" => Vec::new(),
            p => p.split(',').map(str::to_string).collect(),
        };
        out.push(UnitSpec {
            name: name.to_string(),
            top: top.to_string(),
            files: files.split(',').map(str::to_string).collect(),
            params,
            dsp_vs_model,
            reason,
            line: line.to_string(),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_parse_and_a_difference_needs_a_reason() {
        let p = Path::new("units.tsv");
        let u = parse_units(
            "# c\nsqrt svo_sqrt svo_sqrt.v N=64 0\nw top a.v,b.v - +18 Yosys slices 17 bits\n",
            p,
        )
        .unwrap();
        assert_eq!(u.len(), 2);
        assert_eq!(u[1].dsp_vs_model, 18);
        assert_eq!(u[1].reason, "Yosys slices 17 bits");
        assert_eq!(u[1].files, ["a.v", "b.v"]);
        let e = parse_units("w top a.v - 6\n", p).unwrap_err().to_string();
        assert!(e.contains("units.tsv:1") && e.contains("reason"), "{e}");
        assert!(parse_units("w top a.v -\n", p).is_err());
        assert!(parse_units("w top a.v - x\n", p).is_err());
    }
}
