//! Clean interruption: SIGINT and SIGTERM set a flag that the long loops check; the exit path
//! removes every unfinished temporary and ends with 130 (SIGINT) or 143 (SIGTERM).
//!
//! Pipeline position: beside the one output writer ([`super::writer`]), whose temporaries it
//! removes ([`super::temporaries`]). The `sim` binary calls [`install`] once; the frame loop
//! (`run::frames`), the studies' runner (`run::parallel`) and the other long loops call
//! [`check`] between units of work (a frame, a configuration, a case) and return
//! [`Interrupted`], which the binary's `main` turns into one line saying what was kept, the
//! removal of what was not, and the exit status. Outputs already complete stay; nothing
//! half-written does.
//!
//! The handler itself does nothing but record the signal (`signal-hook`'s iterator: an
//! async-signal-safe write to a pipe); a normal thread reads it and sets the flag. A second
//! signal while the first is being honoured ends the process at once from that thread, after
//! removing the temporaries (the user insisted; a loop may be in a long unit of work).

use super::temporaries;
use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::sync::atomic::{AtomicI32, Ordering};
use thiserror::Error;

/// The first signal received (0: none).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// Work stopped by a signal.
#[derive(Debug, Error)]
#[error("interrupted by {} at {at}", signal_name(*signal))]
pub struct Interrupted {
    /// The signal number (SIGINT 2, SIGTERM 15).
    pub signal: i32,
    /// Where the work stopped, e.g. `frame 7 of 48`.
    pub at: String,
    /// What was kept, e.g. `out/frame_0000.png … out/frame_0006.png`; empty: nothing.
    pub kept: String,
}

impl Interrupted {
    /// The process exit status: 128 + the signal number (130, 143), as a shell reports it.
    pub fn exit_status(&self) -> u8 {
        exit_status(self.signal)
    }
}

/// 128 + `signal`.
pub fn exit_status(signal: i32) -> u8 {
    u8::try_from(128 + signal).unwrap_or(1)
}

/// The name of a signal this module handles.
pub fn signal_name(signal: i32) -> &'static str {
    match signal {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        _ => "a signal",
    }
}

/// Installs the SIGINT and SIGTERM handling for the process (the `sim` binary, once).
pub fn install() -> std::io::Result<()> {
    let mut signals = Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for sig in signals.forever() {
                if SIGNAL
                    .compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst)
                    .is_err()
                {
                    temporaries::remove_all_and_exit(i32::from(exit_status(sig)), |n| {
                        format!(
                            "interrupted again by {}: stopped at once; removed {n} unfinished file{}",
                            signal_name(sig),
                            if n == 1 { "" } else { "s" }
                        )
                    });
                }
            }
        })?;
    Ok(())
}

/// The signal received, if any.
pub fn received() -> Option<i32> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}

/// `Err(Interrupted)` once a signal was received; `at` and `kept` describe the point reached
/// and are only computed then.
pub fn check(
    at: impl FnOnce() -> String,
    kept: impl FnOnce() -> String,
) -> Result<(), Interrupted> {
    match received() {
        None => Ok(()),
        Some(signal) => Err(Interrupted {
            signal,
            at: at(),
            kept: kept(),
        }),
    }
}

/// The one line printed when the process ends on a signal: `head` (where it stopped, e.g.
/// `interrupted by SIGINT at frame 7 of 48`), what was kept, how many unfinished files were
/// removed. Removes every live temporary first.
pub fn finish_line(head: &str, kept: &str) -> String {
    let removed = temporaries::remove_all();
    let kept = if kept.is_empty() { "nothing" } else { kept };
    format!(
        "{head}: kept {kept}; removed {removed} unfinished file{}",
        if removed == 1 { "" } else { "s" }
    )
}
