//! Reciprocal 1/d of a direction component: leading-zero normalisation, a seed from a small
//! ROM, Newton–Raphson iterations, denormalisation and one final rounding.
//!
//! Pipeline position: between the transform unit and the octree walker, once per
//! (ray, candidate) and axis, so that every slab and midpoint t-value is a product
//! t = (x − o)·(1/d) rather than a division.
//!
//! Datapath (bit for bit what [`reciprocal`] computes; `docs/units/reciprocal.md` has the
//! stages, widths, latency and the error bound's derivation):
//!
//! 1. Sign and magnitude: a = |d| (the code's two's complement negated if negative). The sign
//!    of a zero code cannot be seen in two's complement (there is no −0), so it travels
//!    separately as `sign_negative`, the transform stage's sign bit.
//! 2. Zero test: a ≤ 2^(F_in − k), with k the output's magnitude integer bits, means
//!    |1/d| ≥ 2^k does not fit the output: the unit flags `zero` and returns ±max (§3.3 of
//!    Revelles et al.: the walker then uses ±∞ for that axis). A non-zero code flushed this
//!    way is reported in `flushed` (an approximation within the walker's bound, not an
//!    overflow); an exact zero is exact (1/0 = ±∞).
//! 3. Normalise: e = 63 − lzc(a); the mantissa m = a/2^e ∈ [1, 2) truncated to uQ1.G, where
//!    G = F_out + 2 (two guard bits below the output LSB at |1/d| ≈ 1), clamped to 2..=62.
//! 4. Seed: the next `table_bits` = t bits of m index a ROM of 2^t entries
//!    y0 = round(2^(t+2) · 2/(a_i + b_i)) / 2^(t+2), the reciprocal of the interval
//!    [a_i, b_i) = [1 + i/2^t, 1 + (i+1)/2^t) chosen to balance the relative error at its ends
//!    ([`seed_table`] generates them).
//! 5. Newton–Raphson, `iterations` times, all in G fraction bits with truncation:
//!    p = ⌊m·y⌋, q = 2 − p, y ← ⌊y·q⌋ (two multiplies and a subtraction each).
//! 6. Denormalise and round: 1/|d| = y·2^(F_in − e); the signed value ±y is shifted to the
//!    output's fraction bits and rounded and saturated by the output format (counted).

use crate::fixed::{
    dsp48e2_per_product, product_latency_cycles, quantize, Format, Overflows, Quant, SignalId,
};
use serde::{Deserialize, Serialize};

/// Largest seed table: 2^16 entries (beyond this a ROM costs more than an iteration).
pub const MAX_TABLE_BITS: u8 = 16;
/// Most Newton–Raphson iterations: each doubles the correct bits, and 6 take even a one-entry
/// table (2 correct bits) past the 62-bit mantissa.
pub const MAX_ITERATIONS: u8 = 6;
/// Mantissa fraction bits G beyond the output's fraction bits.
const GUARD_BITS: i32 = 2;
/// Limits of G: products of two (G+1)-bit operands must fit 127 bits.
const MIN_MANTISSA_FRAC: i32 = 2;
const MAX_MANTISSA_FRAC: i32 = 62;

/// Formats and parameters of the reciprocal unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReciprocalConfig {
    /// Direction component in (signed).
    pub input: Format,
    /// 1/d out (signed). Its magnitude integer bits k set the zero threshold |d| ≤ 2^−k;
    /// its fraction bits F set the mantissa width G = F + 2; its quantisation mode is the
    /// final rounding.
    pub output: Format,
    /// Seed ROM index bits t (2^t entries of t + 1 stored bits), at most 16 and at most G.
    pub table_bits: u8,
    /// Newton–Raphson iterations after the seed, at most 6.
    pub iterations: u8,
}

impl Default for ReciprocalConfig {
    /// sQ2.30 in, sQ22.30 out rounded to nearest even, an 8-bit table, 2 iterations.
    ///
    /// - Input sQ2.30: the transform unit's direction format (unit-vector components,
    ///   |d| ≤ 1, LSB 2^-30).
    /// - Output sQ22.30 (52 bits): 21 magnitude integer bits, so every |d| > 2^-21 has a finite 1/d
    ///   (|1/d| < 2^21) and smaller ones are flagged zero. An axis with |d| ≤ 2^-21 moves the
    ///   ray less than 0.5 µm per metre (61 µm over a 128 m reach: treating it as parallel is
    ///   a direction error of at most 2^-21 on that axis, counted), and its input code is at
    ///   most 2^9, so its reciprocal would be known only to about 0.2 % anyway.
    ///   30 fraction bits give 1/d to 1.2·10^-9 near |d| = 1 (the bound), i.e. t to about
    ///   0.15 µm over a 128 m reach. 26 bits (the default until `sim sweep` measured the
    ///   choice, `docs/accuracy.md` §7) left 4–6× more depth error at the same DSP48E2 count:
    ///   the Newton–Raphson products grow from 29×29 to 33×33 bits and stay within 2×2 tiles,
    ///   the walker's root products from 41×48 to 41×52 and stay within 2×3.
    /// - Round to nearest, ties to even: symmetric, so d and −d give the same magnitude code
    ///   and a mirrored walk (§3.4) sees exactly the reciprocal of the unmirrored one.
    /// - 8 table bits, 2 iterations: the seed is good to 2^-8.7; two iterations take that to
    ///   2^-34.9, below the 2^-31 floor the 32-bit mantissa's truncations set. The ROM is
    ///   256 × 9 bits (LUTs); a 12-bit table with one iteration would need 4 DSPs instead of
    ///   12 but 2 BRAM36 and 3× the error (`docs/units/reciprocal.md`).
    fn default() -> Self {
        Self {
            input: Format::sq(2, 30).with_quant(Quant::RndConv),
            output: Format::sq(22, 30).with_quant(Quant::RndConv),
            table_bits: 8,
            iterations: 2,
        }
    }
}

impl ReciprocalConfig {
    /// Checks the configuration: valid formats, a signed output, G = F_out + 2 within 2..=62,
    /// `table_bits` ≤ min(16, G), `iterations` ≤ 6. An invalid configuration still computes
    /// without panicking, with G, `table_bits` and `iterations` clamped into those ranges.
    pub fn validate(&self) -> Result<(), String> {
        for (name, f) in [("input", self.input), ("output", self.output)] {
            if !f.is_valid() {
                return Err(format!(
                    "reciprocal.{name}: format {} is not valid",
                    f.name()
                ));
            }
        }
        if !self.output.signed {
            return Err(format!(
                "reciprocal.output: {} must be signed (1/d has the sign of d)",
                self.output.name()
            ));
        }
        let g = i32::from(self.output.frac) + GUARD_BITS;
        if !(MIN_MANTISSA_FRAC..=MAX_MANTISSA_FRAC).contains(&g) {
            return Err(format!(
                "reciprocal: mantissa fraction bits F_out + {GUARD_BITS} = {g} outside {MIN_MANTISSA_FRAC}..={MAX_MANTISSA_FRAC}"
            ));
        }
        if self.table_bits > MAX_TABLE_BITS || i32::from(self.table_bits) > g {
            return Err(format!(
                "reciprocal.table_bits: {} exceeds min({MAX_TABLE_BITS}, G = {g})",
                self.table_bits
            ));
        }
        if self.iterations > MAX_ITERATIONS {
            return Err(format!(
                "reciprocal.iterations: {} exceeds {MAX_ITERATIONS}",
                self.iterations
            ));
        }
        Ok(())
    }
}

/// The unit's result for one component.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Reciprocal {
    /// 1/d in the output format; ±max (the sign of d) when `zero`.
    pub raw: i64,
    /// |d| ≤ 2^−k ([`zero_threshold`]): 1/d does not fit, treat the axis as d = 0 (±∞).
    pub zero: bool,
    /// d is negative: the code's sign, or `sign_negative` for a zero code (so −0 is negative).
    pub negative: bool,
    /// A non-zero code flushed to `zero`: the documented §3.3 approximation (the ray moves
    /// less than `zero_threshold` per metre along that axis), reported here rather than as
    /// an overflow, since nothing saturated.
    pub flushed: bool,
}

impl Reciprocal {
    /// |raw|: the magnitude 1/|d| in the output format, for a walker that mirrors negative
    /// axes. Round-to-nearest outputs give d and −d the same magnitude.
    pub fn magnitude(&self) -> i64 {
        i64::try_from(self.raw.unsigned_abs()).unwrap_or(i64::MAX)
    }
}

/// Effective internal parameters (clamped into their supported ranges).
#[derive(Clone, Copy, Debug)]
struct Plan {
    /// Mantissa fraction bits G.
    g: u32,
    /// Table index bits t.
    tb: u32,
    /// Newton–Raphson iterations.
    iters: u32,
    /// Zero test: a ≤ 2^zero_exp, zero_exp = F_in − k.
    zero_exp: i32,
}

fn plan(cfg: &ReciprocalConfig) -> Plan {
    let g = (i32::from(cfg.output.frac) + GUARD_BITS).clamp(MIN_MANTISSA_FRAC, MAX_MANTISSA_FRAC)
        as u32;
    Plan {
        g,
        tb: u32::from(cfg.table_bits.min(MAX_TABLE_BITS)).min(g),
        iters: u32::from(cfg.iterations.min(MAX_ITERATIONS)),
        zero_exp: i32::from(cfg.input.frac) - output_magnitude_bits(cfg.output),
    }
}

/// Magnitude integer bits k of a format: its values are below 2^k in magnitude.
fn output_magnitude_bits(out: Format) -> i32 {
    i32::from(out.width) - i32::from(out.frac) - i32::from(out.signed)
}

/// Fraction bits of a seed-table entry for `table_bits` = t: t + 2.
pub fn seed_frac_bits(table_bits: u8) -> u32 {
    u32::from(table_bits.min(MAX_TABLE_BITS)) + 2
}

/// Entry `idx` of the seed table for t index bits, in uQ0.(t+2): the nearest code to
/// 2/(a + b) for the mantissa interval [a, b) = [1 + idx/2^t, 1 + (idx+1)/2^t), i.e.
/// round(2^(t+2) · 2^(t+1) / (2^(t+1) + 2·idx + 1)). The divisor is odd, so no ties.
fn seed_entry(tb: u32, idx: u64) -> u64 {
    let tf = tb + 2;
    let num = 1u128 << (tf + tb + 1);
    let den = (1u128 << (tb + 1)) + 2 * u128::from(idx) + 1;
    // round(num/den) = ⌊(2·num + den) / (2·den)⌋; < 2^tf since den > 2^(t+1).
    ((2 * num + den) / (2 * den)) as u64
}

/// The seed ROM for `table_bits` = t (clamped to 16): 2^t entries in uQ0.(t+2), each in
/// [1/2, 1), so the stored word drops the always-set top bit and keeps t + 1 bits. Generated,
/// not typed in: export it for `$readmemh` from here.
///
/// ```
/// use rtl_model::units::reciprocal::seed_table;
/// // t = 2: 1/1.125, 1/1.375, 1/1.625, 1/1.875 to 4 fraction bits.
/// assert_eq!(seed_table(2), vec![14, 12, 10, 9]);
/// ```
pub fn seed_table(table_bits: u8) -> Vec<u64> {
    let tb = u32::from(table_bits.min(MAX_TABLE_BITS));
    (0..1u64 << tb).map(|i| seed_entry(tb, i)).collect()
}

/// A seed entry placed into the mantissa's G fraction bits (uQ1.G).
fn placed_seed(p: &Plan, idx: u64) -> u128 {
    let y0 = u128::from(seed_entry(p.tb, idx));
    let tf = p.tb + 2;
    if p.g >= tf {
        y0 << (p.g - tf)
    } else {
        // Only when t > G − 2: the entry is truncated to the mantissa's width.
        y0 >> (tf - p.g)
    }
}

/// The magnitude |d| at and below which the unit flags `zero`: 2^−k, k = the output's
/// magnitude integer bits (1/|d| ≥ 2^k cannot be held). 2^-21 for the default.
pub fn zero_threshold(cfg: &ReciprocalConfig) -> f64 {
    2f64.powi(-output_magnitude_bits(cfg.output))
}

/// Mantissa fraction bits G of the Newton–Raphson datapath (F_out + 2, clamped to 2..=62).
pub fn mantissa_frac_bits(cfg: &ReciprocalConfig) -> u32 {
    plan(cfg).g
}

/// 1/d for the direction code `d_raw` (in `cfg.input`) into `cfg.output`.
///
/// `sign_negative` is the sign of the component before it was rounded to a code (the
/// transform stage's sign bit): it decides `negative` only when `d_raw` is 0 — a tiny
/// negative value rounded to 0, or −0.0 — so that the walker applies the negative-direction
/// rule of Revelles §3.3/§3.4 to it. For a non-zero code the code's own sign wins.
///
/// Never panics: any `i64` is accepted (codes outside the input format are treated as their
/// value). Zero-flagged non-zero codes and saturations of the final rounding are counted on
/// `sig`; an exact zero is not counted (its reciprocal ±∞ is exact).
///
/// ```
/// use rtl_model::fixed::{Overflows, SignalId};
/// use rtl_model::units::reciprocal::{reciprocal, ReciprocalConfig};
/// let cfg = ReciprocalConfig::default();
/// let mut ov = Overflows::new(&["inv_d"]);
/// // d = 0.5 (sQ2.30) → 1/d = 2.0 (sQ22.30)
/// let r = reciprocal(1 << 29, false, &cfg, &mut ov, SignalId(0));
/// assert_eq!((r.raw, r.zero, r.negative), (2 << 30, false, false));
/// // d = −0: zero flag, negative, −max.
/// let z = reciprocal(0, true, &cfg, &mut ov, SignalId(0));
/// assert_eq!((z.raw, z.zero, z.negative), (-cfg.output.max_raw(), true, true));
/// assert_eq!(ov.total(), 0);
/// ```
pub fn reciprocal(
    d_raw: i64,
    sign_negative: bool,
    cfg: &ReciprocalConfig,
    ov: &mut Overflows,
    sig: SignalId,
) -> Reciprocal {
    let p = plan(cfg);
    evaluate(
        d_raw,
        sign_negative,
        cfg,
        &p,
        |idx| placed_seed(&p, idx),
        ov,
        sig,
    )
}

/// The reciprocal unit with its seed ROM built once: the same results as [`reciprocal`],
/// for callers that evaluate many components with one configuration (the frame loop).
#[derive(Clone, Debug)]
pub struct ReciprocalUnit {
    cfg: ReciprocalConfig,
    plan: Plan,
    rom: Vec<u128>,
}

impl ReciprocalUnit {
    /// Builds the ROM for `cfg`.
    pub fn new(cfg: &ReciprocalConfig) -> Self {
        let plan = plan(cfg);
        let rom = (0..1u64 << plan.tb)
            .map(|i| placed_seed(&plan, i))
            .collect();
        Self {
            cfg: *cfg,
            plan,
            rom,
        }
    }

    /// [`reciprocal`] of one component.
    #[inline]
    pub fn eval(
        &self,
        d_raw: i64,
        sign_negative: bool,
        ov: &mut Overflows,
        sig: SignalId,
    ) -> Reciprocal {
        evaluate(
            d_raw,
            sign_negative,
            &self.cfg,
            &self.plan,
            |idx| self.rom[idx as usize],
            ov,
            sig,
        )
    }
}

/// The unit's stages, with the seed ROM read through `seed`. Always inlined: the functional
/// model evaluates three per walk (docs/cycle-model.md §2.7).
#[inline(always)]
fn evaluate(
    d_raw: i64,
    sign_negative: bool,
    cfg: &ReciprocalConfig,
    p: &Plan,
    seed: impl Fn(u64) -> u128,
    ov: &mut Overflows,
    sig: SignalId,
) -> Reciprocal {
    // Stage 1: sign and magnitude (|i64::MIN| = 2^63 fits u64).
    let negative = match d_raw.signum() {
        -1 => true,
        1 => false,
        _ => sign_negative,
    };
    let a = d_raw.unsigned_abs();

    // Stage 1 (in parallel): zero test against the constant 2^(F_in − k).
    let zero = match p.zero_exp {
        e if e < 0 => a == 0,
        e if e >= 64 => true,
        e => a <= 1u64 << e,
    };
    if zero {
        let max = i128::from(cfg.output.max_raw());
        let code = if negative { -max } else { max };
        // ±max fits any signed output; an (invalid) unsigned output clamps −max to 0, counted.
        let raw = quantize(code, i32::from(cfg.output.frac), cfg.output, ov, sig);
        return Reciprocal {
            raw,
            zero: true,
            negative,
            flushed: a != 0,
        };
    }

    // Stage 2: normalise. `norm` has its leading one at bit 63; m = norm / 2^63 ∈ [1, 2).
    let lz = a.leading_zeros();
    let lead = 63 - lz as i32; // |d| = m · 2^(lead − F_in)
    let norm = a << lz;
    let m = u128::from(norm >> (63 - p.g)); // uQ1.G, truncated
    let idx = if p.tb == 0 {
        0
    } else {
        (norm << 1) >> (64 - p.tb) // the t bits after the leading one
    };

    // Stage 3: seed ROM.
    let mut y = seed(idx); // uQ1.G, in [1/2, 1)

    // Stages 4..: Newton–Raphson. Invariants (docs/units/reciprocal.md): y ≤ 1 and
    // p = ⌊m·y⌋ < 2, so q = 2 − p ∈ (0, 2) and every product stays below 2^(2G+2).
    // G ≤ 62 (`plan`), so masking the shift changes nothing and tells the compiler that it
    // stays within one word (a funnel shift, no test for shifts of 64 or more).
    let g = p.g & 63;
    let two = 2u128 << g;
    for _ in 0..p.iters {
        let prod = (m * y) >> g; // uQ2.G, truncated
        let q = two.saturating_sub(prod); // uQ1.G; saturation cannot trigger (prod < 2)
        y = (y * q) >> g; // uQ1.G, truncated
    }

    // Final stage: ±y · 2^(F_in − lead) has G + lead − F_in fraction bits; round and saturate
    // into the output (y ≤ 2^G < 2^63, so the signed code is exact).
    let code = if negative { -(y as i128) } else { y as i128 };
    let frac = p.g as i32 + lead - i32::from(cfg.input.frac);
    let raw = quantize(code, frac, cfg.output, ov, sig);
    Reciprocal {
        raw,
        zero: false,
        negative,
        flushed: false,
    }
}

/// Worst-case error of [`reciprocal`] against the exact 1/d of the input code:
/// |result − 1/d| ≤ `rel`·|1/d| + `abs` for every code that is not flagged zero and does not
/// saturate (both are counted).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReciprocalErrorBound {
    /// Relative part: table, Newton–Raphson truncations and mantissa truncation.
    pub rel: f64,
    /// Absolute part: the final rounding (one output LSB truncating, half rounding).
    pub abs: f64,
    /// The seed's worst relative error |1 − m·y0| over the table (exact, from the table).
    pub seed_rel: f64,
}

impl ReciprocalErrorBound {
    /// The bound for a result of magnitude `inv_abs` = |1/d|.
    pub fn at(&self, inv_abs: f64) -> f64 {
        self.rel * inv_abs + self.abs
    }
}

/// Upward rounding margin for the f64 arithmetic of the bound (far below any term).
const BOUND_MARGIN: f64 = 1.0 + 1e-12;

/// The error bound of a configuration (derivation in `docs/units/reciprocal.md`):
///
/// ```text
/// R0       = max over table entries and the ends of their mantissa interval of |1 − m·y0|
/// R(i+1)   = R(i)² + 2^(1−G)            (quadratic convergence + two truncations per step)
/// rel      = R(n)·(1 + 2^−G) + 2^−G     (+ truncating the input mantissa to G bits)
/// abs      = 2^−F_out (truncating modes) or 2^−F_out / 2 (round to nearest)
/// ```
///
/// ```
/// use rtl_model::units::reciprocal::{error_bound, ReciprocalConfig};
/// let b = error_bound(&ReciprocalConfig::default());
/// assert!(b.rel < 2f64.powi(-30) && b.abs == 2f64.powi(-31));
/// ```
pub fn error_bound(cfg: &ReciprocalConfig) -> ReciprocalErrorBound {
    let p = plan(cfg);
    let g = p.g;
    // R0 exactly in integers: ε·2^(2G) = 2^(2G) − m·y0 at the interval's ends
    // m ∈ [a_i, b_i − 2^−G] (m is truncated to G bits, and t ≤ G).
    let one = 1i128 << (2 * g);
    let step = 1i128 << (g - p.tb);
    let mut worst = 0i128;
    for idx in 0..1u64 << p.tb {
        let y0 = placed_seed(&p, idx) as i128;
        let lo = ((1i128 << p.tb) + i128::from(idx)) * step;
        let hi = lo + step - 1;
        worst = worst.max((one - lo * y0).abs()).max((one - hi * y0).abs());
    }
    let ulp = 2f64.powi(-(g as i32));
    let seed_rel = worst as f64 * ulp * ulp * BOUND_MARGIN;
    let mut r = seed_rel;
    for _ in 0..p.iters {
        r = (r * r + 2.0 * ulp) * BOUND_MARGIN;
    }
    let rel = (r * (1.0 + ulp) + ulp) * BOUND_MARGIN;
    let abs = match cfg.output.quant {
        Quant::Trn | Quant::TrnZero => cfg.output.lsb(),
        _ => 0.5 * cfg.output.lsb(),
    };
    ReciprocalErrorBound { rel, abs, seed_rel }
}

/// Operand widths (unsigned bits) of the two multiplies of each iteration: p = m·y and
/// y·q. The first iteration's y is the seed, with only t + 2 significant bits.
fn multiplies(p: &Plan) -> Vec<(u32, u32)> {
    let full = p.g + 1;
    let seed = (p.tb + 2).min(full);
    (0..p.iters)
        .flat_map(|i| {
            let y = if i == 0 { seed } else { full };
            [(full, y), (y, full)]
        })
        .collect()
}

/// Operand widths (unsigned bits) of every multiply of the unit, two per iteration in
/// order: m·y and y·q, the first iteration's y the seed (t + 2 bits). `sim sweep` prints the
/// widest.
pub fn multiplier_widths(cfg: &ReciprocalConfig) -> Vec<(u32, u32)> {
    multiplies(&plan(cfg))
}

/// An unsigned operand of `bits` bits (the mantissas are unsigned).
fn mantissa(bits: u32) -> Format {
    Format::uq(bits.min(64) as u8, 0)
}

fn dsp_for(a_bits: u32, b_bits: u32) -> u32 {
    dsp48e2_per_product(mantissa(a_bits), mantissa(b_bits))
}

/// DSP48E2 slices of one reciprocal unit: the sum over every multiply of its 27×18 tiles
/// (unsigned operands: 26 × 17 value bits per slice). 12 for the default (4 for the first
/// iteration, whose seed operand is 10 bits, and 8 for the second, 33 × 33 bits).
pub fn dsp48e2_count(cfg: &ReciprocalConfig) -> u32 {
    multiplies(&plan(cfg))
        .iter()
        .map(|&(a, b)| dsp_for(a, b))
        .sum()
}

/// Pipeline latency in cycles at one result per cycle: sign/magnitude and zero compare (1),
/// leading-zero count (1), normalising shift (1), ROM read (1); per iteration two multiplies
/// (3 cycles in the DSP, +1 to add partial products when a multiply spans several slices)
/// and the subtraction 2 − p (1); then the sign ±y (1), the denormalising shift with the
/// rounding decision (1), the rounding increment (1) and saturation (1). Each of those is a
/// stage of its own so that every stage of `svo_reciprocal.v` meets the clock rule at
/// 300 MHz (`cost::timing`, docs/cycle-model.md §1.5). 26 for the default.
pub fn latency_cycles(cfg: &ReciprocalConfig) -> u32 {
    let p = plan(cfg);
    let muls: u32 = multiplies(&p)
        .iter()
        .map(|&(a, b)| product_latency_cycles(mantissa(a), mantissa(b)))
        .sum();
    4 + muls + p.iters + 4
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_entries_lie_in_half_open_unit_interval() {
        for tb in 0..=12u8 {
            let tf = seed_frac_bits(tb);
            for (i, &y) in seed_table(tb).iter().enumerate() {
                assert!(
                    y >= 1 << (tf - 1) && y < 1 << tf,
                    "t = {tb}, entry {i} = {y}"
                );
            }
        }
    }

    #[test]
    fn default_costs() {
        let cfg = ReciprocalConfig::default();
        cfg.validate().unwrap();
        assert_eq!(mantissa_frac_bits(&cfg), 32);
        assert_eq!(dsp48e2_count(&cfg), 12);
        assert_eq!(latency_cycles(&cfg), 26);
        assert_eq!(zero_threshold(&cfg), 2f64.powi(-21));
    }
}
