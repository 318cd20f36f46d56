//! Typed failures of the dynamics computations.

use pkm_traits::{IntegrationError, InvalidInput, KinematicsError};
use thiserror::Error;

/// A failure at one configuration $q$ of the model. The model has no clock: the functions of
/// one configuration ([`ExtendedModel::joint_motion`](crate::ExtendedModel::joint_motion), the
/// methods of [`Configuration`](crate::Configuration), [`crate::inverse::torques`]) return this,
/// and the functions that walk samples in time ([`crate::inverse::sample`],
/// [`crate::inverse::hamilton`], [`crate::inverse::lagrange`]) attach the time of the failing
/// sample with [`ConfigurationError::at`]. So no error ever carries a placeholder time.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ConfigurationError {
    /// The point is out of reach; the kinematics error names the leg and the numbers.
    #[error("unreachable: {0}")]
    Unreachable(#[from] KinematicsError),
    /// A constraint Jacobian block cannot be solved.
    #[error("{matrix} is singular")]
    Singular {
        /// Which matrix (`"Phi_x^T"`, `"Phi_theta"`).
        matrix: &'static str,
    },
    /// A computed torque or acceleration is NaN or infinite.
    #[error("non-finite {what}")]
    NonFinite {
        /// What became non-finite.
        what: &'static str,
    },
}

impl ConfigurationError {
    /// The same failure at time `t` of a trajectory.
    ///
    /// # Example
    /// ```
    /// use pkm_dynamics_hamilton::{ConfigurationError, DynamicsError};
    /// let e = ConfigurationError::Singular { matrix: "Phi_x^T" }.at(0.25);
    /// assert_eq!(e, DynamicsError::Singular { matrix: "Phi_x^T", t: 0.25 });
    /// assert_eq!(e.to_string(), "Phi_x^T is singular at t = 0.25 s");
    /// ```
    pub fn at(self, t: f64) -> DynamicsError {
        match self {
            Self::Unreachable(source) => DynamicsError::Unreachable { t, source },
            Self::Singular { matrix } => DynamicsError::Singular { matrix, t },
            Self::NonFinite { what } => DynamicsError::NonFinite { what, t },
        }
    }
}

/// Failures of inverse and forward dynamics along a trajectory or a simulation, each at the
/// time it happened (or of the settings, which have none).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// The trajectory leaves the workspace at time `t`.
    #[error("trajectory point at t = {t} s is unreachable: {source}")]
    Unreachable {
        /// Time of the point.
        t: f64,
        /// Which leg, from the inverse kinematics.
        source: KinematicsError,
    },
    /// A constraint Jacobian block or the saddle-point matrix cannot be solved.
    #[error("{matrix} is singular at t = {t} s")]
    Singular {
        /// Which matrix (`"Phi_x^T"`, `"Phi_theta"`, `"[M Phi_q^T; Phi_q 0]"`).
        matrix: &'static str,
        /// Time at which it happened.
        t: f64,
    },
    /// A computed torque or state is NaN or infinite.
    #[error("non-finite {what} at t = {t} s")]
    NonFinite {
        /// What became non-finite.
        what: &'static str,
        /// Time at which it happened.
        t: f64,
    },
    /// Settings that cannot work (a non-positive step, too few samples, an empty trajectory).
    #[error(transparent)]
    Invalid(#[from] InvalidInput),
    /// The integrator failed (cannot meet its tolerance, step underflow, ...).
    #[error(transparent)]
    Integration(#[from] IntegrationError),
}
