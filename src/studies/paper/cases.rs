//! The four cases of the paper's Fig. 7 as this model runs them: the scene and the switches.
//!
//! Pipeline position: the input of [`super::measure`]. (a) and (c) are the paper's static and
//! optimised animated cars, (b) its animated car with none of §4's optimisations; (a') adds
//! the hit buffer to the static car, which the paper did not run (its static case had no
//! animation, hence nothing to reuse across frames in its implementation).

use crate::models::reference::RenderOptions;
use serde::Serialize;

/// RON of the static car: `scenes/car_static.ron`, compiled in.
pub const CAR_STATIC_RON: &str = include_str!("../../../scenes/car_static.ron");

/// Which car a case renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Car {
    /// The eight parts at frame 0 in one SVO (`scenes/car_static.ron`).
    Static,
    /// The animated car of eight SVOs (`scenes/car.ron`, the default scene).
    Animated,
}

/// One case of the experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Case {
    /// Short id: "a", "a'", "b", "c".
    pub id: &'static str,
    /// What it is, for tables and the chart's legend.
    pub label: &'static str,
    /// The scene.
    pub car: Car,
    /// The switches.
    pub options: RenderOptions,
}

/// The four cases, in the table's order.
pub fn cases() -> [Case; 4] {
    let d = RenderOptions::default();
    [
        Case {
            id: "a",
            label: "static, one SVO",
            car: Car::Static,
            options: RenderOptions {
                use_hit_buffer: false,
                ..d
            },
        },
        Case {
            id: "a'",
            label: "static, one SVO, hit buffer",
            car: Car::Static,
            options: d,
        },
        Case {
            id: "b",
            label: "animated, no optimisation",
            car: Car::Animated,
            options: RenderOptions::NONE,
        },
        Case {
            id: "c",
            label: "animated, all optimisations",
            car: Car::Animated,
            options: d,
        },
    ]
}

/// The switches of a case as the command line spells them.
pub fn flags(o: &RenderOptions) -> String {
    let mut v = Vec::new();
    if !o.culling {
        v.push("--no-culling");
    }
    if !o.sort {
        v.push("--no-sort");
    }
    if !o.early_termination {
        v.push("--no-early-termination");
    }
    if !o.use_hit_buffer {
        v.push("--no-hit-buffer");
    }
    if v.is_empty() {
        "(defaults)".into()
    } else {
        v.join(" ")
    }
}
