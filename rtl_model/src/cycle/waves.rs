//! Waveform recorder for the cycle model: value changes of pipeline signals written as VCD.
//!
//! Where it sits: the cycle model's stages, FIFOs, walkers and memory report their visible
//! signals here once per cycle (valid/ready, FIFO occupancy, walker states as small integers,
//! memory request addresses); [`Waves::write_to`] writes the result to any `Write`, and the
//! simulator's `--vcd FILE` hands it its one output writer (this crate opens no files), which
//! opens in GTKWave. Nothing here feeds back into the model: recording never changes cycles.
//!
//! # Format choices
//!
//! - **Time.** `$timescale 1 ps`; cycle `c` starts at time `c × period_ps`, where
//!   [`Timebase::period_ps`] is the clock period rounded to an *even* number of picoseconds so
//!   that the optional clock's falling edge (half a period later) lands on an integer time. A
//!   viewer therefore shows real nanoseconds, and the cycle of any change is exactly
//!   `time / period_ps`. At 300 MHz the period is 3334 ps instead of 3333.3 ps (0.02 % slow);
//!   cycle counts are exact, only the absolute time scale carries that rounding.
//! - **Registered semantics.** A value set for cycle `c` is shown from the rising edge that
//!   starts cycle `c` until the next change. If a signal is set several times in one cycle the
//!   last value wins, and a signal set to its current value writes nothing.
//! - **Window.** Only cycles in the inclusive [`Window`] `[from, to]` are written. The file
//!   starts at `from × period_ps` with a `$dumpvars` block holding every signal's value as of
//!   cycle `from` (the last value set at or before `from`, or `x` if none was), then the changes
//!   in `(from, to]`, then a bare timestamp one cycle after the last recorded cycle so the final
//!   cycle has a visible width. Changes outside the window are not stored at all, so a long run
//!   with a short window costs little memory. A pixel window is the caller's to translate into
//!   cycles; the model is deterministic, so a first run can find the cycles at which the window's
//!   first pixel enters and its last pixel leaves, and a second run records them.
//! - **Encoding.** One top scope, [`TOP_SCOPE`], holds the optional clock `clk` and the scopes
//!   declared with [`Waves::scope`] (one per stage, e.g. `sphere`, `sorter`, `walker0`), which
//!   may nest. All signals are `wire`s; multi-bit ones carry a `[msb:0]` index so viewers show
//!   the width. Vector values are written without leading zeros, as VCD allows (the reader
//!   extends them with zeros), which keeps 32-bit addresses short.
//! - **Determinism.** No `$date`; identifier codes follow declaration order (the clock takes the
//!   code after the last signal); within a timestamp changes are written in declaration order.
//!   The same declarations and `set` calls give a byte-identical file.
//!
//! # Example
//!
//! ```
//! use rtl_model::cycle::waves::{Timebase, Waves, Window};
//!
//! # fn main() -> Result<(), rtl_model::cycle::waves::WavesError> {
//! let mut waves = Waves::new(Timebase::from_clock_mhz(250.0)?, Window::all());
//! let sphere = waves.scope("sphere")?;
//! let valid = waves.signal(sphere, "valid", 1)?;
//! let occupancy = waves.signal(sphere, "occupancy", 4)?;
//! for cycle in 0..10 {
//!     waves.set(valid, cycle, cycle % 3 == 0)?;
//!     waves.set(occupancy, cycle, cycle / 2)?;
//! }
//! let mut vcd = Vec::new();
//! waves.write_to(&mut vcd)?;
//! assert!(String::from_utf8_lossy(&vcd).contains("$timescale 1 ps $end"));
//! # Ok(())
//! # }
//! ```

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::io::{self, BufWriter, Write};

use thiserror::Error;
use vcd::{IdCode, ReferenceIndex, SimulationCommand, TimescaleUnit, Value, VarType, Writer};

/// Name of the scope that encloses every other scope and the clock.
pub const TOP_SCOPE: &str = "top";

/// Name of the optional clock signal inside [`TOP_SCOPE`]; reserved even when the clock is off,
/// so turning it on can never collide with a declared signal.
pub const CLOCK_NAME: &str = "clk";

/// Widest signal the recorder holds; values are `u64`.
pub const MAX_WIDTH: u32 = 64;

/// Errors from declaring, recording or writing waveforms.
#[derive(Debug, Error)]
pub enum WavesError {
    /// A scope or signal name that VCD cannot carry (empty, whitespace, or a leading `$`).
    #[error(
        "invalid VCD name {0:?}: names must be non-empty, without whitespace or a leading '$'"
    )]
    InvalidName(String),
    /// A name already used by a scope or signal in the same parent scope.
    #[error("name {0:?} is already used in this scope")]
    DuplicateName(String),
    /// A signal width outside `1..=64`.
    #[error("signal width {0} is out of range (1 to {MAX_WIDTH})")]
    InvalidWidth(u32),
    /// A scope handle that this recorder did not hand out.
    #[error("unknown scope handle {0}")]
    UnknownScope(usize),
    /// A signal handle that this recorder did not hand out.
    #[error("unknown signal handle {0}")]
    UnknownSignal(usize),
    /// A value with bits above the signal's width.
    #[error("value {value:#x} does not fit signal {name:?} of width {width}")]
    ValueTooWide {
        /// Signal name.
        name: String,
        /// Declared width in bits.
        width: u32,
        /// The value that was set.
        value: u64,
    },
    /// A `set` for an earlier cycle than the signal's previous `set`.
    #[error("signal {name:?} set for cycle {cycle} after cycle {last}")]
    TimeWentBack {
        /// Signal name.
        name: String,
        /// The cycle of the rejected `set`.
        cycle: u64,
        /// The cycle of the previous `set`.
        last: u64,
    },
    /// A window whose start is after its end.
    #[error("window start {from} is after its end {to}")]
    InvalidWindow {
        /// First cycle.
        from: u64,
        /// Last cycle.
        to: u64,
    },
    /// A clock frequency that gives no usable period (not finite, not positive, or above
    /// 500 GHz, where the half period rounds to zero picoseconds).
    #[error("clock of {0} MHz gives no even period of at least 2 ps")]
    InvalidClock(f64),
    /// A clock period that is zero or odd (the falling edge must land on an integer time).
    #[error("clock period of {0} ps is not a positive even number")]
    InvalidPeriod(u64),
    /// A cycle whose time in picoseconds does not fit a `u64`.
    #[error("cycle {0} is beyond the last time a VCD timestamp can hold at this period")]
    TimeOverflow(u64),
    /// Writing the file failed.
    #[error("writing VCD: {0}")]
    Io(#[from] io::Error),
}

/// How cycles map to VCD time: the clock period in picoseconds, always even.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timebase {
    period_ps: u64,
}

impl Timebase {
    /// The period nearest to `1 / clock_mhz` that is an even number of picoseconds.
    ///
    /// Rounding to even costs at most 1 ps per cycle of absolute time and keeps the clock's
    /// falling edge on an integer timestamp; cycle numbers stay exact.
    pub fn from_clock_mhz(clock_mhz: f64) -> Result<Self, WavesError> {
        if !(clock_mhz.is_finite() && clock_mhz > 0.0) {
            return Err(WavesError::InvalidClock(clock_mhz));
        }
        // Half period in ps = 1e6 / MHz / 2; rounding the half keeps the whole period even.
        let half = (500_000.0 / clock_mhz).round();
        if !(1.0..=(u64::MAX / 2) as f64).contains(&half) {
            return Err(WavesError::InvalidClock(clock_mhz));
        }
        Ok(Self {
            period_ps: 2 * half as u64,
        })
    }

    /// A period given directly in picoseconds; it must be even and non-zero.
    pub fn from_period_ps(period_ps: u64) -> Result<Self, WavesError> {
        if period_ps == 0 || period_ps % 2 != 0 {
            return Err(WavesError::InvalidPeriod(period_ps));
        }
        Ok(Self { period_ps })
    }

    /// The clock period in picoseconds (VCD time units per cycle).
    pub fn period_ps(self) -> u64 {
        self.period_ps
    }

    /// VCD time of the rising edge that starts `cycle`.
    pub fn time_of(self, cycle: u64) -> Result<u64, WavesError> {
        cycle
            .checked_mul(self.period_ps)
            .ok_or(WavesError::TimeOverflow(cycle))
    }
}

/// The inclusive range of cycles `[from, to]` that is written; see the module doc for what
/// the file holds at the window's start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    from: u64,
    to: u64,
}

impl Window {
    /// Every cycle.
    pub fn all() -> Self {
        Self {
            from: 0,
            to: u64::MAX,
        }
    }

    /// Cycles `from..=to`.
    pub fn cycles(from: u64, to: u64) -> Result<Self, WavesError> {
        if from > to {
            return Err(WavesError::InvalidWindow { from, to });
        }
        Ok(Self { from, to })
    }

    /// First cycle written.
    pub fn from(self) -> u64 {
        self.from
    }

    /// Last cycle written.
    pub fn to(self) -> u64 {
        self.to
    }

    /// Whether `cycle` is written.
    pub fn contains(self, cycle: u64) -> bool {
        (self.from..=self.to).contains(&cycle)
    }
}

/// Handle of a declared scope.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ScopeId(usize);

impl ScopeId {
    /// The top scope, [`TOP_SCOPE`]; signals declared here sit beside the clock.
    pub const TOP: ScopeId = ScopeId(0);
}

/// Handle of a declared signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SignalId(usize);

/// Header entries in declaration order, so the header is written as declared.
#[derive(Clone, Copy, Debug)]
enum Item {
    Scope(usize),
    Signal(usize),
}

#[derive(Debug)]
struct ScopeDecl {
    name: String,
    items: Vec<Item>,
}

#[derive(Debug)]
struct Signal {
    name: String,
    width: u32,
    /// Value as of the window's first cycle (`None` is `x`: never set by then).
    initial: Option<u64>,
    /// Changes in `(from, to]`, by strictly increasing cycle, each differing from the one
    /// before (or from `initial`).
    changes: Vec<(u64, u64)>,
    /// Cycle of the latest `set`, in or out of the window, to reject time going backwards.
    last_set: Option<u64>,
}

impl Signal {
    /// The value in force after the latest `set` (`skip_last` false), or just before the latest
    /// stored change (`skip_last` true); `None` is `x`.
    fn value_before(&self, skip_last: bool) -> Option<u64> {
        let n = self.changes.len() - usize::from(skip_last && !self.changes.is_empty());
        match n.checked_sub(1) {
            Some(i) => self.changes.get(i).map(|&(_, v)| v),
            None => self.initial,
        }
    }
}

/// Records value changes of pipeline signals, cycle by cycle, and writes them as VCD.
///
/// Declare scopes and signals first (their order fixes the file's order), then call
/// [`Waves::set`] as the model runs; each signal's `set` calls must come in non-decreasing
/// cycle order, while different signals may interleave freely.
#[derive(Debug)]
pub struct Waves {
    timebase: Timebase,
    window: Window,
    clock: bool,
    scopes: Vec<ScopeDecl>,
    signals: Vec<Signal>,
    /// Latest cycle the model is known to have reached (from `set` or `advance_to`).
    last_cycle: Option<u64>,
}

impl Waves {
    /// An empty recorder with only the top scope, the clock off.
    pub fn new(timebase: Timebase, window: Window) -> Self {
        Self {
            timebase,
            window,
            clock: false,
            scopes: vec![ScopeDecl {
                name: TOP_SCOPE.to_owned(),
                items: Vec::new(),
            }],
            signals: Vec::new(),
            last_cycle: None,
        }
    }

    /// Turns the `clk` signal on or off. It costs two changes per written cycle, which can
    /// double a sparse trace, so it is off by default; viewers show cycles without it, but edges
    /// make cycle boundaries easy to see.
    pub fn with_clock(mut self, clock: bool) -> Self {
        self.clock = clock;
        self
    }

    /// The time base in use.
    pub fn timebase(&self) -> Timebase {
        self.timebase
    }

    /// The window in use.
    pub fn window(&self) -> Window {
        self.window
    }

    /// Declares a scope inside the top scope, e.g. one per stage.
    pub fn scope(&mut self, name: &str) -> Result<ScopeId, WavesError> {
        self.subscope(ScopeId::TOP, name)
    }

    /// Declares a scope inside `parent`, e.g. `walker0` inside `walkers`.
    pub fn subscope(&mut self, parent: ScopeId, name: &str) -> Result<ScopeId, WavesError> {
        self.check_new_name(parent, name)?;
        let id = self.scopes.len();
        self.scopes.push(ScopeDecl {
            name: name.to_owned(),
            items: Vec::new(),
        });
        self.push_item(parent, Item::Scope(id))?;
        Ok(ScopeId(id))
    }

    /// Declares a `width`-bit signal in `scope`; its value is `x` until first set.
    pub fn signal(
        &mut self,
        scope: ScopeId,
        name: &str,
        width: u32,
    ) -> Result<SignalId, WavesError> {
        if !(1..=MAX_WIDTH).contains(&width) {
            return Err(WavesError::InvalidWidth(width));
        }
        self.check_new_name(scope, name)?;
        let id = self.signals.len();
        self.signals.push(Signal {
            name: name.to_owned(),
            width,
            initial: None,
            changes: Vec::new(),
            last_set: None,
        });
        self.push_item(scope, Item::Signal(id))?;
        Ok(SignalId(id))
    }

    /// Sets `signal` to `value` from `cycle` on. Repeating the current value records nothing;
    /// a second `set` in the same cycle replaces the first. Values before the window only
    /// update the value shown at the window's start; values after it are dropped.
    pub fn set(
        &mut self,
        signal: SignalId,
        cycle: u64,
        value: impl Into<u64>,
    ) -> Result<(), WavesError> {
        let value = value.into();
        let Window { from, to } = self.window;
        let sig = self
            .signals
            .get_mut(signal.0)
            .ok_or(WavesError::UnknownSignal(signal.0))?;
        if sig.width < 64 && value >> sig.width != 0 {
            return Err(WavesError::ValueTooWide {
                name: sig.name.clone(),
                width: sig.width,
                value,
            });
        }
        if let Some(last) = sig.last_set {
            if cycle < last {
                return Err(WavesError::TimeWentBack {
                    name: sig.name.clone(),
                    cycle,
                    last,
                });
            }
        }
        sig.last_set = Some(cycle);
        self.last_cycle = Some(self.last_cycle.map_or(cycle, |c| c.max(cycle)));

        if cycle <= from {
            // The `$dumpvars` block at the window's start shows the latest such value.
            sig.initial = Some(value);
        } else if cycle <= to {
            let same_cycle = sig.changes.last().is_some_and(|&(c, _)| c == cycle);
            if same_cycle {
                // Last write in a cycle wins; if it restores the earlier value, there is no
                // change left to show.
                if sig.value_before(true) == Some(value) {
                    sig.changes.pop();
                } else if let Some(last) = sig.changes.last_mut() {
                    last.1 = value;
                }
            } else if sig.value_before(false) != Some(value) {
                sig.changes.push((cycle, value));
            }
        }
        Ok(())
    }

    /// Notes that the model has reached `cycle` even if no signal changed, so the written
    /// trace extends to it (within the window).
    pub fn advance_to(&mut self, cycle: u64) {
        self.last_cycle = Some(self.last_cycle.map_or(cycle, |c| c.max(cycle)));
    }

    /// Number of value changes stored (inside the window, excluding initial values and the
    /// clock): a measure of the file's size before writing it.
    pub fn change_count(&self) -> usize {
        self.signals.iter().map(|s| s.changes.len()).sum()
    }

    /// The last cycle written: the latest cycle reached, clipped to the window, and never
    /// before the window's start (the file then holds only the start values).
    pub fn end_cycle(&self) -> u64 {
        let reached = self.last_cycle.unwrap_or(self.window.from);
        reached.min(self.window.to).max(self.window.from)
    }

    /// Writes the VCD to `out` (buffered internally; `out` is flushed at the end).
    pub fn write_to(&self, out: impl Write) -> Result<(), WavesError> {
        let mut w = Writer::new(BufWriter::new(out));
        self.write_header(&mut w)?;
        self.write_body(&mut w)?;
        w.flush()?;
        Ok(())
    }

    fn clock_code(&self) -> IdCode {
        IdCode::from(self.signals.len() as u64)
    }

    fn write_header<W: Write>(&self, w: &mut Writer<W>) -> Result<(), WavesError> {
        w.version(concat!(
            "rtl_model ",
            env!("CARGO_PKG_VERSION"),
            " cycle::waves"
        ))?;
        let window = if self.window == Window::all() {
            "all cycles".to_owned()
        } else {
            format!("cycles {}..={}", self.window.from, self.window.to)
        };
        let period = self.timebase.period_ps;
        w.comment(&format!(
            "1 cycle = {period} ps; cycle = time / {period}; window: {window}"
        ))?;
        w.timescale(1, TimescaleUnit::PS)?;
        self.write_scope(w, 0)?;
        w.enddefinitions()?;
        Ok(())
    }

    fn write_scope<W: Write>(&self, w: &mut Writer<W>, scope: usize) -> Result<(), WavesError> {
        let decl = self
            .scopes
            .get(scope)
            .ok_or(WavesError::UnknownScope(scope))?;
        w.add_module(&decl.name)?;
        if scope == 0 && self.clock {
            w.var_def(VarType::Wire, 1, self.clock_code(), CLOCK_NAME, None)?;
        }
        for &item in &decl.items {
            match item {
                Item::Scope(child) => self.write_scope(w, child)?,
                Item::Signal(s) => {
                    let sig = self.signals.get(s).ok_or(WavesError::UnknownSignal(s))?;
                    let index =
                        (sig.width > 1).then(|| ReferenceIndex::Range(sig.width as i32 - 1, 0));
                    w.var_def(
                        VarType::Wire,
                        sig.width,
                        IdCode::from(s as u64),
                        &sig.name,
                        index,
                    )?;
                }
            }
        }
        w.upscope()?;
        Ok(())
    }

    fn write_body<W: Write>(&self, w: &mut Writer<W>) -> Result<(), WavesError> {
        let tb = self.timebase;
        let half = tb.period_ps / 2;
        let from = self.window.from;
        let end = self.end_cycle();
        // Checked once for the latest time written; every earlier time then fits too.
        let end_time = end
            .checked_add(1)
            .ok_or(WavesError::TimeOverflow(end))
            .and_then(|c| tb.time_of(c))?;

        w.timestamp(tb.time_of(from)?)?;
        w.begin(SimulationCommand::Dumpvars)?;
        if self.clock {
            w.change_scalar(self.clock_code(), Value::V1)?;
        }
        for (i, sig) in self.signals.iter().enumerate() {
            write_value(w, IdCode::from(i as u64), sig.width, sig.initial)?;
        }
        w.end()?;

        let mut merge = ChangeMerge::new(&self.signals);
        if self.clock {
            let clk = self.clock_code();
            w.timestamp(from * tb.period_ps + half)?;
            w.change_scalar(clk, Value::V0)?;
            for cycle in from + 1..=end {
                w.timestamp(cycle * tb.period_ps)?;
                w.change_scalar(clk, Value::V1)?;
                merge.write_at(w, cycle)?;
                w.timestamp(cycle * tb.period_ps + half)?;
                w.change_scalar(clk, Value::V0)?;
            }
        } else {
            while let Some(cycle) = merge.next_cycle() {
                w.timestamp(cycle * tb.period_ps)?;
                merge.write_at(w, cycle)?;
            }
        }
        // A bare timestamp one cycle on gives the last cycle its width in a viewer.
        w.timestamp(end_time)?;
        Ok(())
    }

    fn check_new_name(&self, parent: ScopeId, name: &str) -> Result<(), WavesError> {
        if name.is_empty() || name.starts_with('$') || name.chars().any(char::is_whitespace) {
            return Err(WavesError::InvalidName(name.to_owned()));
        }
        let decl = self
            .scopes
            .get(parent.0)
            .ok_or(WavesError::UnknownScope(parent.0))?;
        let taken = (parent == ScopeId::TOP && name == CLOCK_NAME)
            || decl.items.iter().any(|&item| match item {
                Item::Scope(s) => self.scopes.get(s).is_some_and(|d| d.name == name),
                Item::Signal(s) => self.signals.get(s).is_some_and(|d| d.name == name),
            });
        if taken {
            return Err(WavesError::DuplicateName(name.to_owned()));
        }
        Ok(())
    }

    fn push_item(&mut self, parent: ScopeId, item: Item) -> Result<(), WavesError> {
        self.scopes
            .get_mut(parent.0)
            .ok_or(WavesError::UnknownScope(parent.0))?
            .items
            .push(item);
        Ok(())
    }
}

/// Merges the per-signal change lists by (cycle, declaration order): the file's order.
struct ChangeMerge<'a> {
    signals: &'a [Signal],
    /// (cycle, signal index, index into that signal's changes), smallest first.
    heap: BinaryHeap<Reverse<(u64, usize, usize)>>,
}

impl<'a> ChangeMerge<'a> {
    fn new(signals: &'a [Signal]) -> Self {
        let heap = signals
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.changes.first().map(|&(c, _)| Reverse((c, i, 0))))
            .collect();
        Self { signals, heap }
    }

    /// Cycle of the earliest change not yet written.
    fn next_cycle(&self) -> Option<u64> {
        self.heap.peek().map(|&Reverse((c, _, _))| c)
    }

    /// Writes every change at `cycle`, in declaration order.
    fn write_at<W: Write>(&mut self, w: &mut Writer<W>, cycle: u64) -> io::Result<()> {
        while let Some(&Reverse((c, i, k))) = self.heap.peek() {
            if c != cycle {
                break;
            }
            self.heap.pop();
            if let Some(sig) = self.signals.get(i) {
                if let Some(&(_, v)) = sig.changes.get(k) {
                    write_value(w, IdCode::from(i as u64), sig.width, Some(v))?;
                }
                if let Some(&(next, _)) = sig.changes.get(k + 1) {
                    self.heap.push(Reverse((next, i, k + 1)));
                }
            }
        }
        Ok(())
    }
}

/// Writes one value: scalars as `0`/`1`/`x`, vectors MSB first without leading zeros.
fn write_value<W: Write>(
    w: &mut Writer<W>,
    id: IdCode,
    width: u32,
    value: Option<u64>,
) -> io::Result<()> {
    match (width, value) {
        (1, Some(v)) => w.change_scalar(id, v != 0),
        (1, None) => w.change_scalar(id, Value::X),
        (_, Some(v)) => {
            let bits = (u64::BITS - v.leading_zeros()).max(1);
            w.change_vector(id, (0..bits).rev().map(|b| Value::from((v >> b) & 1 == 1)))
        }
        // A single leading `x` extends to the whole width.
        (_, None) => w.change_vector(id, [Value::X]),
    }
}
