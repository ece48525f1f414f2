//! Hit-buffer record: the packed BRAM word one pixel keeps between frames (paper §4.3).
//!
//! Pipeline position: the last unit of a ray. The hit-buffer check reads the pixel's word
//! from the previous frame; its instance field, with the dirty flags and *this* frame's sphere
//! count (never the stored `kind`: an instance may have moved in front since, DESIGN.md §3),
//! decides reuse. The walk's result, or the reused record with its kind refreshed, is packed
//! and written back, and the frame buffer shades from the same fields, so a reused pixel and a
//! re-traced one go through the same quantisation.
//!
//! Fields, from bit 0 up (`docs/units/hit-record.md` has the table with offsets):
//!
//! | field | bits (default) | meaning |
//! |---|---|---|
//! | kind | 2 | spheres pierced this frame: 0 none, 1 one, 2 several (3 reserved, read as several) |
//! | instance | `instance_bits` (8) | instance hit; all ones = none (a miss) |
//! | t | `t.width` (22, uQ8.14) | ray parameter of the hit, metres; the far code (the maximum) on a miss |
//! | normal u, v | 2 × `normal_bits` (2 × 8) | octahedral shading normal, signed codes, value = code / (2^(N−1) − 1) |
//! | colour | 24 (RGB888) or 16 (RGB565) | leaf colour, B in the low bits, R in the high bits |
//! | voxel x, y, z | 3 × `voxel_bits` (3 × 11), only if `include_voxel` | leaf coordinates, for accuracy checks |
//!
//! Control fields come first so the reuse check's bits keep their offsets whatever the
//! payload widths; the optional voxel fields come last so switching them off moves nothing.
//! Out-of-range inputs saturate and are counted on the record's signal; nothing panics.

use crate::fixed::{from_f64, to_f64, Format, Overflows, Quant, SignalId};
use serde::{Deserialize, Serialize};

mod bram;
mod reuse;
pub use bram::{bram36_count, uram288_count, BRAM36_SHAPES};
pub use reuse::{reuse, ReuseInputs};

/// How many bounding spheres the pixel's ray pierced in the frame that wrote the record (the
/// paper's "nature of the hit"). A miss is told by the instance field, not by this.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SphereCount {
    /// No sphere: nothing can be hit.
    #[default]
    None,
    /// Exactly one sphere (the reuse rule's case, when it holds in the current frame).
    One,
    /// Two or more spheres.
    Several,
}

impl SphereCount {
    /// From a candidate count.
    pub fn from_count(n: usize) -> Self {
        match n {
            0 => Self::None,
            1 => Self::One,
            _ => Self::Several,
        }
    }

    /// The 2-bit code.
    pub fn code(self) -> u8 {
        match self {
            Self::None => 0,
            Self::One => 1,
            Self::Several => 2,
        }
    }

    /// From a 2-bit code. The reserved code 3 reads as `Several`: a corrupted or unknown code
    /// then forbids reuse rather than allowing a wrong one.
    pub fn from_code(c: u8) -> Self {
        match c & 3 {
            0 => Self::None,
            1 => Self::One,
            _ => Self::Several,
        }
    }
}

/// Colour format of the record.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ColourFormat {
    /// 5/6/5 bits, rounded to nearest from the leaf's 8-bit channels.
    Rgb565,
    /// 8/8/8 bits: the leaf's colour unchanged (alpha is not stored).
    Rgb888,
}

impl ColourFormat {
    /// Bits of R, G, B.
    pub fn channel_bits(self) -> [u32; 3] {
        match self {
            Self::Rgb565 => [5, 6, 5],
            Self::Rgb888 => [8, 8, 8],
        }
    }

    /// Bits of the colour field.
    pub fn bits(self) -> u32 {
        self.channel_bits().iter().sum()
    }
}

/// Field widths and formats of the hit record.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HitRecordConfig {
    /// Format of t. Default uQ8.14, truncating and saturating (22 bits): t ≥ 0 always, 256 m
    /// covers the scenes (`vox_traffic` lies within ~40 m of its camera), and 61 µm is a
    /// thirtieth of a depth-11 voxel of the 4 m car. The record's t is a depth value for
    /// output and checks; the walker compares its own wider t, never this one.
    pub t: Format,
    /// Bits of the instance id. Default 8: instances 0..=254 and the none code 255.
    pub instance_bits: u8,
    /// Bits per octahedral normal component. Default 8: the normal only shades, and 8-bit
    /// octahedral codes are within about a degree, below what 8-bit colour shows.
    pub normal_bits: u8,
    /// Colour format. Default RGB888: the leaf colour unchanged, so a correct hit's colour
    /// equals the f64 reference's exactly and any colour mismatch means a wrong voxel.
    pub colour: ColourFormat,
    /// Bits per voxel coordinate. Default 11 (the paper's depth-11 octree), up to 20.
    pub voxel_bits: u8,
    /// Store the leaf coordinates (for accuracy checks; off in the default record, which
    /// then fills one 72-bit BRAM word exactly).
    pub include_voxel: bool,
}

impl Default for HitRecordConfig {
    fn default() -> Self {
        Self {
            t: Format::uq(8, 14),
            instance_bits: 8,
            normal_bits: 8,
            colour: ColourFormat::Rgb888,
            voxel_bits: 11,
            include_voxel: false,
        }
    }
}

/// Widest word [`pack`] returns.
pub const MAX_WORD_BITS: u32 = 128;

/// Where one field sits in the word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct FieldLayout {
    /// Field name (`kind`, `instance`, `t`, `normal_u`, `normal_v`, `colour_b`, `colour_g`,
    /// `colour_r`, `voxel_x`, `voxel_y`, `voxel_z`).
    pub name: &'static str,
    /// Offset of the field's least significant bit.
    pub offset: u32,
    /// Width in bits.
    pub width: u32,
    /// Two's complement (else unsigned).
    pub signed: bool,
    /// Fraction bits (0 for integer fields).
    pub frac: i32,
}

/// Field positions, computed once from the widths (each clamped into its legal range, so an
/// invalid configuration still has a layout; [`HitRecordConfig::validate`] reports it).
#[derive(Clone, Copy, Debug)]
struct Layout {
    instance: u32,
    t: u32,
    normal: u32,
    colour: [u32; 3],
    voxel: u32, // 0 when not included
}

impl Layout {
    fn of(cfg: &HitRecordConfig) -> Self {
        Self {
            instance: u32::from(cfg.instance_bits.clamp(1, 16)),
            t: u32::from(cfg.t.width.clamp(1, 64)),
            normal: u32::from(cfg.normal_bits.clamp(2, 16)),
            colour: cfg.colour.channel_bits(),
            voxel: if cfg.include_voxel {
                u32::from(cfg.voxel_bits.clamp(1, 32))
            } else {
                0
            },
        }
    }

    /// (name, width, signed, frac) of every field, from bit 0 up.
    fn fields(&self, t: Format) -> Vec<(&'static str, u32, bool, i32)> {
        let mut v = vec![
            ("kind", 2, false, 0),
            ("instance", self.instance, false, 0),
            ("t", self.t, t.signed, i32::from(t.frac)),
            ("normal_u", self.normal, true, 0),
            ("normal_v", self.normal, true, 0),
            ("colour_b", self.colour[2], false, 0),
            ("colour_g", self.colour[1], false, 0),
            ("colour_r", self.colour[0], false, 0),
        ];
        if self.voxel > 0 {
            v.push(("voxel_x", self.voxel, false, 0));
            v.push(("voxel_y", self.voxel, false, 0));
            v.push(("voxel_z", self.voxel, false, 0));
        }
        v
    }
}

impl HitRecordConfig {
    /// Checks the widths: instance 1..=16 bits, normal 2..=16 per component, voxel 1..=20
    /// per axis, a valid t format, and the whole word at most [`MAX_WORD_BITS`].
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=16).contains(&self.instance_bits) {
            return Err(format!(
                "hit_record.instance_bits {} is outside 1..=16",
                self.instance_bits
            ));
        }
        if !(2..=16).contains(&self.normal_bits) {
            return Err(format!(
                "hit_record.normal_bits {} is outside 2..=16",
                self.normal_bits
            ));
        }
        if self.include_voxel && !(1..=20).contains(&self.voxel_bits) {
            return Err(format!(
                "hit_record.voxel_bits {} is outside 1..=20",
                self.voxel_bits
            ));
        }
        if !self.t.is_valid() {
            return Err(format!(
                "hit_record.t: format {} is not valid",
                self.t.name()
            ));
        }
        let w = self.word_bits();
        if w > MAX_WORD_BITS {
            return Err(format!(
                "hit_record: word of {w} bits exceeds {MAX_WORD_BITS}"
            ));
        }
        Ok(())
    }

    /// The fields with their offsets, from bit 0 up: the table of `docs/units/hit-record.md`
    /// and what a vector manifest lists.
    pub fn layout(&self) -> Vec<FieldLayout> {
        let mut offset = 0;
        Layout::of(self)
            .fields(self.t)
            .into_iter()
            .map(|(name, width, signed, frac)| {
                let f = FieldLayout {
                    name,
                    offset,
                    width,
                    signed,
                    frac,
                };
                offset += width;
                f
            })
            .collect()
    }

    /// Width of the packed word in bits: 72 for the default record, 105 with voxels.
    pub fn word_bits(&self) -> u32 {
        Layout::of(self).fields(self.t).iter().map(|f| f.1).sum()
    }

    /// The instance code meaning "no instance": all ones (255 for 8 bits).
    pub fn instance_none(&self) -> u16 {
        mask(Layout::of(self).instance) as u16
    }

    /// BRAM36 blocks for a buffer of `width_px` × `height_px` records (see [`bram36_count`]).
    pub fn bram36_for(&self, width_px: u32, height_px: u32) -> u64 {
        bram36_count(self.word_bits(), u64::from(width_px) * u64::from(height_px))
    }
}

/// The record's t, a depth value in metres: a raw code of [`HitRecordConfig::t`] (default
/// uQ8.14). The walker's own, wider t reaches it through the host's f64 path (`quantise`),
/// never by a shift between the two formats.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct RecordT {
    /// The code.
    pub raw: i64,
}

impl RecordT {
    /// The far code a miss stores: the format's largest.
    pub fn far(cfg: &HitRecordConfig) -> Self {
        Self {
            raw: cfg.t.max_raw(),
        }
    }

    /// Metres.
    pub fn to_f64(self, cfg: &HitRecordConfig) -> f64 {
        to_f64(self.raw, cfg.t)
    }
}

/// One record's fields as raw codes: what [`unpack`] returns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct HitRecordFields {
    /// Spheres pierced in the frame that wrote the record.
    pub kind: SphereCount,
    /// Instance hit; `None` on a miss (stored as the all-ones code).
    pub instance: Option<u16>,
    /// t.
    pub t: RecordT,
    /// Octahedral normal (u, v) as signed `normal_bits`-bit codes, value = code / (2^(N−1) − 1)
    /// (the most negative code also reads as −1).
    pub normal: [i32; 2],
    /// R, G, B codes at the colour format's channel widths.
    pub colour: [u8; 3],
    /// Leaf coordinates; [0; 3] when the configuration does not store them.
    pub voxel: [u32; 3],
}

/// A record in floating point, as the f64 reference or a test produces it; [`quantise`]
/// turns it into fields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitRecordF64 {
    /// Spheres pierced.
    pub kind: SphereCount,
    /// Instance hit, or `None`.
    pub instance: Option<u16>,
    /// Ray parameter of the hit, metres; +∞ on a miss.
    pub t: f64,
    /// Shading normal in world space (any length; zero on a miss).
    pub normal: [f64; 3],
    /// Leaf colour, 8 bits per channel.
    pub colour: [u8; 3],
    /// Leaf coordinates.
    pub voxel: [u32; 3],
}

/// Low `w` bits set (w ≤ 128).
#[inline]
fn mask(w: u32) -> u128 {
    if w >= 128 {
        u128::MAX
    } else {
        (1u128 << w) - 1
    }
}

/// Writes the low `w` bits of `v` at `off`; bits at or above 128 are lost (only an invalid
/// configuration has any, and [`pack`] counts it).
#[inline]
fn put(word: &mut u128, off: u32, w: u32, v: u128) {
    if off < 128 {
        *word |= (v & mask(w)) << off;
    }
}

/// Reads `w` bits at `off` (zero above bit 127).
#[inline]
fn get(word: u128, off: u32, w: u32) -> u128 {
    if off < 128 {
        (word >> off) & mask(w)
    } else {
        0
    }
}

/// Sign-extends the low `w` bits of `v` (1 ≤ w ≤ 64).
#[inline]
fn sext(v: u128, w: u32) -> i64 {
    let s = 128 - w;
    (((v << s) as i128) >> s) as i64
}

/// Clamps `v` into `lo..=hi`, counting a clamp on `sig`.
#[inline]
fn sat(v: i64, lo: i64, hi: i64, ov: &mut Overflows, sig: SignalId) -> i64 {
    if v < lo || v > hi {
        ov.hit(sig);
        v.clamp(lo, hi)
    } else {
        v
    }
}

/// Packs a record into its word (bit 0 = bit 0 of the kind field). Out-of-range fields
/// saturate, each counted on `sig`: t into its format, normal codes into `normal_bits` signed
/// bits, colour codes into their channel widths, voxel coordinates into `voxel_bits`; an
/// instance id at or above the none code becomes none (the pixel shows as a miss, not as
/// another instance). An invalid configuration is counted once, and bits beyond 128 are lost.
///
/// ```
/// use rtl_model::fixed::{Overflows, SignalId};
/// use rtl_model::units::hit_record::*;
/// let cfg = HitRecordConfig::default();
/// let mut ov = Overflows::new(&["hit_record"]);
/// let r = HitRecordFields { kind: SphereCount::One, instance: Some(3), t: RecordT { raw: 5 << 14 },
///     normal: [0, 127], colour: [200, 34, 42], voxel: [0; 3] };
/// let w = pack(&r, &cfg, &mut ov, SignalId(0));
/// assert!(w < 1 << 72);
/// assert_eq!(unpack(w, &cfg), r);
/// assert_eq!(ov.total(), 0);
/// ```
pub fn pack(r: &HitRecordFields, cfg: &HitRecordConfig, ov: &mut Overflows, sig: SignalId) -> u128 {
    if cfg.validate().is_err() {
        ov.hit(sig);
    }
    let l = Layout::of(cfg);
    let none = mask(l.instance) as u16;
    let mut w = 0u128;
    let mut off = 0;
    let mut field = |w_bits: u32, v: u128, word: &mut u128| {
        put(word, off, w_bits, v);
        off += w_bits;
    };

    field(2, u128::from(r.kind.code()), &mut w);

    let inst = match r.instance {
        Some(id) if id < none => id,
        Some(_) => {
            ov.hit(sig);
            none
        }
        None => none,
    };
    field(l.instance, u128::from(inst), &mut w);

    let t = if cfg.t.is_valid() {
        sat(r.t.raw, cfg.t.min_raw(), cfg.t.max_raw(), ov, sig)
    } else {
        r.t.raw
    };
    field(l.t, t as u128, &mut w); // two's complement, cut to the field width

    let nmax = (1i64 << (l.normal - 1)) - 1;
    for c in r.normal {
        let c = sat(i64::from(c), -nmax - 1, nmax, ov, sig);
        field(l.normal, c as u128, &mut w);
    }

    for ch in [2, 1, 0] {
        let bits = l.colour[ch];
        let c = sat(i64::from(r.colour[ch]), 0, mask(bits) as i64, ov, sig);
        field(bits, c as u128, &mut w);
    }

    if l.voxel > 0 {
        for v in r.voxel {
            let c = sat(i64::from(v), 0, mask(l.voxel) as i64, ov, sig);
            field(l.voxel, c as u128, &mut w);
        }
    }
    w
}

/// Unpacks a word. Every word decodes (bits above the layout are ignored): the reserved kind
/// code reads as several spheres, the all-ones instance code as none.
pub fn unpack(word: u128, cfg: &HitRecordConfig) -> HitRecordFields {
    let l = Layout::of(cfg);
    let mut off = 0;
    let mut next = |w: u32| {
        let v = get(word, off, w);
        off += w;
        v
    };
    let kind = SphereCount::from_code(next(2) as u8);
    let inst = next(l.instance) as u16;
    let instance = (inst != mask(l.instance) as u16).then_some(inst);
    let traw = next(l.t);
    let t = RecordT {
        raw: if cfg.t.signed {
            sext(traw, l.t)
        } else {
            traw as i64 // a 64-bit unsigned code above i64::MAX cannot be packed (max_raw)
        },
    };
    let u = sext(next(l.normal), l.normal) as i32;
    let v = sext(next(l.normal), l.normal) as i32;
    let b = next(l.colour[2]) as u8;
    let g = next(l.colour[1]) as u8;
    let r = next(l.colour[0]) as u8;
    let mut voxel = [0u32; 3];
    if l.voxel > 0 {
        for c in &mut voxel {
            *c = next(l.voxel) as u32;
        }
    }
    HitRecordFields {
        kind,
        instance,
        t,
        normal: [u, v],
        colour: [r, g, b],
        voxel,
    }
}

/// Rounds an 8-bit channel to `bits` (5 or 6) to nearest: round(x · (2^bits − 1) / 255) with
/// the exact division-by-255 identity (adds and shifts only).
pub fn channel_from_u8(x: u8, bits: u32) -> u8 {
    if bits >= 8 {
        return x;
    }
    let v = u32::from(x) * ((1 << bits) - 1) + 128;
    ((v + (v >> 8)) >> 8) as u8
}

/// Expands a `bits`-bit channel to 8 bits by bit replication (0 → 0, all ones → 255).
pub fn channel_to_u8(c: u8, bits: u32) -> u8 {
    if bits >= 8 || bits == 0 {
        return c;
    }
    let max = (1u32 << bits) - 1;
    let c = u32::from(c) & max;
    if bits >= 4 {
        // Bit replication: wires only, and within one step of exact rounding.
        ((c << (8 - bits)) | (c >> (2 * bits - 8))) as u8
    } else {
        ((c * 255 + max / 2) / max) as u8
    }
}

/// Reduces a leaf attribute's snorm16 octahedral component (value = code / 32767) to a
/// `bits`-bit code (value = code / (2^(bits−1) − 1)), rounded to nearest, ties away from
/// zero, in integers: one constant multiply in RTL. This is the hardware path from the leaf
/// attribute word to the record.
pub fn normal_from_snorm16(code: i16, bits: u8) -> i32 {
    let s = (1i64 << (bits.clamp(2, 16) - 1)) - 1;
    let c = i64::from(code).max(-32767); // −32768 reads as −1, like −32767
    let num = 2 * c * s;
    let den = 2 * 32767;
    ((num + num.signum() * 32767) / den) as i32 // truncation toward zero of (x + ½·sign)
}

/// Octahedral encoding of a normal into two `bits`-bit codes, rounded to nearest. A zero
/// vector (a miss) encodes +z; a non-finite one also encodes +z and is counted on `sig`.
pub fn encode_normal(n: [f64; 3], bits: u8, ov: &mut Overflows, sig: SignalId) -> [i32; 2] {
    if n.iter().any(|c| !c.is_finite()) {
        ov.hit(sig);
        return [0, 0];
    }
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    if !(l1 > 0.0 && l1.is_finite()) {
        return [0, 0];
    }
    let (mut u, mut v, z) = (n[0] / l1, n[1] / l1, n[2] / l1);
    if z < 0.0 {
        // Fold the lower hemisphere over the diagonals of the octahedron.
        let (pu, pv) = (u, v);
        u = (1.0 - pv.abs()) * if pu >= 0.0 { 1.0 } else { -1.0 };
        v = (1.0 - pu.abs()) * if pv >= 0.0 { 1.0 } else { -1.0 };
    }
    let s = ((1i64 << (bits.clamp(2, 16) - 1)) - 1) as f64;
    [
        (u.clamp(-1.0, 1.0) * s).round() as i32,
        (v.clamp(-1.0, 1.0) * s).round() as i32,
    ]
}

/// Decodes the record's octahedral normal to a unit vector.
pub fn decode_normal(code: [i32; 2], bits: u8) -> [f64; 3] {
    let s = ((1i64 << (bits.clamp(2, 16) - 1)) - 1) as f64;
    let u = (f64::from(code[0]) / s).clamp(-1.0, 1.0);
    let v = (f64::from(code[1]) / s).clamp(-1.0, 1.0);
    crate::svo::attr::octahedral_unfold(u, v)
}

/// Worst-case angle, radians, between a unit normal and its `bits`-bit octahedral code
/// decoded ([`encode_normal`] then [`decode_normal`]); 0.0167 rad (0.96°) for 8 bits.
///
/// Derivation (`docs/units/hit-record.md`): rounding moves (u, v) by at most h = 1/(2s) per
/// component, s = 2^(bits−1) − 1. The map from (u, v) to the octahedron point p is piecewise
/// linear and continuous, moving p by at most √(h² + h² + (2h)²) = √6·h. Every point of the
/// octahedron |x| + |y| + |z| = 1 is at least 1/√3 from the origin, and two vectors at least
/// r long and d apart make an angle of at most 2·asin(d / 2r): here 2·asin(3h/√2).
pub fn normal_error_bound_rad(bits: u8) -> f64 {
    let s = ((1i64 << (bits.clamp(2, 16) - 1)) - 1) as f64;
    let h = 0.5 / s;
    2.0 * (3.0 * h / 2f64.sqrt()).min(1.0).asin()
}

/// Worst-case error of t, metres, for a t within the format's range: one LSB when the format
/// truncates (the stored t is never above the true one), half an LSB when it rounds.
pub fn t_error_bound(cfg: &HitRecordConfig) -> f64 {
    match cfg.t.quant {
        Quant::Trn | Quant::TrnZero => cfg.t.lsb(),
        _ => 0.5 * cfg.t.lsb(),
    }
}

/// Quantises a floating-point record into fields, counting on `sig` what does not fit: t
/// by [`from_f64`] in the t format (a miss's +∞ becomes the far code, the format's maximum,
/// without a count: it is the meaning of a miss, not an overflow); the normal by
/// [`encode_normal`]; the colour by [`channel_from_u8`]; voxels and the instance as [`pack`]
/// does. `pack` of the result counts nothing further.
pub fn quantise(
    r: &HitRecordF64,
    cfg: &HitRecordConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> HitRecordFields {
    let l = Layout::of(cfg);
    let none = mask(l.instance) as u16;
    let instance = match r.instance {
        Some(id) if id < none => Some(id),
        Some(_) => {
            ov.hit(sig);
            None
        }
        None => None,
    };
    let t = if !cfg.t.is_valid() {
        ov.hit(sig);
        RecordT::default()
    } else if r.instance.is_none() && r.t == f64::INFINITY {
        RecordT::far(cfg)
    } else {
        RecordT {
            raw: from_f64(r.t, cfg.t, ov, sig),
        }
    };
    let colour = [0, 1, 2].map(|i| channel_from_u8(r.colour[i], l.colour[i]));
    let voxel = if l.voxel > 0 {
        r.voxel.map(|v| {
            if u128::from(v) > mask(l.voxel) {
                ov.hit(sig);
                mask(l.voxel) as u32
            } else {
                v
            }
        })
    } else {
        [0; 3]
    };
    HitRecordFields {
        kind: r.kind,
        instance,
        t,
        normal: encode_normal(r.normal, l.normal as u8, ov, sig),
        colour,
        voxel,
    }
}

/// Latency in cycles of packing a record's fields into its word (`svo_hit_pack`): one
/// register (concatenation, t saturation).
pub const PACK_WORD_LATENCY_CYCLES: u32 = 1;

/// Latency in cycles of the record stage's packing (`units.hit_pack` by default): the normal
/// unit ([`crate::units::normal`], the record's octahedral normal from the hit's attribute)
/// and then the word packer, in one pipe.
pub const PACK_LATENCY_CYCLES: u32 =
    crate::units::normal::LATENCY_CYCLES + PACK_WORD_LATENCY_CYCLES;

/// Latency in cycles of unpacking a word read from the hit buffer: one register (wiring and
/// the none-code compare).
pub const UNPACK_LATENCY_CYCLES: u32 = 1;
