//! Field layouts of packed transaction words: every field's name, direction, bit offset,
//! width, signedness, fraction bits and, for fixed-point fields, the quantisation and
//! overflow modes that produced it. What the JSON manifest and the SystemVerilog package
//! describe.
//!
//! Pipeline position: the encoding layer; each stage module declares its layout once from
//! the datapath configuration and packs every transaction through it. Fields are placed from
//! bit 0 upwards in declaration order (inputs first by convention), with no gaps.

use super::word::Word;
use crate::fixed::{Format, OverflowMode, Quant};
use serde::Serialize;

/// Whether a field is driven into the unit or expected from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// A stimulus: the testbench drives it.
    Input,
    /// An expected result: the testbench compares the unit's output with it.
    Output,
}

/// What a field's bits mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldKind {
    /// A fixed-point code: value = code · 2^−frac (two's complement if signed).
    Fixed,
    /// A plain integer (index, count, id, packed word).
    Integer,
    /// One bit.
    Flag,
    /// An IEEE 754 binary64 bit pattern (host-side values before quantisation).
    Float64,
}

/// One field of a layout.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Field {
    /// Name, unique within the layout (`snake_case`; the package upper-cases it).
    pub name: String,
    /// Input or expected output.
    pub direction: Direction,
    /// Bit offset of the least significant bit.
    pub offset: u32,
    /// Width in bits.
    pub width: u32,
    /// What the bits mean.
    pub kind: FieldKind,
    /// Two's complement (else unsigned).
    pub signed: bool,
    /// Fraction bits (0 for integers and flags).
    pub frac: i32,
    /// Q-notation name of a fixed-point field's format (`sQ8.32`), else `None`.
    pub format: Option<String>,
    /// `ap_fixed` name of the quantisation mode that produced the value (`AP_RND_CONV`), for
    /// fixed-point fields; `None` for others.
    pub quantisation: Option<&'static str>,
    /// `ap_fixed` name of the overflow mode (`AP_SAT`), for fixed-point fields.
    pub overflow: Option<&'static str>,
    /// One line on what the field is.
    pub description: String,
}

/// The `ap_fixed` name of a quantisation mode.
pub fn quant_name(q: Quant) -> &'static str {
    match q {
        Quant::Trn => "AP_TRN",
        Quant::TrnZero => "AP_TRN_ZERO",
        Quant::Rnd => "AP_RND",
        Quant::RndZero => "AP_RND_ZERO",
        Quant::RndMinInf => "AP_RND_MIN_INF",
        Quant::RndInf => "AP_RND_INF",
        Quant::RndConv => "AP_RND_CONV",
    }
}

/// The `ap_fixed` name of an overflow mode.
pub fn overflow_name(o: OverflowMode) -> &'static str {
    match o {
        OverflowMode::Sat => "AP_SAT",
        OverflowMode::SatSym => "AP_SAT_SYM",
        OverflowMode::Wrap => "AP_WRAP",
    }
}

/// An ordered list of fields packed from bit 0 up.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Layout {
    fields: Vec<Field>,
    bits: u32,
}

impl Layout {
    /// An empty layout.
    pub fn new() -> Self {
        Self::default()
    }

    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        name: &str,
        direction: Direction,
        width: u32,
        kind: FieldKind,
        signed: bool,
        frac: i32,
        fmt: Option<Format>,
        description: &str,
    ) {
        debug_assert!(
            self.index(name).is_none(),
            "duplicate field {name} in a layout"
        );
        self.fields.push(Field {
            name: name.to_string(),
            direction,
            offset: self.bits,
            width,
            kind,
            signed,
            frac,
            format: fmt.map(|f| f.name()),
            quantisation: fmt.map(|f| quant_name(f.quant)),
            overflow: fmt.map(|f| overflow_name(f.overflow)),
            description: description.to_string(),
        });
        self.bits += width;
    }

    /// A fixed-point field in format `f`.
    pub fn fixed(&mut self, name: &str, dir: Direction, f: Format, description: &str) {
        self.push(
            name,
            dir,
            u32::from(f.width),
            FieldKind::Fixed,
            f.signed,
            i32::from(f.frac),
            Some(f),
            description,
        );
    }

    /// An unsigned integer field of `width` bits.
    pub fn uint(&mut self, name: &str, dir: Direction, width: u32, description: &str) {
        self.push(
            name,
            dir,
            width,
            FieldKind::Integer,
            false,
            0,
            None,
            description,
        );
    }

    /// A signed (two's complement) integer field of `width` bits.
    pub fn sint(&mut self, name: &str, dir: Direction, width: u32, description: &str) {
        self.push(
            name,
            dir,
            width,
            FieldKind::Integer,
            true,
            0,
            None,
            description,
        );
    }

    /// A one-bit flag.
    pub fn flag(&mut self, name: &str, dir: Direction, description: &str) {
        self.push(name, dir, 1, FieldKind::Flag, false, 0, None, description);
    }

    /// A 64-bit IEEE 754 binary64 pattern.
    pub fn float64(&mut self, name: &str, dir: Direction, description: &str) {
        self.push(
            name,
            dir,
            64,
            FieldKind::Float64,
            false,
            0,
            None,
            description,
        );
    }

    /// The fields from bit 0 up.
    pub fn fields(&self) -> &[Field] {
        &self.fields
    }

    /// Width of a packed word.
    pub fn word_bits(&self) -> u32 {
        self.bits
    }

    /// Position of a field by name.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.fields.iter().position(|f| f.name == name)
    }

    /// The field called `name`.
    pub fn field(&self, name: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// Packs one value per field, in field order (two's-complement bit patterns as `u128`).
    /// The stage modules build `values` in the order they declared the fields; a length
    /// mismatch is a programming error caught by every stage's round-trip test.
    pub fn pack(&self, values: &[u128]) -> Word {
        debug_assert_eq!(values.len(), self.fields.len(), "one value per field");
        debug_assert!(
            self.misfits(values).is_empty(),
            "values that do not fit their fields: {:?}",
            self.misfits(values)
        );
        let mut w = Word::zero(self.bits);
        for (f, &v) in self.fields.iter().zip(values) {
            w.put(f.offset, f.width, v);
        }
        w
    }

    /// The names of the fields whose value in `values` (field order) does not fit the
    /// field: a signed value outside −2^(w−1)..2^(w−1), an unsigned one at or above 2^w.
    /// Rows must never carry such values (the RTL would see a different number); every
    /// stage's tests check it.
    pub fn misfits(&self, values: &[u128]) -> Vec<String> {
        self.fields
            .iter()
            .zip(values)
            .filter(|(f, &v)| {
                let w = f.width.min(128);
                if w >= 128 {
                    return false;
                }
                if f.signed {
                    let x = v as i128;
                    x < -(1i128 << (w - 1)) || x >= 1i128 << (w - 1)
                } else {
                    v >> w != 0
                }
            })
            .map(|(f, _)| f.name.clone())
            .collect()
    }

    /// A field of a packed word, sign-extended if the field is signed; `None` for an unknown
    /// name.
    pub fn read(&self, w: &Word, name: &str) -> Option<i128> {
        let f = self.field(name)?;
        Some(if f.signed {
            w.get_signed(f.offset, f.width)
        } else {
            w.get(f.offset, f.width) as i128
        })
    }
}

/// A signed code as the `u128` bit pattern [`Layout::pack`] takes.
pub fn s(v: i64) -> u128 {
    i128::from(v) as u128
}

/// An unsigned value as the `u128` [`Layout::pack`] takes.
pub fn u(v: u64) -> u128 {
    u128::from(v)
}

/// A flag as the `u128` [`Layout::pack`] takes.
pub fn b(v: bool) -> u128 {
    u128::from(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_packed_without_gaps_and_read_back() {
        let mut l = Layout::new();
        l.fixed("x", Direction::Input, Format::sq(8, 32), "x");
        l.flag("f", Direction::Output, "f");
        l.uint("n", Direction::Output, 7, "n");
        assert_eq!(l.word_bits(), 48);
        assert_eq!(l.field("n").map(|f| f.offset), Some(41));
        let w = l.pack(&[s(-3), b(true), u(100)]);
        assert_eq!(l.read(&w, "x"), Some(-3));
        assert_eq!(l.read(&w, "f"), Some(1));
        assert_eq!(l.read(&w, "n"), Some(100));
        assert_eq!(l.read(&w, "nope"), None);
        let x = &l.fields()[0];
        assert_eq!(x.format.as_deref(), Some("sQ8.32"));
        assert_eq!(
            (x.quantisation, x.overflow),
            (Some("AP_TRN"), Some("AP_SAT"))
        );
    }
}
