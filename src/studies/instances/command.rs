//! `sim instances` end to end: runs the measurements of `super::measure`, prints the tables and
//! writes `instances.md`, `instances.json` and `instances.png` into the output folder (all or
//! nothing: the files are written only after every run succeeded).
//!
//! Pipeline position: called by `src/bin/sim/instances.rs` with plain options.

use super::measure::{binning, fps_points, reuse, speed, BinRow, FpsPoint, SpeedRow};
use super::scene::{CrowdCase, SIZE};
use crate::output::writer::write_files;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Options of the study.
#[derive(Clone, Debug)]
pub struct InstancesCommand {
    /// Instance counts of the frame-rate table.
    pub counts: Vec<u32>,
    /// Largest count the flat scheme is simulated at (beyond: its sphere-lane bound).
    pub flat_limit: u32,
    /// Image size of the frame-rate table.
    pub size: (u32, u32),
    /// Asset depth.
    pub depth: u8,
    /// Skip the speed and reuse measurements.
    pub fps_only: bool,
    /// Output folder.
    pub out: PathBuf,
}

impl Default for InstancesCommand {
    fn default() -> Self {
        Self {
            counts: vec![1, 10, 100, 1000, 10_000],
            flat_limit: 100,
            size: SIZE,
            depth: 6,
            fps_only: false,
            out: PathBuf::from("instances"),
        }
    }
}

/// Everything the study measured.
#[derive(Clone, Debug, Serialize)]
pub struct InstancesResult {
    /// Image size.
    pub size: (u32, u32),
    /// Frame-rate points.
    pub fps: Vec<FpsPoint>,
    /// Functional speed at 8 and 1,000 instances.
    pub speed: Vec<SpeedRow>,
    /// Reuse of frame 1 (still camera): (instances, moving fraction, reuse).
    pub reuse: Vec<(u32, f64, f64)>,
    /// The host's binning per instance count.
    pub binning: Vec<BinRow>,
}

/// Runs the study; `progress` receives one line per finished run.
pub fn run(
    c: &InstancesCommand,
    progress: &mut dyn FnMut(&str),
) -> Result<InstancesResult, String> {
    let mut fps = Vec::new();
    for &n in &c.counts {
        for moving_camera in [false, true] {
            crate::output::interrupt::check(|| format!("{n} instances"), String::new)
                .map_err(|e| e.to_string())?;
            let case = CrowdCase {
                n,
                moving_camera,
                moving: 1.0,
                size: c.size,
                depth: c.depth,
            };
            let pts = fps_points(&case, c.flat_limit)?;
            for p in &pts {
                progress(&format!(
                    "{n} instances, {} camera, {}: {:.1} fps ({})",
                    p.camera, p.scheme, p.fps, p.bound
                ));
            }
            fps.extend(pts);
        }
    }
    let mut speeds = Vec::new();
    let mut reuses = Vec::new();
    let mut bins = Vec::new();
    for &n in &c.counts {
        let case = CrowdCase {
            n,
            moving_camera: false,
            moving: 1.0,
            size: c.size,
            depth: c.depth,
        };
        bins.push(binning(&case)?);
    }
    if !c.fps_only {
        for n in [8, 1000] {
            let case = CrowdCase {
                n,
                moving_camera: false,
                moving: 1.0,
                size: (640, 384),
                depth: c.depth,
            };
            let s = speed(&case, 2)?;
            progress(&format!(
                "speed at {n}: reference {:.2e}/{:.2e}, fixed {:.2e}/{:.2e} rays/s",
                s.reference_flat, s.reference_two_level, s.fixed_flat, s.fixed_two_level
            ));
            speeds.push(s);
        }
        for n in [10, 100, 1000, 10_000] {
            for moving in [0.0, 0.1, 0.5, 1.0] {
                let case = CrowdCase {
                    n,
                    moving_camera: false,
                    moving,
                    size: c.size,
                    depth: c.depth,
                };
                let r = reuse(&case)?;
                progress(&format!(
                    "reuse at {n}, {moving} moving: {:.1} %",
                    100.0 * r
                ));
                reuses.push((n, moving, r));
            }
        }
    }
    Ok(InstancesResult {
        size: c.size,
        fps,
        speed: speeds,
        reuse: reuses,
        binning: bins,
    })
}

/// The tables as Markdown.
pub fn tables(r: &InstancesResult) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## Modelled frame rate at {}×{} (frame 1; 300 MHz, XCVU9P)\n",
        r.size.0, r.size.1
    );
    let _ = writeln!(
        s,
        "| instances | camera | scheme | cycles | fps | bound | simulated | sphere tests/ray | reuse | DSP/BRAM36/URAM | fits |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for p in &r.fps {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.1} | {} | {} | {:.2} | {:.1} % | {}/{}/{} | {} |",
            p.n,
            p.camera,
            p.scheme,
            p.cycles,
            p.fps,
            p.bound,
            if p.simulated { "yes" } else { "no (bound)" },
            p.tests_per_ray,
            100.0 * p.reuse,
            p.resources.0,
            p.resources.1,
            p.resources.2,
            if p.fits { "yes" } else { "no" }
        );
    }
    let _ = writeln!(
        s,
        "\n## The host's binning (frame 0, 16-pixel tiles, 8 ids a word, default list memory)\n"
    );
    let _ = writeln!(
        s,
        "| instances | entries | mean list | longest | words | flat tiles | host µs | bytes written |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for b in &r.binning {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {} | {} | {} | {:.0} | {} |",
            b.n, b.entries, b.mean_len, b.max_len, b.words, b.flat_tiles, b.host_us, b.host_bytes
        );
    }
    if !r.speed.is_empty() {
        let _ = writeln!(
            s,
            "\n## Functional speed, rays/s (640×384, frame 0 traced in full, best of 2)\n"
        );
        let _ = writeln!(
            s,
            "| instances | reference flat | reference two-level | fixed flat | fixed two-level |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|");
        for v in &r.speed {
            let _ = writeln!(
                s,
                "| {} | {:.3e} | {:.3e} | {:.3e} | {:.3e} |",
                v.n, v.reference_flat, v.reference_two_level, v.fixed_flat, v.fixed_two_level
            );
        }
    }
    if !r.reuse.is_empty() {
        let _ = writeln!(
            s,
            "\n## Hit-buffer reuse of frame 1, still camera, against instances and the moving fraction\n"
        );
        let _ = writeln!(s, "| instances | 0 moving | 10 % | 50 % | all |");
        let _ = writeln!(s, "|---|---|---|---|---|");
        let mut ns: Vec<u32> = r.reuse.iter().map(|x| x.0).collect();
        ns.dedup();
        for n in ns {
            let cells: Vec<String> = r
                .reuse
                .iter()
                .filter(|x| x.0 == n)
                .map(|x| format!("{:.1} %", 100.0 * x.2))
                .collect();
            let _ = writeln!(s, "| {n} | {} |", cells.join(" | "));
        }
    }
    s
}

/// Runs the study, prints the tables and writes the files.
pub fn run_command(c: &InstancesCommand) -> Result<String, String> {
    crate::output::writer::refuse_stdout_folder("--out", &c.out).map_err(|e| e.to_string())?;
    let r = run(c, &mut |line| eprintln!("  {line}"))?;
    let md = tables(&r);
    let img = super::plot::render(&r.fps, 300)?;
    let png = crate::output::figure::encode_png_best(&img, "instances.png")?;
    let json = serde_json::to_vec_pretty(&r).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&c.out).map_err(|e| format!("{}: {e}", c.out.display()))?;
    write_files(
        &c.out,
        &[
            ("instances.md", md.clone().into_bytes()),
            ("instances.json", json),
            ("instances.png", png),
        ],
    )?;
    Ok(md)
}
