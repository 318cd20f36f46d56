//! Why a robot file is refused. Kinematic failures on a loaded robot are
//! [`pkm_traits::KinematicsError`]s.

use thiserror::Error;

/// Why a robot file could not be turned into a robot.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RobotFileError {
    /// The text is not valid TOML or does not match the schema (an unknown key, a wrong type).
    #[error("line {line}, column {column}: {message}")]
    Parse {
        /// Line of the offending text, from 1 (0 when the parser gave no position).
        line: usize,
        /// Column, from 1.
        column: usize,
        /// What the parser found.
        message: String,
    },
    /// A robot given as data rather than text (a table of a study, a JSON value) does not
    /// match the schema.
    #[error("{key}: {message}")]
    Schema {
        /// Key path of the offending value (`legs[0].joints[1].axis`).
        key: String,
        /// What the deserializer found.
        message: String,
    },
    /// A value that violates its requirement, named by its key path (`legs[1].joints[0].axis`).
    #[error("{key} = {value}: {requirement}")]
    Invalid {
        /// Key path of the value in the file.
        key: String,
        /// The value, as written.
        value: String,
        /// What it must satisfy.
        requirement: String,
    },
    /// The architecture name does not describe the expanded joints.
    #[error("name {name:?} does not match the legs: the joints read {found:?}")]
    NameMismatch {
        /// The name in the file.
        name: String,
        /// The name the expanded joints spell (`3-PRS`).
        found: String,
    },
    /// The platform twist system at the home pose has the wrong dimension, or does not move
    /// the declared coordinates.
    #[error(
        "mobility check failed: {reason}; the platform twist system at home has dimension {found} \
         (basis [ω; v_O]: {twist_system:?})"
    )]
    Mobility {
        /// What is wrong, in words with the numbers.
        reason: String,
        /// Dimension of the twist system found.
        found: usize,
        /// An orthonormal basis of the platform twist system, ray order `[ω; v_O]`.
        twist_system: Vec<[f64; 6]>,
    },
    /// A redundantly actuated robot was requested as a model of the square kinematics traits.
    #[error(
        "the robot has {actuators} actuators for {task} task coordinates (redundant actuation): \
         the square kinematics traits (`Robot<N>`) do not apply; use `RobotModel` directly"
    )]
    Redundant {
        /// Number of actuators.
        actuators: usize,
        /// Number of task coordinates.
        task: usize,
    },
    /// The robot has `found` task coordinates but was requested with `expected`.
    #[error("the robot has {found} task coordinates, the model type takes {expected}")]
    Dimension {
        /// Task dimension of the requested type.
        expected: usize,
        /// Task dimension of the file.
        found: usize,
    },
}

impl RobotFileError {
    /// An [`RobotFileError::Invalid`] for `key`.
    pub(crate) fn invalid(
        key: impl Into<String>,
        value: impl std::fmt::Debug,
        requirement: impl Into<String>,
    ) -> Self {
        Self::Invalid {
            key: key.into(),
            value: format!("{value:?}"),
            requirement: requirement.into(),
        }
    }
}
