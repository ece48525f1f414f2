//! The files of a `sim` run: PNG frames (and the fixed-point models' difference images), the
//! hit dump, the cycle model's waveforms and transaction log, and the JSON report, all
//! through the one output writer (`crate::output::writer`).
//!
//! Pipeline position: around the frame loop of [`super::frames::run`]. [`RunFiles::check`]
//! runs before any work (every path's folder exists, no path is a folder, at most one output
//! is `-`); [`RunFiles::open`] opens the dump and creates the PNG folder; [`RunFiles::frame`]
//! writes a finished frame; [`RunFiles::finish_dump`] and the `write_*` functions write what
//! needs the whole run. What was written is remembered, so an interruption can say what it
//! kept ([`RunFiles::kept`]).

use super::frames::RunConfig;
use crate::models::cycle::runner::CycleRun;
use crate::models::fixed::diff_image;
use crate::models::reference::HitRecord;
use crate::output::report::Report;
use crate::output::writer::{refuse_stdout_folder, Destination, Output};
use crate::output::{dump, png};
use anyhow::{bail, Context, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The open outputs of a run and what it has written so far.
pub struct RunFiles {
    dump: Option<(Output, bool)>,
    frames_written: Vec<PathBuf>,
    diffs_written: Vec<PathBuf>,
}

impl RunFiles {
    /// Checks every output path of `cfg` before any work: each single output's folder exists
    /// and it is no folder; `-` (standard output) is allowed for one of them only, and not for
    /// the PNG folder.
    pub fn check(cfg: &RunConfig) -> Result<()> {
        let singles = [
            ("--report-json", cfg.report_json.as_deref()),
            ("--dump-hits", cfg.dump_hits.as_deref()),
            ("--vcd", cfg.vcd.as_ref().map(|v| v.path.as_path())),
            (
                "--transaction-log",
                cfg.transaction_log.as_ref().map(|(p, _)| p.as_path()),
            ),
        ];
        let mut to_stdout = Vec::new();
        for (option, path) in singles {
            let Some(p) = path else { continue };
            if Destination::of(p).with_context(|| option.to_string())? == Destination::Stdout {
                to_stdout.push(option);
            }
        }
        if to_stdout.len() > 1 {
            bail!(
                "{} are all `-`: only one output can go to standard output",
                to_stdout.join(" and ")
            );
        }
        if let Some(dir) = &cfg.out_dir {
            refuse_stdout_folder("--out", dir)?;
            if dir.exists() && !dir.is_dir() {
                bail!("--out {} exists and is not a folder", dir.display());
            }
        }
        Ok(())
    }

    /// Opens the hit dump (writing its header) and creates the PNG folder. Opening a FIFO
    /// waits for its reader.
    pub fn open(cfg: &RunConfig) -> Result<Self> {
        let (w, h) = cfg.scene.file.resolution;
        let dump = match &cfg.dump_hits {
            Some(p) => {
                let csv = p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
                let mut o = Output::create(p).context("--dump-hits")?;
                let header = if csv {
                    writeln!(o, "{}", dump::CSV_HEADER)
                } else {
                    dump::write_header(&mut o, w, h, cfg.scene.file.frames)
                };
                header.with_context(|| format!("cannot write {}", p.display()))?;
                Some((o, csv))
            }
            None => None,
        };
        if let Some(dir) = &cfg.out_dir {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("cannot create output folder {}", dir.display()))?;
        }
        Ok(Self {
            dump,
            frames_written: Vec::new(),
            diffs_written: Vec::new(),
        })
    }

    /// Writes frame `f`: its shaded PNG (of `records`, the output model's), the difference
    /// image against `reference` when a fixed-point model made `records`, and its dump records.
    pub fn frame(
        &mut self,
        cfg: &RunConfig,
        f: u32,
        reference: &[HitRecord],
        fixed: Option<&[HitRecord]>,
    ) -> Result<()> {
        let scene = &cfg.scene;
        let (w, h) = scene.file.resolution;
        let records = fixed.unwrap_or(reference);
        if let Some(dir) = &cfg.out_dir {
            if let Some(fixed) = fixed {
                let img = diff_image(reference, fixed, w, h, 1e-6);
                let path = dir.join(format!("diff_{f:04}.png"));
                crate::output::writer::write_whole(&path, &png::encode_png(&img)?)?;
                self.diffs_written.push(path);
            }
            let l = &scene.file.light;
            let img = png::shade(records, w, h, l.direction, l.ambient, scene.file.background);
            let path = dir.join(format!("frame_{f:04}.png"));
            crate::output::writer::write_whole(&path, &png::encode_png(&img)?)?;
            self.frames_written.push(path);
        }
        if let Some((o, csv)) = self.dump.as_mut() {
            let r = if *csv {
                dump::write_frame_csv(o, f, w, records)
            } else {
                dump::write_frame(o, f, w, records)
            };
            r.with_context(|| format!("cannot write {}", o.path().display()))?;
        }
        Ok(())
    }

    /// Completes the hit dump.
    pub fn finish_dump(&mut self) -> Result<()> {
        if let Some((o, _)) = self.dump.take() {
            o.commit().context("cannot finish the hit dump")?;
        }
        Ok(())
    }

    /// What the run has kept so far, for the line of an interruption: the finished frames'
    /// PNGs as a range (`out/frame_0000.png … out/frame_0006.png`); empty: nothing.
    pub fn kept(&self) -> String {
        let range = |v: &[PathBuf]| match v {
            [] => None,
            [one] => Some(one.display().to_string()),
            [first, .., last] => Some(format!(
                "{} … {} ({} files)",
                first.display(),
                last.display(),
                v.len()
            )),
        };
        [range(&self.frames_written), range(&self.diffs_written)]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>()
            .join(" and ")
    }
}

/// Writes the cycle model's waveforms and transaction log, when asked for.
pub fn write_cycle_files(cfg: &RunConfig, cr: &mut CycleRun) -> Result<()> {
    if let Some(v) = &cfg.vcd {
        if let Some(waves) = cr.model().take_waves() {
            let mut o = Output::create(&v.path).context("--vcd")?;
            waves
                .write_to(&mut o)
                .with_context(|| format!("cannot write --vcd {}", v.path.display()))?;
            o.commit()?;
        }
    }
    if let Some((p, _)) = &cfg.transaction_log {
        let w = cfg.scene.file.resolution.0;
        let mut text = String::new();
        for (pixel, stamps) in &cr.model().log {
            let line = serde_json::json!({
                "pixel": pixel,
                "x": pixel % w,
                "y": pixel / w,
                "stages": stamps.iter().map(|s| serde_json::json!({
                    "stage": crate::models::cycle::pipeline::STAGE_NAMES
                        .get(usize::from(s.stage.0)).copied().unwrap_or("?"),
                    "entered": s.entered,
                    "left": s.left,
                })).collect::<Vec<_>>(),
            });
            text.push_str(&line.to_string());
            text.push('\n');
        }
        crate::output::writer::write_whole(p, text.as_bytes()).context("--transaction-log")?;
    }
    Ok(())
}

/// Writes the JSON report to `path` (`-`: standard output).
pub fn write_report(path: &Path, report: &Report) -> Result<()> {
    let text = serde_json::to_string_pretty(report)?;
    crate::output::writer::write_whole(path, text.as_bytes()).context("--report-json")?;
    Ok(())
}
