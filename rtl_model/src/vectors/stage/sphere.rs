//! Sphere-test vectors: one ray against one bounding sphere (`units::sphere::sphere_test`),
//! the conservative test with its entry distance, square root included. Every per-instance
//! constant the host programs (threshold, inside threshold, Δt, reach) is an input field, so
//! a row is self-contained.
//!
//! Adversarial cases: axis-parallel rays in both directions, a zero direction, origins at
//! the centre, grazing rays whose p² equals the threshold exactly (kept) or exceeds it by one
//! code (culled), the "origin inside" and "sphere behind" decisions at equality, |c − o| at
//! the reach and one code beyond, saturating t_ca, thresholds 0 and maximal.

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::fixed::{from_f64, Format, Overflows, Quant, SignalId};
use crate::units::sphere::{
    self, sphere_radicand, sphere_test, SphereConfig, SphereRaw, SphereSignals,
};
use crate::units::sqrt;
use crate::vectors::layout::{b, s, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One transaction: the ray and the sphere's programmed constants, as raw codes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereTxn {
    /// Ray origin (`pos`).
    pub o: [i64; 3],
    /// Ray direction (`dir`).
    pub d: [i64; 3],
    /// Sphere centre (`pos`).
    pub centre: [i64; 3],
    /// Rejection threshold T = r² + W (`sq`).
    pub threshold: i64,
    /// "Origin may be inside" threshold (`sq`).
    pub inside: i64,
    /// Δt (`tca`).
    pub delta_t: i64,
    /// Reach (`pos`).
    pub reach: i64,
}

impl SphereTxn {
    /// The transaction of a ray against a sphere the host programmed (`SphereRaw::new`).
    pub fn of(o: [i64; 3], d: [i64; 3], sphere: &SphereRaw) -> Self {
        Self {
            o,
            d,
            centre: sphere.centre,
            threshold: sphere.threshold,
            inside: sphere.inside,
            delta_t: sphere.delta_t,
            reach: sphere.reach,
        }
    }

    /// The unit's view of the sphere: the programmed codes plus the model's f64 pre-filter
    /// constants, derived from the threshold as `SphereRaw::new` derives them.
    fn raw(&self, cfg: &SphereConfig) -> SphereRaw {
        let scale = 2f64.powi(2 * i32::from(cfg.pos.frac) - i32::from(cfg.sq.frac));
        SphereRaw {
            centre: self.centre,
            threshold: self.threshold,
            inside: self.inside,
            delta_t: self.delta_t,
            reach: self.reach,
            reject_above: self.threshold as f64 * scale * (1.0 + 1e-6),
            dir_scale: 2f64.powi(-i32::from(cfg.dir.frac)),
        }
    }
}

/// The sphere stage for a datapath configuration.
pub struct SphereStage {
    cfg: SphereConfig,
    timing: Timing,
}

const AXES: [&str; 3] = ["x", "y", "z"];

fn code(x: f64, f: Format) -> i64 {
    from_f64(x, f, &mut Overflows::new(&["host"]), SignalId(0))
}

impl SphereStage {
    /// The sphere unit of `dp`; its latency is the sphere lane's plus its square root's.
    pub fn new(dp: &DatapathConfig) -> Self {
        let lat = sphere::latency_cycles(&dp.sphere)
            + sqrt::latency_cycles(&sphere::sqrt_config(&dp.sphere));
        Self {
            cfg: dp.sphere,
            timing: Timing {
                latency_cycles: lat,
                ii: 1,
            },
        }
    }

    fn m(&self, metres: f64) -> i64 {
        code(metres, self.cfg.pos)
    }

    fn sphere(&self, centre: [i64; 3], r: f64) -> SphereRaw {
        SphereRaw::new(centre, r, &self.cfg)
    }

    /// The radicand the sphere unit hands its square root for `t`
    /// (`units::sphere::sphere_radicand`: T − p² in `sq`, the unit's pre-checks included), or
    /// `None` where the unit takes no root (beyond the reach, or culled by p² > T). Used to
    /// capture the square root's real-frame transactions; the stage test checks it against
    /// `sphere_test`'s entry distance.
    pub fn radicand(&self, t: &SphereTxn) -> Option<i64> {
        let x = sphere_radicand(
            t.o,
            t.d,
            &t.raw(&self.cfg),
            &self.cfg,
            &mut Overflows::new(&["x"]),
            SphereSignals {
                tca: SignalId(0),
                sq: SignalId(0),
                t_enter: SignalId(0),
                reach: SignalId(0),
            },
        )?;
        // T − p² ≤ T, a code of `sq`, so it fits an i64.
        Some(i64::try_from(x).unwrap_or(i64::MAX))
    }
}

impl Stage for SphereStage {
    type Txn = SphereTxn;

    fn name(&self) -> &'static str {
        "sphere"
    }

    fn description(&self) -> &'static str {
        "one ray against one bounding sphere per row: ray, centre and the programmed constants in; kept flag, entry distance and overflow flags out"
    }

    fn layout(&self) -> Layout {
        let c = &self.cfg;
        let mut l = Layout::new();
        for a in AXES {
            l.fixed(&format!("o_{a}"), Input, c.pos, "ray origin, m");
        }
        for a in AXES {
            l.fixed(&format!("d_{a}"), Input, c.dir, "ray direction (unit)");
        }
        for a in AXES {
            l.fixed(&format!("c_{a}"), Input, c.pos, "sphere centre, m");
        }
        l.fixed(
            "threshold",
            Input,
            c.sq,
            "T = r^2 + W: cull iff p^2 > T, m^2",
        );
        l.fixed(
            "inside",
            Input,
            c.sq,
            "origin may be inside iff l.l <= this, m^2",
        );
        l.fixed(
            "delta_t",
            Input,
            c.tca.with_quant(Quant::Trn),
            "Δt, the entry distance's margin, m",
        );
        l.fixed(
            "reach",
            Input,
            Format {
                signed: false,
                ..c.pos
            },
            "largest |c - o| per axis the bound covers, m (unsigned: it may be 2^(W-1))",
        );
        l.flag("hit", Output, "sphere kept (a candidate); 0 = culled");
        l.fixed(
            "t_enter",
            Output,
            c.t_enter.with_quant(Quant::Trn),
            "entry distance (sort key), 0 when culled or the origin may be inside",
        );
        l.flag(
            "ov_reach",
            Output,
            "|c - o| beyond the reach: kept with t_enter 0",
        );
        l.flag("ov_t_enter", Output, "entry distance saturated");
        l
    }

    fn adversarial(&self) -> Vec<SphereTxn> {
        let cfg = &self.cfg;
        let one = 1i64 << cfg.dir.frac.clamp(0, 62);
        let (dmin, pmax) = (cfg.dir.min_raw(), cfg.pos.max_raw());
        let zero = [0i64; 3];
        let base = self.sphere(zero, 1.0);
        let (dt, reach) = (base.delta_t, base.reach);
        let sqmax = cfg.sq.max_raw();
        let pf = i32::from(cfg.pos.frac);
        let up = (2 * pf).max(2 * i32::from(cfg.tca.frac)) - i32::from(cfg.sq.frac);
        // A code whose square, at 2·pf fraction bits, is an exact multiple of 2^up.
        let exact = |metres: f64| (self.m(metres) >> (up / 2 + 1)) << (up / 2 + 1);
        let sq_of = |c: i64| ((i128::from(c) * i128::from(c)) >> up) as i64;
        let txn = |o, d, centre, threshold, inside| SphereTxn {
            o,
            d,
            centre,
            threshold,
            inside,
            delta_t: dt,
            reach,
        };
        let mut v = Vec::new();
        let ten = self.m(10.0);
        // Axis-parallel rays, both ways, on each axis; a zero direction.
        for k in 0..3 {
            for sign in [1, -1] {
                let mut d = zero;
                d[k] = sign * one;
                let mut c = zero;
                c[k] = ten;
                v.push(SphereTxn::of(zero, d, &self.sphere(c, 1.0)));
                let mut off = c;
                off[(k + 1) % 3] = self.m(0.999);
                v.push(SphereTxn::of(zero, d, &self.sphere(off, 1.0)));
            }
        }
        v.push(SphereTxn::of(zero, zero, &self.sphere([ten, 0, 0], 1.0)));
        v.push(SphereTxn::of(
            zero,
            zero,
            &self.sphere([self.m(0.5), 0, 0], 1.0),
        ));
        v.push(SphereTxn::of(
            [ten; 3],
            [one, 0, 0],
            &self.sphere([ten; 3], 2.0),
        ));
        // Grazing: p² = y_c² exactly; T = p² keeps, T − 1 culls, T + 1 keeps with root 1.
        for yc in [exact(1.5), exact(0.001), exact(7.25)] {
            let t = sq_of(yc);
            for thr in [t, t - 1, t + 1] {
                v.push(txn(zero, [one, 0, 0], [ten, yc, 0], thr, 0));
                v.push(txn(zero, [0, 0, -one], [0, -yc, -ten], thr, 0));
            }
        }
        // Origin inside at equality (t_enter 0) and one code short of it.
        let xc = exact(2.0);
        for inside in [sq_of(xc), sq_of(xc) - 1] {
            v.push(txn(
                zero,
                [one, 0, 0],
                [xc, 0, 0],
                sq_of(xc) + sq_of(xc),
                inside,
            ));
        }
        // Sphere behind: t_ca + Δt + √T = 0 keeps (t_enter clamps to 0), one code more culls.
        let root = 1i64 << 20; // root code at the square root's fraction bits
        let rf = i32::from(cfg.sq.frac) / 2;
        let shift = i32::from(cfg.tca.frac) - rf;
        let t_sq = root * root;
        if (0..40).contains(&shift) {
            let edge = dt + (root << shift);
            for x in [edge, edge + 1, edge - 1] {
                v.push(txn(zero, [-one, 0, 0], [x, 0, 0], t_sq, 0));
            }
        }
        // The reach: |l_x| = reach takes the exact path, reach + 1 is flagged.
        // (o and c split the distance, so both stay codes of `pos` even when the reach is not.)
        for x in [reach, reach + 1, -reach, -reach - 1] {
            let (c, o) = (x / 2, x / 2 - x);
            v.push(txn([o, 0, 0], [one, 0, 0], [c, 0, 0], sqmax, 0));
            v.push(txn([0, 0, o], [0, 0, one], [0, 0, c], sqmax, 0));
        }
        v.push(txn([pmax; 3], [one, 0, 0], [-pmax; 3], sqmax, 0));
        // t_ca saturates: |l·d| = 3 · 2 · reach exceeds the t_ca format.
        let near = reach.min(pmax);
        v.push(txn(zero, [dmin; 3], [near; 3], sqmax, 0));
        v.push(txn(zero, [dmin; 3], [-near; 3], sqmax, 0));
        v.push(txn(zero, [one; 3], [near; 3], sqmax, sqmax));
        // Threshold 0 (only rays through the centre) and thresholds at the maximum.
        v.push(txn(zero, [one, 0, 0], [ten, 0, 0], 0, 0));
        v.push(txn(zero, [one, 0, 0], [ten, 1, 0], 0, 0));
        v.push(txn(zero, [0, one, 0], [0, near, near], sqmax, 0));
        // Tiny and diagonal directions.
        let diag = code(1.0 / 3f64.sqrt(), cfg.dir);
        v.push(SphereTxn::of(zero, [diag; 3], &self.sphere([ten; 3], 0.5)));
        v.push(SphereTxn::of(zero, [1, -1, 1], &self.sphere([ten; 3], 0.5)));
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> SphereTxn {
        let cfg = &self.cfg;
        if rng.one_in(8) {
            let p = |rng: &mut Rng| rng.signed_code(u32::from(cfg.pos.width));
            let sphere = self.sphere([0; 3].map(|_| p(rng)), rng.range(0.0, 50.0));
            let d = [0; 3].map(|_| rng.signed_code(u32::from(cfg.dir.width)));
            return SphereTxn::of([0; 3].map(|_| p(rng)), d, &sphere);
        }
        // A ray aimed at a point near the sphere's rim: hits, misses and grazes.
        let o = [0; 3].map(|_| rng.range(-20.0, 20.0));
        let r = rng.range(0.05, 12.0);
        let c = [0; 3].map(|k| o[k] + rng.range(-90.0, 90.0));
        let u = rng.unit_vector();
        let reach = rng.range(0.0, 1.3) * r;
        let target = [0, 1, 2].map(|k| c[k] + u[k] * reach);
        let dir = [0, 1, 2].map(|k| target[k] - o[k]);
        let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2])
            .sqrt()
            .max(1e-9);
        let d = dir.map(|x| code(x / n, cfg.dir));
        let sphere = self.sphere(c.map(|x| self.m(x)), r);
        SphereTxn::of(o.map(|x| self.m(x)), d, &sphere)
    }

    fn encode(&self, t: &SphereTxn) -> Vec<u128> {
        let mut ov = Overflows::new(&["tca", "sq", "t_enter", "reach"]);
        let sig = SphereSignals {
            tca: SignalId(0),
            sq: SignalId(1),
            t_enter: SignalId(2),
            reach: SignalId(3),
        };
        let hit = sphere_test(t.o, t.d, &t.raw(&self.cfg), &self.cfg, &mut ov, sig);
        let mut v: Vec<u128> = Vec::with_capacity(20);
        v.extend(t.o.map(s));
        v.extend(t.d.map(s));
        v.extend(t.centre.map(s));
        v.extend([s(t.threshold), s(t.inside), s(t.delta_t), s(t.reach)]);
        v.push(b(hit.is_some()));
        v.push(s(hit.map_or(0, |h| h.t_enter)));
        v.push(b(ov.count(SignalId(3)) > 0));
        v.push(b(ov.count(SignalId(2)) > 0));
        v
    }

    fn timing(&self) -> Option<Timing> {
        Some(self.timing)
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", self.cfg);
        t.param("sqrt_config", sphere::sqrt_config(&self.cfg));
        t.param(
            "latency_split",
            serde_json::json!({
                "sphere_lane_cycles": sphere::latency_cycles(&self.cfg),
                "sqrt_cycles": sqrt::latency_cycles(&sphere::sqrt_config(&self.cfg)),
            }),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_decode_to_the_model_and_the_radicand_matches() {
        let dp = DatapathConfig::default();
        let st = SphereStage::new(&dp);
        let l = st.layout();
        let mut rng = Rng::new(11);
        let mut cases = st.adversarial();
        cases.extend((0..2000).map(|_| st.random(&mut rng)));
        let (mut kept, mut culled, mut reach) = (0, 0, 0);
        for t in &cases {
            let w = l.pack(&st.encode(t));
            assert_eq!(l.read(&w, "threshold"), Some(i128::from(t.threshold)));
            let hit = l.read(&w, "hit") == Some(1);
            let t_enter = l.read(&w, "t_enter").unwrap_or(-1);
            kept += usize::from(hit);
            culled += usize::from(!hit);
            reach += usize::from(l.read(&w, "ov_reach") == Some(1));
            // The captured radicand reproduces the entry distance of a kept, outside sphere
            // within the reach (beyond it the unit keeps the sphere with entry 0, flagged).
            let far = l.read(&w, "ov_reach") == Some(1);
            let l2: i128 = (0..3)
                .map(|k| (i128::from(t.centre[k]) - i128::from(t.o[k])).pow(2))
                .sum();
            let outside = l2 > i128::from(t.inside) << 16;
            if let (true, true, false, Some(x)) = (hit, outside, far, st.radicand(t)) {
                let root = i128::from(sqrt::isqrt(x as u64));
                let dot: i128 = (0..3)
                    .map(|k| (i128::from(t.centre[k]) - i128::from(t.o[k])) * i128::from(t.d[k]))
                    .sum();
                // t_ca sQ10.24 (62 − 24 = 38 bits dropped), root uQ8.24, entry uQ10.22.
                let tca = (dot >> 38).clamp(-(1 << 33), (1 << 33) - 1);
                let e = ((tca - i128::from(t.delta_t) - root).max(0) >> 2).min(u32::MAX.into());
                assert_eq!(t_enter, e, "{t:?}");
            }
        }
        assert!(
            kept > 100 && culled > 100 && reach >= 2,
            "{kept} {culled} {reach}"
        );
        assert_eq!(st.timing.latency_cycles, 48);
    }
}
