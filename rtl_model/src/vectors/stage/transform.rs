//! Transform vectors: a world ray into an instance's local frame, o' = Rᵀ(o − c), d' = Rᵀd
//! (`units::transform::transform_with_signs`), with the signs of the exact direction sums
//! that carry −0 to the reciprocal unit.
//!
//! Adversarial cases: identity and signed axis permutations with axis-parallel rays, origin
//! at the centre, extreme matrix and position codes (the outputs saturate), exact rounding
//! ties of the round-to-nearest-even outputs (both parities, both signs), direction sums that
//! cancel to exactly zero (+0), and tiny negative sums that round to code 0 (−0: sign set).

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::fixed::{from_f64, Format, Overflows, SignalId};
use crate::units::transform::{
    transform_with_signs, InstanceRaw, TransformConfig, TransformSignals,
};
use crate::vectors::layout::{b, s, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One transaction: world origin and direction, the instance's rotation and centre (codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TransformTxn {
    /// World origin (`pos`).
    pub o: [i64; 3],
    /// World direction (`dir`).
    pub d: [i64; 3],
    /// The instance: columns of its world-from-local rotation (`mat`) and its centre (`pos`).
    pub inst: InstanceRaw,
}

/// The transform stage for a datapath configuration.
pub struct TransformStage {
    cfg: TransformConfig,
    latency: u32,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl TransformStage {
    /// The transform unit of `dp`, with the model's latency.
    pub fn new(dp: &DatapathConfig) -> Self {
        Self {
            cfg: dp.transform,
            latency: crate::units::transform::latency_cycles(&dp.transform),
        }
    }

    fn one(&self) -> i64 {
        1i64 << self.cfg.mat.frac.clamp(0, 62)
    }

    fn metres(&self, m: f64) -> i64 {
        code(m, self.cfg.pos)
    }

    fn txn(&self, o: [i64; 3], d: [i64; 3], axes: [[i64; 3]; 3], c: [i64; 3]) -> TransformTxn {
        TransformTxn {
            o,
            d,
            inst: InstanceRaw { axes, centre: c },
        }
    }
}

fn code(x: f64, f: Format) -> i64 {
    from_f64(x, f, &mut Overflows::new(&["host"]), SignalId(0))
}

/// Columns of the rotation of a unit quaternion (w, x, y, z).
fn rotation(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y + w * z),
            2.0 * (x * z - w * y),
        ],
        [
            2.0 * (x * y - w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z + w * x),
        ],
        [
            2.0 * (x * z + w * y),
            2.0 * (y * z - w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

impl Stage for TransformStage {
    type Txn = TransformTxn;

    fn name(&self) -> &'static str {
        "transform"
    }

    fn description(&self) -> &'static str {
        "one ray into one instance's frame per row: o, d, the rotation's columns and the centre in; local o, local d, direction signs and overflow flags out"
    }

    fn layout(&self) -> Layout {
        let c = &self.cfg;
        let mut l = Layout::new();
        for a in AXES {
            l.fixed(&format!("o_{a}"), Input, c.pos, "world ray origin, m");
        }
        for a in AXES {
            l.fixed(
                &format!("d_{a}"),
                Input,
                c.dir,
                "world ray direction (unit)",
            );
        }
        for k in 0..3 {
            for a in AXES {
                l.fixed(
                    &format!("axis{k}_{a}"),
                    Input,
                    c.mat,
                    "column k of the world-from-local rotation R: local axis k in world space",
                );
            }
        }
        for a in AXES {
            l.fixed(
                &format!("c_{a}"),
                Input,
                c.pos,
                "instance (octree) centre, m",
            );
        }
        for a in AXES {
            l.fixed(
                &format!("local_o_{a}"),
                Output,
                c.local_pos,
                "R^T (o - c), m",
            );
        }
        for a in AXES {
            l.fixed(&format!("local_d_{a}"), Output, c.local_dir, "R^T d");
        }
        for a in AXES {
            l.flag(
                &format!("sign_{a}"),
                Output,
                "exact direction sum negative before rounding (a code 0 with sign 1 is -0)",
            );
        }
        l.flag("ov_origin", Output, "a local origin component saturated");
        l.flag("ov_dir", Output, "a local direction component saturated");
        l
    }

    fn adversarial(&self) -> Vec<TransformTxn> {
        let one = self.one();
        let (pmax, pmin) = (self.cfg.pos.max_raw(), self.cfg.pos.min_raw());
        let (mmax, mmin) = (self.cfg.mat.max_raw(), self.cfg.mat.min_raw());
        let id = [[one, 0, 0], [0, one, 0], [0, 0, one]];
        let zero3 = [0; 3];
        let o = [self.metres(1.5), self.metres(-2.25), self.metres(3.0)];
        let c = [self.metres(0.5), self.metres(0.25), self.metres(-1.0)];
        let mut v = Vec::new();
        // Axis-parallel rays through the identity and signed permutations.
        let perms = [
            id,
            [[0, one, 0], [0, 0, one], [one, 0, 0]],
            [[0, 0, -one], [one, 0, 0], [0, -one, 0]],
            [[-one, 0, 0], [0, -one, 0], [0, 0, one]],
        ];
        for axes in perms {
            for d in [
                [one, 0, 0],
                [0, one, 0],
                [0, 0, one],
                [-one, 0, 0],
                [0, -one, 0],
                [0, 0, -one],
                zero3,
            ] {
                v.push(self.txn(o, d, axes, c));
            }
            v.push(self.txn(c, [one, 0, 0], axes, c)); // origin at the centre
        }
        // Extreme codes: every output saturates one way or the other.
        for (m, p, q) in [
            (mmax, pmax, pmin),
            (mmin, pmax, pmin),
            (mmax, pmin, pmax),
            (mmin, pmin, pmax),
        ] {
            v.push(self.txn([p; 3], [m; 3], [[m; 3]; 3], [q; 3]));
        }
        v.push(self.txn([pmax; 3], [mmax; 3], id, [pmin; 3]));
        // Round-half-even ties: a product of exactly half an output LSB times an odd code.
        let half = 1i64 << (self.cfg.mat.frac.clamp(1, 62) - 1);
        for k in [1, 3, 5, -1, -3, -5] {
            let axes = [[half, 0, 0], [0, half, 0], [0, 0, half]];
            v.push(self.txn([k, -k, 2 * k], [k, -k, 2 * k], axes, zero3));
            v.push(self.txn([k + 1, 0, 0], [k + 1, 0, 0], axes, [1, 0, 0]));
        }
        // Direction sums that cancel exactly (+0) and tiny negative ones (−0).
        let a = one / 3;
        v.push(self.txn(
            o,
            [a, a, 0],
            [[one, -one, 0], [0, 0, one], [one, one, 0]],
            c,
        ));
        for tiny in [1, half - 1, half, half + 1, 3 * half] {
            let axes = [[-tiny, 0, 0], [0, tiny, 0], [0, 0, -1]];
            v.push(self.txn(o, [1, 1, 1], axes, c));
            v.push(self.txn(o, [-1, -1, 1], axes, c));
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> TransformTxn {
        let cfg = &self.cfg;
        if rng.one_in(8) {
            // Raw codes anywhere in the formats: saturation and wide sums.
            let p = |rng: &mut Rng| rng.signed_code(u32::from(cfg.pos.width));
            let m = |rng: &mut Rng| rng.signed_code(u32::from(cfg.mat.width));
            let o = [0; 3].map(|_| p(rng));
            let c = [0; 3].map(|_| p(rng));
            let d = [0; 3].map(|_| m(rng));
            let axes = [[0; 3]; 3].map(|col| col.map(|_| m(rng)));
            return self.txn(o, d, axes, c);
        }
        let q = {
            let v = rng.unit_vector();
            let w = rng.range(-1.0, 1.0);
            let n = (1.0 - w * w).sqrt();
            [w, v[0] * n, v[1] * n, v[2] * n]
        };
        let r = rotation(q);
        let axes = r.map(|col| col.map(|x| code(x, cfg.mat)));
        let o = [0; 3].map(|_| self.metres(rng.range(-60.0, 60.0)));
        let c = [0; 3].map(|_| self.metres(rng.range(-60.0, 60.0)));
        let d = rng.unit_vector().map(|x| code(x, cfg.dir));
        self.txn(o, d, axes, c)
    }

    fn encode(&self, t: &TransformTxn) -> Vec<u128> {
        let mut ov = Overflows::new(&["origin", "dir"]);
        let sig = TransformSignals {
            origin: SignalId(0),
            dir: SignalId(1),
        };
        let (lo, ld, signs) = transform_with_signs(t.o, t.d, &t.inst, &self.cfg, &mut ov, sig);
        let mut v: Vec<u128> = Vec::with_capacity(32);
        v.extend(t.o.map(s));
        v.extend(t.d.map(s));
        for col in t.inst.axes {
            v.extend(col.map(s));
        }
        v.extend(t.inst.centre.map(s));
        v.extend(lo.map(s));
        v.extend(ld.map(s));
        v.extend(signs.map(b));
        v.push(b(ov.count(SignalId(0)) > 0));
        v.push(b(ov.count(SignalId(1)) > 0));
        v
    }

    fn timing(&self) -> Option<Timing> {
        Some(Timing {
            latency_cycles: self.latency,
            ii: 1,
        })
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", self.cfg);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_decode_to_the_model() {
        let st = TransformStage::new(&DatapathConfig::default());
        let l = st.layout();
        let mut rng = Rng::new(3);
        let mut cases = st.adversarial();
        cases.extend((0..200).map(|_| st.random(&mut rng)));
        let (mut neg_zero, mut sat) = (0, 0);
        for t in cases {
            let w = l.pack(&st.encode(&t));
            assert_eq!(l.read(&w, "axis2_y"), Some(i128::from(t.inst.axes[2][1])));
            // Independent check of d'_x: Σ_j R_j0 d_j rounded half-even, 30 bits dropped.
            let sum: i128 = (0..3)
                .map(|j| i128::from(t.inst.axes[0][j]) * i128::from(t.d[j]))
                .sum();
            let (fl, rem) = (sum >> 30, sum & ((1 << 30) - 1));
            let up = rem > 1 << 29 || (rem == 1 << 29 && fl & 1 == 1);
            let want = (fl + i128::from(up)).clamp(-(1 << 31), (1 << 31) - 1);
            assert_eq!(l.read(&w, "local_d_x"), Some(want), "{t:?}");
            assert_eq!(l.read(&w, "sign_x"), Some(i128::from(sum < 0)));
            neg_zero += usize::from(want == 0 && sum < 0);
            sat += usize::from(l.read(&w, "ov_origin") == Some(1));
        }
        assert!(
            neg_zero > 0 && sat > 0,
            "-0 cases {neg_zero}, saturations {sat}"
        );
        assert_eq!(st.latency, 9);
    }
}
