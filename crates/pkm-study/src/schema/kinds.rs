//! The five mechanisms of the papers as study mechanisms: each table's design variables,
//! actuation, workspace, reach region and drawing, stated once.

use super::mechanism::{
    LinearDeltaSpec, RotaryDeltaSpec, StewartSpec, ThreeUpuSpec, TsaiSpec, linear_delta,
    rotary_delta, stewart_orientation, three_upu, tsai,
};
use crate::design_variables;
use crate::registry::{Actuation, BuildError, StudyMechanism, WorkspaceVisitor, visit};
use crate::scene::first_drawable;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pkm_mechanisms::{LegBranch, LinearDeltaMode, Skeleton};
use pkm_traits::WorkspaceConstraint;
use pkm_workspace_indices::Region;

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

    fn kind(&self) -> &'static str {
        "rotary_delta"
    }

    fn actuation(&self) -> Actuation {
        Actuation::Revolute
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(&rotary_delta(self)?, &self.elbow, constraints, visitor)
    }

    fn reach_region(&self) -> Result<Option<Region>, BuildError> {
        let delta = rotary_delta(self)?;
        let (radius, half_height) = delta.reach_cylinder();
        let z0 = delta.motor_plane_z();
        Ok(Some(Region::axial_cylinder(
            radius,
            z0 - half_height,
            z0 + half_height,
        )))
    }

    fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let robot = rotary_delta(self).map_err(|e| e.to_string())?;
        let tries = self
            .elbow
            .iter()
            .map(|e| Skeleton::rotary_delta(&robot, p, *e));
        first_drawable(p, tries)
    }
}

impl StudyMechanism for TsaiSpec {
    design_variables! {
        "a" Length => |s| s.a.0,
        "b" Length => |s| s.b.0,
        "d_plus_e" Length => |s| s.d_plus_e.0,
        "c_minus_r" Length => |s| s.c_minus_r.0,
        "phi2_deg" Angle => |s| s.phi2_deg.0,
        "phi3_deg" Angle => |s| s.phi3_deg.0,
    }

    fn kind(&self) -> &'static str {
        "tsai"
    }

    fn actuation(&self) -> Actuation {
        Actuation::Revolute
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(&tsai(self)?, &self.modes, constraints, visitor)
    }

    fn reach_region(&self) -> Result<Option<Region>, BuildError> {
        Ok(Some(Region::Hemisphere {
            center: Vector3::zeros(),
            radius: tsai(self)?.reach(),
        }))
    }

    /// The modes with every leg on one elbow, θ3 principal: the branch [`Skeleton::tsai`]
    /// draws.
    fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let robot = tsai(self).map_err(|e| e.to_string())?;
        let uniform = self.modes.iter().filter(|m| m.iter().all(|e| *e == m[0]));
        let tries = uniform.map(|m| {
            let branch = LegBranch {
                principal_theta3: true,
                elbow: m[0],
            };
            Skeleton::tsai(&robot, p, branch)
        });
        first_drawable(p, tries)
    }

    /// Its six design values: the column quadrature of its volume is smooth in them.
    fn smooth_objective(&self) -> Result<[f64; 6], String> {
        Ok([
            self.a.0,
            self.b.0,
            self.d_plus_e.0,
            self.c_minus_r.0,
            self.phi2_deg.0,
            self.phi3_deg.0,
        ])
    }
}

impl StudyMechanism for LinearDeltaSpec {
    design_variables! {
        "l1_over_yr" Ratio => |s| s.l1_over_yr.0,
        "ya_over_yr" Ratio => |s| s.ya_over_yr.0,
        "zr_over_yr" Ratio => |s| s.zr_over_yr.0,
        "l2_over_l1" Ratio => |s| s.l2_over_l1.0,
        "yr" Length => |s| s.yr.0,
    }

    fn kind(&self) -> &'static str {
        "linear_delta"
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        let mode = LinearDeltaMode {
            leans_positive: self.leans_positive,
        };
        visit(&linear_delta(self)?, &[mode], constraints, visitor)
    }

    fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let robot = linear_delta(self).map_err(|e| e.to_string())?;
        let mode = LinearDeltaMode {
            leans_positive: self.leans_positive,
        };
        first_drawable(p, [Skeleton::linear_delta(&robot, p, mode)])
    }

    /// Unbounded along its rails: the box $|x| \le L$ around the rails widened by the longest
    /// arm $L$ in $y$ and $z$.
    fn drawing_region(&self) -> Result<Region, String> {
        let robot = linear_delta(self).map_err(|e| e.to_string())?;
        let reach = robot.arm_lengths().into_iter().fold(0.0, f64::max);
        let rails = robot.rails();
        let (mut lower, mut upper) = (
            Vector3::new(-reach, 0.0, 0.0),
            Vector3::new(reach, 0.0, 0.0),
        );
        for axis in [1, 2] {
            let along = rails.iter().map(|r| r[axis - 1]);
            lower[axis] = along.clone().fold(f64::INFINITY, f64::min) - reach;
            upper[axis] = along.fold(f64::NEG_INFINITY, f64::max) + reach;
        }
        Ok(Region::Box { lower, upper })
    }

    /// The plane $x = x_c$ across the rails.
    fn drawing_plane(&self) -> (usize, usize, usize) {
        (1, 2, 0)
    }

    fn section_ratios(&self) -> Option<[f64; 4]> {
        Some([
            self.l1_over_yr.0,
            self.ya_over_yr.0,
            self.zr_over_yr.0,
            self.l2_over_l1.0,
        ])
    }
}

impl StudyMechanism for ThreeUpuSpec {
    design_variables! {
        "base_radius" Length => |s| s.base_radius.0,
        "platform_radius" Length => |s| s.platform_radius.0,
        "beta1_deg" Angle => |s| s.beta1_deg.0,
        "gamma1_deg" Angle => |s| s.gamma1_deg.0,
        "beta2_deg" Angle => |s| s.beta2_deg.0,
        "gamma2_deg" Angle => |s| s.gamma2_deg.0,
        "beta3_deg" Angle => |s| s.beta3_deg.0,
        "gamma3_deg" Angle => |s| s.gamma3_deg.0,
    }

    fn kind(&self) -> &'static str {
        "three_upu"
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(&three_upu(self)?, &[()], constraints, visitor)
    }

    fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let robot = three_upu(self).map_err(|e| e.to_string())?;
        let pose = Isometry3::translation(p.x, p.y, p.z);
        first_drawable(p, [Skeleton::three_upu(&robot, &pose)])
    }
}

impl StudyMechanism for StewartSpec {
    design_variables! {
        "base_radius" Length => |s| s.base_radius.0,
        "platform_radius" Length => |s| s.platform_radius.0,
        "base_separation_deg" Angle => |s| s.base_separation_deg.0,
        "platform_separation_deg" Angle => |s| s.platform_separation_deg.0,
    }

    fn kind(&self) -> &'static str {
        "stewart_gough"
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(&stewart_orientation(self)?, &[()], constraints, visitor)
    }

    fn skeleton_at(&self, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let view = stewart_orientation(self).map_err(|e| e.to_string())?;
        let pose = Isometry3::from_parts(
            Translation3::from(*p),
            UnitQuaternion::from_rotation_matrix(view.rotation()),
        );
        first_drawable(p, [Skeleton::stewart_gough(view.platform(), &pose)])
    }
}
