//! Library errors as Python exceptions, with the CLI's one-line message.

use filmsplat::Error;
use pyo3::PyErr;
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyPermissionError, PyRuntimeError,
    PyValueError,
};

/// `Io` → `OSError` (`FileNotFoundError`, `PermissionError` where they apply); `Format` and
/// `Invalid` (bad input) → `ValueError`; `Cancelled` → `KeyboardInterrupt`; `Internal` →
/// `RuntimeError`. The message is the one the CLI prints.
pub fn to_py(e: Error) -> PyErr {
    let msg = e.to_string();
    match &e {
        Error::Io { source, .. } => match source.kind() {
            std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(msg),
            std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(msg),
            _ => PyOSError::new_err(msg),
        },
        Error::Format { .. } | Error::Invalid(_) | Error::Usage(_) => PyValueError::new_err(msg),
        Error::Cancelled => PyKeyboardInterrupt::new_err(msg),
        Error::Internal(_) => PyRuntimeError::new_err(msg),
    }
}

/// A `ValueError` with `msg`.
pub fn invalid(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}
