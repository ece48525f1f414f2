//! One stage's vector table: the layout, the packed rows, where each block of rows came from
//! (adversarial, captured from a real frame, random), the unit's timing, and the parameters
//! a testbench needs beside the rows. From it come the three files of a stage: the hex rows,
//! the JSON manifest and the SystemVerilog package.
//!
//! Pipeline position: the output of every stage module, the input of the file writers.

use super::layout::Layout;
use super::word::Word;
use serde::Serialize;

/// Where a block of consecutive rows came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Origin {
    /// Hand-built edge cases: zeros and −0, saturation edges, ties, grazing spheres,
    /// axis-parallel rays.
    Adversarial,
    /// Transactions recorded from a real frame of the scene.
    Captured,
    /// Seeded random stimulus.
    Random,
    /// Memory contents (ROM, SVO image), not transactions.
    Table,
}

/// A block of rows `first .. first + count` of one origin.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct RowBlock {
    /// Where they came from.
    pub origin: Origin,
    /// First row.
    pub first: usize,
    /// Number of rows.
    pub count: usize,
}

/// Latency and initiation interval the model's default hardware configuration assumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Timing {
    /// Cycles from a transaction entering the unit to its result leaving it.
    pub latency_cycles: u32,
    /// Cycles between two transactions the unit accepts.
    pub ii: u32,
}

/// Per-row timing of a unit whose cycles depend on the data (the walker): which output
/// fields hold the cycle model's prediction, for which memory latency each, and what is
/// counted. The manifest's `timing` then holds this instead of a fixed latency.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct RowTiming {
    /// What a predicted count measures.
    pub cycles: String,
    /// The output fields with the predictions, one per memory latency.
    pub fields: Vec<String>,
    /// The fixed memory latency (cycles per read) of each field.
    pub memory_latencies: Vec<u32>,
    /// Where the prediction comes from.
    pub model: String,
}

/// One stage's vectors.
#[derive(Clone, Debug)]
pub struct VectorTable {
    /// Stage name: the file stem (`sqrt` → `sqrt.hex`, `sqrt.json`, `sqrt_pkg.sv`).
    pub name: String,
    /// What a row is.
    pub description: String,
    /// Field layout of every row.
    pub layout: Layout,
    /// The rows.
    pub rows: Vec<Word>,
    /// Where they came from, in row order.
    pub blocks: Vec<RowBlock>,
    /// The unit's timing, for units with a fixed latency.
    pub timing: Option<Timing>,
    /// The per-row timing, for units whose cycles depend on the data (instead of `timing`).
    pub row_timing: Option<RowTiming>,
    /// Extra `localparam int`s of the package (name, value, comment): configuration a
    /// testbench needs beside the fields (memory sizes, latencies).
    pub constants: Vec<(String, i64, String)>,
    /// Extra bit-vector `localparam`s of the package: (name, width in bits, value as hex
    /// digits, most significant first, comment). For tables an RTL unit elaborates from,
    /// such as the sorter's comparator pairs, too wide for an `int`.
    pub bit_constants: Vec<(String, u32, String, String)>,
    /// Constants of the stage (formats, configuration, companion files) for the manifest.
    pub parameters: serde_json::Map<String, serde_json::Value>,
    /// Whether the stage gets a SystemVerilog package (memory tables do not).
    pub package: bool,
}

impl VectorTable {
    /// A table with no rows.
    pub fn new(name: &str, description: &str, layout: Layout) -> Self {
        Self {
            name: name.to_string(),
            description: description.to_string(),
            layout,
            rows: Vec::new(),
            blocks: Vec::new(),
            timing: None,
            row_timing: None,
            constants: Vec::new(),
            bit_constants: Vec::new(),
            parameters: serde_json::Map::new(),
            package: true,
        }
    }

    /// Appends rows of one origin as a block.
    pub fn push_block(&mut self, origin: Origin, rows: Vec<Word>) {
        if rows.is_empty() {
            return;
        }
        self.blocks.push(RowBlock {
            origin,
            first: self.rows.len(),
            count: rows.len(),
        });
        self.rows.extend(rows);
    }

    /// Records a parameter for the manifest.
    pub fn param(&mut self, key: &str, value: impl Serialize) {
        let v = serde_json::to_value(value).unwrap_or(serde_json::Value::Null);
        self.parameters.insert(key.to_string(), v);
    }

    /// Rows of one origin.
    pub fn count(&self, origin: Origin) -> usize {
        self.blocks
            .iter()
            .filter(|b| b.origin == origin)
            .map(|b| b.count)
            .sum()
    }
}

/// How many captured and random rows a stage gets besides its adversarial ones for a requested
/// `count`: half of `count` (rounded up) captured from the frame, spread evenly over what the
/// frame offered (fewer if it offered fewer), and random rows for the rest.
pub fn plan_rows(captured_available: usize, count: usize) -> (usize, usize) {
    let captured = captured_available.min(count.div_ceil(2));
    (captured, count - captured)
}

/// `k` items spread evenly over `items` (first, then every len/k-th), in order.
pub fn spread<T: Clone>(items: &[T], k: usize) -> Vec<T> {
    if k == 0 || items.is_empty() {
        return Vec::new();
    }
    let k = k.min(items.len());
    (0..k).map(|i| items[i * items.len() / k].clone()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_planned_and_spread() {
        assert_eq!(plan_rows(1000, 100), (50, 50));
        assert_eq!(plan_rows(20, 100), (20, 80));
        assert_eq!(plan_rows(20, 5), (3, 2));
        assert_eq!(spread(&[0, 1, 2, 3, 4, 5], 3), vec![0, 2, 4]);
        assert_eq!(spread(&[0, 1], 5), vec![0, 1]);
    }
}
