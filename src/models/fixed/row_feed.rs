//! Rows of a frame's trace handed from the functional model to the cycle model while the
//! frame is still being rendered, so the two run at the same time on two cores.
//!
//! Pipeline position: the functional/timing split (`docs/architecture.md` §4, `trace.rs`). The functional
//! model renders rows top to bottom and publishes each [`RowTrace`] when it is complete; the
//! cycle model's ray generation asks for a row before it generates that row's first pixel,
//! and waits (in wall time only: no simulated cycle passes) until it is there. Every later
//! stage sees only pixels that ray generation has already let in, so it never waits.
//!
//! The producer publishes in row order; a producer that stops early (cancelled, or panicking:
//! see [`FeedGuard`]) marks the feed closed, so a waiting consumer gets an error instead of
//! waiting for ever.

use super::trace::RowTrace;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex, OnceLock};
use thiserror::Error;

/// Why a row cannot be had.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum FeedError {
    /// The feed was closed (the producer stopped) before the row was published.
    #[error("the functional model stopped before row {0} was rendered")]
    Closed(usize),
    /// The row is outside the frame.
    #[error("row {row} is outside the frame's {rows} rows")]
    OutOfRange {
        /// Row asked for.
        row: usize,
        /// Rows of the frame.
        rows: usize,
    },
    /// Rows were published out of order (a producer bug).
    #[error("row {got} published while row {expected} was due")]
    OutOfOrder {
        /// Row due.
        expected: usize,
        /// Row offered.
        got: usize,
    },
}

#[derive(Debug, Default)]
struct Progress {
    published: usize,
    closed: bool,
}

/// The rows of one frame, published once each, in order.
#[derive(Debug)]
pub struct RowFeed {
    rows: Vec<OnceLock<RowTrace>>,
    progress: Mutex<Progress>,
    changed: Condvar,
    cancelled: AtomicBool,
}

impl RowFeed {
    /// An empty feed for `rows` rows.
    pub fn new(rows: usize) -> Self {
        Self {
            rows: (0..rows).map(|_| OnceLock::new()).collect(),
            progress: Mutex::new(Progress::default()),
            changed: Condvar::new(),
            cancelled: AtomicBool::new(false),
        }
    }

    /// Rows of the frame.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether the frame has no rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Progress> {
        // A panic while holding this lock leaves only two integers behind, both consistent.
        self.progress.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Publishes row `row`, which must be the next one.
    pub fn publish(&self, row: usize, trace: RowTrace) -> Result<(), FeedError> {
        let mut p = self.lock();
        if p.closed {
            return Err(FeedError::Closed(row));
        }
        if row != p.published {
            return Err(FeedError::OutOfOrder {
                expected: p.published,
                got: row,
            });
        }
        let Some(cell) = self.rows.get(row) else {
            return Err(FeedError::OutOfRange {
                row,
                rows: self.rows.len(),
            });
        };
        if cell.set(trace).is_err() {
            return Err(FeedError::OutOfOrder {
                expected: p.published,
                got: row,
            });
        }
        p.published += 1;
        drop(p);
        self.changed.notify_all();
        Ok(())
    }

    /// Marks the feed closed: no more rows will come.
    pub fn close(&self) {
        self.lock().closed = true;
        self.changed.notify_all();
    }

    /// Asks the producer to stop (the consumer has failed and needs no more rows).
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether the consumer asked the producer to stop.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// Waits until row `row` is published and returns how many rows are (at least `row + 1`).
    pub fn wait_for(&self, row: usize) -> Result<usize, FeedError> {
        if row >= self.rows.len() {
            return Err(FeedError::OutOfRange {
                row,
                rows: self.rows.len(),
            });
        }
        let mut p = self.lock();
        while p.published <= row {
            if p.closed {
                return Err(FeedError::Closed(row));
            }
            p = self.changed.wait(p).unwrap_or_else(|e| e.into_inner());
        }
        Ok(p.published)
    }

    /// Row `row` if it has been published.
    pub fn get(&self, row: usize) -> Option<&RowTrace> {
        self.rows.get(row).and_then(OnceLock::get)
    }
}

/// Closes the feed when dropped: on the producer's normal return and also when it unwinds
/// from a panic, so the consumer is never left waiting.
pub struct FeedGuard<'a>(pub &'a RowFeed);

impl Drop for FeedGuard<'_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(n: usize) -> RowTrace {
        RowTrace {
            ops: vec![n as u64],
            ..RowTrace::default()
        }
    }

    #[test]
    fn rows_arrive_in_order_across_threads() {
        let feed = RowFeed::new(200);
        std::thread::scope(|s| {
            s.spawn(|| {
                let _guard = FeedGuard(&feed);
                for j in 0..200 {
                    feed.publish(j, row(j)).expect("in order");
                }
            });
            let mut have = 0;
            for j in 0..200 {
                if j >= have {
                    have = feed.wait_for(j).expect("published");
                }
                assert_eq!(feed.get(j).map(|t| t.ops[0]), Some(j as u64));
            }
        });
    }

    #[test]
    fn out_of_order_and_out_of_range_are_refused() {
        let feed = RowFeed::new(3);
        assert_eq!(
            feed.publish(1, row(1)),
            Err(FeedError::OutOfOrder {
                expected: 0,
                got: 1
            })
        );
        feed.publish(0, row(0)).expect("first");
        assert_eq!(
            feed.wait_for(3),
            Err(FeedError::OutOfRange { row: 3, rows: 3 })
        );
        assert_eq!(feed.get(1), None);
        feed.close();
        assert_eq!(feed.publish(1, row(1)), Err(FeedError::Closed(1)));
        assert_eq!(feed.wait_for(2), Err(FeedError::Closed(2)));
    }

    #[test]
    fn a_producer_that_panics_releases_the_consumer() {
        let feed = RowFeed::new(10);
        let outcome = std::thread::scope(|s| {
            let producer = s.spawn(|| {
                let _guard = FeedGuard(&feed);
                for j in 0..4 {
                    feed.publish(j, row(j)).expect("in order");
                }
                panic!("producer fails at row 4");
            });
            let waited = feed.wait_for(7);
            (waited, producer.join().is_err())
        });
        assert_eq!(outcome, (Err(FeedError::Closed(7)), true));
        assert_eq!(feed.wait_for(3), Ok(4));
    }
}
