//! Errors that reach the user as one sentence.
//!
//! `Input` errors are the user's to fix (a scene file, a key, a packing file, a command-line
//! argument) and end the program with exit code 2, before any output directory is created.
//! `Run` errors happen while simulating or writing results and end it with exit code 1.

use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input. `origin` names the file (or "command line"), `message` the key and the
    /// allowed range.
    #[error("{origin}: {message}")]
    Input { origin: String, message: String },
    /// A failure while running or writing results.
    #[error("{0}")]
    Run(String),
    /// An `advance` call stopped early, at a whole step, because its bounds
    /// ([`crate::run::CallLimits`]) ran out or it was cancelled. The run is consistent and
    /// may be advanced again.
    #[error("{0}")]
    Interrupted(String),
}

impl Error {
    pub fn input(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Input {
            origin: origin.into(),
            message: message.into(),
        }
    }

    pub fn run(message: impl Into<String>) -> Self {
        Error::Run(message.into())
    }

    /// A run error for an I/O failure on `path`.
    pub fn io(path: &Path, what: &str, err: std::io::Error) -> Self {
        Error::Run(format!("{}: cannot {what} ({err})", path.display()))
    }

    /// The process exit code for this error: 2 for bad input, 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Input { .. } => 2,
            Error::Run(_) | Error::Interrupted(_) => 1,
        }
    }
}

pub type Result<T> = std::result::Result<T, Error>;
