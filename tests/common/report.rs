//! The model's own report (`sim --report-json`) as the tests that set an RTL run beside the
//! model read it: a count of one frame by its key (`frames[i].cycles`, `hit_buffer_reused`, …),
//! with a failure that names the key and the file when it is missing.
//!
//! Where it sits: test support only. It reads what the report writer wrote (docs/report.md);
//! it computes nothing the tests compare against.

use serde_json::Value;

/// A parsed `--report-json` file.
pub struct ModelReport {
    json: Value,
    path: String,
}

impl ModelReport {
    /// Reads and parses the report at `path`, failing the test with the path and the reason.
    pub fn read(path: &str) -> Self {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("cannot read the model's report {path}: {e}"));
        let json = serde_json::from_str(&text)
            .unwrap_or_else(|e| panic!("the model's report {path} is not JSON: {e}"));
        Self {
            json,
            path: path.to_string(),
        }
    }

    /// `frames[frame].key` as an unsigned count, failing the test when it is absent.
    pub fn frame(&self, frame: usize, key: &str) -> u64 {
        self.json["frames"][frame][key]
            .as_u64()
            .unwrap_or_else(|| panic!("no frames[{frame}].{key} in {}", self.path))
    }
}
