//! The one place where a study's `[mechanism.*]` and `[constraints]` tables become library
//! values: the mechanism with its working modes, its workspace constraints, its reach region
//! and the design variables a sweep may vary.
//!
//! Lengths are metres, angles in keys ending in `_deg` degrees (converted to radians here),
//! ratios dimensionless.

use super::units::{
    ConeDegrees, DegreeRange, Degrees, MetreRange, Metres, NonNegativeMetres, PositiveMetres, Real,
};
use crate::StudyError;
use crate::registry::Actuation;
use nalgebra::Vector3;
use pkm_mechanisms::{
    AngleMode, ConstantOrientation, Elbow, ElbowMode, JointLayout, LinearDelta, LinearDeltaDesign,
    LinearDeltaMode, LinearDeltaRatios, Pairing, Placement, RotaryDelta, RotaryDeltaDesign,
    StewartDesign, StewartGough, ThreeUpu, ThreeUpuDesign, Tsai3Dof, TsaiDesign, UJointAxes,
};
use pkm_traits::{ConstrainedWorkspace, WorkspaceConstraint};
use pkm_workspace_indices::{Dim, TranslationalCondition, Workspace};
use serde::{Deserialize, Serialize};

crate::mechanisms! {
    /// The `[mechanism.<kind>]` table: exactly one kind, one line per mechanism.
    pub enum MechanismSpec {
        /// Rotary Delta / NUWAR family (Miller 2004): motors inclined by α and turned by β.
        RotaryDelta(RotaryDeltaSpec),
        /// The Tsai 3-DOF translational platform (Stamper, Tsai & Walsh 1997).
        Tsai(TsaiSpec),
        /// The Linear Delta (Miller 2004 §2.2): three parallel rails along x.
        LinearDelta(LinearDeltaSpec),
        /// The 3-UPU (Wolf & Shoham §4.4) in its translational model: platform at $R = I$.
        ThreeUpu(ThreeUpuSpec),
        /// The Stewart–Gough platform (Wolf & Shoham Fig. 3) at one fixed orientation.
        StewartGough(StewartSpec),
        /// Any translational robot from a robot file (`docs/robots.md`), inline or by `file`.
        RobotFile(super::robot_file::RobotFileSpec),
    }
}

/// `[mechanism.three_upu]`: the 3-UPU's joint circles. The upper U-joint axes do not enter the
/// translational model (they only orient the constraint couples), so they are Park's.
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
}

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

/// `[mechanism.linear_delta]`: the ratios of Miller 2004, Table 1, and the scale YR.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinearDeltaSpec {
    /// L1/YR, outer arm length over actuator separation (≥ 1).
    pub l1_over_yr: Real,
    /// YA/YR, horizontal eccentricity of the centre rail (|YA/YR| < 1).
    pub ya_over_yr: Real,
    /// ZR/YR, vertical eccentricity of the centre rail.
    pub zr_over_yr: Real,
    /// L2/L1, centre arm over outer arm length (> 0).
    pub l2_over_l1: Real,
    /// The actuator separation YR (m), the length unit of the ratios.
    #[serde(default = "one_m")]
    pub yr: PositiveMetres,
    /// Which way each arm leans along the rails (default: the paper's `[true, true, false]`).
    #[serde(default = "paper_leans")]
    pub leans_positive: [bool; 3],
}

fn park_azimuths() -> [Degrees; 3] {
    [Degrees(-90.0), Degrees(30.0), Degrees(150.0)]
}
fn no_rotation() -> [Degrees; 3] {
    [Degrees(0.0); 3]
}
fn zero_deg() -> Degrees {
    Degrees(0.0)
}
fn deg_120() -> Degrees {
    Degrees(120.0)
}
fn deg_240() -> Degrees {
    Degrees(240.0)
}
fn zero_m() -> Metres {
    Metres(0.0)
}
fn zero_nonneg() -> NonNegativeMetres {
    NonNegativeMetres(0.0)
}
fn one_m() -> PositiveMetres {
    PositiveMetres(1.0)
}
fn default_elbows() -> Vec<ElbowMode> {
    vec![ElbowMode::Out]
}
fn default_tsai_modes() -> Vec<[Elbow; 3]> {
    vec![[Elbow::Out; 3]]
}
fn paper_leans() -> [bool; 3] {
    LinearDeltaMode::PAPER.leans_positive
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
    /// Every revolute actuated joint within `[lower, upper]` (degrees).
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
            (_, Some(r), _) => out.push(
                WorkspaceConstraint::joint_range(r.lower.to_radians(), r.upper.to_radians())
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
            out.push(WorkspaceConstraint::joint_range_of(j.joint, lo, hi).map_err(library)?);
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

/// Receives a built workspace, whatever the mechanism type (closures cannot be generic).
pub trait WorkspaceVisitor {
    /// What the visit returns.
    type Output;
    /// Works on `workspace` (`NQ` actuated joints: 3, or a Stewart–Gough platform's 6).
    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>;
}

/// Why a design has no workspace: an invalid design (recorded as infeasible in sweeps) or a
/// constraint the mechanism cannot evaluate (an error of the study).
#[derive(Debug, Clone, PartialEq)]
pub enum BuildError {
    /// The design parameters are invalid (the library's reason).
    Design(String),
    /// A constraint does not apply to this mechanism.
    Constraint(String),
}

impl std::fmt::Display for BuildError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Design(m) | Self::Constraint(m) => f.write_str(m),
        }
    }
}

pub(crate) fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, V: WorkspaceVisitor, const NQ: usize>(
    mechanism: &M,
    modes: &[M::WorkingMode],
    constraints: &[WorkspaceConstraint],
    visitor: V,
) -> Result<V::Output, BuildError>
where
    Dim<NQ>: TranslationalCondition<NQ>,
{
    let workspace = Workspace::new(mechanism, modes, constraints)
        .map_err(|e| BuildError::Constraint(e.to_string()))?;
    Ok(visitor.visit(&workspace))
}

fn design_error(e: pkm_traits::DesignError) -> BuildError {
    BuildError::Design(e.to_string())
}

/// The rotary Delta of a `[mechanism.rotary_delta]` table.
///
/// # Errors
/// [`BuildError::Design`] with the library's reason for an invalid design.
pub fn rotary_delta(s: &RotaryDeltaSpec) -> Result<RotaryDelta, BuildError> {
    let placement = Placement {
        motor_plane_z: s.motor_plane_z.0,
        azimuth_motor_1: s.azimuth_motor_1_deg.radians(),
    };
    let delta = RotaryDelta::new(RotaryDeltaDesign {
        base_radius: s.base_radius.0,
        plate_offset: s.plate_offset.0,
        arm: s.arm.0,
        forearm: s.forearm.0,
        alpha: s.alpha_deg.radians(),
        beta: s.beta_deg.radians(),
        placement,
    })
    .map_err(design_error)?;
    Ok(if s.turned_plate_offsets {
        delta.with_turned_plate_offsets()
    } else {
        delta
    })
}

/// The Tsai platform of a `[mechanism.tsai]` table.
///
/// # Errors
/// [`BuildError::Design`] with the library's reason for an invalid design.
pub fn tsai(s: &TsaiSpec) -> Result<Tsai3Dof, BuildError> {
    Tsai3Dof::new(TsaiDesign::from_deg(
        s.a.0,
        s.b.0,
        s.d_plus_e.0,
        s.c_minus_r.0,
        s.phi2_deg.0,
        s.phi3_deg.0,
    ))
    .map_err(design_error)
}

/// The Linear Delta of a `[mechanism.linear_delta]` table.
///
/// # Errors
/// [`BuildError::Design`] with the library's reason for an invalid design.
pub fn linear_delta(s: &LinearDeltaSpec) -> Result<LinearDelta, BuildError> {
    let ratios = LinearDeltaRatios {
        l1_over_yr: s.l1_over_yr.0,
        ya_over_yr: s.ya_over_yr.0,
        zr_over_yr: s.zr_over_yr.0,
        l2_over_l1: s.l2_over_l1.0,
    };
    LinearDelta::new(LinearDeltaDesign { ratios, yr: s.yr.0 }).map_err(design_error)
}

/// The 3-UPU of a `[mechanism.three_upu]` table (Park's U-joint axes at its azimuths).
///
/// # Errors
/// [`BuildError::Design`] with the library's reason for an invalid design.
pub fn three_upu(s: &ThreeUpuSpec) -> Result<ThreeUpu, BuildError> {
    let azimuths = s.azimuths_deg.map(Degrees::radians);
    ThreeUpu::new(ThreeUpuDesign {
        base_radius: s.base_radius.0,
        platform_radius: s.platform_radius.0,
        azimuths,
        upper: azimuths.map(UJointAxes::park),
    })
    .map_err(design_error)
}

/// The constant-orientation view of a `[mechanism.stewart_gough]` table.
///
/// # Errors
/// [`BuildError::Design`] with the library's reason for an invalid design or rotation.
pub fn stewart_orientation(s: &StewartSpec) -> Result<ConstantOrientation, BuildError> {
    let d = s;
    let platform = StewartGough::new(StewartDesign {
        layout: stewart_layout(d),
        ..StewartDesign::from_deg(
            d.base_radius.0,
            d.platform_radius.0,
            d.base_separation_deg.0,
            d.platform_separation_deg.0,
        )
    })
    .map_err(design_error)?;
    let w = Vector3::from(s.rotation_deg.map(Degrees::radians));
    ConstantOrientation::new(platform, w).map_err(design_error)
}

impl From<BuildError> for StudyError {
    fn from(e: BuildError) -> Self {
        Self::invalid("mechanism", e.to_string())
    }
}

/// The library's joint layout of a `[mechanism.stewart_gough]` table.
pub fn stewart_layout(spec: &StewartSpec) -> JointLayout {
    JointLayout {
        pairing: spec.pairing,
        angle_mode: spec.angle_mode,
        offset_deg: spec.offset_deg.0,
    }
}
