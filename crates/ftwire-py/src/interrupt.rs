//! Long calls that Ctrl-C ends: the work runs on a thread of its own, while the calling thread
//! waits without the GIL and checks Python's signals every [`POLL`]. A SIGINT then raises
//! `KeyboardInterrupt` within that period, instead of being seen only after the work (and
//! then in the middle of building the result, which aborted the interpreter or raised a
//! `PanicException`). The interrupted work runs on to its end in the background and its result
//! is dropped: the library's searches take no cancellation.

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::Mutex;
use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread checks for signals.
const POLL: Duration = Duration::from_millis(50);

/// Runs `work` on its own thread and returns its value, or Python's exception (a
/// `KeyboardInterrupt`) when a signal handler raises one first. A panic of `work` goes on
/// unwinding in the caller, as if `work` had run there.
///
/// # Errors
/// The signal handler's exception; a `RuntimeError` when the thread cannot be started.
pub fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (sender, receiver) = channel();
    std::thread::Builder::new()
        .name("ftwire-work".to_owned())
        .spawn(move || {
            // The receiver is gone after an interrupt: the value is dropped.
            let _ = sender.send(catch_unwind(AssertUnwindSafe(work)));
        })
        .map_err(|e| PyRuntimeError::new_err(format!("starting the work's thread: {e}")))?;
    // Shared with the GIL-free wait by reference: a lock makes the receiver `Sync`.
    let receiver = Mutex::new(receiver);
    let wait = || match receiver.lock() {
        Ok(receiver) => receiver.recv_timeout(POLL),
        Err(_) => Err(RecvTimeoutError::Disconnected),
    };
    loop {
        match py.detach(wait) {
            Ok(Ok(value)) => return Ok(value),
            Ok(Err(panic)) => resume_unwind(panic),
            Err(RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "the work's thread ended without an answer",
                ));
            }
        }
    }
}
