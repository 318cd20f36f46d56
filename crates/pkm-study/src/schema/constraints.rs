//! The `[constraints]` table of a study: workspace limits in the units of their keys, and how a
//! mechanism's actuated joints move (which decides the unit of its joint ranges).

use super::units::{ConeDegrees, DegreeRange, MetreRange, Metres, NonNegativeMetres, Real};
use nalgebra::Vector3;
use pkm_traits::WorkspaceConstraint;
use serde::{Deserialize, Serialize};

/// How the actuated joints move: it decides the unit of joint ranges in `[constraints]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Actuation {
    /// Revolute motors: ranges in degrees (`joint_range_deg`).
    Revolute,
    /// Prismatic actuators (carriages, legs): ranges in metres (`joint_range`).
    Prismatic,
}

/// The `[constraints]` table: workspace limits in the units of their keys.
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsSpec {
    /// Positions at or below this height (m).
    pub below_z: Option<Metres>,
    /// Half-spaces n·x ≤ offset.
    #[serde(default)]
    pub half_spaces: Vec<HalfSpaceSpec>,
    /// Every revolute actuated joint within `[lower, upper]` (degrees), modulo 360°: an angle
    /// holds when some turn of it lies in the range, so `[-180, 180]` holds every angle.
    pub joint_range_deg: Option<DegreeRange>,
    /// Every prismatic actuated joint within `[lower, upper]` (m).
    pub joint_range: Option<MetreRange>,
    /// One revolute actuated joint's range (degrees).
    #[serde(default)]
    pub joint_ranges_deg: Vec<JointRangeDegSpec>,
    /// One prismatic actuated joint's range (m).
    #[serde(default)]
    pub joint_ranges: Vec<JointRangeSpec>,
    /// Largest bend of the passive ball joints (degrees).
    pub passive_cone_deg: Option<ConeDegrees>,
    /// Smallest distance between neighbouring legs' links (m).
    pub leg_clearance: Option<NonNegativeMetres>,
}

/// A half-space n·x ≤ offset.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HalfSpaceSpec {
    /// Outward normal n (dimensionless, any length).
    pub normal: [Real; 3],
    /// Offset (m, for a unit normal).
    pub offset: Metres,
}

/// The range of one revolute joint (from 0), degrees.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct JointRangeDegSpec {
    /// Joint number, from 0.
    pub joint: usize,
    /// `[lower, upper]` (degrees).
    pub range_deg: DegreeRange,
}

/// The range of one prismatic joint (from 0), metres.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct JointRangeSpec {
    /// Joint number, from 0.
    pub joint: usize,
    /// `[lower, upper]` (m).
    pub range: MetreRange,
}

impl ConstraintsSpec {
    /// The library constraints of this table (SI units, radians) for a mechanism `mechanism`
    /// whose actuated joints move as `kind`.
    ///
    /// # Errors
    /// A message when a joint range is given in the wrong unit for these joints or the library
    /// refuses a value.
    pub fn to_library(
        &self,
        mechanism: &str,
        kind: Actuation,
    ) -> Result<Vec<WorkspaceConstraint>, String> {
        let spec = self;
        let wrong_unit = |key: &str, use_key: &str| {
            format!(
                "{key}: the actuated joints of {mechanism} are {}; use {use_key}",
                match kind {
                    Actuation::Revolute => "revolute (angles in degrees)",
                    Actuation::Prismatic =>
                        "prismatic (carriage positions or leg lengths in metres)",
                }
            )
        };
        let library = |e: pkm_traits::ConstraintError| e.to_string();
        let mut out = Vec::new();
        if let Some(z) = spec.below_z {
            out.push(WorkspaceConstraint::below(z.0).map_err(library)?);
        }
        for h in &spec.half_spaces {
            let normal = Vector3::new(h.normal[0].0, h.normal[1].0, h.normal[2].0);
            out.push(WorkspaceConstraint::half_space(normal, h.offset.0).map_err(library)?);
        }
        match (kind, spec.joint_range_deg, spec.joint_range) {
            (Actuation::Prismatic, Some(_), _) => {
                return Err(wrong_unit("joint_range_deg", "joint_range"));
            }
            (Actuation::Revolute, _, Some(_)) => {
                return Err(wrong_unit("joint_range", "joint_range_deg"));
            }
            // Revolute: an angle range, tested modulo 2π.
            (_, Some(r), _) => out.push(
                WorkspaceConstraint::angle_range(r.lower.to_radians(), r.upper.to_radians())
                    .map_err(library)?,
            ),
            (_, None, Some(r)) => {
                out.push(WorkspaceConstraint::joint_range(r.lower, r.upper).map_err(library)?);
            }
            (_, None, None) => {}
        }
        if kind == Actuation::Prismatic && !spec.joint_ranges_deg.is_empty() {
            return Err(wrong_unit("joint_ranges_deg", "joint_ranges"));
        }
        if kind == Actuation::Revolute && !spec.joint_ranges.is_empty() {
            return Err(wrong_unit("joint_ranges", "joint_ranges_deg"));
        }
        for j in &spec.joint_ranges_deg {
            let (lo, hi) = (
                j.range_deg.lower.to_radians(),
                j.range_deg.upper.to_radians(),
            );
            out.push(WorkspaceConstraint::angle_range_of(j.joint, lo, hi).map_err(library)?);
        }
        for j in &spec.joint_ranges {
            let (lo, hi) = (j.range.lower, j.range.upper);
            out.push(WorkspaceConstraint::joint_range_of(j.joint, lo, hi).map_err(library)?);
        }
        if let Some(cone) = spec.passive_cone_deg {
            out.push(WorkspaceConstraint::passive_cone(cone.0.to_radians()).map_err(library)?);
        }
        if let Some(d) = spec.leg_clearance {
            out.push(WorkspaceConstraint::leg_clearance(d.0).map_err(library)?);
        }
        Ok(out)
    }
}
