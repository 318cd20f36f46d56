//! The robot file: the TOML schema as serde types, read with unknown keys refused and errors at
//! line and column. `docs/robots.md` documents every field with its unit.

use crate::error::RobotFileError;
use crate::parameters::{fields, with_parameters};
use crate::pose::OrientationKind;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Most legs a robot may have (a working mode is one bit per leg).
pub const MAX_LEGS: usize = 64;

/// A robot file as written: one rigid base, one rigid platform, the legs (or one leg template
/// and a [`SymmetrySpec`]), the task coordinates and the home configuration. Lengths in metres,
/// angles in radians, every point and axis in the base frame at the home pose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotFile {
    /// Architecture name, `<legs>-<joints>` (`3-PRS`, `6-UPS`) or legs joined by `+`
    /// (`RR+RRR`); checked against the expanded joints.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Orientation coordinates of the pose: `rotation_vector` (default) or `tilt_torsion`.
    #[serde(default)]
    pub orientation: OrientationKind,
    /// Independent task coordinates, names from the pose coordinates of `orientation`.
    pub task: Vec<String>,
    /// Pose coordinates the legs determine from the task coordinates (solved, never assumed).
    #[serde(default)]
    pub dependent: Vec<String>,
    /// Pose coordinates the legs leave free and nobody cares about (the spin of a point
    /// platform); held at their home value.
    #[serde(default)]
    pub idle: Vec<String>,
    /// Length (m) that converts rotations into lengths in the singularity margins; default the
    /// mean distance of the platform joint centres from the platform origin (1 m if zero).
    #[serde(default, deserialize_with = "fields::optional_scalar")]
    pub characteristic_length: Option<f64>,
    /// Named scalars that numbers of the file may stand for by name (`docs/robots.md`,
    /// "Parameters"); `_deg` names in degrees. Every number below is already resolved.
    #[serde(default)]
    pub parameters: BTreeMap<String, f64>,
    /// The home configuration: every joint at its `offset`, the platform at this pose.
    pub home: HomeSpec,
    /// Repeat the listed legs `count` times about an axis.
    pub symmetry: Option<SymmetrySpec>,
    /// Gravitational acceleration in the base frame (m/s²), for the dynamics: `[0, 0, -9.81]`
    /// with z up, `[0, 0, 0]` to switch it off. No default: the dynamics refuses a file
    /// without it.
    #[serde(default, deserialize_with = "fields::optional_vector")]
    pub gravity: Option<[f64; 3]>,
    /// The platform's mass properties, for the dynamics.
    pub platform: Option<BodySpec>,
    /// The legs (the template when `symmetry` is given).
    pub legs: Vec<LegSpec>,
}

/// The platform pose at home; every joint axis and point in the file is given at this pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HomeSpec {
    /// Position of the platform origin (m).
    #[serde(deserialize_with = "fields::vector")]
    pub position: [f64; 3],
    /// Orientation coordinates (rad), in the file's `orientation`; default zero.
    #[serde(default, deserialize_with = "fields::vector")]
    pub orientation: [f64; 3],
}

/// Symmetry shorthand: the listed legs are repeated `count` times, copy `k` turned by
/// $2\pi k/\text{count}$ about the line through `point` along `axis`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SymmetrySpec {
    /// Number of copies (the listed legs are copy 0).
    pub count: usize,
    /// Rotation axis; default $+z$.
    #[serde(default = "z_axis", deserialize_with = "fields::vector")]
    pub axis: [f64; 3],
    /// A point on the rotation axis (m); default the origin.
    #[serde(default, deserialize_with = "fields::vector")]
    pub point: [f64; 3],
}

fn z_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// One leg: a serial chain from the base to the platform.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LegSpec {
    /// Joints from the base to the platform.
    pub joints: Vec<JointSpec>,
    /// Mass properties of the links for the dynamics: link `m` is the body between joints
    /// `m` and `m + 1` (one fewer than the joints, or none for a massless leg).
    #[serde(default)]
    pub links: Vec<BodySpec>,
}

/// Mass properties of one rigid body at the home pose, in the base frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Mass (kg), at least 0.
    #[serde(deserialize_with = "fields::scalar")]
    pub mass: f64,
    /// Centre of mass at home (m, base frame); default the platform origin for the platform
    /// and the midpoint of the link's two joint points for a link.
    #[serde(default, deserialize_with = "fields::optional_vector")]
    pub center_of_mass: Option<[f64; 3]>,
    /// Inertia tensor about the centre of mass, base axes at home (kg m²), symmetric positive
    /// semidefinite with principal moments obeying the triangle inequality; default zero (a
    /// point mass).
    #[serde(default, deserialize_with = "fields::optional_matrix")]
    pub inertia: Option<[[f64; 3]; 3]>,
}

/// The joint letters of an architecture name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum JointType {
    /// Revolute: `axis` and `point`.
    R,
    /// Prismatic: `axis`.
    P,
    /// Universal: `axes` (two) through `point`.
    U,
    /// Spherical: `point` (its centre).
    S,
    /// Cylindrical: `axis` and `point` (a revolute then a prismatic joint on the same axis).
    C,
}

/// One joint of a leg, at the home pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// `R`, `P`, `U`, `S` or `C`.
    #[serde(rename = "type")]
    pub kind: JointType,
    /// Axis direction (R, P, C); normalised on load.
    #[serde(default, deserialize_with = "fields::optional_vector")]
    pub axis: Option<[f64; 3]>,
    /// The two axes of a U joint, base side first.
    #[serde(default, deserialize_with = "fields::optional_axes")]
    pub axes: Option<[[f64; 3]; 2]>,
    /// A point on the axis (R, C), the centre (U, S), in metres.
    #[serde(default, deserialize_with = "fields::optional_vector")]
    pub point: Option<[f64; 3]>,
    /// Whether this joint carries the leg's actuator (exactly one per leg; R or P only).
    #[serde(default)]
    pub actuated: bool,
    /// Joint coordinate at home (rad or m): the actuator reports `offset` plus its motion.
    #[serde(default, deserialize_with = "fields::scalar")]
    pub offset: f64,
    /// Actuator range `[min, max]` (rad or m), checked by the inverse kinematics.
    #[serde(default, deserialize_with = "fields::optional_pair")]
    pub limits: Option<[f64; 2]>,
    /// A point mass (kg) at the joint's point (R, U, S, C), carried by the body after the joint
    /// (Miller lumps the Delta's elbows so).
    #[serde(default, deserialize_with = "fields::optional_scalar")]
    pub mass: Option<f64>,
    /// Rotor inertia of the actuator's motor (kg m²), actuated joints only.
    #[serde(default, deserialize_with = "fields::optional_scalar")]
    pub rotor_inertia: Option<f64>,
    /// Transmission ratio: motor rad per joint rad (R) or per joint m (P); default 1. The
    /// rotor adds `rotor_inertia * gear_ratio²` to the joint's inertia.
    #[serde(default, deserialize_with = "fields::optional_scalar")]
    pub gear_ratio: Option<f64>,
}

/// The `[parameters]` table alone (every other key ignored): read before the rest of the file,
/// whose numbers may name them.
#[derive(Deserialize)]
struct ParametersOnly {
    #[serde(default)]
    parameters: BTreeMap<String, f64>,
}

impl RobotFile {
    /// Reads a robot file from TOML text, its numbers resolved against its `[parameters]`.
    ///
    /// # Errors
    /// [`RobotFileError::Parse`] with the line and column of the offending text (an unknown
    /// parameter name included).
    pub fn from_toml(text: &str) -> Result<Self, RobotFileError> {
        check_size(text.len())?;
        let parse_error = |e: toml::de::Error| {
            let start = e.span().map(|span| span.start);
            let (line, column) = start.map_or((0, 0), |s| line_and_column(text, s));
            let mut message = e.message().trim_end().to_string();
            if message.starts_with("unknown field")
                && let Some(header) = start.and_then(|s| header_above(text, s))
            {
                message.push_str(&format!(
                    " (read as a key of `{header}`, the table header above it: is a header \
                     such as `[symmetry]` missing?)"
                ));
            }
            RobotFileError::Parse {
                line,
                column,
                message,
            }
        };
        let parameters = toml::from_str::<ParametersOnly>(text).map_err(parse_error)?;
        let parameters = checked(parameters.parameters)?;
        with_parameters(&parameters, || toml::from_str(text)).map_err(parse_error)
    }

    /// Reads a robot file from any serde data model (a TOML table, a JSON value, a Python
    /// dict), its numbers resolved against its `parameters`.
    ///
    /// # Errors
    /// [`RobotFileError::Schema`] with the key path of the offending value.
    pub fn from_deserializer<'de, D>(deserializer: D) -> Result<Self, RobotFileError>
    where
        D: serde::Deserializer<'de> + Clone,
        D::Error: std::fmt::Display,
    {
        let schema = |e: serde_path_to_error::Error<D::Error>| RobotFileError::Schema {
            key: e.path().to_string(),
            message: e.inner().to_string(),
        };
        let parameters: ParametersOnly =
            serde_path_to_error::deserialize(deserializer.clone()).map_err(schema)?;
        let parameters = checked(parameters.parameters)?;
        with_parameters(&parameters, || {
            serde_path_to_error::deserialize(deserializer)
        })
        .map_err(schema)
    }
}

/// The parameters, each finite.
fn checked(parameters: BTreeMap<String, f64>) -> Result<BTreeMap<String, f64>, RobotFileError> {
    match parameters.iter().find(|(_, v)| !v.is_finite()) {
        Some((name, v)) => Err(RobotFileError::invalid(
            format!("parameters.{name}"),
            v,
            "must be finite",
        )),
        None => Ok(parameters),
    }
}

/// Line and column (from 1) of byte `offset` in `text`.
/// The last table header (`[home]`, `[[legs]]`) before byte `offset` of `text`, if any.
fn header_above(text: &str, offset: usize) -> Option<&str> {
    text.get(..offset)?.lines().rev().map(str::trim).find(|l| {
        let name = l.trim_start_matches('[').trim_end_matches(']');
        l.starts_with('[')
            && l.ends_with(']')
            && !name.is_empty()
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.'))
    })
}

fn line_and_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Largest robot file read (bytes): 4 MiB, two orders of magnitude above the largest robot
/// the counts admit (64 legs of 12 joints), so that a huge file is refused before it is parsed
/// (a 50 MB file once took 29 s to be refused for its leg count).
pub const MAX_FILE_BYTES: usize = 4 << 20;

/// Refuses a robot file of `bytes` bytes above [`MAX_FILE_BYTES`].
///
/// # Errors
/// [`RobotFileError::Invalid`] at `file` with the size.
pub fn check_size(bytes: usize) -> Result<(), RobotFileError> {
    if bytes > MAX_FILE_BYTES {
        return Err(RobotFileError::invalid(
            "file",
            bytes,
            format!("at most {MAX_FILE_BYTES} bytes (4 MiB) for a robot file"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_key_is_reported_at_its_line() {
        let text = "name = \"1-P\"\ntask = [\"x\"]\nwhat = 3\n";
        let err = RobotFile::from_toml(text).unwrap_err();
        match err {
            RobotFileError::Parse { line, column, .. } => assert_eq!((line, column), (3, 1)),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn line_and_column_count_from_one() {
        assert_eq!(line_and_column("ab\ncd", 4), (2, 2));
        assert_eq!(line_and_column("ab", 99), (1, 3));
    }
}
