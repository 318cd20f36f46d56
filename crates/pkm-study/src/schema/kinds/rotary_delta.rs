//! `[mechanism.rotary_delta]`: the rotary Delta / NUWAR family of Miller 2004 (motors inclined
//! by α and turned by β): its table, the library robot it builds, and what a study asks of it.

use super::{design_error, zero_deg, zero_m};
use crate::design_variables;
use crate::registry::{
    Actuation, BuildError, ForwardVisitor, StudyMechanism, WorkspaceVisitor, visit,
};
use crate::scene::first_drawable;
use crate::schema::units::{Degrees, Metres, PositiveMetres};
use nalgebra::Vector3;
use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, RotaryDeltaDesign, Skeleton};
use pkm_traits::WorkspaceConstraint;
use pkm_workspace_indices::Region;
use serde::{Deserialize, Serialize};

/// `[mechanism.rotary_delta]`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RotaryDeltaSpec {
    /// Radial distance R of the motor points from the centreline (m).
    pub base_radius: PositiveMetres,
    /// Radial offset r of the plate joint pairs (m).
    pub plate_offset: Metres,
    /// Arm length La (m).
    pub arm: PositiveMetres,
    /// Forearm length Lb (m).
    pub forearm: PositiveMetres,
    /// Motor-axis inclination α (degrees); 0 for the Delta, 35.26 for NUWAR.
    #[serde(default = "zero_deg")]
    pub alpha_deg: Degrees,
    /// Motor-axis turn β about the vertical (degrees); 0 for the Delta, 60 for NUWAR.
    #[serde(default = "zero_deg")]
    pub beta_deg: Degrees,
    /// Height z0 of the motor plane (m).
    #[serde(default = "zero_m")]
    pub motor_plane_z: Metres,
    /// Azimuth of motor 1 about the vertical (degrees).
    #[serde(default = "zero_deg")]
    pub azimuth_motor_1_deg: Degrees,
    /// Turn each plate joint pair with its motor by β (default: radial).
    #[serde(default)]
    pub turned_plate_offsets: bool,
    /// Allowed elbow branches (default `["out"]`).
    #[serde(default = "default_elbows")]
    pub elbow: Vec<ElbowMode>,
}

fn default_elbows() -> Vec<ElbowMode> {
    vec![ElbowMode::Out]
}

/// The table of a library design (the papers' presets: `pkm_mechanisms::presets`), with the
/// table's defaults for what the design does not hold (radial plate offsets, the `out` elbow).
impl From<RotaryDeltaDesign> for RotaryDeltaSpec {
    fn from(d: RotaryDeltaDesign) -> Self {
        Self {
            base_radius: PositiveMetres(d.base_radius),
            plate_offset: Metres(d.plate_offset),
            arm: PositiveMetres(d.arm),
            forearm: PositiveMetres(d.forearm),
            alpha_deg: Degrees(d.alpha.to_degrees()),
            beta_deg: Degrees(d.beta.to_degrees()),
            motor_plane_z: Metres(d.placement.motor_plane_z),
            azimuth_motor_1_deg: Degrees(d.placement.azimuth_motor_1.to_degrees()),
            turned_plate_offsets: false,
            elbow: default_elbows(),
        }
    }
}

impl StudyMechanism for RotaryDeltaSpec {
    design_variables! {
        "base_radius" Length => |s| s.base_radius.0,
        "plate_offset" Length => |s| s.plate_offset.0,
        "arm" Length => |s| s.arm.0,
        "forearm" Length => |s| s.forearm.0,
        "alpha_deg" Angle => |s| s.alpha_deg.0,
        "beta_deg" Angle => |s| s.beta_deg.0,
        "motor_plane_z" Length => |s| s.motor_plane_z.0,
        "azimuth_motor_1_deg" Angle => |s| s.azimuth_motor_1_deg.0,
    }

    type Built = RotaryDelta;

    fn kind(&self) -> &'static str {
        "rotary_delta"
    }

    /// The rotary Delta of a `[mechanism.rotary_delta]` table.
    ///
    /// # Errors
    /// [`BuildError::Design`] with the library's reason for an invalid design.
    fn build(&self) -> Result<RotaryDelta, BuildError> {
        let placement = Placement {
            motor_plane_z: self.motor_plane_z.0,
            azimuth_motor_1: self.azimuth_motor_1_deg.radians(),
        };
        let delta = RotaryDelta::new(RotaryDeltaDesign {
            base_radius: self.base_radius.0,
            plate_offset: self.plate_offset.0,
            arm: self.arm.0,
            forearm: self.forearm.0,
            alpha: self.alpha_deg.radians(),
            beta: self.beta_deg.radians(),
            placement,
        })
        .map_err(design_error)?;
        Ok(if self.turned_plate_offsets {
            delta.with_turned_plate_offsets()
        } else {
            delta
        })
    }

    fn actuation(&self) -> Actuation {
        Actuation::Revolute
    }

    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        built: &RotaryDelta,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        Ok(visitor.visit(built))
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        built: &RotaryDelta,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(built, &self.elbow, constraints, visitor)
    }

    fn reach_region(&self, delta: &RotaryDelta) -> Option<Region> {
        let (radius, half_height) = delta.reach_cylinder();
        let z0 = delta.motor_plane_z();
        Some(Region::axial_cylinder(
            radius,
            z0 - half_height,
            z0 + half_height,
        ))
    }

    fn skeleton_at(&self, robot: &RotaryDelta, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let tries = self
            .elbow
            .iter()
            .map(|e| Skeleton::rotary_delta(robot, p, *e));
        first_drawable(p, tries)
    }
}
