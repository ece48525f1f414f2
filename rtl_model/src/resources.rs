//! The resource estimate as the report prints it: resources in the three counted kinds
//! (DSP48E2, BRAM36, URAM288), one line per component, and their sum against the part's
//! budget.
//!
//! Pipeline position: the output of [`HwConfig::resources`](crate::cycle::hw_config::HwConfig::resources)
//! (`cost::estimate`); `sim hardware`, the run report, `sim sweep` and the elaboration's
//! savings read it. Plain types with no dependency on the rest of the crate, so that a unit
//! can price its own memory (`units::tile_list::resource_item`) and `cost` can add the lines
//! up, without a unit importing `cost` (docs/architecture.md §1).

use serde::{Deserialize, Serialize};
use std::fmt;

/// Resources in the three counted kinds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Resources {
    /// DSP48E2 slices.
    pub dsp48e2: u64,
    /// BRAM36 blocks.
    pub bram36: u64,
    /// URAM288 blocks.
    pub uram288: u64,
}

impl Resources {
    /// `n` DSP48E2 slices and nothing else.
    pub const fn dsp48e2(n: u64) -> Self {
        Self {
            dsp48e2: n,
            bram36: 0,
            uram288: 0,
        }
    }

    /// `n` BRAM36 blocks and nothing else.
    pub const fn bram36(n: u64) -> Self {
        Self {
            dsp48e2: 0,
            bram36: n,
            uram288: 0,
        }
    }

    /// `n` URAM288 blocks and nothing else.
    pub const fn uram288(n: u64) -> Self {
        Self {
            dsp48e2: 0,
            bram36: 0,
            uram288: n,
        }
    }

    /// The sum of two estimates (saturating).
    pub fn saturating_add(self, o: Self) -> Self {
        Self {
            dsp48e2: self.dsp48e2.saturating_add(o.dsp48e2),
            bram36: self.bram36.saturating_add(o.bram36),
            uram288: self.uram288.saturating_add(o.uram288),
        }
    }

    /// What `self` needs beyond `o`, per kind (0 where `o` needs more): the saving of a
    /// configuration estimated at `o` against one estimated at `self`.
    pub fn saturating_sub(self, o: Self) -> Self {
        Self {
            dsp48e2: self.dsp48e2.saturating_sub(o.dsp48e2),
            bram36: self.bram36.saturating_sub(o.bram36),
            uram288: self.uram288.saturating_sub(o.uram288),
        }
    }
}

/// One line of the estimate: a component, how many instances, and what they take in all.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ResourceItem {
    /// Component name (`sphere`, `walker_stacks`, `hit_buffer`, …).
    pub name: String,
    /// Instances (lanes, units, walkers, banks; 1 for a single memory).
    pub instances: u64,
    /// Resources of all instances together.
    pub used: Resources,
    /// How the number was obtained.
    pub note: String,
}

impl ResourceItem {
    /// A line of the estimate: `instances` of component `name` take `used` in all; `note`
    /// says how.
    pub fn new(name: &str, instances: u64, used: Resources, note: String) -> Self {
        Self {
            name: name.into(),
            instances,
            used,
            note,
        }
    }
}

/// Estimated use of a configuration against its part's budget.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ResourceReport {
    /// Part name.
    pub part: String,
    /// The estimate component by component.
    pub items: Vec<ResourceItem>,
    /// Sum of the items.
    pub used: Resources,
    /// The part's budget.
    pub available: Resources,
}

impl ResourceReport {
    /// Adds a component the configuration does not describe itself (the tile-list memory of
    /// the two-level instance scheme, which elaboration decides per scene) and its use to the
    /// total.
    pub fn push(&mut self, item: ResourceItem) {
        self.used = self.used.saturating_add(item.used);
        self.items.push(item);
    }

    /// The resources of the items named `names` together (an absent name counts nothing).
    pub fn sum_of(&self, names: &[&str]) -> Resources {
        self.items
            .iter()
            .filter(|i| names.contains(&i.name.as_str()))
            .fold(Resources::default(), |a, i| a.saturating_add(i.used))
    }

    /// Whether every kind fits the part.
    pub fn fits(&self) -> bool {
        self.over_budget().is_empty()
    }

    /// A message per kind that exceeds the part ("URAM288: 1200 used, 960 available").
    pub fn over_budget(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (kind, used, avail) in self.kinds() {
            if used > avail {
                out.push(format!(
                    "{kind}: {used} used, {avail} available on {}",
                    self.part
                ));
            }
        }
        out
    }

    /// Percent of the part used per kind (DSP48E2, BRAM36, URAM288); 0 % of nothing is 0,
    /// any use of nothing is +∞.
    pub fn percent(&self) -> [f64; 3] {
        self.kinds().map(|(_, u, a)| percent(u, a))
    }

    fn kinds(&self) -> [(&'static str, u64, u64); 3] {
        [
            ("DSP48E2", self.used.dsp48e2, self.available.dsp48e2),
            ("BRAM36", self.used.bram36, self.available.bram36),
            ("URAM288", self.used.uram288, self.available.uram288),
        ]
    }
}

fn percent(used: u64, avail: u64) -> f64 {
    if avail == 0 {
        if used == 0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        100.0 * used as f64 / avail as f64
    }
}

impl fmt::Display for ResourceReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "resources on {} (estimate):", self.part)?;
        writeln!(
            f,
            "  {:<16} {:>5} {:>8} {:>8} {:>8}  note",
            "component", "n", "DSP48E2", "BRAM36", "URAM288"
        )?;
        for it in &self.items {
            writeln!(
                f,
                "  {:<16} {:>5} {:>8} {:>8} {:>8}  {}",
                it.name, it.instances, it.used.dsp48e2, it.used.bram36, it.used.uram288, it.note
            )?;
        }
        let p = self.percent();
        writeln!(
            f,
            "  {:<16} {:>5} {:>8} {:>8} {:>8}",
            "used", "", self.used.dsp48e2, self.used.bram36, self.used.uram288
        )?;
        writeln!(
            f,
            "  {:<16} {:>5} {:>8} {:>8} {:>8}",
            "available", "", self.available.dsp48e2, self.available.bram36, self.available.uram288
        )?;
        // A kind the part lacks shows as "none" rather than an infinite percentage.
        let pct = |x: f64| {
            if x.is_finite() {
                format!("{x:.1}%")
            } else {
                "none".to_string()
            }
        };
        write!(
            f,
            "  {:<16} {:>5} {:>8} {:>8} {:>8}  {}",
            "utilisation",
            "",
            pct(p[0]),
            pct(p[1]),
            pct(p[2]),
            if self.fits() {
                "fits".to_string()
            } else {
                format!("DOES NOT FIT: {}", self.over_budget().join("; "))
            }
        )
    }
}
