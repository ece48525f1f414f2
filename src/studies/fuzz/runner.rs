//! The fuzz loop: mutated inputs run one at a time on a worker thread under a time limit; each
//! ends in a result, an error, a panic (caught, with its message) or a hang (the limit passed).
//!
//! Pipeline position: none — a check of the loaders in front of the pipeline. Panics are
//! caught with `catch_unwind` and their messages taken by a panic hook installed for the run
//! (the worker thread's panics only; others go to the previous hook). A hang cannot be
//! stopped on stable Rust without killing the process, so the run ends at the first one with
//! the input saved; the worker is left behind. Memory is bounded by the loaders' own limits;
//! the run reports the process's peak resident size so that a limit that is too generous shows.

use super::corpus::Seed;
use super::mutate::mutate;
use super::targets::Target;
use rtl_model::vectors::rng::Rng;
use std::collections::BTreeMap;
use std::panic::{self, AssertUnwindSafe};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

/// How one input ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Accepted.
    Accepted,
    /// Rejected with this error text.
    Rejected(String),
    /// Panicked with this message.
    Panicked(String),
}

/// An input that panicked or hung.
#[derive(Clone, Debug)]
pub struct Finding {
    /// The target.
    pub target: Target,
    /// Index of the input in its target's stream (replayable with the same seed).
    pub index: u64,
    /// What happened.
    pub message: String,
    /// The input.
    pub input: Vec<u8>,
}

/// What one target's inputs did.
#[derive(Clone, Debug, Default)]
pub struct TargetReport {
    /// Inputs run (seeds included).
    pub inputs: u64,
    /// Of which the parser accepted.
    pub accepted: u64,
    /// Of which it rejected with an error.
    pub rejected: u64,
    /// Rejections by kind: the error's text with numbers and quoted names blanked, cut short.
    pub error_kinds: BTreeMap<String, u64>,
    /// Inputs that panicked.
    pub panics: Vec<Finding>,
    /// The input that hung, if any (the run stops there).
    pub hang: Option<Finding>,
    /// Longest time one input took.
    pub slowest: Duration,
    /// Total time of the target's inputs.
    pub total: Duration,
    /// Seeds the parser rejected unmutated (a corpus problem, reported).
    pub seeds_rejected: Vec<String>,
}

/// Options of a fuzz run.
#[derive(Clone, Debug)]
pub struct FuzzOptions {
    /// Mutated inputs per target (the seeds are run once more, unmutated, first).
    pub inputs: u64,
    /// Seed of the mutation streams (one stream per target, derived from it and the name).
    pub seed: u64,
    /// Longest one input may take before it counts as a hang.
    pub time_limit: Duration,
}

type Job = (Target, Vec<u8>);
type Reply = Outcome;
/// What runs one input: [`Target::run`], or a stand-in in the runner's own tests.
pub type Exec = Arc<dyn Fn(Target, &[u8]) -> Result<(), String> + Send + Sync>;

/// The message of the worker's latest panic, set by the run's panic hook.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);
const WORKER_NAME: &str = "fuzz-worker";

fn spawn_worker(exec: &Exec) -> std::io::Result<(mpsc::Sender<Job>, mpsc::Receiver<Reply>)> {
    let exec = exec.clone();
    let (job_tx, job_rx) = mpsc::channel::<Job>();
    let (reply_tx, reply_rx) = mpsc::channel::<Reply>();
    thread::Builder::new()
        .name(WORKER_NAME.into())
        // The loaders recurse only as deep as their guards allow; a generous stack keeps a
        // debug build's larger frames from turning that depth into an overflow.
        .stack_size(64 << 20)
        .spawn(move || {
            for (target, input) in job_rx {
                let outcome = match panic::catch_unwind(AssertUnwindSafe(|| exec(target, &input))) {
                    Ok(Ok(())) => Outcome::Accepted,
                    Ok(Err(e)) => Outcome::Rejected(e),
                    Err(_) => Outcome::Panicked(
                        LAST_PANIC
                            .lock()
                            .ok()
                            .and_then(|mut m| m.take())
                            .unwrap_or_else(|| "panic without a message".into()),
                    ),
                };
                if reply_tx.send(outcome).is_err() {
                    break;
                }
            }
        })?;
    Ok((job_tx, reply_rx))
}

/// Installs a hook that records the worker's panic messages (with their location) instead of
/// printing them; other threads' panics go to the hook that was there before. Returns a guard
/// that puts the previous hook back.
struct HookGuard(Arc<dyn Fn(&panic::PanicHookInfo<'_>) + Sync + Send + 'static>);

impl HookGuard {
    fn install() -> Self {
        let previous: Arc<dyn Fn(&panic::PanicHookInfo<'_>) + Sync + Send> =
            Arc::from(panic::take_hook());
        let chained = previous.clone();
        panic::set_hook(Box::new(move |info| {
            if thread::current().name() == Some(WORKER_NAME) {
                let payload = info
                    .payload()
                    .downcast_ref::<String>()
                    .map(String::as_str)
                    .or_else(|| info.payload().downcast_ref::<&str>().copied())
                    .unwrap_or("(no message)");
                let at = info
                    .location()
                    .map(|l| format!(" at {}:{}", l.file(), l.line()))
                    .unwrap_or_default();
                if let Ok(mut m) = LAST_PANIC.lock() {
                    *m = Some(format!("{payload}{at}"));
                }
            } else {
                chained(info);
            }
        }));
        HookGuard(previous)
    }
}

impl Drop for HookGuard {
    fn drop(&mut self) {
        let previous = self.0.clone();
        panic::set_hook(Box::new(move |info| previous(info)));
    }
}

/// Blanks the parts of an error text that differ between inputs of the same kind (numbers,
/// quoted text, positions) so that rejections can be counted by kind.
fn error_kind(text: &str) -> String {
    let mut out = String::new();
    let mut in_quote = false;
    for c in text.chars() {
        if c == '"' || c == '`' {
            in_quote = !in_quote;
            out.push('…');
        } else if in_quote {
            continue;
        } else if c.is_ascii_digit() {
            if !out.ends_with('#') {
                out.push('#');
            }
        } else {
            out.push(c);
        }
    }
    out.chars().take(90).collect()
}

/// Runs `opts.inputs` mutated inputs per target (after the seeds themselves); `progress` is
/// called after each input with the target, the input's index and the count per target.
pub fn run(
    targets: &[(Target, Vec<Seed>)],
    opts: &FuzzOptions,
    progress: impl FnMut(Target, u64, u64),
) -> std::io::Result<Vec<(Target, TargetReport)>> {
    run_with(
        Arc::new(|t: Target, i: &[u8]| t.run(i)),
        targets,
        opts,
        progress,
    )
}

/// [`run`] with another executor of one input (the runner's tests inject panics and hangs).
pub fn run_with(
    exec: Exec,
    targets: &[(Target, Vec<Seed>)],
    opts: &FuzzOptions,
    mut progress: impl FnMut(Target, u64, u64),
) -> std::io::Result<Vec<(Target, TargetReport)>> {
    let _hook = HookGuard::install();
    let (mut tx, mut rx) = spawn_worker(&exec)?;
    let mut reports = Vec::new();
    for (target, seeds) in targets {
        let target = *target;
        let mut rep = TargetReport::default();
        if seeds.is_empty() {
            reports.push((target, rep));
            continue;
        }
        let mut rng = Rng::for_stage(opts.seed, target.name());
        let total = seeds.len() as u64 + opts.inputs;
        for index in 0..total {
            if let Err(i) = crate::output::interrupt::check(
                || format!("{} input {index} of {total}", target.name()),
                String::new,
            ) {
                return Err(std::io::Error::new(std::io::ErrorKind::Interrupted, i));
            }
            let input = match seeds.get(index as usize) {
                Some(s) => s.bytes.clone(),
                None => {
                    let a = &seeds[rng.below(seeds.len() as u64) as usize];
                    let b = &seeds[rng.below(seeds.len() as u64) as usize];
                    mutate(&mut rng, &a.bytes, &b.bytes, target.is_text())
                }
            };
            let start = Instant::now();
            if tx.send((target, input.clone())).is_err() {
                // The worker died (it never should: panics are caught); start another.
                (tx, rx) = spawn_worker(&exec)?;
                continue;
            }
            let outcome = match rx.recv_timeout(opts.time_limit) {
                Ok(o) => o,
                Err(_) => {
                    rep.inputs += 1;
                    rep.hang = Some(Finding {
                        target,
                        index,
                        message: format!("no result within {:?}", opts.time_limit),
                        input,
                    });
                    reports.push((target, rep));
                    return Ok(reports);
                }
            };
            let took = start.elapsed();
            rep.slowest = rep.slowest.max(took);
            rep.total += took;
            rep.inputs += 1;
            match outcome {
                Outcome::Accepted => rep.accepted += 1,
                Outcome::Rejected(e) => {
                    rep.rejected += 1;
                    if let Some(s) = seeds.get(index as usize) {
                        rep.seeds_rejected.push(format!("{}: {e}", s.name));
                    }
                    *rep.error_kinds.entry(error_kind(&e)).or_default() += 1;
                }
                Outcome::Panicked(message) => rep.panics.push(Finding {
                    target,
                    index,
                    message,
                    input,
                }),
            }
            progress(target, index + 1, total);
        }
        reports.push((target, rep));
    }
    Ok(reports)
}

/// Peak resident set size of this process in bytes (Linux `VmHWM`), if the system tells.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seeds(bytes: &[&[u8]]) -> Vec<(Target, Vec<Seed>)> {
        let s = bytes
            .iter()
            .map(|b| Seed {
                name: "t".into(),
                bytes: b.to_vec(),
            })
            .collect();
        vec![(Target::Scene, s)]
    }

    fn opts(inputs: u64) -> FuzzOptions {
        FuzzOptions {
            inputs,
            seed: 1,
            time_limit: Duration::from_millis(500),
        }
    }

    #[test]
    fn panics_are_caught_with_their_message() {
        // Inputs containing a digit 7 panic, others are rejected or accepted.
        let exec: Exec = Arc::new(|_, i: &[u8]| {
            if i.contains(&b'7') {
                panic!("seven found");
            }
            if i.len() % 2 == 0 {
                Ok(())
            } else {
                Err("odd".into())
            }
        });
        let r = run_with(
            exec,
            &seeds(&[b"(a: 1, b: 2)", b"(c: 7)"]),
            &opts(300),
            |_, _, _| {},
        )
        .expect("run");
        let rep = &r[0].1;
        assert_eq!(rep.inputs, 302);
        assert_eq!(rep.accepted + rep.rejected + rep.panics.len() as u64, 302);
        assert!(!rep.panics.is_empty());
        assert!(
            rep.panics[0].message.starts_with("seven found at "),
            "{}",
            rep.panics[0].message
        );
        assert!(rep.panics.iter().all(|f| f.input.contains(&b'7')));
        assert_eq!(rep.seeds_rejected.len(), 0);
    }

    #[test]
    fn a_hang_ends_the_run_with_the_input() {
        let exec: Exec = Arc::new(|_, i: &[u8]| {
            if i.contains(&b'9') {
                std::thread::sleep(Duration::from_secs(3));
            }
            Ok(())
        });
        let r = run_with(
            exec,
            &seeds(&[b"(a: 1)", b"(b: 9)"]),
            &opts(50),
            |_, _, _| {},
        )
        .expect("run");
        let rep = &r[0].1;
        let hang = rep.hang.as_ref().expect("the hang is reported");
        assert_eq!(hang.index, 1);
        assert_eq!(hang.input, b"(b: 9)");
        assert_eq!(rep.inputs, 2);
    }

    #[test]
    fn error_kinds_blank_numbers_and_names() {
        assert_eq!(
            error_kind("<x>:3:14: expected `)` but found \"abc\" 12"),
            "<x>:#:#: expected …… but found …… #"
        );
    }
}
