//! `sim paper`: parses the options and runs `svo_sim::studies::paper::command` (the paper's
//! Fig. 7 on this model, docs/paper.md).

use anyhow::{bail, Result};
use clap::Args;
use std::path::PathBuf;
use svo_sim::models::cycle::sample::SampleConfig;
use svo_sim::run::config_files::{check_pair, load_hardware};
use svo_sim::studies::paper::command::run_command;
use svo_sim::studies::paper::measure::PaperConfig;

/// Options of `sim paper`.
#[derive(Args, Debug, Clone)]
pub struct PaperArgs {
    /// Frames of the animation (1 to 48; the scenes' animation has 48).
    #[arg(long, default_value_t = 48)]
    frames: u32,
    /// Resolutions, comma-separated WxH (each at most the hardware's frame, 1280x768 by default).
    #[arg(long, value_delimiter = ',', default_values_t = ["640x384".to_string(), "1280x768".to_string()])]
    resolution: Vec<String>,
    /// Hardware the cycle model runs (RON, as `sim --hw`; default: the documented default),
    /// e.g. configs/default_48x16.ron for the figures measured on that default.
    #[arg(long, value_name = "FILE")]
    hw: Option<PathBuf>,
    /// Reference runs per case; the best is reported (0: no reference timing).
    #[arg(long, default_value_t = 3)]
    repeats: u32,
    /// Do not run the cycle model.
    #[arg(long)]
    no_cycle: bool,
    /// Cycle model: sampled timing at this rate (as `sim --sample`, docs/cycle-model.md §3.5);
    /// default: every cycle simulated.
    #[arg(long, value_name = "RATE")]
    sample: Option<f64>,
    /// Worker threads of the reference (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Folder for paper.md, paper.csv, paper.json and paper.png (created if missing).
    #[arg(long, value_name = "DIR", default_value = "paper")]
    out: PathBuf,
}

/// `WxH` as a resolution within the hardware's frame of `fw` × `fh`.
fn parse_resolution(s: &str, fw: u32, fh: u32) -> Result<(u32, u32)> {
    let Some((w, h)) = s.split_once(['x', 'X']) else {
        bail!("--resolution {s}: expected WxH, e.g. 640x384");
    };
    let (w, h): (u32, u32) = match (w.trim().parse(), h.trim().parse()) {
        (Ok(w), Ok(h)) => (w, h),
        _ => bail!("--resolution {s}: width and height must be whole numbers"),
    };
    if !(1..=fw).contains(&w) || !(1..=fh).contains(&h) {
        bail!("--resolution {s}: at most {fw}x{fh} (the hardware frame), at least 1x1");
    }
    Ok((w, h))
}

/// Runs `sim paper`.
pub fn paper_command(a: PaperArgs) -> Result<()> {
    if !(1..=48).contains(&a.frames) {
        bail!("--frames {}: must be within 1 and 48", a.frames);
    }
    if let Some(t) = a.threads {
        if t == 0 {
            bail!("--threads 0: at least one thread");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .map_err(|e| anyhow::anyhow!("--threads: {e}"))?;
    }
    // The hardware first: its frame bounds the resolutions.
    let hw = load_hardware(a.hw.as_deref())?;
    check_pair(
        &hw,
        a.hw.as_deref(),
        &rtl_model::datapath::DatapathConfig::default(),
        None,
    )?;
    let hw_name = a.hw.as_ref().map_or_else(
        || "default hardware".to_string(),
        |p| format!("hardware {}", p.display()),
    );
    let resolutions = a
        .resolution
        .iter()
        .map(|s| parse_resolution(s, hw.frame.width, hw.frame.height))
        .collect::<Result<Vec<_>>>()?;
    let sample = match a.sample {
        Some(rate) => {
            if a.no_cycle {
                bail!("--sample times the cycle model: it cannot go with --no-cycle");
            }
            Some(
                SampleConfig::from_rate(
                    rate,
                    svo_sim::models::cycle::sample::DEFAULT_BAND_ROWS,
                    None,
                    0,
                )
                .map_err(anyhow::Error::msg)?,
            )
        }
        None => None,
    };
    let cfg = PaperConfig {
        frames: a.frames,
        resolutions,
        repeats: a.repeats,
        cycle: !a.no_cycle,
        sample,
        hw,
        hw_name,
    };
    let (md, paths) =
        run_command(&cfg, &a.out, &mut |line| eprintln!("{line}")).map_err(anyhow::Error::msg)?;
    print!("{md}");
    for p in paths {
        println!("wrote {}", p.display());
    }
    Ok(())
}
