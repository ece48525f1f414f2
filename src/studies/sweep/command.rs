//! The `sim sweep` command line: options, the table on stdout and the default's verdict. Options are
//! plain data: the command line (`src/bin/sim/sweep.rs`) parses them and calls [`run_command`].

use super::configs::{self, NamedConfig};
use super::output::write_outputs;
use super::run::{run_sweep, FrontPlace, NamedScene, SweepOptions, SweepResult, SweepRow};
use crate::world::scene::Scene;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The `--scene` value that means the embedded animated car.
pub const CAR: &str = "car";

/// The scenes swept when no `--scene` is given: the embedded car and the MagicaVoxel traffic
/// scene (paths relative to the current folder, i.e. the repository root).
pub const DEFAULT_SCENES: [&str; 2] = [CAR, "scenes/vox_traffic.ron"];

/// Options of `sim sweep`.
#[derive(Debug, Clone)]
pub struct SweepCommand {
    /// Configurations to sweep: a RON list of named datapath configurations,
    /// `[(name: "a", datapath: (...)), ...]`, each datapath naming only what it changes from
    /// the default (format of `sim datapath`). Default: the built-in list of docs/accuracy.md.
    pub configs: Option<PathBuf>,
    /// Run only these configurations of the list (comma-separated names).
    pub only: Vec<String>,
    /// A scene to sweep over (RON file, or `car` for the embedded car); repeatable.
    /// Default: `car` and `scenes/vox_traffic.ron` (run from the repository root).
    pub scene: Vec<String>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Frames per scene (the first traces every pixel, later ones reuse the hit buffer).
    pub frames: u32,
    /// Octree depth of each scene's deepest asset (1-20; the others keep their offset to it,
    /// as `sim --depth`). Default: the scenes' own depths (the car's body is 10). The
    /// fixed-point model needs memory images, so the car stops at 12.
    pub depth: Option<u8>,
    /// Folder for sweep.csv, sweep.json, sweep_cycles.png and sweep_dsp.png (created if
    /// missing).
    pub out: PathBuf,
    /// Largest `.vox` asset file read, bytes (`--max-vox-mib`).
    pub max_vox_bytes: u64,
}

/// The configurations: the file's or the built-in list, narrowed by `--only`.
fn select_configs(a: &SweepCommand) -> Result<Vec<NamedConfig>> {
    let list = match &a.configs {
        Some(p) => configs::load(p)?,
        None => configs::builtin(),
    };
    if a.only.is_empty() {
        return Ok(list);
    }
    let mut picked = Vec::new();
    for name in &a.only {
        match list.iter().find(|c| &c.name == name) {
            Some(c) if !picked.contains(c) => picked.push(c.clone()),
            Some(_) => bail!("--only {name}: named twice"),
            None => bail!(
                "--only {name}: no such configuration (known: {})",
                list.iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
    Ok(picked)
}

/// Loads the scenes, naming each `car` or by its file's stem (with `_2`, `_3`… on repeats).
fn load_scenes(a: &SweepCommand) -> Result<Vec<NamedScene>> {
    let given: Vec<&str> = if a.scene.is_empty() {
        DEFAULT_SCENES.to_vec()
    } else {
        a.scene.iter().map(String::as_str).collect()
    };
    let mut out: Vec<NamedScene> = Vec::new();
    for s in given {
        let (base, scene) = if s == CAR {
            (CAR.to_string(), Scene::default_car()?)
        } else {
            let p = Path::new(s);
            if a.scene.is_empty() && !p.is_file() {
                bail!("default scene {s} not found: run from the repository root or pass --scene");
            }
            let stem = p
                .file_stem()
                .map_or_else(|| "scene".to_string(), |x| x.to_string_lossy().into_owned());
            let mut scene = Scene::load(p)?;
            scene.max_vox_bytes = a.max_vox_bytes;
            (stem, scene)
        };
        let mut name = base.clone();
        let mut k = 2;
        while out.iter().any(|o| o.name == name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        out.push(NamedScene { name, scene });
    }
    Ok(out)
}

fn row_line(r: &SweepRow, fronts: bool) -> String {
    let e = &r.error;
    let mark = |on: bool| if on { "*" } else { " " };
    let mut s = format!(
        "  {:<20} {:>5} {:>5} {:>5} {:>10.3e} {:>10.3e} {:>5} {:>6} {:>10.3e} {:>9.0} {:>5} {:>8}",
        r.config,
        e.hit_mismatches,
        e.instance_mismatches,
        e.voxel_mismatches,
        e.t_err_max,
        e.t_err_rms,
        e.normal_mismatches,
        e.saturations,
        e.error_score,
        r.cycles_per_frame,
        r.cost.dsp48e2,
        r.cost.stack_bits,
    );
    if fronts {
        s.push_str(&format!(
            " {:>7.2}{} {:>7.1} {:>7.2}{} {:>7.1}",
            100.0 * r.cycles_front.distance,
            mark(r.cycles_front.on_front),
            100.0 * r.cycles_front.excess,
            100.0 * r.dsp_front.distance,
            mark(r.dsp_front.on_front),
            100.0 * r.dsp_front.excess
        ));
    }
    s.push_str(&format!(" {:>8.0}", 1e3 * r.wall_s));
    s
}

fn header(fronts: bool) -> String {
    let mut s = format!(
        "  {:<20} {:>5} {:>5} {:>5} {:>10} {:>10} {:>5} {:>6} {:>10} {:>9} {:>5} {:>8}",
        "config",
        "hit",
        "inst",
        "voxel",
        "t err max",
        "t err rms",
        "face",
        "sat",
        "score",
        "cyc/frame",
        "DSP",
        "stack b"
    );
    if fronts {
        s.push_str(&format!(
            " {:>8} {:>7} {:>8} {:>7}",
            "d_cyc %", "x_cyc %", "d_dsp %", "x_dsp %"
        ));
    }
    s.push_str(&format!(" {:>8}", "wall ms"));
    s
}

fn print_table(result: &SweepResult) {
    for sc in &result.scenes {
        println!(
            "scene {} ({}; {} instances; smallest leaf {:.3e} m):",
            sc.name, sc.origin, sc.instances, sc.leaf_edge
        );
        println!("{}", header(true));
        for r in result.rows.iter().filter(|r| r.scene == sc.name) {
            println!("{}", row_line(r, true));
        }
    }
    println!(
        "(* on the Pareto front; d = relative distance to it, x = share of the error a \
configuration of no greater cost avoids; docs/accuracy.md)"
    );
    for v in &result.default {
        let pos = |f: FrontPlace| {
            if f.on_front {
                "on the front".to_string()
            } else {
                format!(
                    "off the front, distance {:.2} %, error excess {:.1} %",
                    100.0 * f.distance,
                    100.0 * f.excess
                )
            }
        };
        println!(
            "default on {}: error vs cycles {}; error vs DSP {}; within 5 %: {}",
            v.scene,
            pos(v.cycles_front),
            pos(v.dsp_front),
            if v.within_5_percent { "yes" } else { "NO" }
        );
    }
}

/// Runs `sim sweep`.
pub fn run_command(a: &SweepCommand) -> Result<()> {
    let start = Instant::now();
    crate::output::writer::refuse_stdout_folder("--out", &a.out)?;
    if a.out.exists() && !a.out.is_dir() {
        bail!("--out {} exists and is not a folder", a.out.display());
    }
    let configs = select_configs(a)?;
    let scenes = load_scenes(a)?;
    let opts = SweepOptions {
        width: a.width,
        height: a.height,
        frames: a.frames,
        depth: a.depth,
    };
    println!(
        "sim sweep: {} configurations x {} scenes at {}x{}, {} frames each, depth {}",
        configs.len(),
        scenes.len(),
        a.width,
        a.height,
        a.frames,
        a.depth
            .map_or_else(|| "as the scenes".to_string(), |d| d.to_string())
    );
    // The progress header waits for the first row, so an input error is not preceded by an
    // empty table.
    let mut first = true;
    let result = run_sweep(&configs, &scenes, opts, |r| {
        if std::mem::take(&mut first) {
            eprintln!("{}", header(false));
        }
        eprintln!("{}  [{}]", row_line(r, false), r.scene);
    })?;
    print_table(&result);
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    for p in write_outputs(&result, &a.out).map_err(anyhow::Error::msg)? {
        println!("wrote {}", p.display());
    }
    println!(
        "({} configurations x {} scenes in {:.1} s)",
        configs.len(),
        scenes.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
