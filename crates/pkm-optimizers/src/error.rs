use pkm_traits::{Cancelled, ObjectiveError};
use thiserror::Error;

/// Failures of an optimisation run.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum OptimizeError {
    /// The objective failed in a way that is not a recorded infeasibility.
    #[error(transparent)]
    Objective(#[from] ObjectiveError),
    /// Settings that cannot work (no grid points, a non-positive tolerance).
    #[error("invalid optimiser setting: {setting} = {value} ({requirement})")]
    InvalidSetting {
        /// Name of the setting.
        setting: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// Every design evaluated was infeasible: there is no design to return.
    #[error("no feasible design among {evaluations} evaluated ({last_reason})")]
    NoFeasibleDesign {
        /// Designs evaluated.
        evaluations: usize,
        /// Why the last one was infeasible.
        last_reason: String,
    },
    /// A numerical step failed on valid settings (a damped normal matrix that is not positive
    /// definite, an eigen-decomposition that did not converge).
    #[error("numerical failure: {what}")]
    Numerical {
        /// What failed, in words.
        what: &'static str,
    },
    /// The computation was cancelled through [`pkm_traits::Progress`].
    #[error("cancelled")]
    Cancelled,
}

impl From<Cancelled> for OptimizeError {
    fn from(_: Cancelled) -> Self {
        Self::Cancelled
    }
}
