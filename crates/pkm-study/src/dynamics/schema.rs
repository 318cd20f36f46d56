//! The sections of a dynamics study: `[masses]`, `[trajectory]` and `[dynamics]`, plain serde
//! types (the `[mechanism.rotary_delta]` or `[mechanism.robot_file]` table is the shared
//! [`MechanismSpec`]).
//!
//! [`MechanismSpec`]: crate::schema::mechanism::MechanismSpec

use crate::schema::units::{Degrees, Metres, PositiveMetres, Real};
use serde::{Deserialize, Serialize};

/// `[masses]`: the mass model of Miller 2004 §3.5.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MassesSpec {
    /// Plate mass (kg).
    pub plate: Real,
    /// Arm inertia about the motor axis (kg m²).
    pub arm_inertia: Real,
    /// Arm mass (kg; enters the potential only).
    pub arm_mass: Real,
    /// Distance of the arm's centre of mass from the motor axis (m).
    pub arm_centre_of_mass: Metres,
    /// Elbow mass per chain (kg).
    pub elbow: Real,
    /// Mass of one forearm, both rods together (kg).
    pub forearm: Real,
    /// Gravity along −z (m/s²; default 9.81, 0 switches it off).
    #[serde(default = "standard_gravity")]
    pub gravity: Real,
    /// `"rod"` (default: slender rods) or `"lumped"` (half at each end).
    #[serde(default)]
    pub forearm_model: ForearmSpec,
}

fn standard_gravity() -> Real {
    Real(9.81)
}

/// [`ForearmModel`](pkm_dynamics_hamilton::ForearmModel) in a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ForearmSpec {
    /// Slender rods.
    #[default]
    Rod,
    /// Half of each forearm's mass at each end.
    Lumped,
}

/// `[trajectory]`: exactly one of `pick_and_place`, `segments`, `task_segments`, `positions`
/// (or `csv`, which a front end turns into `positions`).
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TrajectorySpec {
    /// Miller's elliptical pick-and-place cycle.
    pub pick_and_place: Option<PickAndPlaceSpec>,
    /// Rest-to-rest segments run one after the other.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segments: Vec<SegmentSpec>,
    /// Rest-to-rest straight lines in a robot file's task coordinates (m and rad), run one
    /// after the other.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub task_segments: Vec<TaskSegmentSpec>,
    /// The name of a CSV file of `t, x, y, z` rows (s, m; for a robot file `t` and its task
    /// coordinates) after a header line, equally spaced in time. The study layer reads no
    /// files: a front end reads it and hands its rows in as [`positions`](Self::positions) (the
    /// `pkm` command reads it relative to the study file).
    pub csv: Option<String>,
    /// Sampled positions `[t, x, y, z]` (s, m; for a robot file `[t, x_1, …, x_n]` in its
    /// task coordinates), equally spaced in time (at least 3): velocities and accelerations are
    /// their differences.
    pub positions: Option<Vec<Vec<Real>>>,
    /// Sampling step of the built-in trajectories (s; default [`DEFAULT_DT`]).
    pub dt: Option<f64>,
}

/// Default sampling step of the built-in trajectories (s).
pub const DEFAULT_DT: f64 = 1e-3;

/// The pick-and-place cycle.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PickAndPlaceSpec {
    /// Cycle time (s).
    pub cycle_time: Real,
    /// `"round_trip"` (default: there and back in the cycle time) or `"each_leg"`.
    #[serde(default)]
    pub reading: ReadingSpec,
}

/// How the cycle time of Miller's cycle is read (Miller 2004, §3.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReadingSpec {
    /// There and back in the cycle time.
    #[default]
    RoundTrip,
    /// Each way in the cycle time (a round trip in twice it).
    EachLeg,
}

/// One `[[trajectory.segments]]` entry.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// The path.
    pub path: PathSpec,
    /// `"parabolic"`, `"cycloidal"` or `"polynomial345"`.
    pub law: LawSpec,
    /// Duration (s).
    pub duration: Real,
    /// Run the path from its end back to its start.
    #[serde(default)]
    pub reverse: bool,
}

/// One `[[trajectory.task_segments]]` entry: $x(t) = x_0 + s(t/T)\,(x_1 - x_0)$ in the
/// robot's task coordinates.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TaskSegmentSpec {
    /// Start $x_0$ (m and rad, one entry per task coordinate).
    pub start: Vec<Real>,
    /// End $x_1$.
    pub end: Vec<Real>,
    /// `"parabolic"`, `"cycloidal"` or `"polynomial345"`.
    pub law: LawSpec,
    /// Duration $T$ (s).
    pub duration: Real,
}

/// [`MotionLaw`](pkm_dynamics_hamilton::trajectory::MotionLaw) in a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LawSpec {
    /// Constant acceleration, then constant deceleration.
    Parabolic,
    /// Cycloidal.
    Cycloidal,
    /// The 3-4-5 polynomial.
    Polynomial345,
}

/// A path shape, lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PathSpec {
    /// Straight line.
    Line {
        /// Start (m).
        start: [Metres; 3],
        /// End (m).
        end: [Metres; 3],
    },
    /// $c + \cos\varphi\,a_1 + \sin\varphi\,a_2$, $\varphi$ from `start_angle_deg` over
    /// `sweep_deg`.
    Ellipse {
        /// Centre (m).
        centre: [Metres; 3],
        /// $a_1$ (m).
        axis_1: [Metres; 3],
        /// $a_2$ (m).
        axis_2: [Metres; 3],
        /// $\varphi_0$ (degrees).
        start_angle_deg: Degrees,
        /// $\Delta\varphi$ (degrees).
        sweep_deg: Degrees,
    },
    /// The ellipse of orthogonal semi-axes sheared along the first by `shear`.
    ShearedEllipse {
        /// Centre (m).
        centre: [Metres; 3],
        /// First semi-axis (m).
        semi_axis_1: [Metres; 3],
        /// Second semi-axis, orthogonal to the first (m).
        semi_axis_2: [Metres; 3],
        /// Shear factor (dimensionless).
        shear: Real,
        /// $\varphi_0$ (degrees).
        start_angle_deg: Degrees,
        /// $\Delta\varphi$ (degrees).
        sweep_deg: Degrees,
    },
    /// Clothoid (Euler spiral).
    Clothoid {
        /// Start (m).
        start: [Metres; 3],
        /// Initial direction (any length).
        tangent: [Real; 3],
        /// Direction of positive curvature (any length).
        normal: [Real; 3],
        /// Initial curvature (1/m).
        curvature: Real,
        /// Rate of curvature along the arc (1/m²).
        sharpness: Real,
        /// Arc length (m).
        length: PositiveMetres,
    },
}

/// The `[dynamics]` section.
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsSection {
    /// Differencing of Hamilton's momenta: `"central"` (default) or `"backward"`.
    #[serde(default)]
    pub differencing: DifferencingSpec,
    /// Lagrange's accelerations: `"trajectory"` (default: the trajectory's, analytic for the
    /// built-in shapes) or `"differenced"` (the joint velocities differenced).
    #[serde(default)]
    pub lagrange_accelerations: LagrangeSpec,
    /// The forward retrace, when present.
    pub forward: Option<ForwardSpec>,
}

/// [`Differencing`](pkm_dynamics_hamilton::inverse::Differencing) in a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DifferencingSpec {
    /// Second-order central differences.
    #[default]
    Central,
    /// First-order backward differences.
    Backward,
}

/// Where Lagrange takes $\ddot q$ from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LagrangeSpec {
    /// The trajectory's accelerations through the acceleration-level inverse kinematics.
    #[default]
    Trajectory,
    /// $\dot q$ differenced with the same scheme as Hamilton's momenta.
    Differenced,
}

/// `[dynamics.forward]`: Dormand–Prince 5(4) on the Hamilton form.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ForwardSpec {
    /// Velocity-level Baumgarte gain κ (1/s; 0 = unstabilised; default 20).
    #[serde(default = "default_kappa")]
    pub kappa: Real,
    /// Relative tolerance (default 1e-8).
    #[serde(default = "default_rtol")]
    pub rtol: Real,
    /// Absolute tolerance (default 1e-11).
    #[serde(default = "default_atol")]
    pub atol: Real,
    /// Step limit (default 1,000,000).
    #[serde(default = "default_max_steps")]
    pub max_steps: usize,
}

impl ForwardSpec {
    /// The default Baumgarte gain κ (1/s).
    pub const DEFAULT_KAPPA: f64 = 20.0;
}

fn default_kappa() -> Real {
    Real(ForwardSpec::DEFAULT_KAPPA)
}
fn default_rtol() -> Real {
    Real(1e-8)
}
fn default_atol() -> Real {
    Real(1e-11)
}
fn default_max_steps() -> usize {
    1_000_000
}

/// `[[effort_maps]]` (a robot file's dynamics): the largest actuator effort at rest over a box
/// of task accelerations ([`pkm_robot_file::RobotModel::peak_efforts_at_rest`]), on a plane of
/// two task coordinates.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EffortMapSpec {
    /// The plane's two task coordinates, by name (`x`, `rz`).
    pub axes: [String; 2],
    /// The range of each axis (m or rad), by name.
    pub range: std::collections::BTreeMap<String, [f64; 2]>,
    /// Values of the other task coordinates (m, rad; default: home).
    #[serde(default)]
    pub at: std::collections::BTreeMap<String, f64>,
    /// Cells per side (default 30, 2 to 256).
    #[serde(default = "default_effort_cells")]
    pub cells: usize,
    /// The bound of each task coordinate's acceleration (m/s² or rad/s²), by name (default 0:
    /// the robot at rest holding its weight).
    #[serde(default)]
    pub acceleration: std::collections::BTreeMap<String, f64>,
}

fn default_effort_cells() -> usize {
    30
}
