//! Helpers for the tests of `sim vectors` and the Icarus testbenches: scratch folders, the
//! golden set's options, and a reader of vector folders written from the manifests alone
//! (plain JSON and hex text), sharing no code with the encoder in `rtl_model::vectors`.

// Each test binary uses a different subset.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The options the committed golden set in `vectors/` was written with (`vectors/README.md`).
pub const GOLDEN_ARGS: [&str; 10] = [
    "--count", "32", "--seed", "2019", "--width", "16", "--height", "10", "--depth", "4",
];

/// The repository root.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A scratch folder, unique per test and process, removed when dropped.
pub struct Tmp {
    /// The folder.
    pub dir: PathBuf,
}

impl Tmp {
    /// A fresh empty folder named after `test`.
    pub fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("svo_sim_vec_{test}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the scratch folder");
        Self { dir }
    }

    /// A path inside, as a string.
    pub fn p(&self, name: &str) -> String {
        self.dir
            .join(name)
            .to_str()
            .expect("UTF-8 temp path")
            .to_string()
    }
}

impl Drop for Tmp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A table's manifest.
pub fn manifest(dir: &Path, name: &str) -> serde_json::Value {
    let p = dir.join(format!("{name}.json"));
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} is not JSON: {e}", p.display()))
}

/// A table's rows: the hex lines, `//` comment lines skipped.
pub fn rows(dir: &Path, name: &str) -> Vec<String> {
    let p = dir.join(format!("{name}.hex"));
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//") && !l.trim().is_empty())
        .map(str::to_string)
        .collect()
}

/// (offset, width, signed) of a field, from the manifest.
pub fn field(m: &serde_json::Value, name: &str) -> (u32, u32, bool) {
    let f = m["fields"]
        .as_array()
        .expect("fields[]")
        .iter()
        .find(|f| f["name"] == name)
        .unwrap_or_else(|| panic!("no field {name} in {}", m["name"]));
    (
        f["offset"].as_u64().expect("offset") as u32,
        f["width"].as_u64().expect("width") as u32,
        f["signed"].as_bool().expect("signed"),
    )
}

/// Bit `i` of a hex row (bit 0 = the last digit's lowest bit).
pub fn bit(row: &str, i: u32) -> bool {
    let digits = row.as_bytes();
    let k = (i / 4) as usize;
    if k >= digits.len() {
        return false;
    }
    let c = char::from(digits[digits.len() - 1 - k]);
    let nibble = c
        .to_digit(16)
        .unwrap_or_else(|| panic!("{c:?} is not a hex digit"));
    (nibble >> (i % 4)) & 1 == 1
}

/// A field's raw bits (width ≤ 128).
pub fn raw(row: &str, offset: u32, width: u32) -> u128 {
    (0..width).fold(0u128, |acc, i| {
        acc | (u128::from(bit(row, offset + i)) << i)
    })
}

/// A field's value by name: sign-extended if the manifest says signed.
pub fn value(m: &serde_json::Value, row: &str, name: &str) -> i128 {
    let (off, w, signed) = field(m, name);
    let r = raw(row, off, w);
    if signed && w < 128 && (r >> (w - 1)) & 1 == 1 {
        r as i128 - (1i128 << w)
    } else {
        r as i128
    }
}

/// The row with bit `i` inverted.
pub fn flip(row: &str, i: u32) -> String {
    let mut digits: Vec<char> = row.chars().collect();
    let k = digits.len() - 1 - (i / 4) as usize;
    let nibble = digits[k].to_digit(16).expect("hex digit") ^ (1 << (i % 4));
    digits[k] = char::from_digit(nibble, 16).expect("nibble");
    digits.into_iter().collect()
}

/// Inverts bit `bit` of field `name` in row `row` of `dir/table.hex` (clamped to the last
/// row), rewriting the file with its header kept: a one-bit corruption of one expected value.
/// Returns (the row corrupted, the table's row count).
pub fn corrupt_field(
    dir: &Path,
    table: &str,
    name: &str,
    row: usize,
    bit: impl Fn(u32) -> u32,
) -> (usize, u64) {
    let m = manifest(dir, table);
    let (off, w, _) = field(&m, name);
    let mut r = rows(dir, table);
    let row = row.min(r.len() - 1);
    r[row] = flip(&r[row], off + bit(w));
    let p = dir.join(format!("{table}.hex"));
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let header: Vec<&str> = text.lines().take_while(|l| l.starts_with("//")).collect();
    let body = [header.join("\n"), r.join("\n")].join("\n") + "\n";
    std::fs::write(&p, body).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    (row, r.len() as u64)
}
