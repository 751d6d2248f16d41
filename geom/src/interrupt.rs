//! Interrupting a render in progress: an [`Interrupter`] runs renders under it
//! ([`Interrupter::run`]) and stops them from any thread ([`Interrupter::interrupt`]). The CPU
//! renderers take the interrupter of the thread that calls them as they start
//! ([`Interruption::since`]) and look at it between rows; the front door then reports the
//! render as interrupted rather than return its unfinished image. A host that turns Ctrl-C into
//! an exception (Python) renders on a thread of its own under an interrupter and interrupts it
//! from its signal check.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

thread_local! {
    /// The interrupter of the renders this thread starts.
    static CURRENT: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// A handle that stops the renders run under it.
#[derive(Clone, Debug, Default)]
pub struct Interrupter(Arc<AtomicBool>);

impl Interrupter {
    /// A new interrupter, not interrupted.
    pub fn new() -> Interrupter {
        Interrupter::default()
    }

    /// Runs `f` on this thread with the renders it starts under this interrupter.
    pub fn run<R>(&self, f: impl FnOnce() -> R) -> R {
        let previous = CURRENT.with(|c| c.replace(Some(Arc::clone(&self.0))));
        /// Puts the previous interrupter back, on a panic too.
        struct Restore(Option<Arc<AtomicBool>>);
        impl Drop for Restore {
            fn drop(&mut self) {
                CURRENT.with(|c| *c.borrow_mut() = self.0.take());
            }
        }
        let _restore = Restore(previous);
        f()
    }

    /// Stops the renders run under this interrupter at their next row (or tile row), from any
    /// thread; those it runs afterwards stop at once.
    pub fn interrupt(&self) {
        self.0.store(true, Ordering::SeqCst);
    }
}

/// What a render looks at between rows: the interrupter of the thread that started it.
#[derive(Clone, Debug)]
pub struct Interruption(Option<Arc<AtomicBool>>);

impl Interruption {
    /// The interrupter of this thread's renders ([`Interrupter::run`]), if any: a render
    /// starting.
    pub fn since() -> Interruption {
        Interruption(CURRENT.with(|c| c.borrow().clone()))
    }

    /// Whether the render was interrupted.
    #[inline]
    pub fn happened(&self) -> bool {
        self.0.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_interrupter_reaches_the_renders_run_under_it_only() {
        assert!(!Interruption::since().happened());
        let i = Interrupter::new();
        let before = i.run(Interruption::since);
        assert!(!before.happened());
        i.interrupt();
        assert!(before.happened());
        assert!(i.run(Interruption::since).happened());
        // Outside `run`, and on another thread, renders are not under it.
        assert!(!Interruption::since().happened());
        let elsewhere = i.run(|| std::thread::spawn(Interruption::since).join().unwrap());
        assert!(!elsewhere.happened());
    }
}
