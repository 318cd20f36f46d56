//! Typed errors shared by every crate. Each variant carries the numbers that explain it.

use thiserror::Error;

/// A design parameter that violates its requirement, found when a model is constructed.
///
/// Models are validated once, at construction; a built model is known to be finite, positive and
/// consistent.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid design: {parameter} = {value} ({requirement})")]
pub struct DesignError {
    /// Name of the offending parameter, as in the paper (`"a"`, `"L1/YR"`, `"x3"`).
    pub parameter: &'static str,
    /// The value that was given.
    pub value: f64,
    /// What the value must satisfy, in words (`"must be finite and > 0"`).
    pub requirement: &'static str,
}

impl DesignError {
    /// Checks that `value` is finite and strictly positive.
    ///
    /// # Errors
    /// A [`DesignError`] naming `parameter` otherwise.
    pub fn require_positive(parameter: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Self {
                parameter,
                value,
                requirement: "must be finite and > 0",
            })
        }
    }

    /// Checks that `value` is finite.
    ///
    /// # Errors
    /// A [`DesignError`] naming `parameter` otherwise.
    pub fn require_finite(parameter: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Self {
                parameter,
                value,
                requirement: "must be finite",
            })
        }
    }
}

/// Failures of kinematic computations on a valid design.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum KinematicsError {
    /// A leg cannot reach the pose: a square root or arc cosine of the closed-form solution would
    /// be taken of an out-of-range argument.
    #[error("leg {leg} cannot reach the pose (discriminant {discriminant:.3e} < 0)")]
    Unreachable {
        /// Index of the leg, from 0.
        leg: usize,
        /// The offending discriminant (negative, or an arc-cosine argument minus 1).
        discriminant: f64,
    },
    /// A matrix that must be inverted is singular (or numerically so) at this configuration.
    #[error("{matrix} is singular here (smallest singular value {sigma_min:.3e})")]
    Singular {
        /// Which matrix (`"J_q"`, `"J_x"`, `"Phi_q"`).
        matrix: &'static str,
        /// Its smallest singular value, or 0 when only the failed inversion is known.
        sigma_min: f64,
    },
    /// An iterative solver (forward kinematics by Newton) did not converge.
    #[error("did not converge in {iterations} iterations (|Φ| = {residual:.3e})")]
    NotConverged {
        /// Iterations spent.
        iterations: usize,
        /// Norm of the loop-closure residual at the last iterate.
        residual: f64,
    },
    /// An input coordinate is NaN or infinite.
    #[error("non-finite input: {what} = {value}")]
    NonFinite {
        /// Which input (`"x[2]"`, `"q[0]"`).
        what: &'static str,
        /// The value that was given.
        value: f64,
    },
}

/// Failures of an objective evaluation. Optimisers record `Infeasible` designs and go on; other
/// errors abort the search.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ObjectiveError {
    /// The design lies outside the feasible set or cannot be evaluated there (unreachable pose,
    /// empty workspace). This is a recorded outcome of a search, not a failure.
    #[error("infeasible design: {reason}")]
    Infeasible {
        /// What makes it infeasible, with numbers.
        reason: String,
    },
    /// The design vector has the wrong length.
    #[error("design has {got} variables, the objective takes {expected}")]
    Dimension {
        /// Expected number of variables.
        expected: usize,
        /// Number that was given.
        got: usize,
    },
    /// The evaluation produced a NaN or infinite value.
    #[error("objective is not finite ({value}) at this design")]
    NonFinite {
        /// The value produced.
        value: f64,
    },
    /// The computation was cancelled through [`crate::Progress`].
    #[error("cancelled")]
    Cancelled,
}

impl From<DesignError> for ObjectiveError {
    fn from(e: DesignError) -> Self {
        Self::Infeasible {
            reason: e.to_string(),
        }
    }
}

impl From<KinematicsError> for ObjectiveError {
    fn from(e: KinematicsError) -> Self {
        Self::Infeasible {
            reason: e.to_string(),
        }
    }
}

impl From<crate::Cancelled> for ObjectiveError {
    fn from(_: crate::Cancelled) -> Self {
        Self::Cancelled
    }
}
