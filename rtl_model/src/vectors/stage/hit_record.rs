//! Hit-record vectors: packing one pixel's record into its hit-buffer word
//! (`units::hit_record::pack`), with every saturation the packer applies.
//!
//! Adversarial cases: each sphere-count code, no instance, the largest instance id and the
//! ids at and above the none code (packed as none, flagged), t below 0, at and beyond the
//! largest code and at the i64 extremes, normals at and beyond their signed range, colour 0
//! and 255.

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::fixed::{Overflows, SignalId};
use crate::units::hit_record::{pack, HitRecordConfig, HitRecordFields, RecordT, SphereCount};
use crate::vectors::layout::{b, s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// The hit-record stage for a datapath configuration.
pub struct HitRecordStage {
    cfg: HitRecordConfig,
}

impl HitRecordStage {
    /// The record of `dp`.
    pub fn new(dp: &DatapathConfig) -> Self {
        Self {
            cfg: dp.hit_record.clone(),
        }
    }

    fn rec(
        &self,
        kind: u8,
        instance: Option<u16>,
        t: i64,
        normal: [i32; 2],
        colour: [u8; 3],
    ) -> HitRecordFields {
        HitRecordFields {
            kind: SphereCount::from_code(kind),
            instance,
            t: RecordT { raw: t },
            normal,
            colour,
            voxel: [0; 3],
        }
    }
}

impl Stage for HitRecordStage {
    type Txn = HitRecordFields;

    fn name(&self) -> &'static str {
        "hit_record"
    }

    fn description(&self) -> &'static str {
        "one record per row: the record's fields as raw codes in (wider than the word's, to exercise saturation); the packed hit-buffer word and the overflow flag out"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.uint(
            "kind",
            Input,
            2,
            "spheres pierced: 0 none, 1 one, 2 several",
        );
        l.flag(
            "instance_valid",
            Input,
            "a hit (0: miss, the instance field is ignored)",
        );
        l.uint("instance", Input, 16, "instance hit");
        l.sint(
            "t",
            Input,
            64,
            "t as a raw code of the record's t format (before saturation)",
        );
        l.sint(
            "normal_u",
            Input,
            32,
            "octahedral normal u code (before saturation)",
        );
        l.sint(
            "normal_v",
            Input,
            32,
            "octahedral normal v code (before saturation)",
        );
        for c in ["colour_r", "colour_g", "colour_b"] {
            l.uint(c, Input, 8, "colour channel code (before saturation)");
        }
        if self.cfg.include_voxel {
            for a in ["voxel_x", "voxel_y", "voxel_z"] {
                l.uint(a, Input, 32, "leaf coordinate (before saturation)");
            }
        }
        l.uint(
            "word",
            Output,
            self.cfg.word_bits(),
            "the packed hit-buffer word (layout in parameters.record_layout)",
        );
        l.flag(
            "ov",
            Output,
            "a field saturated or an id at or above the none code became none",
        );
        l
    }

    fn adversarial(&self) -> Vec<HitRecordFields> {
        let tf = self.cfg.t;
        let none = self.cfg.instance_none();
        let nmax = (1i32 << (self.cfg.normal_bits.clamp(2, 16) - 1)) - 1;
        let mut v = Vec::new();
        for kind in 0..3 {
            v.push(self.rec(kind, None, tf.max_raw(), [0, nmax], [0, 0, 0]));
        }
        for id in [0, 1, none - 1, none, none + 1, u16::MAX] {
            v.push(self.rec(1, Some(id), 1 << 14, [3, -3], [200, 34, 42]));
        }
        for t in [
            -1,
            0,
            1,
            tf.max_raw() - 1,
            tf.max_raw(),
            tf.max_raw() + 1,
            i64::MAX,
            i64::MIN,
        ] {
            v.push(self.rec(2, Some(3), t, [0, 0], [255, 255, 255]));
        }
        for n in [
            nmax,
            nmax + 1,
            -nmax,
            -nmax - 1,
            -nmax - 2,
            i32::MAX,
            i32::MIN,
        ] {
            v.push(self.rec(1, Some(7), 100, [n, -n.saturating_add(1)], [1, 128, 254]));
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> HitRecordFields {
        let none = u64::from(self.cfg.instance_none());
        let tf = self.cfg.t;
        let nmax = (1i64 << (self.cfg.normal_bits.clamp(2, 16) - 1)) - 1;
        let mut n = || {
            if rng.one_in(16) {
                rng.signed_code(32) as i32
            } else {
                (rng.below(2 * nmax as u64 + 2) as i64 - nmax - 1) as i32
            }
        };
        let normal = [n(), n()];
        let t = if rng.one_in(16) {
            rng.signed_code(64)
        } else {
            rng.below(tf.max_raw() as u64 + 1) as i64
        };
        let mut r = self.rec(
            rng.below(3) as u8,
            (!rng.one_in(4)).then(|| rng.below(none + 2) as u16),
            t,
            normal,
            [0; 3].map(|_| rng.below(256) as u8),
        );
        if self.cfg.include_voxel {
            r.voxel = [0; 3].map(|_| rng.bits_up_to(24) as u32);
        }
        r
    }

    fn encode(&self, r: &HitRecordFields) -> Vec<u128> {
        let mut ov = Overflows::new(&["hit_record"]);
        let word = pack(r, &self.cfg, &mut ov, SignalId(0));
        let mut v = vec![
            u(u64::from(r.kind.code())),
            b(r.instance.is_some()),
            u(u64::from(r.instance.unwrap_or(0))),
            s(r.t.raw),
            s(i64::from(r.normal[0])),
            s(i64::from(r.normal[1])),
        ];
        v.extend(r.colour.map(|c| u(u64::from(c))));
        if self.cfg.include_voxel {
            v.extend(r.voxel.map(|c| u(u64::from(c))));
        }
        v.push(word);
        v.push(b(ov.total() > 0));
        v
    }

    fn timing(&self) -> Option<Timing> {
        Some(Timing {
            latency_cycles: crate::cycle::hw_config::UnitTimings::default()
                .hit_pack
                .latency_cycles,
            ii: 1,
        })
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", &self.cfg);
        t.param("record_layout", self.cfg.layout());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::hit_record::unpack;

    #[test]
    fn rows_decode_to_the_model() {
        let dp = DatapathConfig::default();
        let st = HitRecordStage::new(&dp);
        let l = st.layout();
        assert_eq!(l.field("word").map(|f| f.width), Some(72));
        let mut rng = Rng::new(9);
        let mut cases = st.adversarial();
        cases.extend((0..300).map(|_| st.random(&mut rng)));
        let mut flagged = 0;
        for r in cases {
            let w = l.pack(&st.encode(&r));
            let word = l.read(&w, "word").unwrap_or(0) as u128;
            let back = unpack(word, &dp.hit_record);
            assert_eq!(back.kind, r.kind);
            assert_eq!(back.colour, r.colour);
            // Independent check of the t field: bits 10..32, clamped into uQ8.14.
            assert_eq!(
                (word >> 10) & 0x3f_ffff,
                r.t.raw.clamp(0, 0x3f_ffff) as u128
            );
            flagged += usize::from(l.read(&w, "ov") == Some(1));
        }
        assert!(flagged > 10);
    }
}
