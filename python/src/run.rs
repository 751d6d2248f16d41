//! Running a render off the interpreter: on a thread of its own with the GIL released (other
//! Python threads run, and render, meanwhile), under an interrupter that Ctrl-C trips (the
//! interpreter's signal check, every 50 ms), with a panic turned into an exception, and with
//! progress shown on a terminal.

use std::io::IsTerminal;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use penumbra::geom::Interrupter;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// How often the waiting thread looks for a signal.
const POLL: Duration = Duration::from_millis(50);

/// A render's progress, shown on standard error when it is a terminal and the render has run
/// for a second: `what` and the share done of `total` units.
pub struct Progress {
    what: String,
    total: u64,
    start: Instant,
    shown: AtomicU64,
    terminal: bool,
}

impl Progress {
    /// The progress of `total` units of `what`.
    pub fn new(what: String, total: u64) -> Progress {
        Progress {
            what,
            total: total.max(1),
            start: Instant::now(),
            shown: AtomicU64::new(0),
            terminal: std::io::stderr().is_terminal(),
        }
    }

    /// `done` units of the whole are done.
    pub fn set(&self, done: u64) {
        if !self.terminal || self.start.elapsed() < Duration::from_secs(1) {
            return;
        }
        let percent = 100 * done.min(self.total) / self.total;
        if self.shown.fetch_max(percent + 1, Ordering::Relaxed) < percent + 1 {
            eprint!("\r{} {percent:3}%", self.what);
        }
    }

    /// Ends the line, where one was shown.
    fn finish(&self) {
        if self.shown.load(Ordering::Relaxed) > 0 {
            eprint!("\r{}\r", " ".repeat(self.what.len() + 5));
        }
    }
}

/// Runs `f` on a thread of its own, the GIL released, under an interrupter that a signal
/// (Ctrl-C: `KeyboardInterrupt`) trips; `f` must not touch Python objects. A panic in `f`
/// becomes `RuntimeError`. With `threads`, `f`'s parallel work runs on a pool of its own of that
/// many threads rather than on the process's, which every render shares.
pub fn off_interpreter<T: Send>(
    py: Python<'_>,
    progress: Option<&Progress>,
    threads: Option<usize>,
    f: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let pool = match threads {
        Some(0) => return Err(PyValueError::new_err("threads must be 1 or more")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("threads: {e}")))?,
        ),
        None => None,
    };
    let interrupter = Interrupter::new();
    let result = std::thread::scope(|s| {
        let guarded = || interrupter.run(|| catch_unwind(AssertUnwindSafe(f)));
        let worker = s.spawn(|| match &pool {
            Some(p) => p.install(guarded),
            None => guarded(),
        });
        loop {
            let finished = py.detach(|| {
                let until = Instant::now() + POLL;
                while !worker.is_finished() && Instant::now() < until {
                    std::thread::sleep(Duration::from_millis(2));
                }
                worker.is_finished()
            });
            if finished {
                break;
            }
            if let Err(signal) = py.check_signals() {
                interrupter.interrupt();
                // The render stops at its next row; its result is dropped.
                let _ = py.detach(|| worker.join());
                return Err(signal);
            }
        }
        match worker.join() {
            Ok(Ok(value)) => Ok(value),
            Ok(Err(panic)) | Err(panic) => {
                let why = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                Err(PyRuntimeError::new_err(format!(
                    "penumbra failed inside (a bug; please report it with the scene): {why}"
                )))
            }
        }
    });
    if let Some(p) = progress {
        p.finish();
    }
    result
}
