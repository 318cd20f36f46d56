//! The one error type of the command: every failure names what went wrong and, for a study
//! file, the file, line and column.

use pkm_optimizers::OptimizeError;
use pkm_workspace_indices::IndexError;
use std::path::PathBuf;

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// A study file that cannot be used, with the position of the offending text.
    #[error("{file}:{line}:{column}: {message}")]
    Study {
        /// The study file.
        file: String,
        /// Line, from 1.
        line: usize,
        /// Column, from 1.
        column: usize,
        /// What is wrong and what was expected (with units).
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// An index computation refused its input.
    #[error("{0}")]
    Index(IndexError),
    /// A search refused its settings or found no feasible design.
    #[error("{0}")]
    Optimize(OptimizeError),
    /// The user pressed Ctrl-C.
    #[error("cancelled")]
    Cancelled,
    /// A command-line argument or a combination of inputs that cannot be used.
    #[error("{0}")]
    Invalid(String),
}

impl From<pkm_study::StudyError> for CliError {
    fn from(e: pkm_study::StudyError) -> Self {
        use pkm_study::StudyError as E;
        match e {
            E::Cancelled => Self::Cancelled,
            E::Index(e) => Self::Index(e),
            E::Optimize(e) => Self::Optimize(e),
            e => Self::Invalid(e.to_string()),
        }
    }
}

impl From<IndexError> for CliError {
    fn from(e: IndexError) -> Self {
        match e {
            IndexError::Cancelled => Self::Cancelled,
            e => Self::Index(e),
        }
    }
}

impl From<OptimizeError> for CliError {
    fn from(e: OptimizeError) -> Self {
        match e {
            OptimizeError::Cancelled => Self::Cancelled,
            e => Self::Optimize(e),
        }
    }
}

impl From<pkm_traits::Cancelled> for CliError {
    fn from(_: pkm_traits::Cancelled) -> Self {
        Self::Cancelled
    }
}

impl CliError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
