//! The `sim vectors` subcommand's arguments and driver (the binary only dispatches to it).

use super::{generate, write_files, VectorsOptions, MAX_COUNT};
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `sim vectors`.
#[derive(Args, Debug, Clone)]
pub struct VectorsArgs {
    /// Folder for the vector files (created if missing; existing files of the same names
    /// are replaced).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Scene file (RON) whose frame is captured; default: the embedded animated car.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Rows per stage besides the adversarial ones: half captured from the frame (or as many
    /// as it offers), the rest random.
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..=MAX_COUNT as u64))]
    pub count: u64,
    /// Seed of the random rows: the same seed and options give byte-identical files.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Frame of the scene to capture.
    #[arg(long, default_value_t = 0)]
    pub frame: u32,
    /// Width of the captured frame, pixels (also the end-to-end frame).
    #[arg(long, default_value_t = 32)]
    pub width: u32,
    /// Height of the captured frame, pixels.
    #[arg(long, default_value_t = 20)]
    pub height: u32,
    /// Octree depth of the deepest asset (the others keep their offset); default: the
    /// scene's. The memory images are written too, so small depths keep the set small.
    #[arg(long)]
    pub depth: Option<u8>,
}

/// Runs `sim vectors`: generates everything, then writes it, then prints a table per stage.
pub fn run(a: VectorsArgs) -> Result<()> {
    let opts = VectorsOptions {
        scene: a.scene.clone(),
        count: usize::try_from(a.count).context("--count does not fit this machine")?,
        seed: a.seed,
        frame: a.frame,
        width: a.width,
        height: a.height,
        depth: a.depth,
    };
    // An --out that cannot be a folder fails before any work (write_files checks it again).
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
