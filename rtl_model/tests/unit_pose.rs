//! Pose-path units against f64: the CORDIC sine/cosine, keyframe angle interpolation, the
//! Euler-angle matrix, the matrix product and the Newton–Schulz re-orthonormalisation, each
//! within its named bound. The oracles are f64 maths written here (sin/cos from std, rotation
//! matrices multiplied out, quaternion rotations) and share no code with the units. A third
//! of the angles sit on adversarial points: quadrant and octant boundaries, ±½ turn, 0.

mod common;
use common::Rng;
use rtl_model::fixed::{from_f64, to_f64, Format, Overflows, SignalId};
use rtl_model::units::cordic::{error_bound, Cordic, CordicConfig};
use rtl_model::units::keyframe::{
    angle_at, angle_error_bound, euler_matrix, matrix_error_bound, KeyframeConfig, Segment,
};
use rtl_model::units::rotation::{
    incremental_pose_error_bound, mul, orthonormalise, orthonormality_error,
    reorthonormalised_bound, steady_state_orthonormality_bound, MatRaw, RotationConfig,
    RotationSignals,
};
use std::f64::consts::TAU;

fn seed() -> u64 {
    common::seed(0x905e_2019)
}

fn unit(rng: &mut Rng) -> f64 {
    (rng.next() >> 11) as f64 / (1u64 << 53) as f64
}

/// A binary angle code (sQ0.32 turns), a third of them adversarial.
fn angle_code(rng: &mut Rng) -> i64 {
    if rng.below(3) == 0 {
        let special = [
            0i64,
            1 << 29,
            1 << 30,
            3 << 29,
            i32::MIN as i64,
            -(1 << 30),
            -(1 << 29),
        ];
        let base = special[rng.below(special.len() as u64) as usize];
        i64::from((base + rng.below(5) as i64 - 2) as i32)
    } else {
        i64::from(rng.next() as i32)
    }
}

#[test]
fn cordic_within_bound() {
    let seed = seed();
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    let cfg = CordicConfig::default();
    cfg.validate().unwrap();
    let c = Cordic::new(&cfg);
    let b = error_bound(&cfg);
    let s = 2f64.powi(-i32::from(cfg.work_frac));
    let mut worst = 0f64;
    for _ in 0..300_000 {
        let a = angle_code(&mut rng);
        let theta = a as f64 * 2f64.powi(-32) * TAU;
        let (cs, sn) = c.sin_cos(a);
        let e = (cs as f64 * s - theta.cos())
            .abs()
            .max((sn as f64 * s - theta.sin()).abs());
        worst = worst.max(e);
        assert!(e <= b, "angle code {a}: error {e:e} > bound {b:e}");
    }
    println!("CORDIC: worst {worst:.3e}, bound {b:.3e}");
}

/// Rz(γ)·Ry(β)·Rx(α) multiplied out in f64, as rows.
fn euler_f64(a: [f64; 3]) -> [[f64; 3]; 3] {
    let rx = |t: f64| {
        [
            [1.0, 0.0, 0.0],
            [0.0, t.cos(), -t.sin()],
            [0.0, t.sin(), t.cos()],
        ]
    };
    let ry = |t: f64| {
        [
            [t.cos(), 0.0, t.sin()],
            [0.0, 1.0, 0.0],
            [-t.sin(), 0.0, t.cos()],
        ]
    };
    let rz = |t: f64| {
        [
            [t.cos(), -t.sin(), 0.0],
            [t.sin(), t.cos(), 0.0],
            [0.0, 0.0, 1.0],
        ]
    };
    let m = |p: [[f64; 3]; 3], q: [[f64; 3]; 3]| {
        let mut r = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = (0..3).map(|k| p[i][k] * q[k][j]).sum();
            }
        }
        r
    };
    m(m(rz(a[2]), ry(a[1])), rx(a[0]))
}

#[test]
fn keyframe_angles_and_matrices_within_bounds() {
    let seed = seed() ^ 1;
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    let cfg = KeyframeConfig::default();
    cfg.validate().unwrap();
    let cordic = Cordic::new(&cfg.cordic);
    let mut ov = Overflows::new(&["host", "mat"]);
    let (host, msig) = (SignalId(0), SignalId(1));
    let b_mat = matrix_error_bound(&cfg, 0.0);
    let mut worst = 0f64;
    for _ in 0..20_000 {
        let codes = [0, 1, 2].map(|_| angle_code(&mut rng));
        let m = euler_matrix(codes, &cordic, &cfg, &mut ov, msig);
        let exact = euler_f64(codes.map(|c| c as f64 * 2f64.powi(-32) * TAU));
        for (c, col) in m.iter().enumerate() {
            for (r, &v) in col.iter().enumerate() {
                let e = (to_f64(v, cfg.mat) - exact[r][c]).abs();
                worst = worst.max(e);
                assert!(
                    e <= b_mat,
                    "angles {codes:?} entry ({r},{c}): {e:e} > {b_mat:e}"
                );
            }
        }
    }
    println!("Euler matrix: worst {worst:.3e}, bound {b_mat:.3e}");
    // Interpolated angles: exact value of base + step·k (f64 is exact enough: 2^-60 turn).
    let (k_max, step_max) = (1e6, 0.49);
    let b_ang = angle_error_bound(&cfg, k_max, step_max, true);
    for _ in 0..20_000 {
        let base_t = unit(&mut rng) - 0.5;
        let step_t = (unit(&mut rng) - 0.5) * 2.0 * step_max;
        let k = (unit(&mut rng) * k_max).floor();
        let s = Segment {
            base: from_f64(base_t, cfg.angle_base, &mut ov, host),
            step: from_f64(step_t, cfg.angle_step, &mut ov, host),
        };
        let kc = from_f64(k, cfg.frame, &mut ov, host);
        let a = angle_at(&s, kc, &cfg) as f64 * 2f64.powi(-32);
        let want = base_t + step_t * k;
        let d = (a - want) - (a - want).round(); // modulo one turn
        assert!(
            d.abs() * TAU <= b_ang,
            "base {base_t} step {step_t} k {k}: {d:e} turn"
        );
    }
    assert_eq!(ov.total(), 0);
}

/// The rotation of a unit quaternion, by columns.
fn quat_columns(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    let rows = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    [0, 1, 2].map(|c| [rows[0][c], rows[1][c], rows[2][c]])
}

fn random_quat(rng: &mut Rng, max_angle: f64) -> [f64; 4] {
    let axis = loop {
        let v = [0, 1, 2].map(|_| unit(rng) * 2.0 - 1.0);
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.1 && l <= 1.0 {
            break v.map(|c| c / l);
        }
    };
    let h = 0.5 * max_angle * unit(rng);
    [
        h.cos(),
        axis[0] * h.sin(),
        axis[1] * h.sin(),
        axis[2] * h.sin(),
    ]
}

fn f64_mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|j| [0, 1, 2].map(|i| (0..3).map(|k| a[k][i] * b[j][k]).sum()))
}

#[test]
fn incremental_rotation_stays_orthonormal_with_the_correction_and_drifts_without() {
    let seed = seed() ^ 2;
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    let cfg = RotationConfig::default();
    cfg.validate().unwrap();
    let mut ov = Overflows::new(&["mat", "corr"]);
    let sig = RotationSignals {
        mat: SignalId(0),
        corr: SignalId(1),
    };
    let q = |m: &[[f64; 3]; 3], f: Format, ov: &mut Overflows| -> MatRaw {
        m.map(|c| c.map(|v| from_f64(v, f, ov, SignalId(0))))
    };
    let steady = steady_state_orthonormality_bound(&cfg);
    let frames = 3000u64;
    let mut drift_ratio = f64::INFINITY;
    for trial in 0..4 {
        let r0 = quat_columns(random_quat(&mut rng, std::f64::consts::PI));
        let dr = quat_columns(random_quat(&mut rng, 0.2));
        let dq = q(&dr, cfg.delta, &mut ov);
        let (mut with, mut without) = (q(&r0, cfg.acc, &mut ov), q(&r0, cfg.acc, &mut ov));
        let mut exact = r0;
        let mut worst = 0f64;
        for n in 1..=frames {
            with = mul(&with, cfg.acc, &dq, cfg.delta, cfg.acc, &mut ov, sig.mat);
            with = orthonormalise(&with, &cfg, &mut ov, sig);
            without = mul(&without, cfg.acc, &dq, cfg.delta, cfg.acc, &mut ov, sig.mat);
            exact = f64_mul(&exact, &dr);
            let e = orthonormality_error(&with, cfg.acc);
            worst = worst.max(e);
            assert!(e <= steady, "trial {trial} frame {n}: {e:e} > {steady:e}");
            let pose = (0..9)
                .map(|i| (to_f64(with[i / 3][i % 3], cfg.acc) - exact[i / 3][i % 3]).abs())
                .fold(0.0, f64::max);
            let pb = incremental_pose_error_bound(&cfg, n);
            assert!(
                pose <= pb,
                "trial {trial} frame {n}: pose {pose:e} > {pb:e}"
            );
        }
        let drift = orthonormality_error(&without, cfg.acc);
        println!(
            "trial {trial}: with correction worst {worst:.3e} (bound {steady:.3e}); without, after {frames} frames {drift:.3e}"
        );
        drift_ratio = drift_ratio.min(drift / steady);
    }
    assert_eq!(ov.total(), 0);
    assert!(
        drift_ratio > 10.0,
        "without the correction the error should leave the bound far behind: {drift_ratio}"
    );
}

#[test]
fn one_step_squares_a_perturbation() {
    let seed = seed() ^ 3;
    println!("seed = {seed} (SVO_TEST_SEED replays)");
    let mut rng = Rng::new(seed);
    let cfg = RotationConfig::default();
    let mut ov = Overflows::new(&["mat", "corr"]);
    let sig = RotationSignals {
        mat: SignalId(0),
        corr: SignalId(1),
    };
    for _ in 0..20_000 {
        let r = quat_columns(random_quat(&mut rng, std::f64::consts::PI));
        let scale = 10f64.powf(-9.0 + 3.0 * unit(&mut rng));
        let m: MatRaw = r.map(|c| {
            c.map(|v| {
                from_f64(
                    v + scale * (unit(&mut rng) - 0.5),
                    cfg.acc,
                    &mut ov,
                    sig.mat,
                )
            })
        });
        let e_in = orthonormality_error(&m, cfg.acc);
        let out = orthonormalise(&m, &cfg, &mut ov, sig);
        let e_out = orthonormality_error(&out, cfg.acc);
        assert!(
            e_out <= reorthonormalised_bound(&cfg, e_in),
            "in {e_in:e} out {e_out:e}"
        );
    }
    assert_eq!(ov.total(), 0);
}
