//! Waveforms of the cycle model (`sim --vcd FILE`): every FIFO's occupancy, valid and ready,
//! every walker's busy contexts, issue and memory waits, the node memory's outstanding
//! reads, and the frame's pixel counters, in a cycle window or a pixel window.
//!
//! Pipeline position: sampled by `pipeline.rs` once per cycle after all stages are evaluated
//! (the values registers hold during that cycle); written by `rtl_model::cycle::waves`.

use rtl_model::cycle::memory::NodeMemory;
use rtl_model::cycle::walker_pool::WalkerPoolModel;
use rtl_model::cycle::waves::{SignalId, Timebase, Waves, WavesError, Window};
use thiserror::Error;

/// Why a waveform file cannot be written.
#[derive(Debug, Error)]
pub enum WaveFileError {
    /// The recorder or the file failed.
    #[error(transparent)]
    Waves(#[from] WavesError),
    /// Recording failed during the run.
    #[error("waveform recording failed: {0}")]
    Recording(String),
    /// The window saw no cycle of the run.
    #[error("the waveform window {0} saw no cycle of the run")]
    Empty(String),
}

/// FIFO names in the order `pipeline.rs` samples them.
pub const FIFO_NAMES: [&str; 10] = [
    "raygen_to_sphere",
    "sphere_to_sorter",
    "sorter_to_check",
    "check_to_transform",
    "loop_back",
    "transform_to_reciprocal",
    "reciprocal_to_root",
    "root_to_dispatch",
    "walker_to_record",
    "record_to_write",
];

/// Which cycles to record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaveWindow {
    /// Cycles `from..=to` of the run (cycle 0 is the first frame's first cycle).
    Cycles(u64, u64),
    /// From the cycle after pixel `from` (raster index) of `frame` is generated until more
    /// than `to` pixels of that frame have been written (records leave in about raster
    /// order, so this spans the pixels' whole trip through the pipeline).
    Pixels {
        /// Frame.
        frame: u32,
        /// First pixel.
        from: u64,
        /// Last pixel.
        to: u64,
    },
}

#[derive(Clone, Debug)]
struct Sigs {
    frame: SignalId,
    issued: SignalId,
    written: SignalId,
    fifo: Vec<(SignalId, SignalId, SignalId)>,
    walker: Vec<(SignalId, SignalId, SignalId)>,
    outstanding: SignalId,
}

/// The recorder (see the module doc).
pub struct PipelineWaves {
    timebase: Timebase,
    window: WaveWindow,
    walkers: usize,
    contexts: u32,
    rec: Option<(Waves, Sigs)>,
    finished: bool,
    error: Option<String>,
}

fn bits(max: u64) -> u32 {
    (64 - max.leading_zeros()).max(1)
}

/// What one cycle of the pipeline shows in the waveforms.
pub struct WaveSample<'a> {
    /// The cycle.
    pub now: u64,
    /// Registered occupancy of each FIFO, in pipeline order.
    pub occupancy: &'a [&'a usize],
    /// Registered (valid, ready) of each FIFO, in pipeline order.
    pub valid_ready: &'a [(bool, bool)],
    /// The walker pool.
    pub pool: &'a WalkerPoolModel,
    /// The node memory.
    pub mem: &'a NodeMemory,
    /// Rays generated so far this frame.
    pub generated: u64,
    /// Records written so far this frame.
    pub written: u64,
    /// The frame number.
    pub frame: u32,
}

impl PipelineWaves {
    /// A recorder for a pool of `walkers` × `contexts`.
    pub fn new(
        clock_mhz: u32,
        window: WaveWindow,
        walkers: u32,
        contexts: u32,
    ) -> Result<Self, WavesError> {
        if let WaveWindow::Cycles(a, b) = window {
            Window::cycles(a, b)?;
        }
        if let WaveWindow::Pixels { from, to, .. } = window {
            if from > to {
                return Err(WavesError::InvalidWindow { from, to });
            }
        }
        Ok(Self {
            timebase: Timebase::from_clock_mhz(f64::from(clock_mhz))?,
            window,
            walkers: walkers as usize,
            contexts,
            rec: None,
            finished: false,
            error: None,
        })
    }

    fn open(&mut self, from: u64, to: u64) -> Result<(), WavesError> {
        let mut w = Waves::new(self.timebase, Window::cycles(from, to)?).with_clock(true);
        let top = w.scope("pipeline")?;
        let frame = w.signal(top, "frame", 32)?;
        let issued = w.signal(top, "pixels_generated", 32)?;
        let written = w.signal(top, "pixels_written", 32)?;
        let mut fifo = Vec::new();
        for n in FIFO_NAMES {
            let s = w.subscope(top, n)?;
            fifo.push((
                w.signal(s, "occupancy", 17)?,
                w.signal(s, "valid", 1)?,
                w.signal(s, "ready", 1)?,
            ));
        }
        let ws = w.subscope(top, "walkers")?;
        let mut walker = Vec::new();
        let cb = bits(u64::from(self.contexts));
        for i in 0..self.walkers {
            let s = w.subscope(ws, &format!("w{i}"))?;
            walker.push((
                w.signal(s, "busy_contexts", cb)?,
                w.signal(s, "issue", 1)?,
                w.signal(s, "waiting_on_memory", cb)?,
            ));
        }
        let ms = w.subscope(top, "node_memory")?;
        let outstanding = w.signal(ms, "outstanding_reads", 32)?;
        self.rec = Some((
            w,
            Sigs {
                frame,
                issued,
                written,
                fifo,
                walker,
                outstanding,
            },
        ));
        Ok(())
    }

    /// Samples cycle `c.now` (see the module doc). Errors are kept and reported by
    /// [`write_to`](Self::write_to), so a waveform problem never stops the simulation midway.
    pub fn sample(&mut self, c: &WaveSample<'_>) {
        let &WaveSample {
            now,
            occupancy,
            valid_ready,
            pool,
            mem,
            generated,
            written,
            frame,
        } = c;
        if self.finished || self.error.is_some() {
            return;
        }
        match self.window {
            WaveWindow::Cycles(a, b) => {
                if now > b {
                    self.finished = true;
                    return;
                }
                if now < a {
                    return;
                }
                if self.rec.is_none() {
                    if let Err(e) = self.open(a, b) {
                        self.error = Some(e.to_string());
                        return;
                    }
                }
            }
            WaveWindow::Pixels { frame: f, from, to } => {
                if frame < f {
                    return;
                }
                if frame > f || written > to {
                    if self.rec.is_some() {
                        self.finished = true;
                    }
                    return;
                }
                if self.rec.is_none() {
                    if generated <= from {
                        return;
                    }
                    if let Err(e) = self.open(now, u64::MAX / 2) {
                        self.error = Some(e.to_string());
                        return;
                    }
                }
            }
        }
        let Some((w, s)) = self.rec.as_mut() else {
            return;
        };
        let mut r = || -> Result<(), WavesError> {
            w.set(s.frame, now, frame)?;
            w.set(s.issued, now, generated)?;
            w.set(s.written, now, written)?;
            for (k, (o, v, rd)) in s.fifo.iter().enumerate() {
                w.set(*o, now, occupancy.get(k).map_or(0, |x| **x as u64))?;
                let (vv, rr) = valid_ready.get(k).copied().unwrap_or((false, false));
                w.set(*v, now, vv)?;
                w.set(*rd, now, rr)?;
            }
            for (i, (b, iss, wm)) in s.walker.iter().enumerate() {
                w.set(*b, now, pool.walker_busy(i))?;
                w.set(*iss, now, pool.walker_issued(i))?;
                w.set(*wm, now, pool.walker_waiting(i))?;
            }
            w.set(s.outstanding, now, mem.outstanding() as u64)?;
            w.advance_to(now);
            Ok(())
        };
        if let Err(e) = r() {
            self.error = Some(e.to_string());
        }
    }

    /// Whether anything was recorded.
    pub fn recorded(&self) -> bool {
        self.rec.is_some()
    }

    /// Writes the VCD to `out` (the caller's output, from the one output writer
    /// `crate::output::writer`), or reports why it cannot.
    pub fn write_to(&self, out: impl std::io::Write) -> Result<(), WaveFileError> {
        if let Some(e) = &self.error {
            return Err(WaveFileError::Recording(e.clone()));
        }
        match &self.rec {
            Some((w, _)) => Ok(w.write_to(out)?),
            None => Err(WaveFileError::Empty(format!("{:?}", self.window))),
        }
    }
}
