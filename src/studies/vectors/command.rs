//! The `sim vectors` command: options as plain data (the command line, `src/bin/sim/vectors.rs`,
//! parses them) and the driver that generates, writes and tabulates the set.

use super::{generate, write_files, VectorsOptions};
use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `sim vectors`.
#[derive(Debug, Clone)]
pub struct VectorsCommand {
    /// Folder for the vector files (created if missing; existing files of the same names
    /// are replaced).
    pub out: PathBuf,
    /// Scene file (RON) whose frame is captured; default: the embedded animated car.
    pub scene: Option<PathBuf>,
    /// Rows per stage besides the adversarial ones: half captured from the frame (or as many
    /// as it offers), the rest random.
    pub count: u64,
    /// Seed of the random rows: the same seed and options give byte-identical files.
    pub seed: u64,
    /// Frame of the scene to capture.
    pub frame: u32,
    /// Width of the captured frame, pixels (also the end-to-end frame).
    pub width: u32,
    /// Height of the captured frame, pixels.
    pub height: u32,
    /// Octree depth of the deepest asset (the others keep their offset); default: the
    /// scene's. The memory images are written too, so small depths keep the set small.
    pub depth: Option<u8>,
    /// Largest `.vox` asset file read, bytes (`--max-vox-mib`).
    pub max_vox_bytes: u64,
    /// Walk-issue lanes the transform and reciprocal tables are for (`--walk-lanes`).
    pub walk_lanes: u32,
    /// Datapath file (`--datapath`); `None`: the documented default.
    pub datapath: Option<PathBuf>,
}

/// Runs `sim vectors`: generates everything, then writes it, then prints a table per stage.
pub fn run_command(a: &VectorsCommand) -> Result<()> {
    let opts = VectorsOptions {
        scene: a.scene.clone(),
        count: usize::try_from(a.count).context("--count does not fit this machine")?,
        seed: a.seed,
        frame: a.frame,
        width: a.width,
        height: a.height,
        depth: a.depth,
        max_vox_bytes: a.max_vox_bytes,
        walk_lanes: a.walk_lanes,
        datapath: crate::run::config_files::load_datapath(a.datapath.as_deref())?,
    };
    // An --out that cannot be a folder fails before any work (write_files checks it again).
    crate::output::writer::refuse_stdout_folder("--out", &a.out)?;
    if a.out.exists() && !a.out.is_dir() {
        anyhow::bail!("--out {} is a file, not a folder", a.out.display());
    }
    let set = generate(&opts)?;
    write_files(&a.out, &set.files)?;
    println!(
        "sim vectors: {} files in {} (seed {}, {} rows per stage beyond the adversarial ones)",
        set.files.len(),
        a.out.display(),
        opts.seed,
        opts.count
    );
    println!(
        "  {:<22} {:>11} {:>9} {:>8} {:>8} {:>6} {:>8}",
        "table", "adversarial", "captured", "random", "memory", "bits", "latency"
    );
    for t in &set.tables {
        println!(
            "  {:<22} {:>11} {:>9} {:>8} {:>8} {:>6} {:>8}",
            t.name,
            t.rows[0],
            t.rows[1],
            t.rows[2],
            t.rows[3],
            t.word_bits,
            t.latency.map_or("-".to_string(), |l| l.to_string())
        );
    }
    Ok(())
}
