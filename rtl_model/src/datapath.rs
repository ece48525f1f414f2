//! The datapath configuration: the format of every signal and the parameters of every unit,
//! in one RON-serialisable structure with a documented default (`docs/number-formats.md`).
//!
//! Pipeline position: read once per run; every unit takes its part. [`DatapathConfig::validate`]
//! checks each unit and that the units agree where one feeds another.

use crate::fixed::{Format, Overflows, Quant};
use crate::units::hit_record::HitRecordConfig;
use crate::units::reciprocal::ReciprocalConfig;
use crate::units::sorter::SorterConfig;
use crate::units::sphere::SphereConfig;
use crate::units::transform::TransformConfig;
use crate::units::walker::WalkerConfig;
use serde::{Deserialize, Serialize};

/// Ray generation's formats; declared by its unit (`units::raygen`) like every other
/// unit's configuration.
pub use crate::units::raygen::RaygenConfig;

/// Every format and parameter of the fixed-point datapath.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct DatapathConfig {
    /// Ray generation (direction table) and host-written world values.
    pub raygen: RaygenConfig,
    /// Bounding-sphere test.
    pub sphere: SphereConfig,
    /// Candidate sorter.
    pub sorter: SorterConfig,
    /// Ray transform into each instance's frame.
    pub transform: TransformConfig,
    /// 1/d per axis.
    pub reciprocal: ReciprocalConfig,
    /// Octree walker.
    pub walker: WalkerConfig,
    /// Hit-buffer record.
    pub hit_record: HitRecordConfig,
}

impl Default for WalkerConfig {
    /// Local positions as the transform's output (sQ8.32), reciprocals as the reciprocal
    /// unit's (sQ22.30), t in sQ31.31: |t| ≤ (2·128 m)·2^21 < 2^30 with 2^-31 m resolution.
    fn default() -> Self {
        Self {
            pos: Format::sq(8, 32).with_quant(Quant::RndConv),
            inv: Format::sq(22, 30).with_quant(Quant::RndConv),
            t: Format::sq(31, 31),
            max_steps: 100_000,
        }
    }
}

/// Names of the overflow signals, in the order of [`signals`].
pub const SIGNAL_NAMES: [&str; 13] = [
    "raygen/dir",
    "raygen/pos",
    "raygen/mat",
    "sphere/tca",
    "sphere/sq",
    "sphere/t_enter",
    "sphere/reach",
    "transform/origin",
    "transform/dir",
    "reciprocal/out",
    "walker/t",
    "walker/step_limit",
    "hit_record",
];

/// A fresh overflow table with every datapath signal.
pub fn overflow_table() -> Overflows {
    Overflows::new(&SIGNAL_NAMES)
}

/// Ids of the signals in [`overflow_table`].
pub mod signals {
    use crate::fixed::SignalId;
    /// raygen/dir
    pub const RAYGEN_DIR: SignalId = SignalId(0);
    /// raygen/pos
    pub const RAYGEN_POS: SignalId = SignalId(1);
    /// raygen/mat
    pub const RAYGEN_MAT: SignalId = SignalId(2);
    /// sphere/tca
    pub const SPHERE_TCA: SignalId = SignalId(3);
    /// sphere/sq
    pub const SPHERE_SQ: SignalId = SignalId(4);
    /// sphere/t_enter
    pub const SPHERE_T_ENTER: SignalId = SignalId(5);
    /// sphere/reach
    pub const SPHERE_REACH: SignalId = SignalId(6);
    /// transform/origin
    pub const TRANSFORM_ORIGIN: SignalId = SignalId(7);
    /// transform/dir
    pub const TRANSFORM_DIR: SignalId = SignalId(8);
    /// reciprocal/out
    pub const RECIPROCAL: SignalId = SignalId(9);
    /// walker/t
    pub const WALKER_T: SignalId = SignalId(10);
    /// walker/step_limit
    pub const WALKER_STEP_LIMIT: SignalId = SignalId(11);
    /// hit_record
    pub const HIT_RECORD: SignalId = SignalId(12);
}

impl DatapathConfig {
    /// Checks every unit, then every interface: a unit's input format must be the format its
    /// producer writes.
    pub fn validate(&self) -> Result<(), String> {
        self.validate_format_fields()?;
        for (name, f) in [
            ("raygen.dir", self.raygen.dir),
            ("raygen.pos", self.raygen.pos),
            ("raygen.mat", self.raygen.mat),
        ] {
            if !f.is_valid() || !f.signed {
                return Err(format!(
                    "{name}: format {} must be valid and signed",
                    f.name()
                ));
            }
        }
        self.sphere.validate()?;
        self.sorter.validate()?;
        self.transform.validate()?;
        self.reciprocal.validate()?;
        self.walker.validate()?;
        self.hit_record.validate()?;
        let same = |a: Format, b: Format, what: &str| {
            if (a.signed, a.width, a.frac) == (b.signed, b.width, b.frac) {
                Ok(())
            } else {
                Err(format!("{what}: {} ≠ {}", a.name(), b.name()))
            }
        };
        same(
            self.sphere.pos,
            self.raygen.pos,
            "sphere.pos must be raygen.pos",
        )?;
        same(
            self.sphere.dir,
            self.raygen.dir,
            "sphere.dir must be raygen.dir",
        )?;
        same(
            self.sorter.key,
            self.sphere.t_enter,
            "sorter.key must be sphere.t_enter",
        )?;
        same(
            self.transform.pos,
            self.raygen.pos,
            "transform.pos must be raygen.pos",
        )?;
        same(
            self.transform.dir,
            self.raygen.dir,
            "transform.dir must be raygen.dir",
        )?;
        same(
            self.transform.mat,
            self.raygen.mat,
            "transform.mat must be raygen.mat",
        )?;
        same(
            self.reciprocal.input,
            self.transform.local_dir,
            "reciprocal.input must be transform.local_dir",
        )?;
        same(
            self.walker.pos,
            self.transform.local_pos,
            "walker.pos must be transform.local_pos",
        )?;
        same(
            self.walker.inv,
            self.reciprocal.output,
            "walker.inv must be reciprocal.output",
        )?;
        Ok(())
    }
}

impl DatapathConfig {
    /// Every format field, by its path in the RON file: width 1..=64 ([`MAX_FORMAT_WIDTH`])
    /// and at most as many fraction bits as the word has bits. The fixed-point layer allows a
    /// binary point above the word (a format of tiny values), but no signal of this datapath
    /// is one, and a fraction count past the width is a typing slip whose first symptom would
    /// otherwise be a misleading interface mismatch between two formats.
    fn validate_format_fields(&self) -> Result<(), String> {
        let tree = serde_json::to_value(self).map_err(|e| e.to_string())?;
        let mut formats = Vec::new();
        collect_formats(&tree, String::new(), &mut formats);
        for (field, width, frac) in formats {
            if !(1..=i64::from(MAX_FORMAT_WIDTH)).contains(&width) {
                return Err(format!(
                    "{field}.width = {width} is out of range (1 to {MAX_FORMAT_WIDTH} bits)"
                ));
            }
            if frac > width {
                return Err(format!(
                    "{field}.frac = {frac} exceeds {field}.width = {width}: a format's fraction \
                     bits must fit in its word"
                ));
            }
        }
        Ok(())
    }
}

/// Widest format the fixed-point layer computes with (raw values are `i64`).
pub const MAX_FORMAT_WIDTH: u8 = 64;

/// (path, width, frac) of every object in `v` with both a `width` and a `frac` (a format).
fn collect_formats(v: &serde_json::Value, path: String, out: &mut Vec<(String, i64, i64)>) {
    let serde_json::Value::Object(map) = v else {
        return;
    };
    let num = |k: &str| map.get(k).and_then(serde_json::Value::as_i64);
    if let (Some(width), Some(frac)) = (num("width"), num("frac")) {
        out.push((path, width, frac));
        return;
    }
    for (k, child) in map {
        let sub = if path.is_empty() {
            k.clone()
        } else {
            format!("{path}.{k}")
        };
        collect_formats(child, sub, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fraction_beyond_the_width_is_invalid_and_named() {
        let mut dp = DatapathConfig::default();
        dp.raygen.pos.frac = 60;
        assert_eq!(
            dp.validate(),
            Err(
                "raygen.pos.frac = 60 exceeds raygen.pos.width = 40: a format's fraction bits \
                 must fit in its word"
                    .into()
            )
        );
        let mut dp = DatapathConfig::default();
        dp.walker.t.width = 0;
        assert_eq!(
            dp.validate(),
            Err("walker.t.width = 0 is out of range (1 to 64 bits)".into())
        );
        let mut dp = DatapathConfig::default();
        dp.sorter.key.width = 65;
        assert_eq!(
            dp.validate(),
            Err("sorter.key.width = 65 is out of range (1 to 64 bits)".into())
        );
    }

    #[test]
    fn default_is_consistent() {
        DatapathConfig::default().validate().unwrap();
        assert_eq!(SIGNAL_NAMES.len(), usize::from(signals::HIT_RECORD.0) + 1);
    }
}
