//! The one place where a study's `[mechanism.*]` and `[constraints]` tables become library
//! values: the mechanism with its working modes, its workspace constraints, its reach region
//! and the design variables a sweep may vary.
//!
//! Lengths are metres, angles in keys ending in `_deg` degrees (converted to radians here),
//! ratios dimensionless.

pub use super::constraints::{ConstraintsSpec, HalfSpaceSpec, JointRangeDegSpec, JointRangeSpec};
use super::units::{Degrees, Metres, NonNegativeMetres, PositiveMetres, Real};
pub use crate::registry::{BuildError, WorkspaceVisitor};
use nalgebra::Vector3;
use pkm_mechanisms::{
    AngleMode, ConstantOrientation, Elbow, ElbowMode, JointLayout, LinearDelta, LinearDeltaDesign,
    LinearDeltaMode, LinearDeltaRatios, Pairing, Placement, RotaryDelta, RotaryDeltaDesign,
    StewartDesign, StewartGough, ThreeUpu, ThreeUpuDesign, Tsai3Dof, TsaiDesign, UJointAxes,
};
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

/// The 3-UPU of a `[mechanism.three_upu]` table: Park's U-joint axes at its azimuths, tilted
/// by its `beta*_deg`, `gamma*_deg` ([`tilted_axes`]).
///
/// # Errors
/// [`BuildError::Design`] with the library's reason for an invalid design.
pub fn three_upu(s: &ThreeUpuSpec) -> Result<ThreeUpu, BuildError> {
    let azimuths = s.azimuths_deg.map(Degrees::radians);
    ThreeUpu::new(ThreeUpuDesign {
        base_radius: s.base_radius.0,
        platform_radius: s.platform_radius.0,
        azimuths,
        upper: tilted_axes(azimuths, &s.tilts_deg()),
    })
    .map_err(design_error)
}

/// Park's axes $(u_1, u_2)$ of the joints at `azimuths` (radians), joint $i$ tilted by
/// $\beta_i$ about the radial $u_2$, then by $\gamma_i$ about the tangent $u_1$
/// (`tilts_deg = [β1, γ1, β2, γ2, β3, γ3]`, degrees), as in Wolf & Shoham §4.4:
/// $u_j' = R_{u_2}(\beta_i)\,R_{u_1}(\gamma_i)\,u_j$.
pub fn tilted_axes(azimuths: [f64; 3], tilts_deg: &[f64; 6]) -> [UJointAxes; 3] {
    std::array::from_fn(|i| {
        let (beta, gamma) = (tilts_deg[2 * i], tilts_deg[2 * i + 1]);
        UJointAxes::park_tilted(azimuths[i], beta.to_radians(), gamma.to_radians())
    })
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

/// The library's joint layout of a `[mechanism.stewart_gough]` table.
pub fn stewart_layout(spec: &StewartSpec) -> JointLayout {
    JointLayout {
        pairing: spec.pairing,
        angle_mode: spec.angle_mode,
        offset_deg: spec.offset_deg.0,
    }
}
