//! Typed failures of the dynamics computations.

use pkm_traits::{IntegrationError, KinematicsError};
use thiserror::Error;

/// Failures of inverse and forward dynamics.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// The trajectory leaves the workspace.
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
    /// Settings that cannot work.
    #[error("invalid setting: {setting} = {value} ({requirement})")]
    InvalidSetting {
        /// Name of the setting.
        setting: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// The integrator failed (cannot meet its tolerance, step underflow, ...).
    #[error(transparent)]
    Integration(#[from] IntegrationError),
}
