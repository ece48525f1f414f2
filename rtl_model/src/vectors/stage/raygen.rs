//! Ray-generation vectors: the direction-table entry of a pixel and the camera position, as
//! the host quantises them (`units::raygen::direction_entry`, `fixed::from_f64`). The
//! hardware reads the table; these rows say what every entry must hold for the f64 ray the
//! host computed, so a table writer (or an RTL normaliser) can be checked bit for bit.
//!
//! Adversarial cases: +0 and −0, ±1, exact round-half-even ties of both parities and signs,
//! the next doubles either side of a tie, subnormals, values that saturate (2.0, ±∞, 128 m),
//! the most negative codes (exact), NaN (0, flagged), axis-parallel unit directions, and the
//! view's corners (diagonals of all eight octants) at the extreme pixels with the camera at the
//! corners of its range.

use super::{dedup, Stage};
use crate::datapath::{DatapathConfig, RaygenConfig};
use crate::fixed::{from_f64, Overflows, SignalId};
use crate::units::raygen::direction_entry;
use crate::vectors::layout::{b, s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One transaction: a pixel, its f64 ray direction and the f64 camera position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RaygenTxn {
    /// Pixel column and row.
    pub pixel: [u16; 2],
    /// Unit direction (f64, as the host computes it).
    pub dir: [f64; 3],
    /// Camera position, metres.
    pub origin: [f64; 3],
}

/// The ray-generation stage for a datapath configuration.
pub struct RaygenStage {
    cfg: RaygenConfig,
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl RaygenStage {
    /// The direction table and camera position formats of `dp`.
    pub fn new(dp: &DatapathConfig) -> Self {
        Self { cfg: dp.raygen }
    }
}

/// The doubles either side of `x` (same sign).
fn neighbours(x: f64) -> [f64; 2] {
    let bits = x.to_bits();
    [f64::from_bits(bits - 1), f64::from_bits(bits + 1)]
}

impl Stage for RaygenStage {
    type Txn = RaygenTxn;

    fn name(&self) -> &'static str {
        "raygen"
    }

    fn description(&self) -> &'static str {
        "one direction-table entry per row: pixel, f64 direction and camera position in; their codes and overflow flags out"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.uint("pixel_x", Input, 16, "pixel column");
        l.uint("pixel_y", Input, 16, "pixel row");
        for a in AXES {
            l.float64(
                &format!("dir_f64_{a}"),
                Input,
                "unit ray direction, IEEE 754 binary64",
            );
        }
        for a in AXES {
            l.float64(
                &format!("origin_f64_{a}"),
                Input,
                "camera position, m, IEEE 754 binary64",
            );
        }
        for a in AXES {
            l.fixed(
                &format!("dir_{a}"),
                Output,
                self.cfg.dir,
                "direction-table entry",
            );
        }
        for a in AXES {
            l.fixed(
                &format!("origin_{a}"),
                Output,
                self.cfg.pos,
                "camera position code, m",
            );
        }
        l.flag(
            "ov_dir",
            Output,
            "a direction component saturated or was NaN",
        );
        l.flag(
            "ov_origin",
            Output,
            "a position component saturated or was NaN",
        );
        l
    }

    fn adversarial(&self) -> Vec<RaygenTxn> {
        let dl = self.cfg.dir.lsb();
        let pl = self.cfg.pos.lsb();
        let mut dir_values = vec![0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 1e-300, -1e-300, 5e-324];
        dir_values.extend([
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            2.0 - dl,
            -2.0 + dl,
        ]);
        for k in [0.5, 1.5, 2.5, 3.5, 1e6 + 0.5] {
            for x in [k * dl, -k * dl] {
                dir_values.push(x);
                dir_values.extend(neighbours(x));
            }
        }
        let mut pos_values = vec![0.0, -0.0, 128.0, -128.0, 128.0 - pl, 1e9, -1e9];
        pos_values.extend([f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 4.6, -4.4]);
        for k in [0.5, 1.5, 2.5] {
            pos_values.extend([k * pl, -k * pl]);
        }
        let mut v = Vec::new();
        for (i, &x) in dir_values.iter().enumerate() {
            let p = pos_values[i % pos_values.len()];
            v.push(RaygenTxn {
                pixel: [i as u16, 0],
                dir: [x, -x, 0.0],
                origin: [p, -p, 0.0],
            });
        }
        for k in 0..3 {
            for sign in [1.0, -1.0] {
                let mut d = [0.0; 3];
                d[k] = sign;
                d[(k + 1) % 3] = -0.0;
                v.push(RaygenTxn {
                    pixel: [u16::MAX, k as u16],
                    dir: d,
                    origin: [0.0; 3],
                });
            }
        }
        // Corners of the view (unit diagonals in all eight octants) at the extreme pixels,
        // with the camera at the corners of its range (the largest code, the most negative
        // exact code, and one LSB beyond).
        let c = 1.0 / 3f64.sqrt();
        let pixels = [[0, 0], [u16::MAX, u16::MAX], [u16::MAX, 0], [0, u16::MAX]];
        let corner = [128.0 - pl, -128.0, 128.0, -128.0 - pl];
        for k in 0..8 {
            let sg = |b: usize| if k >> b & 1 == 1 { -1.0 } else { 1.0 };
            v.push(RaygenTxn {
                pixel: pixels[k % 4],
                dir: [sg(0) * c, sg(1) * c, sg(2) * c],
                origin: [0, 1, 2].map(|a| sg(a) * corner[(k + a) % 4].abs()),
            });
        }
        dedup_f(v)
    }

    fn random(&self, rng: &mut Rng) -> RaygenTxn {
        RaygenTxn {
            pixel: [rng.below(1 << 16) as u16, rng.below(1 << 16) as u16],
            dir: rng.unit_vector(),
            origin: [0; 3].map(|_| rng.range(-130.0, 130.0)),
        }
    }

    fn encode(&self, t: &RaygenTxn) -> Vec<u128> {
        let mut ov = Overflows::new(&["dir", "pos"]);
        let d = direction_entry(t.dir, &self.cfg, &mut ov, SignalId(0));
        let o = t
            .origin
            .map(|x| from_f64(x, self.cfg.pos, &mut ov, SignalId(1)));
        let mut v = vec![u(u64::from(t.pixel[0])), u(u64::from(t.pixel[1]))];
        v.extend(t.dir.map(|x| u(x.to_bits())));
        v.extend(t.origin.map(|x| u(x.to_bits())));
        v.extend(d.map(s));
        v.extend(o.map(s));
        v.push(b(ov.count(SignalId(0)) > 0));
        v.push(b(ov.count(SignalId(1)) > 0));
        v
    }

    fn timing(&self) -> Option<Timing> {
        // units.raygen of the default hardware: svo_raygen.v is pipelined to it.
        let t = crate::cycle::hw_config::UnitTimings::default().raygen;
        Some(Timing {
            latency_cycles: t.latency_cycles,
            ii: t.ii,
        })
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", self.cfg);
    }
}

/// [`dedup`] by bit pattern (f64 has no `Eq`, and −0 must stay distinct from +0).
fn dedup_f(v: Vec<RaygenTxn>) -> Vec<RaygenTxn> {
    let key = |t: &RaygenTxn| (t.pixel, t.dir.map(f64::to_bits), t.origin.map(f64::to_bits));
    let keys = dedup(v.iter().map(key).collect());
    keys.into_iter()
        .filter_map(|k| v.iter().find(|t| key(t) == k).copied())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_decode_to_the_model() {
        let st = RaygenStage::new(&DatapathConfig::default());
        let l = st.layout();
        let cases = st.adversarial();
        assert!(cases
            .iter()
            .any(|t| t.dir[0].to_bits() == (-0.0f64).to_bits()));
        for t in cases {
            let w = l.pack(&st.encode(&t));
            let bits = l.read(&w, "dir_f64_x").unwrap_or(0) as u64;
            assert_eq!(bits, t.dir[0].to_bits());
            // Independent check: a finite in-range component is the nearest code, ties even.
            let x = t.dir[0];
            if x.is_finite() && x.abs() < 1.99 {
                let scaled = x * (1u64 << 30) as f64;
                let want = scaled.round_ties_even() as i128;
                assert_eq!(l.read(&w, "dir_x"), Some(want), "x = {x:e}");
            }
        }
    }
}
