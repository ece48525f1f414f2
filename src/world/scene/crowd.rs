//! The procedural crowd: a `crowds: [(...)]` entry in a scene file that the loader expands into
//! `count` instances of the scene's own assets (shared: every instance of a model walks the
//! same SVO), each on its own straight path across a rectangular area while it turns about its
//! vertical axis, all drawn from a seeded generator (docs/scene-format.md §10, docs/instances.md).
//!
//! Pipeline position: scene loading, before validation — the expanded instances are checked as
//! if written by hand, so a renderer never sees the block.

use super::format::{InstanceKey, InstanceSpec, SceneFile};
use rtl_model::vectors::rng::Rng;
use serde::{Deserialize, Serialize};

/// Largest crowd (instance ids are 16 bits; 65,535 means "none").
pub const MAX_CROWD: u32 = 65_535;

/// One entry of a scene file's `crowds` list.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrowdSpec {
    /// Instances to generate (1 ..= 65,535 with the hand-written ones).
    pub count: u32,
    /// Seed of the generator: the same seed gives the same crowd.
    pub seed: u64,
    /// Side lengths (x, z) in metres of the area, centred on `centre`, where paths start.
    pub area: (f64, f64),
    /// Centre of the area (x, y, z); y is the height of every instance's centre.
    #[serde(default)]
    pub centre: [f64; 3],
    /// Asset names to draw from (uniformly).
    pub models: Vec<String>,
    /// Speed range (min, max) in metres per frame; each instance draws its own. (0, 0) keeps
    /// the crowd still.
    pub speed: (f64, f64),
    /// Fraction of the instances that move (0 ..= 1; the others stand still, unturned).
    #[serde(default = "one")]
    pub moving: f64,
    /// Largest turn rate in degrees per frame; each moving instance draws one in ±this.
    #[serde(default = "default_turn")]
    pub turn_deg: f64,
    /// Uniform scale of every instance.
    #[serde(default = "one")]
    pub scale: f64,
}

fn one() -> f64 {
    1.0
}

fn default_turn() -> f64 {
    3.0
}

impl CrowdSpec {
    /// Checks the block against the scene (`existing` hand-written instances); the message
    /// names the field.
    pub fn validate(&self, file: &SceneFile, existing: usize) -> Result<(), String> {
        let room = MAX_CROWD as usize - existing.min(MAX_CROWD as usize);
        if self.count == 0 || self.count as usize > room {
            return Err(format!(
                "crowd.count: {} is out of range (1 to {room} beside the {existing} other instance(s))",
                self.count
            ));
        }
        let (ax, az) = self.area;
        if !(ax.is_finite() && az.is_finite() && ax >= 0.0 && az >= 0.0) {
            return Err(format!(
                "crowd.area ({ax}, {az}) must be finite and non-negative"
            ));
        }
        if !self.centre.iter().all(|v| v.is_finite()) {
            return Err(format!("crowd.centre {:?} must be finite", self.centre));
        }
        if self.models.is_empty() {
            return Err("crowd.models: at least one asset name is needed".into());
        }
        for (i, m) in self.models.iter().enumerate() {
            if !file.assets.iter().any(|a| &a.name == m) {
                let known: Vec<_> = file.assets.iter().map(|a| a.name.as_str()).collect();
                return Err(format!(
                    "crowd.models[{i}]: unknown asset \"{m}\" (known: {})",
                    known.join(", ")
                ));
            }
        }
        let (s0, s1) = self.speed;
        if !(s0.is_finite() && s1.is_finite() && 0.0 <= s0 && s0 <= s1) {
            return Err(format!(
                "crowd.speed ({s0}, {s1}) must be finite with 0 ≤ min ≤ max"
            ));
        }
        if !(0.0..=1.0).contains(&self.moving) {
            return Err(format!(
                "crowd.moving {} must be within 0 and 1",
                self.moving
            ));
        }
        if !(self.turn_deg.is_finite() && self.turn_deg >= 0.0) {
            return Err(format!(
                "crowd.turn_deg {} must be finite and non-negative",
                self.turn_deg
            ));
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(format!("crowd.scale {} must be positive", self.scale));
        }
        Ok(())
    }

    /// The generated instances, named `crowd<k>`: each starts at a uniform point of the
    /// area with a uniform heading; a moving one goes `speed` metres per frame along its
    /// heading and turns at its own rate; two keys, frame 0 and the scene's last frame.
    pub fn expand(&self, frames: u32, first: usize) -> Vec<InstanceSpec> {
        // splitmix64, the generator of the vectors: the same crowd on every machine.
        let mut rng = Rng::new(self.seed);
        let last = f64::from(frames.saturating_sub(1).max(1));
        let [cx, cy, cz] = self.centre;
        (0..self.count)
            .map(|k| {
                let model = &self.models[(rng.below(self.models.len() as u64)) as usize];
                let x = cx + rng.range(-0.5, 0.5) * self.area.0;
                let z = cz + rng.range(-0.5, 0.5) * self.area.1;
                let heading = rng.range(0.0, 360.0);
                let moves = rng.range(0.0, 1.0) < self.moving;
                let speed = rng.range(self.speed.0, self.speed.1);
                let turn = rng.range(-1.0, 1.0) * self.turn_deg;
                let s = [self.scale; 3];
                let start = InstanceKey {
                    frame: 0.0,
                    translation: [x, cy, z],
                    rotation_deg: [0.0, heading, 0.0],
                    scale: s,
                };
                let keys = if moves {
                    // The model's forward axis is its local z; yaw h turns it to (sin h, cos h).
                    let h = heading.to_radians();
                    let (dx, dz) = (h.sin() * speed * last, h.cos() * speed * last);
                    vec![
                        start.clone(),
                        InstanceKey {
                            frame: last,
                            translation: [x + dx, cy, z + dz],
                            rotation_deg: [0.0, heading + turn * last, 0.0],
                            scale: s,
                        },
                    ]
                } else {
                    vec![start]
                };
                InstanceSpec {
                    name: format!("crowd{}", first + k as usize),
                    asset: model.clone(),
                    pivot: [0.0; 3],
                    keys,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_crowd_other_seed_other_crowd() {
        let file: SceneFile = ron::from_str(
            r#"(resolution: (8, 8), frames: 4, camera: [(frame: 0, position: (0, 1, 9), look_at: (0, 0, 0), vfov_deg: 40)],
               assets: [(name: "b", depth: 3, source: Sdf(shape: Sphere(radius: 0.5)))], instances: [])"#,
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let spec = CrowdSpec {
            count: 50,
            seed: 3,
            area: (20.0, 10.0),
            centre: [0.0; 3],
            models: vec!["b".into()],
            speed: (0.1, 0.2),
            moving: 0.5,
            turn_deg: 2.0,
            scale: 1.0,
        };
        assert!(spec.validate(&file, 0).is_ok());
        let a = spec.expand(4, 0);
        assert_eq!(a, spec.expand(4, 0));
        assert_eq!(a.len(), 50);
        let movers = a.iter().filter(|i| i.keys.len() == 2).count();
        assert!((10..=40).contains(&movers), "{movers}");
        assert!(a.iter().all(|i| i.keys[0].translation[0].abs() <= 10.0));
        assert_ne!(
            a,
            CrowdSpec {
                seed: 4,
                ..spec.clone()
            }
            .expand(4, 0)
        );
        let bad = CrowdSpec {
            models: vec!["nope".into()],
            ..spec.clone()
        };
        assert!(bad
            .validate(&file, 0)
            .unwrap_err()
            .contains("crowd.models[0]"));
        let bad = CrowdSpec {
            speed: (2.0, 1.0),
            ..spec.clone()
        };
        assert!(bad
            .validate(&file, 0)
            .unwrap_err()
            .starts_with("crowd.speed"));
        let bad = CrowdSpec { count: 0, ..spec };
        assert!(bad
            .validate(&file, 0)
            .unwrap_err()
            .starts_with("crowd.count"));
    }
}
