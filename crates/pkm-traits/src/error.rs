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

    /// Checks that a quantity *derived* from the given parameters (a reach, a squared length, a
    /// mass coefficient) is finite: given parameters that are each finite can still overflow
    /// together, and a model is validated on what it computes with.
    ///
    /// # Errors
    /// A [`DesignError`] naming the derived quantity `parameter` otherwise.
    ///
    /// # Example
    /// ```
    /// use pkm_traits::DesignError;
    /// let arm = 1e200;
    /// assert!(DesignError::require_derived_finite("La^2", arm * arm).is_err());
    /// ```
    pub fn require_derived_finite(parameter: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Self {
                parameter,
                value,
                requirement: "derived from the design, must be finite (the design overflows)",
            })
        }
    }

    /// Checks that a positive quantity *derived* from the design (the cube of a reach, the
    /// square of a scale) is a normal number: neither overflowed to infinity nor underflowed to
    /// zero or a subnormal, where it would lose every digit (a volume of 0 for a robot of
    /// 1e-300 m, a cross-section reported empty for one of 1e300).
    ///
    /// # Errors
    /// A [`DesignError`] naming the derived quantity `parameter` otherwise.
    ///
    /// # Example
    /// ```
    /// use pkm_traits::DesignError;
    /// let reach = 1e-120;
    /// assert!(DesignError::require_derived_normal("reach^3", reach * reach * reach).is_err());
    /// assert!(DesignError::require_derived_normal("reach^3", 8.0).is_ok());
    /// ```
    pub fn require_derived_normal(parameter: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_normal() && value > 0.0 {
            Ok(value)
        } else {
            Err(Self {
                parameter,
                value,
                requirement: "derived from the design, must be a positive normal number (the \
                              design overflows or underflows)",
            })
        }
    }
}

/// An argument that violates its requirement: the one error shape for invalid input to an
/// algorithm (an interval, a count, a tolerance), `{ name, value, requirement }`.
///
/// [`DesignError`] has the same shape for the parameters of a model; the two stay separate types
/// so that an invalid input is never mistaken for an infeasible design.
///
/// ```
/// use pkm_traits::InvalidInput;
/// let e = InvalidInput::require_positive("tolerance", -1.0).unwrap_err();
/// assert_eq!(e.to_string(), "invalid input: tolerance = -1 (must be finite and > 0)");
/// ```
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid input: {name} = {value} ({requirement})")]
pub struct InvalidInput {
    /// Name of the argument or setting (`"lower"`, `"n_starts"`, `"tolerance"`).
    pub name: &'static str,
    /// The value given (counts as `f64`, `inf` when they do not fit).
    pub value: f64,
    /// What the value must satisfy, in words.
    pub requirement: &'static str,
}

impl InvalidInput {
    /// The error `{ name, value, requirement }`.
    pub fn new(name: &'static str, value: f64, requirement: &'static str) -> Self {
        Self {
            name,
            value,
            requirement,
        }
    }

    /// Checks that `value` is finite and strictly positive.
    ///
    /// # Errors
    /// An [`InvalidInput`] naming `name` otherwise.
    pub fn require_positive(name: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Self::new(name, value, "must be finite and > 0"))
        }
    }

    /// Checks that `value` is finite.
    ///
    /// # Errors
    /// An [`InvalidInput`] naming `name` otherwise.
    pub fn require_finite(name: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Self::new(name, value, "must be finite"))
        }
    }

    /// Checks that the count `value` is at least 1 (an iteration or step limit, a number of
    /// nodes).
    ///
    /// # Errors
    /// An [`InvalidInput`] naming `name` for 0.
    pub fn require_nonzero_count(name: &'static str, value: usize) -> Result<usize, Self> {
        if value > 0 {
            Ok(value)
        } else {
            Err(Self::new(name, 0.0, "must be >= 1"))
        }
    }

    /// Checks that the count `value` is at most `max`, before anything of that size is
    /// allocated or iterated.
    ///
    /// # Errors
    /// An [`InvalidInput`] naming `name` otherwise.
    pub fn require_count_at_most(
        name: &'static str,
        value: usize,
        max: usize,
        requirement: &'static str,
    ) -> Result<usize, Self> {
        if value <= max {
            Ok(value)
        } else {
            Err(Self::new(name, value as f64, requirement))
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
    /// The numerical solution of one leg's joints did not converge from any of its starts.
    #[error(
        "leg {leg}: the {stage} did not converge from {starts} starts (best |Φ| = {residual:.3e})"
    )]
    LegNotConverged {
        /// Index of the leg, from 0.
        leg: usize,
        /// What was solved (`"passive joints"` with the actuator held, `"joints"` of a leg
        /// without a closed form).
        stage: &'static str,
        /// Starts tried (home values, then seeded ones).
        starts: usize,
        /// The smallest loop-closure residual reached, or NaN when no start evaluated.
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
    /// A solver setting that cannot work (a tolerance that is not positive).
    #[error(transparent)]
    InvalidInput(#[from] InvalidInput),
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
        /// The typed error behind `reason` when a mechanism found it (an invalid design, an
        /// unreachable leg), so a search can tell them apart without parsing `reason`.
        #[source]
        cause: Option<InfeasibleCause>,
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
    /// An argument that cannot work (empty or non-finite bounds): an input error, not an
    /// infeasible design, so searches do not record and skip it.
    #[error(transparent)]
    InvalidInput(#[from] InvalidInput),
}

/// The typed error that made a design infeasible.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum InfeasibleCause {
    /// The design's parameters are invalid.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// The design is valid but its kinematics fail (an unreachable pose, a singularity).
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
}

impl ObjectiveError {
    /// An infeasible design described by `reason` alone (no typed cause).
    ///
    /// # Example
    /// ```
    /// use pkm_traits::ObjectiveError;
    /// let e = ObjectiveError::infeasible("empty workspace");
    /// assert_eq!(e.to_string(), "infeasible design: empty workspace");
    /// assert!(e.cause().is_none());
    /// ```
    pub fn infeasible(reason: impl Into<String>) -> Self {
        Self::Infeasible {
            reason: reason.into(),
            cause: None,
        }
    }

    /// The typed error behind an [`ObjectiveError::Infeasible`], if a mechanism reported one.
    ///
    /// # Example
    /// ```
    /// use pkm_traits::{DesignError, InfeasibleCause, ObjectiveError};
    /// let design = DesignError { parameter: "a", value: -1.0, requirement: "must be > 0" };
    /// let e = ObjectiveError::from(design.clone());
    /// assert_eq!(e.cause(), Some(&InfeasibleCause::Design(design)));
    /// ```
    pub fn cause(&self) -> Option<&InfeasibleCause> {
        match self {
            Self::Infeasible { cause, .. } => cause.as_ref(),
            _ => None,
        }
    }
}

impl From<InfeasibleCause> for ObjectiveError {
    fn from(cause: InfeasibleCause) -> Self {
        Self::Infeasible {
            reason: cause.to_string(),
            cause: Some(cause),
        }
    }
}

impl From<DesignError> for ObjectiveError {
    fn from(e: DesignError) -> Self {
        InfeasibleCause::from(e).into()
    }
}

impl From<KinematicsError> for ObjectiveError {
    fn from(e: KinematicsError) -> Self {
        InfeasibleCause::from(e).into()
    }
}

impl From<crate::Cancelled> for ObjectiveError {
    fn from(_: crate::Cancelled) -> Self {
        Self::Cancelled
    }
}
