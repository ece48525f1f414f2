//! Studies that run many independent configurations or scenes (`sim sweep`, `sim bench
//! --scaling`) run them on all cores through [`map_in_order`], with output identical to a
//! sequential run: results come back in input order and the progress callback sees them in
//! that order, whatever order the workers finish in.
//!
//! Pipeline position: around whole runs of the models, never inside one (a cycle-model run is
//! sequential by design, its functional model on its own thread beside it;
//! docs/cycle-model.md §2.7). The worker count is rayon's global pool (`--threads`).

use crate::output::interrupt::{self, Interrupted};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// `items.iter().map(f)` on the rayon pool, with the result of a sequential loop that stops at
/// the first error: `progress` is called for each result in input order up to the first error,
/// and that error (the first in input order) is returned. Items after a failed one may be
/// skipped. Each `f` call must be independent of the others (no shared mutable state), so
/// its result does not depend on which worker ran it or when.
///
/// Once SIGINT or SIGTERM was received (`crate::output::interrupt`), items not yet started
/// fail with `Interrupted` at "`what` N of M", so a study stops within one item's time.
pub fn map_in_order<I, R, E>(
    what: &str,
    items: &[I],
    f: impl Fn(&I) -> Result<R, E> + Sync,
    mut progress: impl FnMut(&R),
) -> Result<Vec<R>, E>
where
    I: Sync,
    R: Send,
    E: Send + From<Interrupted>,
{
    let n = items.len();
    let mut slots: Vec<Option<Result<R, E>>> = (0..n).map(|_| None).collect();
    // The lowest failed index so far: later items need not run.
    let failed = AtomicUsize::new(usize::MAX);
    let (tx, rx) = mpsc::channel::<(usize, Result<R, E>)>();
    let mut next = 0usize;
    let mut stopped = false;
    std::thread::scope(|s| {
        let (failed, f) = (&failed, &f);
        s.spawn(move || {
            items
                .par_iter()
                .enumerate()
                .for_each_with(tx, |tx, (i, item)| {
                    if i > failed.load(Ordering::Relaxed) {
                        return;
                    }
                    let r = interrupt::check(|| format!("{what} {} of {n}", i + 1), String::new)
                        .map_err(E::from)
                        .and_then(|()| f(item));
                    if r.is_err() {
                        failed.fetch_min(i, Ordering::Relaxed);
                    }
                    // The receiver lives until every sender is dropped.
                    let _ = tx.send((i, r));
                });
        });
        // Results as they finish; progress in input order as soon as a prefix is complete.
        for (i, r) in rx {
            slots[i] = Some(r);
            while !stopped && next < n {
                match &slots[next] {
                    Some(Ok(v)) => progress(v),
                    Some(Err(_)) => stopped = true,
                    None => break,
                }
                if !stopped {
                    next += 1;
                }
            }
        }
    });
    let mut out = Vec::with_capacity(n);
    for slot in slots {
        match slot {
            Some(Ok(v)) => out.push(v),
            Some(Err(e)) => return Err(e),
            // Skipped only after a failure at a lower index, which returned above.
            None => break,
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::map_in_order;

    /// Work whose duration varies, so workers finish out of order.
    fn work(x: &u64) -> Result<u64, Failure> {
        let mut h = *x;
        for _ in 0..(x % 7) * 20_000 {
            h = h.wrapping_mul(6364136223846793005).wrapping_add(1);
        }
        if *x == 13 {
            return Err(Failure(format!("item {x} fails")));
        }
        Ok(h)
    }

    /// A work item's error (or an interruption, which this test never sends).
    #[derive(Debug, PartialEq)]
    struct Failure(String);

    impl From<crate::output::interrupt::Interrupted> for Failure {
        fn from(i: crate::output::interrupt::Interrupted) -> Self {
            Self(i.to_string())
        }
    }

    fn sequential(items: &[u64]) -> (Result<Vec<u64>, Failure>, Vec<u64>) {
        let mut seen = Vec::new();
        let mut out = Vec::new();
        for x in items {
            match work(x) {
                Ok(v) => {
                    seen.push(v);
                    out.push(v);
                }
                Err(e) => return (Err(e), seen),
            }
        }
        (Ok(out), seen)
    }

    #[test]
    fn same_results_and_progress_as_a_sequential_loop() {
        let ok: Vec<u64> = (0..40).filter(|&x| x != 13).collect();
        let bad: Vec<u64> = (0..40).collect();
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for items in [&ok, &bad] {
                let mut seen = Vec::new();
                let got = pool.install(|| map_in_order("item", items, work, |v| seen.push(*v)));
                let (want, want_seen) = sequential(items);
                assert_eq!(got, want, "{threads} threads");
                assert_eq!(seen, want_seen, "{threads} threads");
            }
        }
        let none: Vec<u64> = Vec::new();
        assert_eq!(map_in_order("item", &none, work, |_| {}), Ok(vec![]));
    }
}
