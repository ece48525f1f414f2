//! Transform unit (paper Eq. 3): carries a world-space ray into an instance's local frame,
//! d' = Rᵀ d and o' = Rᵀ (o − c), with R the instance's world-from-local rotation (its
//! columns are the local axes in world space) and c its octree centre.
//!
//! Pipeline position: after the sorter, once per (ray, candidate); its outputs feed the
//! reciprocal unit and the octree walker. Scale is not applied here: it lives in the octree's
//! box extents (paper §3.2), so t is the same in world and local space.
//!
//! Arithmetic, as the RTL does it: o − c is an exact subtraction (one bit wider than `pos`);
//! each output component is the dot product of one column of R with the vector, formed from
//! three exact products summed in full width as (p_x + p_y) + p_z — the order of the f64
//! reference — and rounded once into the output format. So the only errors are the inputs'
//! quantisation and that one rounding; see [`origin_error_bound`] and [`dir_error_bound`].

use crate::fixed::{quantize, Format, Overflows, Products, Quant, SignalId};
use serde::{Deserialize, Serialize};

/// Formats of the transform unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformConfig {
    /// World positions in: ray origin and instance centre (metres).
    pub pos: Format,
    /// World direction components in (unit vector).
    pub dir: Format,
    /// Rotation matrix entries (each within [−1, 1]).
    pub mat: Format,
    /// Local origin out (metres).
    pub local_pos: Format,
    /// Local direction components out.
    pub local_dir: Format,
}

impl TransformConfig {
    /// Checks that the formats are valid and that the exact dot products fit the 127-bit
    /// accumulator: (mat width + pos width + 1) + 2 carry bits ≤ 127.
    pub fn validate(&self) -> Result<(), String> {
        for (name, f) in [
            ("pos", self.pos),
            ("dir", self.dir),
            ("mat", self.mat),
            ("local_pos", self.local_pos),
            ("local_dir", self.local_dir),
        ] {
            if !f.is_valid() {
                return Err(format!(
                    "transform.{name}: format {} is not valid",
                    f.name()
                ));
            }
        }
        if self.pos.width > 62 {
            return Err(format!(
                "transform.pos: {} is wider than 62 bits (o − c must fit 64)",
                self.pos.name()
            ));
        }
        let widest = u32::from(self.pos.width.max(self.dir.width)) + 1;
        if u32::from(self.mat.width) + widest + 2 > 127 {
            return Err(
                "transform: mat width + pos/dir width exceed the 127-bit accumulator".into(),
            );
        }
        Ok(())
    }
}

impl Default for TransformConfig {
    /// sQ8.32 positions (±128 m, 2^-32 m ≈ 2.3e-10 m), sQ2.30 directions and matrix entries
    /// (2^-30 ≈ 9.3e-10); the outputs keep the input formats. Reasons in
    /// `docs/number-formats.md`.
    fn default() -> Self {
        let pos = Format::sq(8, 32).with_quant(Quant::RndConv);
        let unit = Format::sq(2, 30).with_quant(Quant::RndConv);
        Self {
            pos,
            dir: unit,
            mat: unit,
            local_pos: pos,
            local_dir: unit,
        }
    }
}

/// Overflow signals of the unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TransformSignals {
    /// o' out of the local position range.
    pub origin: SignalId,
    /// d' out of the local direction range.
    pub dir: SignalId,
}

/// An instance as the transform unit receives it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct InstanceRaw {
    /// Columns of the world-from-local rotation (local x, y, z axes in world space), `mat`.
    pub axes: [[i64; 3]; 3],
    /// Octree centre in world space, `pos`.
    pub centre: [i64; 3],
}

/// Column k of R dotted with v (both exact), summed as (p0 + p1) + p2, rounded into `out`.
#[inline]
fn dot(
    col: [i64; 3],
    v: [i64; 3],
    frac: i32,
    out: Format,
    ov: &mut Overflows,
    sig: SignalId,
) -> i64 {
    let p = [0, 1, 2].map(|j| i128::from(col[j]) * i128::from(v[j]));
    quantize((p[0] + p[1]) + p[2], frac, out, ov, sig)
}

/// The transaction: world origin `o` and direction `d` (raw codes) into the local frame of
/// `inst`. Returns (o', d') as raw codes in `local_pos` and `local_dir`.
pub fn transform(
    o: [i64; 3],
    d: [i64; 3],
    inst: &InstanceRaw,
    cfg: &TransformConfig,
    ov: &mut Overflows,
    sig: TransformSignals,
) -> ([i64; 3], [i64; 3]) {
    let (o_local, d_local, _) = transform_with_signs(o, d, inst, cfg, ov, sig);
    (o_local, d_local)
}

/// [`transform`] plus the signs of the exact direction sums d'_k before rounding, which the
/// hardware takes from the same adders: the walker mirrors an axis on this bit (Revelles §3.4),
/// and a component that rounds to the code 0 keeps the side it came from, which two's
/// complement alone cannot say (there is no −0 code). An exact 0 is +0.
pub fn transform_with_signs(
    o: [i64; 3],
    d: [i64; 3],
    inst: &InstanceRaw,
    cfg: &TransformConfig,
    ov: &mut Overflows,
    sig: TransformSignals,
) -> ([i64; 3], [i64; 3], [bool; 3]) {
    let o_local = transform_origin(o, inst, cfg, ov, sig.origin);
    let (d_local, signs) = transform_direction(d, inst, cfg, ov, sig.dir);
    (o_local, d_local, signs)
}

/// The origin half of [`transform_with_signs`]: o' = Rᵀ(o − c) in `local_pos`, saturations
/// counted on `sig`. Split out because o is the camera for every primary ray, so a caller may
/// compute it once per instance and frame (the result depends on nothing else).
#[inline]
pub fn transform_origin(
    o: [i64; 3],
    inst: &InstanceRaw,
    cfg: &TransformConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> [i64; 3] {
    // Exact o − c: both in `pos`, so the difference needs one more bit and no rounding.
    // `validate` keeps positions within 62 bits, so o − c is exact in 64 and every product a
    // single 64×64 → 128-bit multiply.
    let rel = [0, 1, 2].map(|j| o[j].wrapping_sub(inst.centre[j]));
    let pf = i32::from(cfg.mat.frac) + i32::from(cfg.pos.frac);
    [0, 1, 2].map(|k| dot(inst.axes[k], rel, pf, cfg.local_pos, ov, sig))
}

/// The direction half of [`transform_with_signs`]: d' = Rᵀd in `local_dir` and the signs of
/// the exact sums, saturations counted on `sig`.
#[inline]
pub fn transform_direction(
    d: [i64; 3],
    inst: &InstanceRaw,
    cfg: &TransformConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> ([i64; 3], [bool; 3]) {
    let df = i32::from(cfg.mat.frac) + i32::from(cfg.dir.frac);
    let mut signs = [false; 3];
    let mut d_local = [0i64; 3];
    // A plain loop rather than `map` with a closure: the closure was left out of line in the
    // functional model's walk input (one call per component).
    for k in 0..3 {
        let col = inst.axes[k];
        let p = [0, 1, 2].map(|j| i128::from(col[j]) * i128::from(d[j]));
        let sum = (p[0] + p[1]) + p[2];
        signs[k] = sum < 0;
        d_local[k] = quantize(sum, df, cfg.local_dir, ov, sig);
    }
    (d_local, signs)
}

/// Worst-case error of converting an exact value into `f` (by its quantisation mode).
pub fn conversion_error(f: Format) -> f64 {
    match f.quant {
        Quant::Trn | Quant::TrnZero => f.lsb(),
        _ => 0.5 * f.lsb(),
    }
}

/// Bound on |o'_fixed − o'_exact| per component, for inputs converted from exact values into
/// the configured formats and |o − c| ≤ `max_rel` per component (metres):
///
/// ```text
/// o'_k = Σ_j R̃_jk (õ_j − c̃_j) with |R̃ − R| ≤ e_m, |õ − o|, |c̃ − c| ≤ e_p, |R| ≤ 1:
/// |Σ R̃ (õ − c̃) − Σ R (o − c)| ≤ Σ_j (|R̃_jk − R_jk|·|o_j − c_j| + |R̃_jk|·2e_p)
///                             ≤ 3·(e_m·max_rel + (1 + e_m)·2e_p)
/// plus the output rounding e_out.
/// ```
pub fn origin_error_bound(cfg: &TransformConfig, max_rel: f64) -> f64 {
    let (em, ep) = (conversion_error(cfg.mat), conversion_error(cfg.pos));
    3.0 * (em * max_rel + (1.0 + em) * 2.0 * ep) + conversion_error(cfg.local_pos)
}

/// Bound on |d'_fixed − d'_exact| per component for a unit direction:
/// 3·(e_m·1 + (1 + e_m)·e_d) + e_out, by the same argument as [`origin_error_bound`].
pub fn dir_error_bound(cfg: &TransformConfig) -> f64 {
    let (em, ed) = (conversion_error(cfg.mat), conversion_error(cfg.dir));
    3.0 * (em + (1.0 + em) * ed) + conversion_error(cfg.local_dir)
}

/// The products of one transform unit, side by side: R·(o − c) (9 of mat × (pos+1), o − c
/// the exact difference) and R·d (9 of mat × dir).
pub fn products(cfg: &TransformConfig) -> [Products; 2] {
    [
        Products::new(9, cfg.mat, cfg.pos.exact_difference()),
        Products::new(9, cfg.mat, cfg.dir),
    ]
}

/// DSP48E2 slices of one transform unit: the tiles of its [`products`] (72 by default).
pub fn dsp48e2_count(cfg: &TransformConfig) -> u32 {
    products(cfg).iter().map(Products::dsp48e2).sum()
}

/// Latency of the transform unit, as stages: o − c (1); the 18 products in parallel (one
/// product); the dot sum (p_x + p_y) + p_z (2); the rounding increment and the saturation
/// decided on the floor (1); the increment added and saturated (1) — two stages so that
/// every stage of `svo_transform.v` meets the clock rule at 300 MHz (docs/cycle-model.md
/// §1.5). 9 for the default.
pub fn latency_cycles(cfg: &TransformConfig) -> u32 {
    let [rel, dir] = products(cfg);
    1 + rel.latency_cycles().max(dir.latency_cycles()) + 2 + 2
}

/// Latency of a transform unit without products (no instance rotates, the hardware's
/// `transform_products: false`): o − c (1) and rounding and saturation (1).
pub const LATENCY_WITHOUT_PRODUCTS: u32 = 2;
