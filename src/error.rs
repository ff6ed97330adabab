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

/// The longest run of non-blank characters a message echoes whole; a longer one (a value of
/// 10 MB given as a key, a line of a damaged file) is cut there and ends in "…".
pub const ECHO_LIMIT: usize = 200;
/// The longest message: a longer one keeps its head and its tail (where the allowed range is).
const MESSAGE_LIMIT: usize = 4000;

/// `message` with every run of more than [`ECHO_LIMIT`] non-blank characters cut to that many
/// and "…", and the whole held to `MESSAGE_LIMIT` characters: error messages echo what they
/// were given, and a 10 MB value came back whole on the terminal and through the C ABI.
pub fn shorten(message: &str) -> String {
    if message.len() <= ECHO_LIMIT {
        return message.to_string();
    }
    let mut out = String::with_capacity(message.len().min(MESSAGE_LIMIT + 8));
    let mut run = 0;
    let mut cut = false;
    for c in message.chars() {
        if c.is_whitespace() {
            run = 0;
            cut = false;
            out.push(c);
        } else if run < ECHO_LIMIT {
            run += 1;
            out.push(c);
        } else if !cut {
            cut = true;
            out.push('…');
        }
    }
    let count = out.chars().count();
    if count <= MESSAGE_LIMIT {
        return out;
    }
    let head: String = out.chars().take(MESSAGE_LIMIT / 2).collect();
    let tail: String = out.chars().skip(count - MESSAGE_LIMIT / 2).collect();
    format!("{head} … {tail}")
}

impl Error {
    pub fn input(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Input {
            origin: shorten(&origin.into()),
            message: shorten(&message.into()),
        }
    }

    pub fn run(message: impl Into<String>) -> Self {
        Error::Run(shorten(&message.into()))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_values_are_cut_and_short_messages_kept() {
        let short = "material.young = -1 Pa is outside the allowed range (0, inf) Pa";
        assert_eq!(shorten(short), short);
        let value = "a".repeat(10_000_000);
        let long = format!("model.kind = \"{value}\" is not a model; allowed values: granular");
        let got = shorten(&long);
        assert!(got.len() < 400, "{} bytes", got.len());
        assert!(got.contains('…'));
        assert!(got.ends_with("is not a model; allowed values: granular"));
        let words = "ab ".repeat(1_000_000) + "allowed range (0, 1]";
        let got = shorten(&words);
        assert!(got.chars().count() <= MESSAGE_LIMIT + 3);
        assert!(got.ends_with("allowed range (0, 1]"));
    }
}
