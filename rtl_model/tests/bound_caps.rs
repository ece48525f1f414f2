//! Every error-bound function of the default datapath against a value derived by hand from
//! the default formats (issue 14 part 4): the bound functions are the numbers the accuracy
//! tests judge against, so a slip in one (a lost term, a wrong LSB) would loosen or break
//! every test that trusts it. Each case gives its derivation from the formats in
//! `docs/number-formats.md` (LSBs written as powers of two here, not read from the code) and
//! requires the function to agree with the hand value to 0.5 % — a cap above and a floor
//! below. A deliberate change of a default format fails here first: re-derive, then update.
//! The square root, transform and reciprocal bounds of the two non-default datapaths of the
//! unit tests' tightness checks (`datapaths/mod.rs`: narrow, truncating) are pinned the same way.

mod datapaths;

use rtl_model::cost::direction_error_bound;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::cordic::{self, CordicConfig};
use rtl_model::units::keyframe::{angle_error_bound, matrix_error_bound, KeyframeConfig};
use rtl_model::units::rotation::{
    composed_bound, incremental_pose_error_bound, reorthonormalised_bound,
    steady_state_orthonormality_bound, RotationConfig,
};
use rtl_model::units::{hit_record, raygen, reciprocal, sqrt, transform, walker};

fn p2(e: i32) -> f64 {
    2f64.powi(e)
}

/// The bound agrees with the hand value within 0.5 % (and both are positive).
fn agrees(what: &str, bound: f64, hand: f64) {
    println!("{what:<34} bound {bound:.4e}   by hand {hand:.4e}");
    assert!(hand > 0.0 && bound > 0.0, "{what}: {bound:e}");
    assert!(
        (bound - hand).abs() <= 0.005 * hand,
        "{what}: the bound function gives {bound:e}, the hand derivation {hand:e}"
    );
}

#[test]
fn leaf_unit_bounds_match_the_hand_derivation() {
    let dp = DatapathConfig::default();
    // Square root uQ16.48 → uQ8.24, truncated: below one output LSB.
    agrees(
        "sqrt",
        sqrt::error_bound(&sqrt::SqrtConfig::default()),
        p2(-24),
    );
    // Ray generation: directions sQ2.30 rounded to nearest: half an LSB.
    agrees("raygen direction", raygen::error_bound(&dp.raygen), p2(-31));
    // Hit record: t uQ8.14 truncated: one LSB.
    agrees(
        "hit record t",
        hit_record::t_error_bound(&dp.hit_record),
        p2(-14),
    );
    // Octahedral normal, 8 bits: s = 127, h = 1/(2s); 2·asin(3h/√2) = 2·asin(0.0083517).
    agrees(
        "hit record normal (rad)",
        hit_record::normal_error_bound_rad(8),
        2.0 * (3.0 / 254.0 / 2f64.sqrt()).asin(),
    );
}

#[test]
fn transform_and_reciprocal_bounds_match_the_hand_derivation() {
    let dp = DatapathConfig::default();
    // Transform origin, |o − c| ≤ 128 m per component: e_m = 2^−31 (sQ2.30 nearest),
    // e_p = 2^−33 (sQ8.32 nearest), output sQ8.32 nearest:
    // 3·(e_m·128 + (1 + e_m)·2·e_p) + 2^−33 = 3·(5.9605e-8 + 2.328e-10) + 1.164e-10 = 1.7963e-7.
    let em = p2(-31);
    agrees(
        "transform origin (128 m)",
        transform::origin_error_bound(&dp.transform, 128.0),
        3.0 * (em * 128.0 + (1.0 + em) * 2.0 * p2(-33)) + p2(-33),
    );
    // Transform direction: 3·(e_m + (1 + e_m)·e_d) + e_out with e_d = e_out = 2^−31: ≈ 7·2^−31.
    agrees(
        "transform direction",
        transform::dir_error_bound(&dp.transform),
        7.0 * p2(-31),
    );
    // Reciprocal sQ2.30 → sQ22.30, t = 8, two iterations, G = 32 mantissa fraction bits.
    // R0 = 2.37·10⁻³ (docs/units/reciprocal.md §6, the worst interval end of the ROM);
    // R1 = R0² + 2^−31 = 5.617e-6; R2 = R1² + 2^−31 = 4.973e-10; rel = R2·(1 + 2^−32) + 2^−32
    // = 7.301e-10. abs: half an LSB of sQ22.30 = 2^−31. Zero threshold: k = 52 − 30 − 1 = 21
    // magnitude bits, |d| ≤ 2^−21.
    let b = reciprocal::error_bound(&dp.reciprocal);
    let r1 = 2.37e-3f64.powi(2) + p2(-31);
    let r2 = r1 * r1 + p2(-31);
    agrees("reciprocal relative", b.rel, r2 * (1.0 + p2(-32)) + p2(-32));
    agrees("reciprocal absolute", b.abs, p2(-31));
    agrees(
        "reciprocal zero threshold",
        reciprocal::zero_threshold(&dp.reciprocal),
        p2(-21),
    );
    // The direction error any ray's walk follows: transform + reciprocal relative + the zero
    // threshold (a flushed component tilts the ray by up to 2^−21).
    agrees(
        "direction (any ray)",
        direction_error_bound(&dp),
        7.0 * p2(-31) + 7.301e-10 + p2(-21),
    );
}

#[test]
fn sphere_bounds_match_the_hand_derivation() {
    let s = DatapathConfig::default().sphere;
    // reach 128 m; e_d = 2^−31, e_p = 2^−33; t_ca sQ10.24 truncated: lsb 2^−24; squares
    // uQ16.48: lsb 2^−48; entry uQ10.22: lsb 2^−22.
    // Δt = 128·√3·2^−31 + 2√3·2^−33 + 2^−24 = 1.0326e-7 + 4.03e-10 + 5.960e-8 = 1.6326e-7
    // Δl² = 2·128·(2√3·2^−33) + (2√3·2^−33)² = 1.0319e-7
    // W = Δl² + 2·128·Δt + Δt² + 2·2^−48 = 4.1898e-5 m²
    let s3 = 3f64.sqrt();
    let dt = 128.0 * s3 * p2(-31) + 2.0 * s3 * p2(-33) + p2(-24);
    let dl = 2.0 * s3 * p2(-33);
    let w = 2.0 * 128.0 * dl + dl * dl + 2.0 * 128.0 * dt + dt * dt + 2.0 * p2(-48);
    agrees("sphere widening W (m²)", s.widening(), w);
    // Entry earlier by at most 2Δt + √(2W) + √(2^−48) + 2·2^−22 = 9.155e-3 m.
    agrees(
        "sphere entry (m)",
        s.t_enter_error_bound(1.0),
        2.0 * dt + (2.0 * w).sqrt() + p2(-24) + 2.0 * p2(-22),
    );
}

#[test]
fn walker_bounds_match_the_hand_derivation() {
    let dp = DatapathConfig::default();
    // The walker's t is sQ31.31 truncated (docs/number-formats.md): lsb 2^−31.
    // Spatial, 20 m reach, depth 11, with the transform origin bound at 20 m
    // (3·(2^−31·20 + 2·2^−33) + 2^−33 = 2.8756e-8) and the direction bound above:
    // origin + 20·dir + 2^−31·(2 + 11).
    let origin = 3.0 * (p2(-31) * 20.0 + 2.0 * p2(-33)) + p2(-33);
    let dir = 7.0 * p2(-31) + 7.301e-10 + p2(-21);
    let spatial = walker::spatial_error_bound(&dp.walker, origin, dir, 20.0, 11);
    agrees(
        "walker spatial (20 m, depth 11)",
        spatial,
        origin + 20.0 * dir + 13.0 * p2(-31),
    );
    // A voxel of the 4.2 m car at depth 11 is 2 mm: the bound must stay far inside it.
    assert!(spatial < 2e-3 / 100.0, "spatial bound {spatial:e} m");
    // t of a leaf at depth 11, 1/|d| ≤ 2^21 (the zero threshold), reach 20 m, 1/d error
    // 2^−31 absolute + 7.3e-10 relative at 2^21: origin·2^21 + 20·inv_err + 2^−31·12.
    let inv_err = 7.301e-10 * p2(21) + p2(-31);
    agrees(
        "walker t (depth 11)",
        walker::t_error_bound(&dp.walker, origin, inv_err, p2(21), 20.0, 11),
        origin * p2(21) + 20.0 * inv_err + 12.0 * p2(-31),
    );
}

#[test]
fn pose_bounds_match_the_hand_derivation() {
    // CORDIC, 36 iterations, work 40 and angle 44 fraction bits, K = 1.6467602581:
    // angle residual atan(2^−35) + 2π·36·½·2^−44 = 2.9104e-11 + 6.4296e-12; floors
    // 36·√2·K·2^−40 = 7.6233e-11; start K·½·2^−40 = 7.489e-13; total 1.1252e-10.
    let k = 1.646_760_258_1_f64;
    let e_c = p2(-35).atan()
        + 2.0 * std::f64::consts::PI * 36.0 * 0.5 * p2(-44)
        + 36.0 * 2f64.sqrt() * k * p2(-40)
        + k * 0.5 * p2(-40);
    agrees(
        "CORDIC sin/cos",
        cordic::error_bound(&CordicConfig::default()),
        e_c,
    );
    // Euler matrix entries from exact angles: 6·e_c·(1 + e_c)² + output sQ2.30 nearest 2^−31.
    agrees(
        "keyframe matrix entry",
        matrix_error_bound(&KeyframeConfig::default(), 0.0),
        6.0 * e_c + p2(-31),
    );
}

#[test]
fn animation_bounds_match_the_hand_derivation() {
    let tau = std::f64::consts::TAU;
    let k = KeyframeConfig::default();
    // Interpolated angle (turns → radians): base sQ0.48 and step sQ16.48 rounded to nearest
    // (2^−49 each), the output angle code with 32 fraction bits of a turn (2^−33); integer
    // keys make k exact. 1,000 frames: τ·(2^−49 + 1000·2^−49 + 2^−33) = 7.426e-10 rad.
    agrees(
        "keyframe angle (1000 frames)",
        angle_error_bound(&k, 1000.0, 0.01, true),
        tau * (1001.0 * p2(-49) + p2(-33)),
    );
    // A fractional key adds k's quantisation (uQ24.8 nearest, 2^−9) times |step| (0.01 turn).
    agrees(
        "keyframe angle (k inexact)",
        angle_error_bound(&k, 1000.0, 0.01, false),
        tau * (1001.0 * p2(-49) + 0.01 * p2(-9) + p2(-33)),
    );
    // Incremental rotation, ΔR and R in sQ2.30 nearest (e = 2^−31), C with 60 fraction bits
    // (2^−61, negligible here). Rounding a rotation: η = 2√3·e + 3e² = 1.6133e-9.
    let r = RotationConfig::default();
    let e = p2(-31);
    let eta = 2.0 * 3f64.sqrt() * e + 3.0 * e * e;
    // R·ΔR from an exact R: η (ΔR) + 0 + η (the product's rounding) = 2η.
    agrees(
        "rotation composed (exact R)",
        composed_bound(&r, 0.0),
        2.0 * eta,
    );
    // One Newton–Schulz step from 2·10⁻⁶: ¾(3·2·10⁻⁶)² = 2.7e-11 left, plus η.
    agrees(
        "rotation re-orthonormalised",
        reorthonormalised_bound(&r, 2e-6),
        eta + 0.75 * (6e-6f64).powi(2),
    );
    // The steady state: composing takes η to 5η = 8.07e-9, one step squares that away
    // (¾(3·5η)² ≈ 4e-16) and leaves η: the fixed point is η to 0.5 %.
    let steady = steady_state_orthonormality_bound(&r);
    agrees("rotation steady state", steady, eta);
    // Pose error after n frames: per frame δ = 3e + 6e + 4.5·(5η) = 4.049e-8, carried by
    // (1 + η)^n: at 1,000 frames (1 + η)^1000·(3e + 1000·δ) = 4.049e-5.
    let delta = 9.0 * e + 4.5 * 5.0 * eta;
    agrees(
        "rotation pose (1000 frames)",
        incremental_pose_error_bound(&r, 1000),
        (1.0 + eta).powi(1000) * (3.0 * e + 1000.0 * delta),
    );
}

/// The sphere's bounds by hand for reach 128 m, from the conversion errors e_d (directions)
/// and e_p (positions) and the LSBs of t_ca, the squares and the entry (as the default's
/// derivation in `sphere_bounds_match_the_hand_derivation`): (W, entry error).
fn sphere_by_hand(e_d: f64, e_p: f64, tca: f64, sq: f64, entry: f64) -> (f64, f64) {
    let s3 = 3f64.sqrt();
    let dt = 128.0 * s3 * e_d + 2.0 * s3 * e_p + tca;
    let dl = 2.0 * s3 * e_p;
    let w = 2.0 * 128.0 * dl + dl * dl + 2.0 * 128.0 * dt + dt * dt + 2.0 * sq;
    (w, 2.0 * dt + (2.0 * w).sqrt() + sq.sqrt() + 2.0 * entry)
}

/// The narrow datapath (`datapaths/mod.rs`): sQ2.22 directions and matrix entries, sQ8.24
/// positions, all rounded to nearest; squares uQ16.40; 1/d sQ2.22 → sQ22.22.
#[test]
fn narrow_datapath_bounds_match_the_hand_derivation() {
    let [(_, dp), _] = datapaths::non_default();
    // Sphere: e_d = 2^−23, e_p = 2^−25 (nearest); t_ca sQ10.24 truncated 2^−24, squares
    // uQ16.40 2^−40, entry uQ10.22 2^−22.
    let (w, entry) = sphere_by_hand(p2(-23), p2(-25), p2(-24), p2(-40), p2(-22));
    agrees("narrow sphere widening W (m²)", dp.sphere.widening(), w);
    agrees(
        "narrow sphere entry (m)",
        dp.sphere.t_enter_error_bound(1.0),
        entry,
    );
    // Square root uQ16.40 → uQ8.20, truncated (sphere::sqrt_config): one output LSB.
    agrees(
        "narrow sqrt",
        sqrt::error_bound(&rtl_model::units::sphere::sqrt_config(&dp.sphere)),
        p2(-20),
    );
    // Transform origin, 128 m: e_m = 2^−23 (sQ2.22 nearest), e_p = 2^−25 (sQ8.24 nearest),
    // output sQ8.24 nearest 2^−25: 3·(2^−23·128 + (1 + 2^−23)·2·2^−25) + 2^−25 = 4.5985e-5.
    let em = p2(-23);
    agrees(
        "narrow transform origin (128 m)",
        transform::origin_error_bound(&dp.transform, 128.0),
        3.0 * (em * 128.0 + (1.0 + em) * 2.0 * p2(-25)) + p2(-25),
    );
    // Transform direction: 3·(e_m + (1 + e_m)·e_d) + e_out, e_d = e_out = 2^−23: ≈ 7·2^−23.
    agrees(
        "narrow transform direction",
        transform::dir_error_bound(&dp.transform),
        7.0 * p2(-23),
    );
    // Reciprocal sQ2.22 → sQ22.22, t = 8, two iterations, G = F_out + 2 = 24:
    // R0 = 2.373·10⁻³ (the ROM's worst interval end, as the default's); R1 = R0² + 2·2^−24
    // = 5.751e-6; R2 = R1² + 2^−23 = 1.1924e-7; rel = R2·(1 + 2^−24) + 2^−24 = 1.7884e-7.
    // abs: half an LSB of sQ22.22 = 2^−23. Zero threshold: 44 − 22 − 1 = 21 magnitude bits.
    let b = reciprocal::error_bound(&dp.reciprocal);
    let r1 = 2.373e-3f64.powi(2) + p2(-23);
    let r2 = r1 * r1 + p2(-23);
    agrees(
        "narrow reciprocal relative",
        b.rel,
        r2 * (1.0 + p2(-24)) + p2(-24),
    );
    agrees("narrow reciprocal absolute", b.abs, p2(-23));
    agrees(
        "narrow reciprocal zero threshold",
        reciprocal::zero_threshold(&dp.reciprocal),
        p2(-21),
    );
}

/// The truncating datapath (`datapaths/mod.rs`): the default widths, every rounding a
/// truncation (a whole LSB where rounding to nearest loses half); squares uQ20.44.
#[test]
fn truncating_datapath_bounds_match_the_hand_derivation() {
    let [_, (_, dp)] = datapaths::non_default();
    // Sphere: e_d = 2^−30, e_p = 2^−32 (truncated: a whole LSB); t_ca 2^−24, squares uQ20.44
    // 2^−44, entry 2^−22.
    let (w, entry) = sphere_by_hand(p2(-30), p2(-32), p2(-24), p2(-44), p2(-22));
    agrees("truncating sphere widening W (m²)", dp.sphere.widening(), w);
    agrees(
        "truncating sphere entry (m)",
        dp.sphere.t_enter_error_bound(1.0),
        entry,
    );
    // Square root uQ20.44 → uQ10.22, truncated: one output LSB.
    agrees(
        "truncating sqrt",
        sqrt::error_bound(&rtl_model::units::sphere::sqrt_config(&dp.sphere)),
        p2(-22),
    );
    // Transform origin, 128 m: e_m = 2^−30 (sQ2.30 truncated), e_p = 2^−32 (sQ8.32
    // truncated), output 2^−32: 3·(2^−30·128 + (1 + 2^−30)·2·2^−32) + 2^−32 = 3.5926e-7.
    let em = p2(-30);
    agrees(
        "truncating transform origin (128 m)",
        transform::origin_error_bound(&dp.transform, 128.0),
        3.0 * (em * 128.0 + (1.0 + em) * 2.0 * p2(-32)) + p2(-32),
    );
    // Transform direction: e_d = e_out = 2^−30: ≈ 7·2^−30.
    agrees(
        "truncating transform direction",
        transform::dir_error_bound(&dp.transform),
        7.0 * p2(-30),
    );
    // Reciprocal sQ2.30 → sQ22.30 truncated: the iterations as the default's (G = 32,
    // rel = 7.301e-10), abs one whole LSB 2^−30, zero threshold 2^−21.
    let b = reciprocal::error_bound(&dp.reciprocal);
    let r1 = 2.37e-3f64.powi(2) + p2(-31);
    let r2 = r1 * r1 + p2(-31);
    agrees(
        "truncating reciprocal relative",
        b.rel,
        r2 * (1.0 + p2(-32)) + p2(-32),
    );
    agrees("truncating reciprocal absolute", b.abs, p2(-30));
    agrees(
        "truncating reciprocal zero threshold",
        reciprocal::zero_threshold(&dp.reciprocal),
        p2(-21),
    );
}
