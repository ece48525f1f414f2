//! Bounding-sphere test unit (paper Eq. 4) in fixed point, conservative by construction.
//!
//! Pipeline position: after ray generation, once per (ray, instance), in world space; its
//! entry distance is the sorter's key. With l = c − o and unit d the exact test rejects iff
//! p² = l·l − (l·d)² > r². This unit may keep a sphere the exact test rejects, never the
//! reverse, and its entry distance is never later than the exact one, so early termination
//! stays exact:
//!
//! - l = c − o is exact; t_ca = l·d is summed exactly and rounded down once into `tca`;
//!   l·l is exact; p² = l·l − t_ca² uses the rounded t_ca.
//! - The inputs o, c, d are quantised (errors e_p per position component, e_d per direction
//!   component, so |Δl| ≤ 2√3·e_p, |Δd| ≤ √3·e_d and |d| is not exactly 1). For |l| ≤
//!   `reach`, t_ca moves by at most Δt = reach·√3·e_d + 2√3·e_p + lsb_tca, l·l by at most
//!   Δl² = 2·reach·2√3·e_p + (2√3·e_p)², so p² = l·l − t_ca² by at most
//!   W = Δl² + 2·reach·Δt + Δt² + 2·lsb_sq ([`SphereConfig::widening`]). The host programs
//!   each instance's threshold as T = r² + W ([`SphereConfig::threshold`]); the unit rejects
//!   iff p² > T. A ray with |l| > reach is outside the analysis: it is kept (entry 0) and
//!   counted on the `reach` signal, never silently wrong. The guard compares the length
//!   (exact l·l against reach², a comparator on a product the unit forms anyway), not the
//!   components: along a diagonal every |l_k| can be within the reach while |l| is up to √3
//!   times it, where W is too small and an exact hit could be rejected (found by
//!   `sim stress`, case `far_diagonal`; regression test in `rtl_model/tests/unit_sphere.rs`).
//! - Entry: t_enter = max(0, t_ca − Δt − √(T − p²)), the square root by the digit-recurrence
//!   unit (floor), all rounded toward −∞; 0 when the origin may be inside (l·l ≤ r² + Δl²).
//!   Culled as behind only if even t_ca + Δt + √(T − p²) < 0.

use crate::fixed::{quantize, Format, Overflows, Quant, SignalId};
use crate::units::sqrt::isqrt_fast as isqrt;
use serde::{Deserialize, Serialize};

/// Formats of the sphere unit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereConfig {
    /// World positions in (ray origin, sphere centre).
    pub pos: Format,
    /// Direction components in.
    pub dir: Format,
    /// t_ca = l·d, rounded down.
    pub tca: Format,
    /// Squared distances (p², threshold T), m²; unsigned, at most 64 bits, even fraction bits.
    pub sq: Format,
    /// Entry distance out (the sort key), unsigned.
    pub t_enter: Format,
    /// Largest |c − o| the error bound covers (metres).
    pub reach: f64,
}

impl Default for SphereConfig {
    /// sQ8.32 positions, sQ2.30 directions (as the transform unit), t_ca sQ10.24, squares
    /// uQ16.48 (up to 65 536 m²; its square root has 24 fraction bits), sort key uQ10.22.
    /// t_ca only feeds the conservative entry distance (the sort key, 22 fraction bits), so
    /// 24 fraction bits render the same records as 32 and its square t_ca² takes 4 DSP48E2
    /// per lane instead of 6 (`sim sweep`, `docs/accuracy.md` §7).
    fn default() -> Self {
        Self {
            pos: Format::sq(8, 32).with_quant(Quant::RndConv),
            dir: Format::sq(2, 30).with_quant(Quant::RndConv),
            tca: Format::sq(10, 24),
            sq: Format::uq(16, 48),
            t_enter: Format::uq(10, 22),
            reach: 128.0,
        }
    }
}

/// Overflow signals of the unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereSignals {
    /// t_ca out of range.
    pub tca: SignalId,
    /// A square out of range.
    pub sq: SignalId,
    /// Entry distance out of range.
    pub t_enter: SignalId,
    /// |c − o| beyond the configured reach (the sphere is kept, entry 0).
    pub reach: SignalId,
}

/// Result of one test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereHit {
    /// Entry distance in `t_enter` (0 when the origin may be inside).
    pub t_enter: i64,
}

fn conv_err(f: Format) -> f64 {
    match f.quant {
        Quant::Trn | Quant::TrnZero => f.lsb(),
        _ => 0.5 * f.lsb(),
    }
}

impl SphereConfig {
    /// Checks formats: valid, `sq` unsigned, ≤ 64 bits, even fraction count (so its square
    /// root has exactly half), and the exact products within 127 bits.
    pub fn validate(&self) -> Result<(), String> {
        for (name, f) in [
            ("pos", self.pos),
            ("dir", self.dir),
            ("tca", self.tca),
            ("sq", self.sq),
            ("t_enter", self.t_enter),
        ] {
            if !f.is_valid() {
                return Err(format!("sphere.{name}: format {} is not valid", f.name()));
            }
        }
        if self.sq.signed || self.sq.frac % 2 != 0 || self.sq.frac < 0 {
            return Err(format!(
                "sphere.sq: {} must be unsigned with an even, non-negative fraction count",
                self.sq.name()
            ));
        }
        let (lf, tf) = (2 * i32::from(self.pos.frac), 2 * i32::from(self.tca.frac));
        let f2 = lf.max(tf);
        if f2 < i32::from(self.sq.frac) {
            return Err(
                "sphere.sq: its fraction count must not exceed 2·pos.frac or 2·tca.frac".into(),
            );
        }
        let l2_bits = 2 * (i32::from(self.pos.width) + 1) + 2 + (f2 - lf);
        let tca2_bits = 2 * i32::from(self.tca.width) + (f2 - tf);
        let thr_bits = i32::from(self.sq.width) + (f2 - i32::from(self.sq.frac));
        if l2_bits.max(tca2_bits).max(thr_bits) > 125 {
            return Err("sphere: squares exceed the 127-bit accumulator".into());
        }
        if !(self.reach.is_finite() && self.reach > 0.0) {
            return Err("sphere.reach must be positive".into());
        }
        if self.reach * 2f64.powi(i32::from(self.pos.frac)) >= 2f64.powi(62) {
            return Err("sphere.reach: its code in `pos` must stay below 2^62".into());
        }
        Ok(())
    }

    /// Δt: how far input quantisation and rounding can move t_ca (metres).
    pub fn delta_t(&self) -> f64 {
        let s3 = 3f64.sqrt();
        self.reach * s3 * conv_err(self.dir) + 2.0 * s3 * conv_err(self.pos) + self.tca.lsb()
    }

    /// How far they can move l·l (m²).
    pub fn delta_l2(&self) -> f64 {
        let dl = 2.0 * 3f64.sqrt() * conv_err(self.pos);
        2.0 * self.reach * dl + dl * dl
    }

    /// W: how far they can move p² (m²), the threshold's widening.
    pub fn widening(&self) -> f64 {
        let dt = self.delta_t();
        self.delta_l2() + 2.0 * self.reach * dt + dt * dt + 2.0 * self.sq.lsb()
    }

    fn code_up(&self, v: f64) -> i64 {
        let code = (v / self.sq.lsb()).ceil();
        if code >= self.sq.max_raw() as f64 {
            self.sq.max_raw()
        } else {
            code as i64
        }
    }

    /// The threshold T = r² + W of a sphere of radius `r`, as a raw code in `sq` (rounded up).
    pub fn threshold(&self, r: f64) -> i64 {
        self.code_up(r * r + self.widening())
    }

    /// The "origin may be inside" threshold r² + Δl² as a raw code in `sq` (rounded up).
    pub fn inside_threshold(&self, r: f64) -> i64 {
        self.code_up(r * r + self.delta_l2())
    }

    /// Bound on how much earlier than the exact entry distance the unit reports. The computed
    /// p² is at most W below the exact one, so √(T − p_q²) − √(r² − p²) ≤ √(2W) (using
    /// √a − √b ≤ √(a − b)), and t_ca − Δt is at most 2Δt below the exact t_ca:
    /// t_exact − t_enter ≤ 2Δt + √(2W) + √lsb_sq + 2·lsb_out. About 7 mm with the defaults
    /// (reach 128 m): it only makes early termination slightly less eager.
    pub fn t_enter_error_bound(&self, _r: f64) -> f64 {
        2.0 * self.delta_t()
            + (2.0 * self.widening()).sqrt()
            + self.sq.lsb().sqrt()
            + 2.0 * self.t_enter.lsb()
    }
}

/// A sphere as the host programs it per instance and frame.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SphereRaw {
    /// Centre in world space (`pos`).
    pub centre: [i64; 3],
    /// Rejection threshold T = r² + W ([`SphereConfig::threshold`]), in `sq`.
    pub threshold: i64,
    /// "Origin may be inside" threshold ([`SphereConfig::inside_threshold`]), in `sq`.
    pub inside: i64,
    /// Δt as a raw code of `tca`, rounded up (a constant of the configuration).
    pub delta_t: i64,
    /// The reach as a raw code of `pos` (a constant of the configuration).
    pub reach: i64,
    /// Model speed-up, not hardware: the threshold in f64 at l·l's scale, widened by a
    /// millionth, for the pre-rejection in [`sphere_test`].
    pub reject_above: f64,
    /// 2^−dir.frac, to scale l·d to l's units in that pre-rejection.
    pub dir_scale: f64,
}

impl SphereRaw {
    /// The sphere of radius `r` around `centre` (already in `pos`).
    pub fn new(centre: [i64; 3], r: f64, cfg: &SphereConfig) -> Self {
        Self {
            centre,
            threshold: cfg.threshold(r),
            inside: cfg.inside_threshold(r),
            delta_t: (cfg.delta_t() * 2f64.powi(i32::from(cfg.tca.frac))).ceil() as i64,
            reach: (cfg.reach * 2f64.powi(i32::from(cfg.pos.frac))) as i64,
            reject_above: cfg.threshold(r) as f64
                * 2f64.powi(2 * i32::from(cfg.pos.frac) - i32::from(cfg.sq.frac))
                * (1.0 + 1e-6),
            dir_scale: 2f64.powi(-i32::from(cfg.dir.frac)),
        }
    }
}

/// What the unit has computed when it reaches its square root (the front half of
/// [`sphere_test`]).
enum Front {
    /// |c − o| beyond the reach: kept with entry 0, flagged on `reach`; no root.
    Reach,
    /// p² > T: culled before the root.
    Culled,
    /// The root's radicand and what the entry distance needs besides.
    Root {
        /// T − p² in `sq`, rounded down (the square root's input).
        radicand: u64,
        /// t_ca in `tca`.
        tca: i64,
        /// l·l at the aligned fraction count.
        l2: i128,
        /// Left shift from `sq` to that fraction count.
        up_sq: i32,
    },
}

/// What the unit computes from the ray's origin alone, against one sphere: l = c − o, the
/// reach guards and l·l. Every primary ray of a frame shares the camera's origin, so a caller
/// may compute this once per instance and frame and test each direction against it with
/// [`sphere_test_prepared`] (a model speed-up: the hardware forms these per ray, the results
/// are the same).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereOrigin {
    /// |c − o| beyond the reach (component or length): the test keeps the sphere with entry
    /// 0 and counts it on the `reach` signal, every time.
    beyond_reach: bool,
    /// l = c − o (fits 64 bits when within the reach; zeros otherwise).
    l: [i64; 3],
    /// l·l, exact, with 2·pos.frac fraction bits.
    l2_exact: i128,
    /// The components of l as f64, for the pre-rejection.
    lf: [f64; 3],
    /// l·l in f64 (as the pre-rejection forms it).
    l2_f: f64,
    /// The pre-rejection's bound: the sphere's `reject_above` plus the slack 1e-12·l·l.
    reject_limit: f64,
}

impl SphereOrigin {
    /// The origin-only part of the test of origin `o` against `sphere`.
    #[inline]
    pub fn new(o: [i64; 3], sphere: &SphereRaw) -> Self {
        let c = sphere.centre;
        let l = [0, 1, 2].map(|k| i128::from(c[k]) - i128::from(o[k]));
        let reach = i128::from(sphere.reach);
        let beyond = Self {
            beyond_reach: true,
            l: [0; 3],
            l2_exact: 0,
            lf: [0.0; 3],
            l2_f: 0.0,
            reject_limit: 0.0,
        };
        if l.iter().any(|v| v.abs() > reach) {
            return beyond;
        }
        // Within the reach |l_k| fits 64 bits (reach < 2^63 codes), so every product below is a
        // single 64×64 → 128-bit multiply.
        let l = l.map(|v| v as i64);
        let li = l.map(i128::from);
        // The analysis needs |l| ≤ reach, the length: l·l exact (< 3·2^124 for reach < 2^62
        // codes) against reach², both with 2·pos.frac fraction bits.
        let l2_exact = (li[0] * li[0] + li[1] * li[1]) + li[2] * li[2];
        if l2_exact > reach * reach {
            return beyond;
        }
        let lf = l.map(|v| v as f64); // via i64: i128 → f64 is a slow library call
        let l2_f = lf[0] * lf[0] + lf[1] * lf[1] + lf[2] * lf[2];
        Self {
            beyond_reach: false,
            l,
            l2_exact,
            lf,
            l2_f,
            reject_limit: sphere.reject_above + 1e-12 * l2_f,
        }
    }
}

/// A ray direction as the unit reads it: the codes, and their values in f64 for the
/// pre-rejection, converted once per ray rather than per sphere (a model speed-up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereRay {
    d: [i64; 3],
    df: [f64; 3],
}

impl SphereRay {
    /// The direction with codes `d` (in `dir`).
    #[inline]
    pub fn new(d: [i64; 3]) -> Self {
        Self {
            d,
            df: d.map(|v| v as f64),
        }
    }
}

/// The model's pre-rejection (not hardware): whether the f64 estimate of p² from the same
/// codes exceeds the threshold by more than a millionth plus a slack a thousand times f64's
/// rounding of it (~1e-15·l·l). Only spheres within the reach are estimated.
#[inline(always)]
fn pre_rejects(pre: &SphereOrigin, ray: &SphereRay, sphere: &SphereRaw) -> bool {
    let (lf, df) = (pre.lf, ray.df);
    let tca_f = (lf[0] * df[0] + lf[1] * df[1] + lf[2] * df[2]) * sphere.dir_scale;
    pre.l2_f - tca_f * tca_f > pre.reject_limit
}

/// The unit up to its square root: the reach guards, t_ca, p² and the cull against T, for
/// direction `d` from the origin `pre` was computed for.
#[inline(always)]
fn front(
    pre: &SphereOrigin,
    ray: &SphereRay,
    sphere: &SphereRaw,
    cfg: &SphereConfig,
    ov: &mut Overflows,
    sig: SphereSignals,
) -> Front {
    if pre.beyond_reach {
        ov.hit(sig.reach);
        return Front::Reach;
    }
    let threshold = sphere.threshold;
    let pf = i32::from(cfg.pos.frac);
    let (l, d) = (pre.l.map(i128::from), ray.d);
    let l2_exact = pre.l2_exact;
    // Model speed-up, not hardware: most spheres are far from most rays, and those whose p²
    // clearly exceeds the threshold are rejected from an f64 estimate ([`pre_rejects`]);
    // everything closer takes the exact path below, so every result is the exact path's.
    if pre_rejects(pre, ray, sphere) {
        return Front::Culled;
    }
    // t_ca = l·d, exact then rounded toward −∞ into `tca`.
    let dot: i128 = (l[0] * i128::from(d[0]) + l[1] * i128::from(d[1])) + l[2] * i128::from(d[2]);
    let tca = quantize(
        dot,
        pf + i32::from(cfg.dir.frac),
        cfg.tca.with_quant(Quant::Trn),
        ov,
        sig.tca,
    );
    // l·l (2·pf fraction bits) and t_ca² (2·tca.frac) exact, aligned to the larger fraction
    // count F2 by exact left shifts, so p² = l·l − t_ca² is exact too; the thresholds (in
    // `sq`, F2 ≥ its fraction count by `validate`) are shifted up to meet it.
    let (lf, tf) = (2 * pf, 2 * i32::from(cfg.tca.frac));
    let f2 = lf.max(tf);
    let l2: i128 = l2_exact << (f2 - lf);
    let tca2 = (i128::from(tca) * i128::from(tca)) << (f2 - tf);
    let p2 = l2 - tca2;
    let up_sq = f2 - i32::from(cfg.sq.frac);
    if p2 > i128::from(threshold) << up_sq {
        return Front::Culled;
    }
    // T − p² in `sq` (rounded down): the square root's input.
    let radicand = (((i128::from(threshold) << up_sq) - p2.max(0)) >> up_sq)
        .clamp(0, i128::from(u64::MAX)) as u64;
    Front::Root {
        radicand,
        tca,
        l2,
        up_sq,
    }
}

/// The radicand the unit hands its square root for ray (o, d) against `sphere` (T − p² in
/// `sq`, rounded down), or `None` where it takes no root: |c − o| beyond the reach (kept,
/// entry 0) or p² > T (culled). The same computation as [`sphere_test`], pre-checks
/// included; the vectors capture the square root's real transactions with it.
pub fn sphere_radicand(
    o: [i64; 3],
    d: [i64; 3],
    sphere: &SphereRaw,
    cfg: &SphereConfig,
    ov: &mut Overflows,
    sig: SphereSignals,
) -> Option<u64> {
    match front(
        &SphereOrigin::new(o, sphere),
        &SphereRay::new(d),
        sphere,
        cfg,
        ov,
        sig,
    ) {
        Front::Root { radicand, .. } => Some(radicand),
        Front::Reach | Front::Culled => None,
    }
}

/// The transaction: ray (o, d) against a sphere. `None` culls the instance.
pub fn sphere_test(
    o: [i64; 3],
    d: [i64; 3],
    sphere: &SphereRaw,
    cfg: &SphereConfig,
    ov: &mut Overflows,
    sig: SphereSignals,
) -> Option<SphereHit> {
    sphere_test_prepared(
        &SphereOrigin::new(o, sphere),
        &SphereRay::new(d),
        sphere,
        cfg,
        ov,
        sig,
    )
}

/// [`sphere_test`] of the direction `ray` from the origin `pre` was prepared for (with this
/// `sphere`): the same result and counts. The pre-rejection is inlined into the caller's loop
/// over the spheres; the rest of the unit is not.
#[inline(always)]
pub fn sphere_test_prepared(
    pre: &SphereOrigin,
    ray: &SphereRay,
    sphere: &SphereRaw,
    cfg: &SphereConfig,
    ov: &mut Overflows,
    sig: SphereSignals,
) -> Option<SphereHit> {
    // What `front` would find first for such a sphere (culled, nothing counted).
    if !pre.beyond_reach && pre_rejects(pre, ray, sphere) {
        return None;
    }
    sphere_test_rest(pre, ray, sphere, cfg, ov, sig)
}

/// [`sphere_test_prepared`] past the inlined pre-rejection: the whole unit.
#[inline(never)]
fn sphere_test_rest(
    pre: &SphereOrigin,
    ray: &SphereRay,
    sphere: &SphereRaw,
    cfg: &SphereConfig,
    ov: &mut Overflows,
    sig: SphereSignals,
) -> Option<SphereHit> {
    let (radicand, tca, l2, up_sq) = match front(pre, ray, sphere, cfg, ov, sig) {
        Front::Reach => return Some(SphereHit { t_enter: 0 }),
        Front::Culled => return None,
        Front::Root {
            radicand,
            tca,
            l2,
            up_sq,
        } => (radicand, tca, l2, up_sq),
    };
    // √(T − p²) has half of `sq`'s fraction bits.
    let root = i128::from(isqrt(radicand));
    let rf = i32::from(cfg.sq.frac) / 2;
    let dt = i128::from(sphere.delta_t);
    // Bring t_ca, Δt and the root to a common fraction count (the larger) and combine.
    let f = i32::from(cfg.tca.frac).max(rf);
    let up = |v: i128, from: i32| v << (f - from);
    let tca_f = up(i128::from(tca), i32::from(cfg.tca.frac));
    let dt_f = up(dt, i32::from(cfg.tca.frac));
    let root_f = up(root, rf);
    if tca_f + dt_f + root_f < 0 {
        return None; // the whole sphere is behind the origin, even allowing for errors
    }
    if l2 <= i128::from(sphere.inside) << up_sq {
        return Some(SphereHit { t_enter: 0 });
    }
    let t = (tca_f - dt_f - root_f).max(0);
    Some(SphereHit {
        t_enter: quantize(t, f, cfg.t_enter.with_quant(Quant::Trn), ov, sig.t_enter),
    })
}

/// The products of one sphere lane, by stage: l·d (3 of (pos+1)×dir) and l·l (3 of
/// (pos+1)×(pos+1)) side by side, then t_ca² (1 of tca×tca). l = c − o is the exact
/// difference ([`Format::exact_difference`]).
pub fn products(s: &SphereConfig) -> [crate::fixed::Products; 3] {
    use crate::fixed::Products;
    let l = s.pos.exact_difference();
    [
        Products::new(3, l, s.dir),
        Products::new(3, l, l),
        Products::new(1, s.tca, s.tca),
    ]
}

/// DSP48E2 of one sphere lane: the tiles of its [`products`] (36 by default). The square
/// root ([`sqrt_config`]) uses none.
pub fn dsp48e2_count(s: &SphereConfig) -> u32 {
    products(s).iter().map(|p| p.dsp48e2()).sum()
}

/// Latency of the sphere lane apart from its square root, as stages: l = c − o (1); l·d and
/// l·l in parallel (one product); the two dot sums (p_x + p_y) + p_z (2); rounding t_ca (1);
/// t_ca² (one product); p² = l·l − t_ca² (1); T − max(p², 0) and the cull test (1) — two
/// stages, each one carry chain, so that every stage of `svo_sphere.v` meets the clock rule at
/// 300 MHz (docs/cycle-model.md §1.5); then after the root, t_ca − Δt − √ and the clamp at 0
/// (2). 16 for the default (products of 4 cycles).
pub fn latency_cycles(s: &SphereConfig) -> u32 {
    let [ld, ll, tca2] = products(s);
    let dots = ld.latency_cycles().max(ll.latency_cycles());
    1 + dots + 2 + 1 + tca2.latency_cycles() + 2 + 2
}

/// The square-root unit the sphere test uses: its radicand is the sphere's `sq` format and
/// its root has half the integer and fraction bits, truncated (the sphere unit floors it).
/// Equal to `SqrtConfig::default()` for the default sphere formats (uQ16.48 → uQ8.24).
pub fn sqrt_config(s: &SphereConfig) -> crate::units::sqrt::SqrtConfig {
    let sq = s.sq;
    let int_bits = i32::from(sq.width) - i32::from(sq.frac);
    let out_int = (int_bits.max(0) as u32).div_ceil(2).min(32) as u8;
    let out_frac = (i32::from(sq.frac).max(0) / 2).min(31) as u8;
    crate::units::sqrt::SqrtConfig {
        input: sq,
        output: Format::uq(out_int, out_frac).with_quant(Quant::Trn),
    }
}
