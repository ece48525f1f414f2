//! `sim vectors`: parses the options and runs `svo_sim::studies::vectors::command`.

use anyhow::Result;
use clap::Args;
use rtl_model::cycle::hw_config::HwConfig;
use std::path::PathBuf;
use svo_sim::studies::vectors;
use svo_sim::studies::vectors::command::VectorsCommand;
use svo_sim::studies::vectors::MAX_COUNT;

/// Options of `sim vectors`.
#[derive(Args, Debug, Clone)]
pub struct VectorsArgs {
    /// Folder for the vector files (created if missing; existing files of the same names
    /// are replaced).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Scene file (RON) whose frame is captured; default: the embedded animated car.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Rows per stage besides the adversarial ones: half captured from the frame (or as many
    /// as it offers), the rest random.
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..=MAX_COUNT as u64))]
    count: u64,
    /// Seed of the random rows: the same seed and options give byte-identical files.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Frame of the scene to capture.
    #[arg(long, default_value_t = 0)]
    frame: u32,
    /// Width of the captured frame, pixels (also the end-to-end frame).
    #[arg(long, default_value_t = 32)]
    width: u32,
    /// Height of the captured frame, pixels.
    #[arg(long, default_value_t = 20)]
    height: u32,
    /// Octree depth of the deepest asset (the others keep their offset); default: the
    /// scene's. The memory images are written too, so small depths keep the set small.
    #[arg(long)]
    depth: Option<u8>,
    /// Largest `.vox` asset file read, MiB (1 to 65536); a larger one is refused without
    /// reading past the limit.
    #[arg(long, value_name = "MIB", default_value_t = crate::args::DEFAULT_VOX_MIB)]
    max_vox_mib: u64,
    /// Walk-issue lanes k (docs/cycle-model.md §2.1): the transform, reciprocal and walker-root
    /// tables are for k transforms, 3k reciprocals and k roots side by side (package `UNITS`,
    /// row i to unit i mod UNITS), and index.json's elaboration is against the default
    /// hardware k wide. Default: the default hardware's lanes (2).
    #[arg(long, value_name = "K", default_value_t = HwConfig::default().walk_lanes())]
    walk_lanes: u32,
    /// Datapath the vectors are for (RON, as printed by `sim datapath`); default: the
    /// documented default. Every table follows it, e.g. the sorter's rows hold 4N keys and
    /// its package the model's N-lane network (NET_PAIRS).
    #[arg(long, value_name = "FILE")]
    datapath: Option<PathBuf>,
}

/// Runs `sim vectors`.
pub fn vectors_command(a: VectorsArgs) -> Result<()> {
    vectors::command::run_command(&VectorsCommand {
        out: a.out,
        scene: a.scene,
        count: a.count,
        seed: a.seed,
        frame: a.frame,
        width: a.width,
        height: a.height,
        depth: a.depth,
        max_vox_bytes: crate::args::vox_cap_bytes(a.max_vox_mib)?,
        walk_lanes: a.walk_lanes,
        datapath: a.datapath,
    })
}
