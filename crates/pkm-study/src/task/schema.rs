//! The schema of a task study: the mechanism, the `[task]` section, its pose and its twists.

use crate::schema::mechanism::MechanismSpec;
use crate::schema::units::{Degrees, Metres, Real};
use nalgebra::{Vector3, Vector6};
use pkm_optimizers::{LmSettings, Multistart, Sense};
use pkm_screw_theory::{ScrewError, Twist};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A task study of a mechanism of the registry `M` (the papers' mechanisms by default).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TaskStudy<M = MechanismSpec> {
    /// Free text.
    pub title: Option<String>,
    /// The nominal design (its values hold for the variables that are not optimised): the
    /// same `[mechanism.<kind>]` table as every other study.
    pub mechanism: M,
    /// What is sought and how.
    pub task: TaskSection,
}

/// The `[task]` section.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TaskSection {
    /// What is sought.
    pub goal: Goal,
    /// The nominal pose.
    #[serde(default)]
    pub pose: PoseSpec,
    /// Stewart–Gough only: the orientation is free within $|\alpha| \le$ this (degrees).
    pub max_angle_deg: Option<Degrees>,
    /// Robot files: the nominal pose by task coordinate (`z = 0.5`, `tilt_x_deg = 10.0`; lengths
    /// in m, angles in degrees), home for the coordinates not given.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub at: BTreeMap<String, f64>,
    /// The optimised variables and their ranges `[lower, upper]`, in the unit of the key.
    pub variables: BTreeMap<String, [f64; 2]>,
    /// The task twists (none with a singularity goal).
    #[serde(default)]
    pub twists: Vec<TwistSpec>,
    /// The multistart.
    pub starts: Multistart,
    /// Levenberg–Marquardt settings (defaults: the library's).
    #[serde(default)]
    pub solver: LmSettings,
}

/// What a task study seeks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Goal {
    /// Largest $F$: the legs move most for the task (good transmission of the task).
    Maximise,
    /// Smallest $F$: the task is as nearly reciprocal to every row as possible.
    Minimise,
    /// 3-UPU: smallest singular value $\sigma_{min}$ of the eq. 18 matrix.
    SingularitySigmaMin,
    /// 3-UPU: smallest $\det^2$ of the eq. 18 matrix.
    SingularityDet,
}

impl Goal {
    /// The sense of the search.
    pub fn sense(self) -> Sense {
        match self {
            Self::Maximise => Sense::Maximise,
            Self::Minimise | Self::SingularitySigmaMin | Self::SingularityDet => Sense::Minimise,
        }
    }

    /// The goal's name in study files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Maximise => "maximise",
            Self::Minimise => "minimise",
            Self::SingularitySigmaMin => "singularity_sigma_min",
            Self::SingularityDet => "singularity_det",
        }
    }

    /// Whether the goal is a singularity search (no twists).
    pub fn is_singularity(self) -> bool {
        matches!(self, Self::SingularitySigmaMin | Self::SingularityDet)
    }
}

/// `[task.pose]`: the platform pose where it is not optimised.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Position $p$ (m).
    #[serde(default = "origin")]
    pub position: [Metres; 3],
    /// Rotation vector $\alpha n$ (degrees).
    #[serde(default = "no_rotation")]
    pub rotation_deg: [Degrees; 3],
}

impl Default for PoseSpec {
    fn default() -> Self {
        Self {
            position: origin(),
            rotation_deg: no_rotation(),
        }
    }
}

fn origin() -> [Metres; 3] {
    [Metres(0.0); 3]
}
fn no_rotation() -> [Degrees; 3] {
    [Degrees(0.0); 3]
}

/// A task twist: a screw (axis, point, pitch, intensity), or the six numbers.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TwistSpec {
    /// Axis direction (dimensionless, normalised).
    pub axis: Option<[Real; 3]>,
    /// A point on the axis (m).
    pub point: Option<[Metres; 3]>,
    /// Pitch (m/rad).
    #[serde(default = "zero_m")]
    pub pitch: Metres,
    /// Angular speed about the axis (rad/s).
    #[serde(default = "one")]
    pub intensity: Real,
    /// Or the twist $[\omega; v]$ itself (rad/s, m/s), instead of axis and point.
    pub vector: Option<[Real; 6]>,
    /// Weight $w_k \ge 0$ (dimensionless).
    #[serde(default = "one")]
    pub weight: Real,
}

fn zero_m() -> Metres {
    Metres(0.0)
}
fn one() -> Real {
    Real(1.0)
}

/// Why a `[[task.twists]]` entry is not a twist.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TwistSpecError {
    /// Neither form, or both.
    #[error("expected either `vector` (rad/s, m/s) or `axis` and `point` (m)")]
    Form,
    /// The screw library refused the axis, pitch or intensity.
    #[error("{0}")]
    Screw(#[from] ScrewError),
}

impl TwistSpec {
    /// The twist.
    ///
    /// # Errors
    /// [`TwistSpecError::Form`] when neither or both forms are given,
    /// [`TwistSpecError::Screw`] when the screw is invalid.
    pub fn twist(&self) -> Result<Twist, TwistSpecError> {
        match (self.vector, self.axis, self.point) {
            (Some(v), None, None) => Ok(Twist::from_vector(Vector6::from(v.map(|x| x.0)))),
            (None, Some(axis), Some(point)) => Ok(Twist::from_screw(
                &Vector3::from(axis.map(|x| x.0)),
                &Vector3::from(point.map(|x| x.0)),
                self.pitch.0,
                self.intensity.0,
            )?),
            _ => Err(TwistSpecError::Form),
        }
    }
}
