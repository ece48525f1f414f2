//! Normal-unit vectors: the record stage's octahedral normal from a leaf's snorm16 code and an
//! instance's sQ2.16 normal matrix (`units::normal::normal_code` at the record's
//! `normal_bits`).
//!
//! Adversarial cases: the six axes and the −z corner through the identity, an axis swap and
//! a 90° rotation (the fold's seam and its signs, ±0), the −32768 code, upper-hemisphere ties,
//! matrices of large anisotropic scale (elements that round to 0), the all-±1 matrix (the
//! widest sums) and the zero matrix (the degenerate (0, 0)).

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::svo::attr::LeafAttr;
use crate::units::normal::{self, normal_code, NormalMatrix, MAT_FORMAT};
use crate::vectors::layout::{s, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One transaction: the attribute's normal word ({v, u} snorm16) and the matrix.
pub type NormalTxn = (u32, NormalMatrix);

/// The normal stage for a datapath configuration.
pub struct NormalStage {
    bits: u8,
}

impl NormalStage {
    /// The record's normal width of `dp`.
    pub fn new(dp: &DatapathConfig) -> Self {
        Self {
            bits: dp.hit_record.normal_bits,
        }
    }
}

fn oct(u: i16, v: i16) -> u32 {
    u32::from(u as u16) | (u32::from(v as u16) << 16)
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Stage for NormalStage {
    type Txn = NormalTxn;

    fn name(&self) -> &'static str {
        "normal"
    }

    fn description(&self) -> &'static str {
        "one record normal per row: attribute octahedral code and instance normal matrix in, the record's (u, v) codes out"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.sint("oct_u", Input, 16, "attribute octahedral u, snorm16");
        l.sint("oct_v", Input, 16, "attribute octahedral v, snorm16");
        for i in AXES {
            for j in AXES {
                l.fixed(
                    &format!("m_{i}{j}"),
                    Input,
                    MAT_FORMAT,
                    "normal matrix element (row = world axis), scaled to a largest |element| of 1",
                );
            }
        }
        let n = u32::from(self.bits);
        l.sint("u", Output, n, "record octahedral normal u code");
        l.sint("v", Output, n, "record octahedral normal v code");
        l
    }

    fn adversarial(&self) -> Vec<NormalTxn> {
        let q = NormalMatrix::quantise;
        let id = q([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let mats = [
            id,
            q([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
            q([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
            q([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
            q([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1e6]]),
            q([[1e-5, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1e-3]]),
            NormalMatrix {
                m_q2_16: [
                    [65536, -65536, 65536],
                    [-65536, 65536, -65536],
                    [65536, 65536, 65536],
                ],
            },
            NormalMatrix {
                m_q2_16: [[-65536; 3]; 3],
            },
            NormalMatrix::default(),
        ];
        let codes = [
            oct(0, 0),
            oct(32767, 0),
            oct(-32767, 0),
            oct(0, 32767),
            oct(0, -32767),
            oct(32767, 32767),
            oct(-32767, -32767),
            oct(-32768, 0),
            oct(-32768, -32768),
            oct(16384, -16384),
            oct(20000, 20000),
            oct(-20000, 20000),
            oct(1, -1),
            oct(i16::MAX, i16::MIN),
        ];
        let mut v = Vec::new();
        for m in mats {
            for c in codes {
                v.push((c, m));
            }
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> NormalTxn {
        let code = if rng.one_in(2) {
            LeafAttr::new([0; 4], rng.unit_vector()).normal_oct16
        } else {
            rng.next_u64() as u32
        };
        let m = if rng.one_in(4) {
            // Raw elements: any code of the matrix format within ±1.
            let mut e = || (rng.signed_code(18)).clamp(-65536, 65536) as i32;
            NormalMatrix {
                m_q2_16: [[e(), e(), e()], [e(), e(), e()], [e(), e(), e()]],
            }
        } else {
            // A rotation (three unit axes made orthonormal) times diag(1/scale), scale up to
            // 1000:1 per axis, as the host quantises it.
            let a = rng.unit_vector();
            let mut b = rng.unit_vector();
            let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            b = [0, 1, 2].map(|i| b[i] - d * a[i]);
            let lb = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt().max(1e-9);
            b = b.map(|x| x / lb);
            let c = [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ];
            let sc = [0, 1, 2].map(|_| 1000f64.powf(rng.range(0.0, 1.0)));
            NormalMatrix::quantise([0, 1, 2].map(|i| [a[i] / sc[0], b[i] / sc[1], c[i] / sc[2]]))
        };
        (code, m)
    }

    fn encode(&self, &(code, m): &NormalTxn) -> Vec<u128> {
        let mut v = vec![
            s(i64::from(code as u16 as i16)),
            s(i64::from((code >> 16) as u16 as i16)),
        ];
        v.extend(m.elements().map(|e| s(i64::from(e))));
        let [u, w] = normal_code(code, &m, self.bits);
        v.extend([s(i64::from(u)), s(i64::from(w))]);
        v
    }

    fn timing(&self) -> Option<Timing> {
        Some(Timing {
            latency_cycles: normal::LATENCY_CYCLES,
            ii: 1,
        })
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("normal_bits", self.bits);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows decode to their inputs, and the identity's outputs are the attribute code
    /// reduced to 8 bits on the upper hemisphere (independent of the unit: round(c·127/32767)).
    #[test]
    fn rows_decode_and_the_identity_reduces_the_code() {
        let st = NormalStage::new(&DatapathConfig::default());
        let l = st.layout();
        assert_eq!(l.word_bits(), 32 + 9 * 18 + 16);
        for t in st.adversarial() {
            let w = l.pack(&st.encode(&t));
            assert_eq!(l.read(&w, "oct_u"), Some(i128::from(t.0 as u16 as i16)));
            assert_eq!(l.read(&w, "m_zz"), Some(i128::from(t.1.m_q2_16[2][2])));
        }
        let id = st.adversarial()[0].1;
        for (u, v) in [(1000i16, -2000i16), (16384, -16384), (-5, 7)] {
            let r = |c: i16| (f64::from(c) * 127.0 / 32767.0).round() as i128;
            let w = l.pack(&st.encode(&(oct(u, v), id)));
            assert_eq!(l.read(&w, "u"), Some(r(u)));
            assert_eq!(l.read(&w, "v"), Some(r(v)));
        }
    }
}
