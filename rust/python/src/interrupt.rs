//! Ctrl-C during a long call of the core.
//!
//! Python runs its signal handlers (the one that raises `KeyboardInterrupt`) only on the main
//! thread, between bytecodes: while the core works without the GIL a Ctrl-C waited for the whole
//! call (3.5 s for 10^8 samples through a pipeline, 28 s for a modified Allan deviation of them).
//! A long call therefore runs on a helper thread while the calling thread runs the handlers every
//! [`POLL`]; once one raises, the work is told to [`Stop`] and the call returns that exception.
//! The work looks at the flag between pieces of a few milliseconds, so the loops over samples are
//! not touched.

use gyrocore::Error;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::Mutex;
use std::time::Duration;

/// Calls over fewer samples than this run on the calling thread: they end within milliseconds,
/// before a helper thread would pay off.
pub(crate) const WATCHED: usize = 1 << 20;

/// How often the calling thread runs the signal handlers while the work runs: what a Ctrl-C waits
/// at most besides the piece of work in hand.
const POLL: Duration = Duration::from_millis(20);

/// Samples per piece of a long call, between looks for a Ctrl-C: a few milliseconds of work, and
/// a call of the core per piece costs nothing next to it.
pub(crate) const PIECE: usize = 1 << 16;

/// Set once a signal handler raised: the work stops at its next look (the core's stoppable
/// functions look at the flag itself).
#[derive(Default)]
pub(crate) struct Stop(pub(crate) AtomicBool);

impl Stop {
    /// Whether the work should stop (what it has done is then thrown away).
    pub(crate) fn requested(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Runs `f` on `0..n` piece by piece ([`PIECE`] samples at most), in order, until `stop` is
/// requested or a piece fails (an empty `n` is one empty piece, so that the core still checks it).
pub(crate) fn pieces<E>(
    n: usize,
    stop: &Stop,
    mut f: impl FnMut(Range<usize>) -> Result<(), E>,
) -> Result<(), E> {
    let mut start = 0;
    loop {
        let end = n.min(start + PIECE);
        f(start..end)?;
        start = end;
        if start == n || stop.requested() {
            return Ok(());
        }
    }
}

/// [`detach_watched`] of work done in [`pieces`] of `0..n`: `f` runs on each piece, and a piece's
/// error names its sample counted from the first of `0..n`.
pub(crate) fn watched_pieces(
    py: Python<'_>,
    n: usize,
    mut f: impl FnMut(Range<usize>) -> Result<(), Error> + Send,
) -> PyResult<Result<(), Error>> {
    detach_watched(py, n, |stop| {
        pieces(n, stop, |range| {
            let start = range.start;
            f(range).map_err(|e| e.with_index_offset(start))
        })
    })
}

/// Runs `work` without the GIL. Over [`WATCHED`] `samples` or more it runs on a helper thread
/// while this one runs the signal handlers; the exception one raises is returned once `work` has
/// stopped, whatever `work` returned (the caller puts back its state). The same on any thread:
/// elsewhere than on the main thread no handler runs, and nothing stops the work.
pub(crate) fn detach_watched<R: Send>(
    py: Python<'_>,
    samples: usize,
    work: impl FnOnce(&Stop) -> R + Send,
) -> PyResult<R> {
    let stop = Stop::default();
    if samples < WATCHED {
        return Ok(py.detach(|| work(&stop)));
    }
    // Taken by the helper thread, or by this one if the system refuses a thread.
    let slot = Mutex::new(Some(work));
    let run = |stop: &Stop| slot.lock().ok().and_then(|mut w| w.take()).map(|w| w(stop));
    let (result, raised) = py.detach(|| {
        std::thread::scope(|s| {
            let (done, finished) = channel();
            let (run, stop) = (&run, &stop);
            let helper = std::thread::Builder::new().spawn_scoped(s, move || {
                let result = run(stop);
                let _ = done.send(());
                result
            });
            let Ok(helper) = helper else {
                return (run(stop), None); // unwatched, as a short call
            };
            let mut raised = None;
            while let Err(RecvTimeoutError::Timeout) = finished.recv_timeout(POLL) {
                if raised.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        stop.0.store(true, Ordering::Relaxed);
                        raised = Some(e);
                    }
                }
            }
            let result = helper
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (result, raised)
        })
    });
    match (result, raised) {
        (_, Some(e)) => Err(e),
        (Some(r), None) => Ok(r),
        // the work is taken once, by the thread that runs it
        (None, None) => Err(PyRuntimeError::new_err("the work of this call was lost")),
    }
}
