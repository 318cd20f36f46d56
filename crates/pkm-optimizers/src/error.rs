use pkm_traits::{Cancelled, InvalidInput, ObjectiveError};
use thiserror::Error;

/// Failures of an optimisation run.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum OptimizeError {
    /// The objective failed (an infeasible design, a wrong dimension, a non-finite value).
    /// Converted by `From`: a cancelled objective becomes [`OptimizeError::Cancelled`] and an
    /// invalid input [`OptimizeError::Invalid`] instead.
    #[error(transparent)]
    Objective(ObjectiveError),
    /// Settings or arguments that cannot work (no grid points, a non-positive tolerance, a start
    /// of the wrong length): the one invalid-input shape `{ name, value, requirement }`.
    #[error(transparent)]
    Invalid(#[from] InvalidInput),
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
    /// A finite-difference derivative came out NaN or infinite: the objective overflows or is
    /// not finite near the design, or the step is too small for its rounding.
    #[error("the finite difference {quantity} of variable {variable} is not finite ({value})")]
    NonFiniteDerivative {
        /// Which derivative (`"gradient"`, `"constraint Jacobian"`, `"Hessian"`).
        quantity: &'static str,
        /// The variable differenced, from 0.
        variable: usize,
        /// The value found.
        value: f64,
    },
    /// The computation was cancelled through [`pkm_traits::Progress`].
    #[error("cancelled")]
    Cancelled,
}

impl OptimizeError {
    /// Whether this is an [`ObjectiveError::Infeasible`] design: a recorded outcome of a
    /// search (a start, a node), not a failure of the run.
    pub fn is_infeasible(&self) -> bool {
        matches!(self, Self::Objective(ObjectiveError::Infeasible { .. }))
    }
}

impl From<ObjectiveError> for OptimizeError {
    /// A cancelled objective is a cancelled run ([`OptimizeError::Cancelled`]), so `?` carries a
    /// Ctrl-C seen inside an objective as every other cancellation; an invalid input is
    /// [`OptimizeError::Invalid`], the one shape of invalid input.
    fn from(e: ObjectiveError) -> Self {
        match e {
            ObjectiveError::Cancelled => Self::Cancelled,
            ObjectiveError::InvalidInput(e) => Self::Invalid(e),
            e => Self::Objective(e),
        }
    }
}

impl From<Cancelled> for OptimizeError {
    fn from(_: Cancelled) -> Self {
        Self::Cancelled
    }
}
