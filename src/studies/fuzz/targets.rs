//! The parsers under fuzz and what each does with an input it accepts.
//!
//! Pipeline position: in front of the pipeline — the `.vox` loader (asset preparation), the
//! scene RON (what is animated), and the hardware and datapath RON (what is modelled). Each
//! target runs the same entry points the `sim` commands use, and for an accepted input also
//! the first computation that consumes it (the scene's animation and range check, the cost
//! and bound text of a configuration), because a parser that accepts a value the next stage
//! cannot handle is the failure a user would meet.

use crate::output::config_text::{datapath_text, hardware_text};
use crate::run::config_files::{datapath_from_text, hardware_from_text};
use crate::run::ranges::check_scene_ranges;
use crate::world::assets::vox::load_vox_bytes;
use crate::world::scene::Scene;
use rtl_model::datapath::DatapathConfig;
use std::path::Path;

/// A parser under fuzz.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Target {
    /// MagicaVoxel `.vox` files (`load_vox_bytes`, depth chosen by the loader).
    Vox,
    /// Scene RON (`Scene::from_ron`), then every frame's camera and poses and the range check.
    Scene,
    /// Hardware RON (`--hw`), then its resource estimate (`sim hardware`'s text).
    Hardware,
    /// Datapath RON (`--datapath`), then its costs and error bounds (`sim datapath`'s text).
    Datapath,
}

/// Most (frame × instance) pairs the scene target animates for one input; a valid scene may
/// have a million frames, and animating all of them is a long run, not a parser bug.
const MAX_ANIMATED: u64 = 100_000;

impl Target {
    /// All targets, in report order.
    pub const ALL: [Target; 4] = [
        Target::Vox,
        Target::Scene,
        Target::Hardware,
        Target::Datapath,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Target::Vox => "vox",
            Target::Scene => "scene",
            Target::Hardware => "hardware",
            Target::Datapath => "datapath",
        }
    }

    /// The target called `name`.
    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Whether inputs are text (RON), so that token-level mutations apply.
    pub fn is_text(self) -> bool {
        self != Target::Vox
    }

    /// Runs one input; `Err` carries the error text the user would see.
    pub fn run(self, input: &[u8]) -> Result<(), String> {
        let name = Path::new("<fuzz input>");
        match self {
            Target::Vox => load_vox_bytes(input, name, None)
                .map(|_| ())
                .map_err(|e| e.to_string()),
            Target::Scene => run_scene(input),
            Target::Hardware => {
                let hw = hardware_from_text(&text(input)?, name).map_err(|e| e.to_string())?;
                let (_, res) = hardware_text(&hw, &DatapathConfig::default());
                res.map(|_| ()).map_err(|e| e.to_string())
            }
            Target::Datapath => {
                let dp = datapath_from_text(&text(input)?, name).map_err(|e| e.to_string())?;
                datapath_text(&dp).map(|_| ()).map_err(|e| e.to_string())
            }
        }
    }
}

fn text(input: &[u8]) -> Result<String, String> {
    String::from_utf8(input.to_vec()).map_err(|e| format!("not UTF-8: {e}"))
}

fn run_scene(input: &[u8]) -> Result<(), String> {
    let scene = Scene::from_ron(&text(input)?, "<fuzz input>", Path::new("."))
        .map_err(|e| e.to_string())?;
    // Assets are not built (a scene may name files that do not exist here); a 1 m half size
    // stands in for each, which exercises the same pose and range arithmetic.
    let half = vec![1.0; scene.file.assets.len()];
    let frames = scene.file.frames;
    let work = u64::from(frames) * (scene.file.instances.len() as u64).max(1);
    if work <= MAX_ANIMATED {
        check_scene_ranges(&scene, &half, &DatapathConfig::default()).map_err(|e| e.to_string())?;
    } else {
        for f in [0, frames / 2, frames - 1] {
            scene.frame_state(f, &half)?;
        }
    }
    Ok(())
}
