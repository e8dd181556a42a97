//! The library's error type. The CLI turns it into a one-line message and an exit code.

use std::path::PathBuf;

/// Result with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong, split into bad input (the user can fix it) and internal faults.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A file was read but its content is malformed.
    #[error("{path}: {format}: {message}")]
    Format {
        /// The file concerned.
        path: PathBuf,
        /// The format it was read as (e.g. "PLY").
        format: &'static str,
        /// What is wrong and where.
        message: String,
    },
    /// A parameter or a value in the data is invalid.
    #[error("{0}")]
    Invalid(String),
    /// A fault inside filmsplat (a bug or an unexpected condition).
    #[error("internal error: {0}")]
    Internal(String),
    /// The command line is wrong (an unknown flag, a missing argument): clap's message with
    /// its usage lines, printed as clap prints it.
    #[error("{0}")]
    Usage(Box<clap::Error>),
    /// The caller asked the work to stop (see `RenderSettings::cancel`).
    #[error("cancelled")]
    Cancelled,
}

impl Error {
    /// Shorthand for [`Error::Invalid`].
    pub fn invalid(msg: impl Into<String>) -> Self {
        Error::Invalid(msg.into())
    }

    /// Shorthand for [`Error::Io`].
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// Process exit code: 2 for bad input (fixable by the user), 1 for internal errors.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Internal(_) => 1,
            _ => 2,
        }
    }
}
