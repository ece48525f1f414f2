//! `sim vectors`: HDL test vectors of every pipeline stage, from adversarial cases, a real
//! frame of a scene and seeded random stimulus, with manifests and SystemVerilog packages
//! (`docs/vectors.md`).
//!
//! Pipeline position: beside the run. [`capture`] replays a small frame through the
//! fixed-point units recording each unit's transactions; `rtl_model::vectors` turns them
//! into tables whose expected outputs come from the golden model; [`generate`] assembles all
//! files in memory and [`write_files`] writes them, each atomically, only after everything
//! was generated without error.

pub mod capture;
pub mod command;

use crate::error::{AssetError, SceneError};
use crate::output::writer::{refuse_stdout_folder, write_whole, OutputError};
use crate::world::assets::{build_assets, effective_depths, Materialise};
use crate::world::scene::Scene;
use rtl_model::cycle::hw_config::{HwConfig, UnitTimings};
use rtl_model::datapath::DatapathConfig;
use rtl_model::vectors::files::{table_files, VectorFile, FORMAT_VERSION};
use rtl_model::vectors::frame::frame_tables;
use rtl_model::vectors::lanes::{set_walk_lanes, units_of, MAX_WALK_LANES};
use rtl_model::vectors::stage::walker::{file_stem, NamedImage};
use rtl_model::vectors::table::{Origin, VectorTable};
use rtl_model::vectors::{unit_tables, VectorError, RTL_UNITS};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Most rows per stage `--count` may ask for (files grow by about 200 bytes per row and
/// stage).
pub const MAX_COUNT: usize = 1_000_000;
/// Largest side of the captured frame.
pub const MAX_FRAME_SIDE: u32 = 512;

/// Why vectors could not be generated or written.
#[derive(Debug, Error)]
pub enum VectorsError {
    /// A bad option value.
    #[error("{0}")]
    Option(String),
    /// The scene could not be loaded or resized.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// An asset could not be built.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// The frame's state could not be computed.
    #[error("frame {frame}: {message}")]
    Frame {
        /// Frame number.
        frame: u32,
        /// Why.
        message: String,
    },
    /// An asset has no memory image.
    #[error("asset \"{0}\" has no memory image (it is walked implicitly); the vectors need a materialised octree: use a smaller --depth")]
    Implicit(String),
    /// The datapath configuration is inconsistent.
    #[error("datapath configuration: {0}")]
    Datapath(String),
    /// The vector encoder failed.
    #[error(transparent)]
    Vectors(#[from] VectorError),
    /// The scene could not be elaborated.
    #[error(transparent)]
    Elaborate(#[from] crate::run::elaborate::ElaborateError),
    /// A file could not be written (the one output writer's error names it).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The output folder or a file could not be written.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
}

/// What to generate.
#[derive(Clone, Debug, PartialEq)]
pub struct VectorsOptions {
    /// Scene file; `None` is the embedded default (the animated car).
    pub scene: Option<PathBuf>,
    /// Rows per stage beyond the adversarial ones (half captured, half random).
    pub count: usize,
    /// Seed of the random rows.
    pub seed: u64,
    /// Frame captured.
    pub frame: u32,
    /// Size of the captured frame.
    pub width: u32,
    /// Height of the captured frame.
    pub height: u32,
    /// Depth of the deepest asset (`None`: the scene's depths).
    pub depth: Option<u8>,
    /// Largest `.vox` asset file read, bytes (`--max-vox-mib`).
    pub max_vox_bytes: u64,
    /// Walk-issue lanes k (`--walk-lanes`): the transform, reciprocal and walker-root tables
    /// are for k transforms, 3k reciprocals and k roots side by side
    /// (`rtl_model::vectors::lanes`), and the recorded elaboration is against the default
    /// hardware with k lanes. Default: the default hardware's lanes (2 since issue 28).
    pub walk_lanes: u32,
    /// The datapath every table is for (`--datapath`; default: the documented default).
    pub datapath: DatapathConfig,
}

impl Default for VectorsOptions {
    fn default() -> Self {
        Self {
            scene: None,
            count: 10_000,
            seed: 1,
            frame: 0,
            width: 32,
            height: 20,
            depth: None,
            max_vox_bytes: crate::input::DEFAULT_VOX_CAP_BYTES,
            walk_lanes: HwConfig::default().walk_lanes(),
            datapath: DatapathConfig::default(),
        }
    }
}

impl VectorsOptions {
    /// Checks the option ranges.
    pub fn validate(&self) -> Result<(), VectorsError> {
        if self.count == 0 || self.count > MAX_COUNT {
            return Err(VectorsError::Option(format!(
                "--count {} is out of range (1 to {MAX_COUNT})",
                self.count
            )));
        }
        for (name, v) in [("--width", self.width), ("--height", self.height)] {
            if v == 0 || v > MAX_FRAME_SIDE {
                return Err(VectorsError::Option(format!(
                    "{name} {v} is out of range (1 to {MAX_FRAME_SIDE}): the vectors capture a small frame"
                )));
            }
        }
        if self.walk_lanes == 0 || self.walk_lanes > MAX_WALK_LANES {
            return Err(VectorsError::Option(format!(
                "--walk-lanes {} is out of range (1 to {MAX_WALK_LANES})",
                self.walk_lanes
            )));
        }
        Ok(())
    }
}

/// A summary line per table, for the CLI.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TableSummary {
    /// Table name.
    pub name: String,
    /// Rows (adversarial, captured, random, memory).
    pub rows: [usize; 4],
    /// Bits per row.
    pub word_bits: u32,
    /// Latency the manifest states, if any.
    pub latency: Option<u32>,
}

/// Everything `sim vectors` writes, in memory.
pub struct VectorSet {
    /// The files, in a fixed order.
    pub files: Vec<VectorFile>,
    /// One summary per table.
    pub tables: Vec<TableSummary>,
}

/// Generates the whole vector set for `opts` (nothing touches the disk).
pub fn generate(opts: &VectorsOptions) -> Result<VectorSet, VectorsError> {
    opts.validate()?;
    let dp = opts.datapath.clone();
    let mut scene = match &opts.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::default_car()?,
    };
    scene.max_vox_bytes = opts.max_vox_bytes;
    if scene.file.resolution != (opts.width, opts.height) {
        scene.set_resolution(opts.width, opts.height)?;
    }
    if opts.frame >= scene.file.frames {
        return Err(VectorsError::Option(format!(
            "--frame {} is out of range: the scene has {} frames (0 to {})",
            opts.frame,
            scene.file.frames,
            scene.file.frames - 1
        )));
    }
    let depths = effective_depths(&scene, opts.depth)?;
    let assets = build_assets(&scene, &depths, Materialise::Auto)?;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let state = scene
        .frame_state(opts.frame, &half)
        .map_err(|message| VectorsError::Frame {
            frame: opts.frame,
            message,
        })?;
    let cap = capture::capture_frame(&scene, &assets, &state, &dp)?;
    let mut images = Vec::with_capacity(assets.len());
    for (i, a) in assets.iter().enumerate() {
        let image = a
            .image()
            .ok_or_else(|| VectorsError::Implicit(a.name.clone()))?;
        images.push(NamedImage {
            name: format!("{i}_{}", file_stem(&a.name)),
            image: image.clone(),
        });
    }
    let mut tables = unit_tables(&dp, &cap.captured, images, opts.count, opts.seed)?;
    set_walk_lanes(&mut tables, opts.walk_lanes);
    tables.extend(frame_tables(
        &dp,
        cap.origin,
        cap.miss_word,
        (opts.width, opts.height),
        &cap.instances,
        &cap.pixels,
    ));
    let mut files = Vec::new();
    for t in &tables {
        files.extend(table_files(t).map_err(VectorError::from)?);
    }
    // The manifest records what the scene's elaborated pipeline keeps (with the default
    // hardware, k walk-issue lanes wide); the unit vectors themselves exercise every unit at
    // its full size.
    let mut hw = rtl_model::cycle::hw_config::HwConfig::for_datapath(&dp);
    hw.transform_units = opts.walk_lanes;
    hw.reciprocal_units = 3 * opts.walk_lanes;
    hw.walker_root_units = opts.walk_lanes;
    let elab = crate::run::elaborate::elaborate(&scene, opts.depth, &hw, &dp, true)?;
    files.push(index_file(opts, &scene, &depths, &dp, &tables, &elab)?);
    Ok(VectorSet {
        files,
        tables: tables.iter().map(summary).collect(),
    })
}

fn summary(t: &VectorTable) -> TableSummary {
    TableSummary {
        name: t.name.clone(),
        rows: [
            Origin::Adversarial,
            Origin::Captured,
            Origin::Random,
            Origin::Table,
        ]
        .map(|o| t.count(o)),
        word_bits: t.layout.word_bits(),
        latency: t.timing.map(|tm| tm.latency_cycles),
    }
}

/// `index.json`: how the set was made and what each file is.
fn index_file(
    opts: &VectorsOptions,
    scene: &Scene,
    depths: &[u8],
    dp: &DatapathConfig,
    tables: &[VectorTable],
    elaboration: &crate::run::elaborate::Elaboration,
) -> Result<VectorFile, VectorsError> {
    let list: Vec<serde_json::Value> = tables
        .iter()
        .map(|t| {
            let mut entry = serde_json::json!({
                "name": t.name,
                "hex_file": format!("{}.hex", t.name),
                "manifest": format!("{}.json", t.name),
                "package_file": t.package.then(|| format!("{}_pkg.sv", t.name)),
                "rows": t.rows.len(),
                "word_bits": t.layout.word_bits(),
                "description": t.description,
            });
            // A walk-issue unit's table says how many instances its bench drives.
            if let (Some(units), Some(obj)) =
                (units_of(&t.name, opts.walk_lanes), entry.as_object_mut())
            {
                obj.insert("units".into(), units.into());
            }
            entry
        })
        .collect();
    let index = serde_json::json!({
        "format_version": FORMAT_VERSION,
        "generator": "sim vectors (svo_sim); docs/vectors.md",
        "scene": scene.origin,
        "frame": opts.frame,
        "width": opts.width,
        "height": opts.height,
        "asset_depths": depths,
        "count": opts.count,
        "seed": opts.seed,
        "walk_lanes": opts.walk_lanes,
        "rtl_units": RTL_UNITS,
        "unit_timings": UnitTimings::for_datapath(dp),
        "datapath": dp,
        "cycle_logs": serde_json::Value::Array(Vec::new()),
        "elaboration": elaboration,
        "tables": list,
    });
    let mut text = serde_json::to_string_pretty(&index).map_err(VectorError::from)?;
    text.push('\n');
    Ok(VectorFile {
        name: "index.json".into(),
        bytes: text.into_bytes(),
    })
}

/// Writes every file into `dir` (created if missing), each atomically.
pub fn write_files(dir: &Path, files: &[VectorFile]) -> Result<(), VectorsError> {
    let io = |path: &Path, source| VectorsError::Io {
        path: path.display().to_string(),
        source,
    };
    refuse_stdout_folder("--out", dir)?;
    if dir.exists() && !dir.is_dir() {
        return Err(VectorsError::Option(format!(
            "--out {} is a file, not a folder",
            dir.display()
        )));
    }
    std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    for f in files {
        let p = dir.join(&f.name);
        write_whole(&p, &f.bytes)?;
    }
    Ok(())
}
