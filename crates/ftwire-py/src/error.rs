//! The lab's errors as Python exceptions: bad input is `ValueError`, no answer (a search or an
//! integration that failed, a file that cannot be written) `RuntimeError`.

use ftwire_lab::LabError;
use ftwire_lab::error::EXIT_BAD_INPUT;
use pyo3::PyErr;
use pyo3::exceptions::{PyRuntimeError, PyValueError};

/// `error` as a Python exception, its message led by `what` (the argument or the call).
pub fn lab_error(error: &LabError, what: &str) -> PyErr {
    let message = format!("{what}: {error}");
    if error.exit_code() == EXIT_BAD_INPUT {
        PyValueError::new_err(message)
    } else {
        PyRuntimeError::new_err(message)
    }
}
