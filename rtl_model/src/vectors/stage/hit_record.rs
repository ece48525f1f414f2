//! Hit-record vectors: per row, packing one pixel's record into its hit-buffer word
//! (`units::hit_record::pack`, with every saturation the packer applies) and, beside it, the
//! check stage's side on another word: unpacking the previous frame's word
//! (`units::hit_record::unpack`) and the reuse rule with its refreshed word
//! (`units::hit_record::reuse`). The two halves are independent; one row carries both so the
//! record unit's RTL (`svo_hit_pack.v`, `svo_hit_check.v`) is checked in one table.
//!
//! Adversarial cases, pack: each sphere-count code, no instance, the largest instance id and
//! the ids at and above the none code (packed as none, flagged), t below 0, at and beyond the
//! largest code and at the i64 extremes, normals at and beyond their signed range, colour 0
//! and 255. Check: a reusable word, then each condition of the rule broken alone (no buffer,
//! camera moved, instance moved, 0, 2 and many candidates, another instance), a miss word
//! (reused whatever the candidate), the reserved kind code 3 and the other kinds (refreshed to
//! one sphere), saturated fields (t at its far code, normals at −2^(N−1), colour 255), all-ones
//! and all-zero words, and candidates beyond the instance field.

use super::{dedup, Stage};
use crate::datapath::DatapathConfig;
use crate::fixed::{Overflows, SignalId};
use crate::units::hit_record::{
    pack, reuse, unpack, HitRecordConfig, HitRecordFields, RecordT, ReuseInputs, SphereCount,
};
use crate::vectors::layout::{b, s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One row's transaction: a record to pack, and a previous word with what the reuse check
/// knows about this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HitRecordTxn {
    /// The record packed into `word`.
    pub record: HitRecordFields,
    /// The word the hit buffer returned for the check (the previous frame's).
    pub prev: u128,
    /// The frame's side of the reuse rule.
    pub check: ReuseInputs,
}

/// A reusable situation for `prev`: buffer on, still camera and instance, one candidate
/// (the word's own instance, or 0 for a miss).
fn still(prev_instance: Option<u16>) -> ReuseInputs {
    ReuseInputs {
        buffer: true,
        camera_dirty: false,
        candidates: 1,
        candidate: prev_instance.unwrap_or(0),
        instance_dirty: false,
    }
}

impl HitRecordTxn {
    /// The record, checked against its own packed word in a still frame (what a captured
    /// pixel's next frame sees with a still camera).
    pub fn still(record: HitRecordFields, cfg: &HitRecordConfig) -> Self {
        let mut ov = Overflows::new(&["hit_record"]);
        let prev = pack(&record, cfg, &mut ov, SignalId(0));
        Self {
            record,
            prev,
            check: still(unpack(prev, cfg).instance),
        }
    }
}

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

    /// The packing cases (see the module doc).
    fn pack_cases(&self) -> Vec<HitRecordFields> {
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

    /// A random record to pack.
    fn random_record(&self, rng: &mut Rng) -> HitRecordFields {
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
}

impl Stage for HitRecordStage {
    type Txn = HitRecordTxn;

    fn name(&self) -> &'static str {
        "hit_record"
    }

    fn description(&self) -> &'static str {
        "one record and one check per row: the record's fields as raw codes in (wider than the word's, to exercise saturation), the packed hit-buffer word and the overflow flag out; a previous word and the frame's reuse inputs in, its unpacked fields, the reuse decision and the refreshed word out"
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
        let wb = self.cfg.word_bits();
        l.uint(
            "prev",
            Input,
            wb,
            "the previous frame's word the check reads",
        );
        l.flag("buffer", Input, "the hit buffer is in use this frame");
        l.flag(
            "camera_dirty",
            Input,
            "the camera moved since the word was written",
        );
        l.uint(
            "candidates",
            Input,
            16,
            "this frame's candidates of the ray",
        );
        l.uint(
            "candidate",
            Input,
            16,
            "the only candidate's instance (when one)",
        );
        l.flag("instance_dirty", Input, "that instance moved");
        l.uint(
            "word",
            Output,
            wb,
            "the packed hit-buffer word (layout in parameters.record_layout)",
        );
        l.flag(
            "ov",
            Output,
            "a field saturated or an id at or above the none code became none",
        );
        let c = &self.cfg;
        let layout = c.layout();
        let width = |name: &str| {
            layout
                .iter()
                .find(|f| f.name == name)
                .map_or(1, |f| f.width)
        };
        l.uint(
            "prev_kind",
            Output,
            2,
            "unpacked sphere count (reserved 3 reads as 2)",
        );
        l.flag(
            "prev_hit",
            Output,
            "the word's instance is not the none code",
        );
        l.uint(
            "prev_instance",
            Output,
            width("instance"),
            "its instance (0 on a miss)",
        );
        l.fixed("prev_t", Output, c.t, "its t code, m");
        l.sint(
            "prev_normal_u",
            Output,
            width("normal_u"),
            "its normal u code",
        );
        l.sint(
            "prev_normal_v",
            Output,
            width("normal_v"),
            "its normal v code",
        );
        for ch in ["colour_r", "colour_g", "colour_b"] {
            l.uint(
                &format!("prev_{ch}"),
                Output,
                width(ch),
                "its colour channel",
            );
        }
        if c.include_voxel {
            for a in ["voxel_x", "voxel_y", "voxel_z"] {
                l.uint(
                    &format!("prev_{a}"),
                    Output,
                    width(a),
                    "its leaf coordinate",
                );
            }
        }
        l.flag(
            "reuse",
            Output,
            "the word stands for this frame's ray (no walk)",
        );
        l.uint(
            "reused_word",
            Output,
            wb,
            "the word written back when reused (sphere count refreshed), else 0",
        );
        l
    }

    fn adversarial(&self) -> Vec<HitRecordTxn> {
        let cfg = &self.cfg;
        let mut v: Vec<HitRecordTxn> = self
            .pack_cases()
            .into_iter()
            .map(|r| HitRecordTxn::still(r, cfg))
            .collect();
        let base = HitRecordTxn::still(self.rec(1, Some(3), 5 << 14, [3, -3], [200, 34, 42]), cfg);
        let mut with = |f: &dyn Fn(&mut HitRecordTxn)| {
            let mut t = base;
            f(&mut t);
            v.push(t);
        };
        with(&|_| {});
        with(&|t| t.check.buffer = false);
        with(&|t| t.check.camera_dirty = true);
        with(&|t| t.check.instance_dirty = true);
        for n in [0, 2, 3, 8, 255, 65535] {
            with(&|t| t.check.candidates = n);
        }
        for k in [2, 4, 255, 256 + 3, 65535] {
            with(&|t| t.check.candidate = k);
        }
        let wb = cfg.word_bits();
        let ones = if wb >= 128 {
            u128::MAX
        } else {
            (1u128 << wb) - 1
        };
        let none = u128::from(cfg.instance_none());
        for (prev, candidate) in [
            (ones, 0),
            (ones, 254),
            (ones, 65535),
            (0, 0),
            (0, 1),
            (ones & !(none << 2), 0), // every field saturated, instance 0
            (ones & !3, 7),           // kind 0, a miss
        ] {
            with(&|t| {
                t.prev = prev;
                t.check.candidate = candidate;
            });
        }
        for kind in 0..4u128 {
            with(&|t| t.prev = (t.prev & !3) | kind);
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> HitRecordTxn {
        let record = self.random_record(rng);
        let wb = self.cfg.word_bits();
        let mut ov = Overflows::new(&["hit_record"]);
        // Half the previous words are packed records (the buffer's real contents), half any
        // bits (reserved kinds and all).
        let prev = if rng.one_in(2) {
            let r = self.random_record(rng);
            pack(&r, &self.cfg, &mut ov, SignalId(0))
        } else {
            let lo = u128::from(rng.next_u64());
            let hi = u128::from(rng.next_u64());
            let w = lo | hi << 64;
            if wb >= 128 {
                w
            } else {
                w & ((1u128 << wb) - 1)
            }
        };
        let own = unpack(prev, &self.cfg).instance;
        let candidates = match rng.below(8) {
            0 => 0,
            1 => 2 + rng.below(7) as usize,
            _ => 1,
        };
        let candidate = if rng.one_in(2) {
            own.unwrap_or(0)
        } else {
            rng.below(u64::from(self.cfg.instance_none()) + 2) as u16
        };
        HitRecordTxn {
            record,
            prev,
            check: ReuseInputs {
                buffer: !rng.one_in(8),
                camera_dirty: rng.one_in(4),
                candidates,
                candidate,
                instance_dirty: rng.one_in(4),
            },
        }
    }

    fn encode(&self, txn: &HitRecordTxn) -> Vec<u128> {
        let r = &txn.record;
        let mut ov = Overflows::new(&["hit_record"]);
        let word = pack(r, &self.cfg, &mut ov, SignalId(0));
        let packed_ov = ov.total() > 0;
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
        let c = &txn.check;
        v.extend([
            txn.prev,
            b(c.buffer),
            b(c.camera_dirty),
            u(c.candidates.min(usize::from(u16::MAX)) as u64),
            u(u64::from(c.candidate)),
            b(c.instance_dirty),
        ]);
        v.push(word);
        v.push(b(packed_ov));
        let old = unpack(txn.prev, &self.cfg);
        v.extend([
            u(u64::from(old.kind.code())),
            b(old.instance.is_some()),
            u(u64::from(old.instance.unwrap_or(0))),
            s(old.t.raw),
            s(i64::from(old.normal[0])),
            s(i64::from(old.normal[1])),
        ]);
        v.extend(old.colour.map(|c| u(u64::from(c))));
        if self.cfg.include_voxel {
            v.extend(old.voxel.map(|c| u(u64::from(c))));
        }
        let mut ov = Overflows::new(&["hit_record"]);
        let reused = reuse(txn.prev, c, &self.cfg, &mut ov, SignalId(0));
        v.push(b(reused.is_some()));
        v.push(reused.unwrap_or(0));
        v
    }

    fn timing(&self) -> Option<Timing> {
        Some(Timing {
            // svo_hit_pack alone: the record stage's normal unit in front of it has its own
            // table (normal.hex).
            latency_cycles: crate::units::hit_record::PACK_WORD_LATENCY_CYCLES,
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
        let mut reused = 0;
        for txn in cases {
            let r = txn.record;
            let w = l.pack(&st.encode(&txn));
            // Independent check of the reuse rule and of the refreshed word: the previous
            // word's instance (bits 2..10) none or the one candidate, kind bits set to 1.
            let inst = (txn.prev >> 2) & 0xff;
            let c = txn.check;
            let want = c.buffer
                && !c.camera_dirty
                && !c.instance_dirty
                && c.candidates == 1
                && (inst == 0xff || inst == u128::from(c.candidate));
            assert_eq!(l.read(&w, "reuse"), Some(i128::from(want)), "{txn:?}");
            let refreshed = if want { (txn.prev & !3) | 1 } else { 0 };
            assert_eq!(l.read(&w, "reused_word"), Some(refreshed as i128));
            reused += usize::from(want);
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
        assert!(reused > 20);
    }
}
