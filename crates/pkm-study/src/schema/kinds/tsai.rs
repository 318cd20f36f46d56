//! `[mechanism.tsai]`: the Tsai 3-DOF translational platform (Stamper, Tsai & Walsh 1997): its
//! table, the library robot it builds, and what a study asks of it.

use super::{design_error, zero_m};
use crate::design_variables;
use crate::registry::{
    Actuation, BuildError, ForwardVisitor, StudyMechanism, WorkspaceVisitor, visit,
};
use crate::scene::first_drawable;
use crate::schema::units::{Degrees, Metres, NonNegativeMetres, PositiveMetres};
use nalgebra::Vector3;
use pkm_design_problems::DesignProblem;
use pkm_mechanisms::{Elbow, LegBranch, Skeleton, Tsai3Dof, TsaiDesign};
use pkm_traits::WorkspaceConstraint;
use pkm_workspace_indices::Region;
use serde::{Deserialize, Serialize};

/// `[mechanism.tsai]`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TsaiSpec {
    /// Lower arm length a (m).
    pub a: PositiveMetres,
    /// Parallelogram length b (m).
    pub b: PositiveMetres,
    /// Offset sum d + e (m).
    #[serde(default = "zero_nonneg")]
    pub d_plus_e: NonNegativeMetres,
    /// Platform minus base radius c − r (m).
    #[serde(default = "zero_m")]
    pub c_minus_r: Metres,
    /// Azimuth of leg 2 (degrees; leg 1 is at 0).
    #[serde(default = "deg_120")]
    pub phi2_deg: Degrees,
    /// Azimuth of leg 3 (degrees).
    #[serde(default = "deg_240")]
    pub phi3_deg: Degrees,
    /// Allowed working modes, one elbow per leg (default `[["out", "out", "out"]]`).
    #[serde(default = "default_tsai_modes")]
    pub modes: Vec<[Elbow; 3]>,
}

fn zero_nonneg() -> NonNegativeMetres {
    NonNegativeMetres(0.0)
}
fn deg_120() -> Degrees {
    Degrees(120.0)
}
fn deg_240() -> Degrees {
    Degrees(240.0)
}
fn default_tsai_modes() -> Vec<[Elbow; 3]> {
    vec![[Elbow::Out; 3]]
}

/// The table of a library design (the papers' presets), in the default working mode.
impl From<TsaiDesign> for TsaiSpec {
    fn from(d: TsaiDesign) -> Self {
        Self {
            a: PositiveMetres(d.a),
            b: PositiveMetres(d.b),
            d_plus_e: NonNegativeMetres(d.d_plus_e),
            c_minus_r: Metres(d.c_minus_r),
            phi2_deg: Degrees(d.phi2.to_degrees()),
            phi3_deg: Degrees(d.phi3.to_degrees()),
            modes: default_tsai_modes(),
        }
    }
}

impl TsaiSpec {
    /// The six design values in the table's units: a, b, d + e, c − r (m), φ2, φ3 (degrees).
    fn values(&self) -> [f64; 6] {
        [
            self.a.0,
            self.b.0,
            self.d_plus_e.0,
            self.c_minus_r.0,
            self.phi2_deg.0,
            self.phi3_deg.0,
        ]
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

    type Built = Tsai3Dof;

    fn kind(&self) -> &'static str {
        "tsai"
    }

    /// The Tsai platform of a `[mechanism.tsai]` table.
    ///
    /// # Errors
    /// [`BuildError::Design`] with the library's reason for an invalid design.
    fn build(&self) -> Result<Tsai3Dof, BuildError> {
        let [a, b, d_plus_e, c_minus_r, phi2_deg, phi3_deg] = self.values();
        Tsai3Dof::new(TsaiDesign::from_deg(
            a, b, d_plus_e, c_minus_r, phi2_deg, phi3_deg,
        ))
        .map_err(design_error)
    }

    fn actuation(&self) -> Actuation {
        Actuation::Revolute
    }

    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        built: &Tsai3Dof,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        Ok(visitor.visit(built))
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        built: &Tsai3Dof,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(built, &self.modes, constraints, visitor)
    }

    fn reach_region(&self, robot: &Tsai3Dof) -> Option<Region> {
        Some(Region::Hemisphere {
            center: Vector3::zeros(),
            radius: robot.reach(),
        })
    }

    /// The modes with every leg on one elbow, θ3 principal: the branch [`Skeleton::tsai`]
    /// draws.
    fn skeleton_at(&self, robot: &Tsai3Dof, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let uniform = self.modes.iter().filter(|m| m.iter().all(|e| *e == m[0]));
        let tries = uniform.map(|m| {
            let branch = LegBranch {
                principal_theta3: true,
                elbow: m[0],
            };
            Skeleton::tsai(robot, p, branch)
        });
        first_drawable(p, tries)
    }

    /// Stamper's §5 at its six design values: the column quadrature of its volume is smooth
    /// in them.
    fn design_problem(&self) -> Option<DesignProblem> {
        Some(DesignProblem::Tsai {
            nominal: self.values(),
        })
    }
}
