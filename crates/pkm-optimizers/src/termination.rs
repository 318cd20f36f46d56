//! Why a solver stopped (cf. argmin's `TerminationReason`): every solver result carries one, so a
//! run that hit its iteration limit or stalled is never mistaken for a converged one.

use serde::Serialize;
use std::fmt;

/// Why a solver stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Termination {
    /// A convergence test was met.
    Converged {
        /// Which test, e.g. `"projected gradient"` or `"relative change in f"`.
        criterion: &'static str,
    },
    /// The iteration limit of the settings was reached before any convergence test was met.
    MaxIterations,
    /// No step made progress: the damping (or step control) reached its limit without finding an
    /// improving step, while the convergence tests were not met.
    Stalled,
}

impl Termination {
    /// Whether a convergence test was met.
    pub fn converged(&self) -> bool {
        matches!(self, Self::Converged { .. })
    }
}

impl fmt::Display for Termination {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Converged { criterion } => write!(f, "converged ({criterion})"),
            Self::MaxIterations => f.write_str("iteration limit reached"),
            Self::Stalled => f.write_str("stalled (no improving step)"),
        }
    }
}
