//! Vector fields and integrator steps.
//!
//! A state $z \in \mathbb{R}^M$ evolves by $\dot z = f(t, z)$ ([`VectorField`]); an
//! [`Integrator`] advances it by one step.

use nalgebra::SVector;
use thiserror::Error;

/// Right-hand side $\dot z = f(t, z)$ of an ordinary differential equation.
pub trait VectorField<const M: usize> {
    /// Writes $f(t, z)$ into `dz` (no allocation).
    ///
    /// # Errors
    /// [`RhsError`] when $f$ cannot be evaluated at $(t, z)$ (a singular constraint Jacobian, a
    /// non-finite value).
    fn rhs(&self, t: f64, z: &SVector<f64, M>, dz: &mut SVector<f64, M>) -> Result<(), RhsError>;
}

/// One-step method for $\dot z = f(t, z)$.
pub trait Integrator<const M: usize> {
    /// Advances `z` from `t` to `t + h` in place.
    ///
    /// Adaptive methods may take a smaller step than `h`: the report says which step was taken
    /// and proposes the next one.
    ///
    /// # Errors
    /// [`IntegrationError`] when the vector field fails, the state becomes non-finite, or an
    /// adaptive step size underflows.
    fn step<F: VectorField<M> + ?Sized>(
        &mut self,
        field: &F,
        t: f64,
        z: &mut SVector<f64, M>,
        h: f64,
    ) -> Result<StepReport, IntegrationError>;
}

/// What one call of [`Integrator::step`] did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepReport {
    /// Step actually taken.
    pub h_taken: f64,
    /// Step proposed for the next call (equal to `h_taken` for fixed-step methods).
    pub h_next: f64,
    /// Weighted local error estimate of the accepted step (0 for methods without one).
    pub error_estimate: f64,
    /// Right-hand-side evaluations spent, rejected attempts included.
    pub evaluations: usize,
    /// Attempts rejected by error control before the accepted one.
    pub rejections: usize,
}

/// A vector field could not be evaluated.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("right-hand side failed at t = {t}: {reason}")]
pub struct RhsError {
    /// Time of the failed evaluation.
    pub t: f64,
    /// What went wrong, with numbers.
    pub reason: String,
}

/// Failures of time integration.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum IntegrationError {
    /// The vector field failed.
    #[error(transparent)]
    Rhs(#[from] RhsError),
    /// The state or its derivative became NaN or infinite.
    #[error("state is not finite at t = {t}")]
    NonFinite {
        /// Time at which it happened.
        t: f64,
    },
    /// Error control asked for a step below the smallest admissible one.
    #[error("step size {h:.3e} underflows at t = {t} (minimum {h_min:.3e})")]
    StepSizeUnderflow {
        /// Time at which it happened.
        t: f64,
        /// The step that was asked for.
        h: f64,
        /// The smallest admissible step.
        h_min: f64,
    },
    /// The run hit its step budget before the end of the interval.
    #[error("gave up after {steps} steps at t = {t}")]
    TooManySteps {
        /// Steps taken.
        steps: usize,
        /// Time reached.
        t: f64,
    },
    /// Settings that cannot work (a non-positive tolerance or step): the one invalid-input
    /// shape `{ name, value, requirement }`.
    #[error(transparent)]
    Invalid(#[from] crate::InvalidInput),
    /// The computation was cancelled through [`crate::Progress`].
    #[error("cancelled")]
    Cancelled,
    /// The nonlinear stage equation of an implicit method did not converge.
    #[error(
        "implicit stage did not converge at t = {t} after {iterations} iterations (residual {residual:.3e})"
    )]
    NotConverged {
        /// Time at the start of the step.
        t: f64,
        /// Iterations spent.
        iterations: usize,
        /// Size of the last update, in the method's norm.
        residual: f64,
    },
}

impl From<crate::Cancelled> for IntegrationError {
    fn from(_: crate::Cancelled) -> Self {
        Self::Cancelled
    }
}
