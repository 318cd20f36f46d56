//! `[mechanism.three_upu]`: the 3-UPU of Wolf & Shoham §4.4 in its translational model
//! (platform at $R = I$): its table, the library robot it builds, and what a study asks of it.

use super::{design_error, zero_deg};
use crate::design_variables;
use crate::registry::{
    Actuation, BuildError, ForwardVisitor, StudyMechanism, WorkspaceVisitor, visit,
};
use crate::scene::first_drawable;
use crate::schema::units::{Degrees, PositiveMetres};
use nalgebra::{Isometry3, Vector3};
use pkm_mechanisms::{Skeleton, ThreeUpu, ThreeUpuDesign, UJointAxes};
use pkm_traits::WorkspaceConstraint;
use serde::{Deserialize, Serialize};

/// `[mechanism.three_upu]`: the 3-UPU's joint circles and the tilts of its upper U-joint axes
/// from Park's (Wolf & Shoham §4.4). The tilts do not enter the translational model of the
/// workspace commands (they only orient the constraint couples of eq. 18, which `task` uses).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ThreeUpuSpec {
    /// Base joint radius $a$ (m).
    pub base_radius: PositiveMetres,
    /// Platform joint radius $b$ (m).
    pub platform_radius: PositiveMetres,
    /// Azimuths $\theta_i$ of the three legs' joints (degrees; default Park's −90, 30, 150).
    #[serde(default = "park_azimuths")]
    pub azimuths_deg: [Degrees; 3],
    /// Tilt $\beta_1$ of joint 1's upper axes about Park's radial axis $u_2$ (degrees).
    #[serde(default = "zero_deg")]
    pub beta1_deg: Degrees,
    /// Tilt $\gamma_1$ of joint 1's upper axes about Park's tangent axis $u_1$ (degrees).
    #[serde(default = "zero_deg")]
    pub gamma1_deg: Degrees,
    /// As `beta1_deg`, joint 2.
    #[serde(default = "zero_deg")]
    pub beta2_deg: Degrees,
    /// As `gamma1_deg`, joint 2.
    #[serde(default = "zero_deg")]
    pub gamma2_deg: Degrees,
    /// As `beta1_deg`, joint 3.
    #[serde(default = "zero_deg")]
    pub beta3_deg: Degrees,
    /// As `gamma1_deg`, joint 3.
    #[serde(default = "zero_deg")]
    pub gamma3_deg: Degrees,
}

impl ThreeUpuSpec {
    /// The tilts $[\beta_1, \gamma_1, \beta_2, \gamma_2, \beta_3, \gamma_3]$ (degrees).
    pub fn tilts_deg(&self) -> [f64; 6] {
        [
            self.beta1_deg.0,
            self.gamma1_deg.0,
            self.beta2_deg.0,
            self.gamma2_deg.0,
            self.beta3_deg.0,
            self.gamma3_deg.0,
        ]
    }
}

fn park_azimuths() -> [Degrees; 3] {
    [Degrees(-90.0), Degrees(30.0), Degrees(150.0)]
}

/// The table of a library design whose upper axes are Park's at its azimuths (untilted; the
/// papers' preset `park_3upu`).
///
/// # Errors
/// The reason, for upper axes that are not Park's within 1e-12: the table gives tilts from
/// Park's axes, and other axes have no such tilts to write.
impl TryFrom<ThreeUpuDesign> for ThreeUpuSpec {
    type Error = String;

    fn try_from(d: ThreeUpuDesign) -> Result<Self, String> {
        let untilted = (0..3).all(|i| {
            let park = UJointAxes::park(d.azimuths[i]);
            (d.upper[i].u1 - park.u1).norm() <= 1e-12 && (d.upper[i].u2 - park.u2).norm() <= 1e-12
        });
        if !untilted {
            return Err(
                "the upper U-joint axes are not Park's: a [mechanism.three_upu] table \
                        gives its axes as tilts from Park's"
                    .into(),
            );
        }
        Ok(Self {
            base_radius: PositiveMetres(d.base_radius),
            platform_radius: PositiveMetres(d.platform_radius),
            azimuths_deg: d.azimuths.map(|a| Degrees(a.to_degrees())),
            beta1_deg: zero_deg(),
            gamma1_deg: zero_deg(),
            beta2_deg: zero_deg(),
            gamma2_deg: zero_deg(),
            beta3_deg: zero_deg(),
            gamma3_deg: zero_deg(),
        })
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

    type Built = ThreeUpu;

    fn kind(&self) -> &'static str {
        "three_upu"
    }

    /// The 3-UPU of a `[mechanism.three_upu]` table: Park's U-joint axes at its azimuths, tilted
    /// by its `beta*_deg`, `gamma*_deg` ([`tilted_axes`](pkm_design_problems::upu::tilted_axes)).
    ///
    /// # Errors
    /// [`BuildError::Design`] with the library's reason for an invalid design.
    fn build(&self) -> Result<ThreeUpu, BuildError> {
        let azimuths = self.azimuths_deg.map(Degrees::radians);
        ThreeUpu::new(ThreeUpuDesign {
            base_radius: self.base_radius.0,
            platform_radius: self.platform_radius.0,
            azimuths,
            upper: pkm_design_problems::upu::tilted_axes(azimuths, &self.tilts_deg()),
        })
        .map_err(design_error)
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        built: &ThreeUpu,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        Ok(visitor.visit(built))
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        built: &ThreeUpu,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(built, &[()], constraints, visitor)
    }

    fn skeleton_at(&self, robot: &ThreeUpu, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let pose = Isometry3::translation(p.x, p.y, p.z);
        first_drawable(p, [Skeleton::three_upu(robot, &pose)])
    }
}
