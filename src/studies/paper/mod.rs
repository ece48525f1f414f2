//! `sim paper`: the paper's own experiment (Espe et al. 2019, Fig. 7) on this model — the
//! static car as one SVO against the animated car without and with §4's optimisations, timed
//! by the f64 reference (wall time, best of N) and by the cycle model (frames per second at
//! the hardware clock), at one or more resolutions (docs/paper.md).
//!
//! Pipeline position: a study over the run layer's inputs: it builds the two scenes
//! (`scenes/car_static.ron`, `scenes/car.ron`, both compiled in) once per resolution, renders
//! each case over the animation with [`crate::models::reference::render_frame`] and
//! [`crate::models::cycle::runner::CycleRun`], and writes a table (text, CSV, JSON) and a bar
//! chart through `output::writer`.

pub mod cases;
pub mod command;
pub mod measure;
pub mod plot;
