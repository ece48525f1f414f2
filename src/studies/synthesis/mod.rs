//! Synthesis of the RTL units with Yosys and their comparison with the model's estimate:
//! per unit LUT, FF, DSP48E2, block RAM and UltraRAM from the mapped netlist, the logic
//! levels of every stage with the clock rule's verdict, beside `HwConfig::resources` /
//! `HwConfig::fabric` of the same unit (`sim hardware --synth`, `tests/synthesis_yosys.rs`).
//!
//! Pipeline position: beside the models, a study of the RTL in `testbench/rtl/`. The unit list
//! is `testbench/synth/units.tsv` (one unit a line, with the DSP48E2 difference from the
//! estimate it is allowed and the recorded reason); each unit is synthesised by
//! `testbench/synth/synth.sh UNIT` into a cache folder keyed by a hash of the script, the unit's
//! line, its RTL files and parameter files and the Yosys version, so an unchanged unit is not
//! synthesised again. Two units run at a time, each worker taking the next unit of the list
//! when its last one is done.

pub mod netlist;
pub mod text;
pub mod units;

use rtl_model::cost::timing::{ClockRule, ULTRASCALE_PLUS_2};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use thiserror::Error;
pub use units::{parse_units, UnitSpec};

/// What can go wrong running the synthesis.
#[derive(Debug, Error)]
pub enum SynthError {
    /// SIGINT or SIGTERM stopped the synthesis between units.
    #[error("{0}")]
    Interrupted(#[from] crate::output::interrupt::Interrupted),
    /// Yosys is not on the PATH.
    #[error("yosys not found on PATH (Debian/Ubuntu: apt-get install yosys): {0}")]
    YosysMissing(String),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The unit list is malformed.
    #[error("{path}:{line}: {message}")]
    Units {
        /// The list.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A unit named on the command line is not in the list.
    #[error("unit `{0}` is not in testbench/synth/units.tsv")]
    UnknownUnit(String),
    /// Yosys failed on a unit.
    #[error("synthesis of `{unit}` failed (log: {log}): {detail}")]
    Failed {
        /// The unit.
        unit: String,
        /// Its Yosys log.
        log: String,
        /// The script's error output.
        detail: String,
    },
    /// The netlist or statistics could not be read.
    #[error("`{unit}`: {message}")]
    Netlist {
        /// The unit.
        unit: String,
        /// What is wrong.
        message: String,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> SynthError + '_ {
    move |source| SynthError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Mapped cells of one unit.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Cells {
    /// LUT1..LUT6.
    pub lut: u64,
    /// Flip-flops (FD*).
    pub ff: u64,
    /// Shift registers (SRL16E, SRLC32E).
    pub srl: u64,
    /// LUTs used as LUT-RAM (8 per RAM32M16/RAM64M8, 4 per RAM32M/RAM64M, 2 per
    /// RAM32X1D/RAM64X1D, 1 per other single-port LUT-RAM).
    pub lutram_luts: u64,
    /// DSP48E2.
    pub dsp48e2: u64,
    /// RAMB36 (a RAMB18 counts a half, rounded up in the total).
    pub ramb36_halves: u64,
    /// URAM288.
    pub uram288: u64,
}

impl Cells {
    /// CLB LUTs as Vivado counts them: logic, shift registers and LUT-RAM.
    pub fn clb_luts(&self) -> u64 {
        self.lut + self.srl + self.lutram_luts
    }

    /// BRAM36 equivalents.
    pub fn bram36(&self) -> u64 {
        self.ramb36_halves.div_ceil(2)
    }

    /// From a Yosys `stat` report.
    pub fn from_stat(stat: &str) -> Self {
        let mut c = Self::default();
        for line in stat.lines() {
            let mut it = line.split_whitespace();
            let (Some(kind), Some(n), None) = (it.next(), it.next(), it.next()) else {
                continue;
            };
            let Ok(n) = n.parse::<u64>() else { continue };
            match kind {
                k if k.starts_with("LUT") && k.len() == 4 => c.lut += n,
                k if k.starts_with("FD") => c.ff += n,
                "SRL16E" | "SRLC32E" | "SRLC16E" => c.srl += n,
                "RAM32M16" | "RAM64M8" => c.lutram_luts += 8 * n,
                "RAM32M" | "RAM64M" => c.lutram_luts += 4 * n,
                "RAM32X1D" | "RAM64X1D" | "RAM128X1S" => c.lutram_luts += 2 * n,
                "RAM32X1S" | "RAM64X1S" => c.lutram_luts += n,
                "RAM128X1D" => c.lutram_luts += 4 * n,
                "DSP48E2" => c.dsp48e2 += n,
                "RAMB36E2" => c.ramb36_halves += 2 * n,
                "RAMB18E2" => c.ramb36_halves += n,
                "URAM288" | "URAM288_BASE" => c.uram288 += n,
                _ => {}
            }
        }
        c
    }
}

/// One unit's synthesis.
#[derive(Clone, Debug)]
pub struct UnitSynthesis {
    /// The unit's line of units.tsv.
    pub spec: UnitSpec,
    /// Its mapped cells.
    pub cells: Cells,
    /// The slowest path into each stage, slowest first.
    pub stages: Vec<netlist::StagePath>,
    /// Whether the result came from the cache.
    pub cached: bool,
    /// Seconds Yosys took (0 when cached).
    pub seconds: f64,
}

/// Where the synthesis runs.
#[derive(Clone, Debug)]
pub struct SynthOptions {
    /// The repository (holding `testbench/` and `vectors/`).
    pub repo: PathBuf,
    /// The cache folder (per unit a subfolder with its logs, netlist and key).
    pub cache: PathBuf,
    /// Units to run (empty: every unit of the list).
    pub units: Vec<String>,
    /// Units synthesised at a time.
    pub jobs: usize,
    /// The clock rule for the levels.
    pub rule: ClockRule,
}

impl SynthOptions {
    /// Every unit of `repo`, cached in `cache`, two at a time, the UltraScale+ −2 rule.
    pub fn new(repo: &Path, cache: &Path) -> Self {
        Self {
            repo: repo.to_path_buf(),
            cache: cache.to_path_buf(),
            units: Vec::new(),
            jobs: 2,
            rule: ULTRASCALE_PLUS_2,
        }
    }
}

/// The version line of the Yosys on the PATH, or why there is none.
pub fn yosys_version() -> Result<String, SynthError> {
    let out = Command::new("yosys")
        .arg("-V")
        .output()
        .map_err(|e| SynthError::YosysMissing(e.to_string()))?;
    if !out.status.success() {
        return Err(SynthError::YosysMissing(format!(
            "`yosys -V` exited with {}",
            out.status
        )));
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// FNV-1a, 64 bits: the cache key of a unit (stable across Rust versions, unlike the
/// standard hasher).
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The cache key of a unit: the script, the unit's line, every RTL and parameter file it
/// reads, and the Yosys version.
fn unit_key(o: &SynthOptions, u: &UnitSpec, version: &str) -> Result<String, SynthError> {
    let mut h = 0xcbf2_9ce4_8422_2325;
    let script = o.repo.join("testbench/synth/synth.sh");
    h = fnv1a(&std::fs::read(&script).map_err(io(&script))?, h);
    h = fnv1a(u.line.as_bytes(), h);
    h = fnv1a(version.as_bytes(), h);
    for f in u.input_files(&o.repo) {
        // The path relative to the repository, so that the key does not depend on where the
        // repository is or how it was named (`.` or absolute).
        let rel = f.strip_prefix(&o.repo).unwrap_or(&f);
        h = fnv1a(rel.to_string_lossy().as_bytes(), h);
        h = fnv1a(&std::fs::read(&f).map_err(io(&f))?, h);
    }
    Ok(format!("{h:016x}"))
}

/// What the synthesis is doing, reported as it happens (a whole run takes minutes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SynthProgress<'a> {
    /// A worker took unit `index` (1-based) of `of`.
    Started {
        /// The unit.
        unit: &'a str,
        /// Its place in the run, 1-based.
        index: usize,
        /// Units in the run.
        of: usize,
    },
    /// Unit `index` of `of` is done (synthesised, or read from the cache), or failed.
    Finished {
        /// The unit.
        unit: &'a str,
        /// Its place in the run, 1-based.
        index: usize,
        /// Units in the run.
        of: usize,
        /// Wall seconds from its start.
        seconds: f64,
        /// Whether the result came from the cache.
        cached: bool,
        /// Whether it failed (the error is returned at the end).
        failed: bool,
    },
}

/// Synthesises (or takes from the cache) every unit `o` names, `o.jobs` at a time; the units
/// in list order.
pub fn synthesise(o: &SynthOptions) -> Result<Vec<UnitSynthesis>, SynthError> {
    synthesise_with_progress(o, &|_| {})
}

/// [`synthesise`], calling `progress` as each unit starts and finishes (from the worker
/// threads, so in the order the units actually run).
pub fn synthesise_with_progress(
    o: &SynthOptions,
    progress: &(dyn Fn(SynthProgress<'_>) + Sync),
) -> Result<Vec<UnitSynthesis>, SynthError> {
    let version = yosys_version()?;
    let list = o.repo.join("testbench/synth/units.tsv");
    let all = parse_units(&std::fs::read_to_string(&list).map_err(io(&list))?, &list)?;
    for n in &o.units {
        if !all.iter().any(|u| &u.name == n) {
            return Err(SynthError::UnknownUnit(n.clone()));
        }
    }
    let todo: Vec<UnitSpec> = all
        .into_iter()
        .filter(|u| o.units.is_empty() || o.units.contains(&u.name))
        .collect();
    std::fs::create_dir_all(&o.cache).map_err(io(&o.cache))?;
    // A work queue, not chunks of `jobs`: a worker takes the next unit as soon as its last
    // one is done, so one slow unit (the walker, the sorter) does not leave a core idle.
    let jobs = o.jobs.max(1).min(todo.len().max(1));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: std::sync::Mutex<BTreeMap<usize, Result<UnitSynthesis, SynthError>>> =
        std::sync::Mutex::new(BTreeMap::new());
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                // After SIGINT/SIGTERM no new unit starts (checked below).
                if crate::output::interrupt::received().is_some() {
                    break;
                }
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(u) = todo.get(i) else { break };
                let (index, of) = (i + 1, todo.len());
                progress(SynthProgress::Started {
                    unit: &u.name,
                    index,
                    of,
                });
                let t0 = std::time::Instant::now();
                let r = synthesise_one(o, u, &version);
                progress(SynthProgress::Finished {
                    unit: &u.name,
                    index,
                    of,
                    seconds: t0.elapsed().as_secs_f64(),
                    cached: r.as_ref().is_ok_and(|s| s.cached),
                    failed: r.is_err(),
                });
                if let Ok(mut m) = results.lock() {
                    m.insert(i, r);
                }
            });
        }
    });
    let results = results.into_inner().unwrap_or_else(|p| p.into_inner());
    crate::output::interrupt::check(
        || format!("unit synthesis ({} of {} done)", results.len(), todo.len()),
        String::new,
    )?;
    if results.len() != todo.len() {
        return Err(SynthError::Netlist {
            unit: "?".into(),
            message: "a synthesis thread panicked".into(),
        });
    }
    results.into_values().collect()
}

fn synthesise_one(
    o: &SynthOptions,
    u: &UnitSpec,
    version: &str,
) -> Result<UnitSynthesis, SynthError> {
    let dir = o.cache.join(&u.name);
    let key = unit_key(o, u, version)?;
    let key_file = dir.join("key");
    let stat = dir.join(format!("{}.stat", u.name));
    let json = dir.join(format!("{}.json", u.name));
    let cached = std::fs::read_to_string(&key_file).is_ok_and(|k| k.trim() == key)
        && stat.is_file()
        && json.is_file();
    let mut seconds = 0.0;
    if !cached {
        // A stale key must not survive a failed run.
        let _ = std::fs::remove_file(&key_file);
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        let t0 = std::time::Instant::now();
        let out = Command::new("bash")
            .arg(o.repo.join("testbench/synth/synth.sh"))
            .arg(&u.name)
            .env("SYNTH_LOGS", &dir)
            .output()
            .map_err(io(&o.repo.join("testbench/synth/synth.sh")))?;
        seconds = t0.elapsed().as_secs_f64();
        if !out.status.success() {
            return Err(SynthError::Failed {
                unit: u.name.clone(),
                log: dir.join(format!("{}.log", u.name)).display().to_string(),
                detail: String::from_utf8_lossy(&out.stderr).trim().to_string(),
            });
        }
        crate::output::writer::write_whole(&key_file, key.as_bytes())
            .map_err(|e| io(&key_file)(std::io::Error::other(e)))?;
    }
    let cells = Cells::from_stat(&std::fs::read_to_string(&stat).map_err(io(&stat))?);
    let text = std::fs::read_to_string(&json).map_err(io(&json))?;
    let stages =
        netlist::stage_paths(&text, &u.top, o.rule).map_err(|message| SynthError::Netlist {
            unit: u.name.clone(),
            message,
        })?;
    Ok(UnitSynthesis {
        spec: u.clone(),
        cells,
        stages,
        cached,
        seconds,
    })
}
