//! `[mechanism.stewart_gough]`: the Stewart–Gough platform of Wolf & Shoham (Fig. 3) at one fixed
//! orientation: its table, the library robot it builds, and what a study asks of it.

use super::{design_error, zero_deg};
use crate::design_variables;
use crate::registry::{
    Actuation, BuildError, ForwardVisitor, StudyMechanism, WorkspaceVisitor, visit,
};
use crate::scene::first_drawable;
use crate::schema::units::{Degrees, PositiveMetres};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pkm_mechanisms::{
    AngleMode, ConstantOrientation, JointLayout, Pairing, Skeleton, StewartDesign, StewartGough,
};
use pkm_traits::WorkspaceConstraint;
use serde::{Deserialize, Serialize};

/// `[mechanism.stewart_gough]`: the design $x = (x_1, x_2, x_3, x_4)$, the joint layout and
/// the platform's orientation in constant-orientation studies (workspace, sweep, Pareto).
/// Leg-length ranges are `[constraints] joint_range`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StewartSpec {
    /// $x_1$, base joint radius (m).
    pub base_radius: PositiveMetres,
    /// $x_2$, platform joint radius (m).
    pub platform_radius: PositiveMetres,
    /// $x_3$, angle between the two joints of a base pair (degrees, 0–120).
    pub base_separation_deg: Degrees,
    /// $x_4$, the same on the platform (degrees, 0–120).
    pub platform_separation_deg: Degrees,
    /// `"same_pattern"` (default) or `"zig_zag"`.
    #[serde(default)]
    pub pairing: Pairing,
    /// `"separation"` (default: $x_3$, $x_4$ are the whole angle) or `"half"`.
    #[serde(default)]
    pub angle_mode: AngleMode,
    /// Azimuth of the first base pair's centre (degrees).
    #[serde(default = "zero_deg")]
    pub offset_deg: Degrees,
    /// Rotation vector $\alpha n$ of the platform in constant-orientation studies (degrees;
    /// default no rotation). Task studies take the pose from `[task]` instead.
    #[serde(default = "no_rotation")]
    pub rotation_deg: [Degrees; 3],
}

fn no_rotation() -> [Degrees; 3] {
    [Degrees(0.0); 3]
}

/// The library's joint layout of a `[mechanism.stewart_gough]` table.
pub fn stewart_layout(spec: &StewartSpec) -> JointLayout {
    JointLayout {
        pairing: spec.pairing,
        angle_mode: spec.angle_mode,
        offset_deg: spec.offset_deg.0,
    }
}

/// The table of a library design (the papers' presets), at no rotation.
impl From<StewartDesign> for StewartSpec {
    fn from(d: StewartDesign) -> Self {
        Self {
            base_radius: PositiveMetres(d.base_radius),
            platform_radius: PositiveMetres(d.platform_radius),
            base_separation_deg: Degrees(d.base_separation.to_degrees()),
            platform_separation_deg: Degrees(d.platform_separation.to_degrees()),
            pairing: d.layout.pairing,
            angle_mode: d.layout.angle_mode,
            offset_deg: Degrees(d.layout.offset_deg),
            rotation_deg: no_rotation(),
        }
    }
}

impl StudyMechanism for StewartSpec {
    design_variables! {
        "base_radius" Length => |s| s.base_radius.0,
        "platform_radius" Length => |s| s.platform_radius.0,
        "base_separation_deg" Angle => |s| s.base_separation_deg.0,
        "platform_separation_deg" Angle => |s| s.platform_separation_deg.0,
    }

    type Built = ConstantOrientation;

    fn kind(&self) -> &'static str {
        "stewart_gough"
    }

    /// The constant-orientation view of a `[mechanism.stewart_gough]` table.
    ///
    /// # Errors
    /// [`BuildError::Design`] with the library's reason for an invalid design or rotation.
    fn build(&self) -> Result<ConstantOrientation, BuildError> {
        let platform = StewartGough::new(StewartDesign {
            layout: stewart_layout(self),
            ..StewartDesign::from_deg(
                self.base_radius.0,
                self.platform_radius.0,
                self.base_separation_deg.0,
                self.platform_separation_deg.0,
            )
        })
        .map_err(design_error)?;
        let w = Vector3::from(self.rotation_deg.map(Degrees::radians));
        ConstantOrientation::new(platform, w).map_err(design_error)
    }

    fn actuation(&self) -> Actuation {
        Actuation::Prismatic
    }

    /// None in the position alone: six legs for three coordinates at a fixed orientation
    /// (the forward kinematics is over the 6-D pose: a robot file of the platform has it).
    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        _built: &ConstantOrientation,
        _visitor: V,
    ) -> Result<V::Output, BuildError> {
        Err(BuildError::Unsupported(
            "the Stewart–Gough platform at a fixed orientation has 6 legs for 3 coordinates; \
             its forward kinematics is over the 6-D pose (examples/robots/stewart_gough.toml)"
                .into(),
        ))
    }

    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        view: &ConstantOrientation,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(view, &[()], constraints, visitor)
    }

    fn skeleton_at(
        &self,
        view: &ConstantOrientation,
        p: &Vector3<f64>,
    ) -> Result<Skeleton, String> {
        let pose = Isometry3::from_parts(
            Translation3::from(*p),
            UnitQuaternion::from_rotation_matrix(view.rotation()),
        );
        first_drawable(p, [Skeleton::stewart_gough(view.platform(), &pose)])
    }
}
