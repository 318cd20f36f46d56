//! `pkm task FILE`: task-based synthesis after Wolf & Shoham: the pose and/or geometry of a
//! Stewart–Gough platform or a 3-UPU that maximises or minimises
//! $F = \sum_k w_k \sum_i (L_i \wedge \chi_k)^2$ (eq. 14, 18) for a weighted set of task twists
//! $\chi_k$, by multistart bounded Levenberg–Marquardt with its first- and second-order report;
//! and, for the 3-UPU, the singularity search: the pose or geometry that minimises the smallest
//! singular value (or the determinant) of the $6 \times 6$ matrix of eq. 18 (three leg lines,
//! three constraint couples).
//!
//! Weighted twists enter as the stacked residuals $\sqrt{w_k}\,(L_i \wedge \chi_k)$
//! ([`pkm_optimizers::WeightedSum`]), so the sum of squares is $F$, and one twist of weight 1
//! is exactly the library's problem.

use super::{Context, Report, Run};
use crate::CliError;
use crate::drawing;
use crate::output::Output;
use crate::plot::{self, Marker, Scatter};
use crate::study::units::{Degrees, Metres, PositiveMetres, Real};
use crate::study::StudyFile;
use crate::study::mechanism::{StewartSpec, stewart_layout};
use nalgebra::{Isometry3, Matrix6, Rotation3, Unit, Vector3, Vector6};
use pkm_screw_theory::{Twist, line_set_rank, task_residuals};
use pkm_mechanisms::{
    Skeleton, StewartDesign, StewartDesignVariable, StewartGough,
    StewartTaskProblem, ThreeUpu, ThreeUpuDesign, UJointAxes, WrenchSystem, pose_from_task,
    presets,
};
use pkm_draw::Scene;
use pkm_optimizers::{
    ActiveBound, LmSettings, LocalOptimum, Multistart, MultistartRun, Sense, WeightedSum,
    levenberg_marquardt, multistart,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals, Task};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Arguments of `pkm task`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

/// The study of `pkm task`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskStudy {
    /// Free text.
    pub title: Option<String>,
    /// The nominal design (its values hold for the variables that are not optimised).
    pub mechanism: toml::Spanned<TaskMechanismSpec>,
    /// What is sought and how.
    pub task: TaskSection,
}

/// The `[mechanism.<kind>]` table of a task study: exactly one kind.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TaskMechanismSpec {
    /// Semi-regular Stewart–Gough platform (Wolf & Shoham §4.1–4.3).
    StewartGough(StewartSpec),
    /// The 3-UPU of §4.4 (joints at Park's azimuths −90°, 30°, 150°).
    ThreeUpu(UpuSpec),
}

/// `[mechanism.three_upu]`: radii and the tilts of the upper U-joint axes from Park's.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct UpuSpec {
    /// Base joint radius $a$ (m).
    pub base_radius: PositiveMetres,
    /// Platform joint radius $b$ (m).
    pub platform_radius: PositiveMetres,
    /// Tilt $\beta_1$ of joint 1's axes about Park's radial axis $u_2$ (degrees).
    #[serde(default = "zero_deg")]
    pub beta1_deg: Degrees,
    /// Tilt $\gamma_1$ of joint 1's axes about Park's tangent axis $u_1$ (degrees).
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

fn zero_deg() -> Degrees {
    Degrees(0.0)
}

/// The `[task]` section.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskSection {
    /// What is sought.
    pub goal: Goal,
    /// The nominal pose.
    #[serde(default)]
    pub pose: PoseSpec,
    /// Stewart–Gough only: the orientation is free within $|\alpha| \le$ this (degrees).
    pub max_angle_deg: Option<toml::Spanned<Degrees>>,
    /// The optimised variables and their ranges `[lower, upper]`, in the unit of the key.
    pub variables: toml::Spanned<BTreeMap<String, [f64; 2]>>,
    /// The task twists (none with a singularity goal).
    #[serde(default)]
    pub twists: Vec<toml::Spanned<TwistSpec>>,
    /// The multistart.
    pub starts: Multistart,
    /// Levenberg–Marquardt settings (defaults: the library's).
    #[serde(default)]
    pub solver: LmSettings,
}

/// What `pkm task` seeks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Goal {
    /// Largest $F$: the legs move most for the task (good transmission of the task).
    Maximise,
    /// Smallest $F$: the task is as nearly reciprocal to every row as possible.
    Minimise,
    /// 3-UPU: smallest singular value $\sigma_{min}$ of the eq. 18 matrix.
    SingularitySigmaMin,
    /// 3-UPU: smallest $\det^2$ of the eq. 18 matrix.
    SingularityDet,
}

impl Goal {
    fn sense(self) -> Sense {
        match self {
            Self::Maximise => Sense::Maximise,
            Self::Minimise | Self::SingularitySigmaMin | Self::SingularityDet => Sense::Minimise,
        }
    }

    /// The goal's name in study files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Maximise => "maximise",
            Self::Minimise => "minimise",
            Self::SingularitySigmaMin => "singularity_sigma_min",
            Self::SingularityDet => "singularity_det",
        }
    }

    fn is_singularity(self) -> bool {
        matches!(self, Self::SingularitySigmaMin | Self::SingularityDet)
    }
}

/// `[task.pose]`: the platform pose where it is not optimised.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSpec {
    /// Position $p$ (m).
    #[serde(default = "origin")]
    pub position: [Metres; 3],
    /// Rotation vector $\alpha n$ (degrees).
    #[serde(default = "no_rotation")]
    pub rotation_deg: [Degrees; 3],
}

impl Default for PoseSpec {
    fn default() -> Self {
        Self {
            position: origin(),
            rotation_deg: no_rotation(),
        }
    }
}

fn origin() -> [Metres; 3] {
    [Metres(0.0); 3]
}
fn no_rotation() -> [Degrees; 3] {
    [Degrees(0.0); 3]
}

/// A task twist: a screw (axis, point, pitch, intensity), or the six numbers.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TwistSpec {
    /// Axis direction (dimensionless, normalised).
    pub axis: Option<[Real; 3]>,
    /// A point on the axis (m).
    pub point: Option<[Metres; 3]>,
    /// Pitch (m/rad).
    #[serde(default = "zero_m")]
    pub pitch: Metres,
    /// Angular speed about the axis (rad/s).
    #[serde(default = "one")]
    pub intensity: Real,
    /// Or the twist $[\omega; v]$ itself (rad/s, m/s), instead of axis and point.
    pub vector: Option<[Real; 6]>,
    /// Weight $w_k \ge 0$ (dimensionless).
    #[serde(default = "one")]
    pub weight: Real,
}

fn zero_m() -> Metres {
    Metres(0.0)
}
fn one() -> Real {
    Real(1.0)
}

impl TwistSpec {
    /// The twist.
    ///
    /// # Errors
    /// A message when neither or both forms are given, or the screw is invalid.
    pub fn twist(&self) -> Result<Twist, String> {
        match (self.vector, self.axis, self.point) {
            (Some(v), None, None) => Ok(Twist::from_vector(Vector6::from(v.map(|x| x.0)))),
            (None, Some(axis), Some(point)) => Twist::from_screw(
                &Vector3::from(axis.map(|x| x.0)),
                &Vector3::from(point.map(|x| x.0)),
                self.pitch.0,
                self.intensity.0,
            )
            .map_err(|e| e.to_string()),
            _ => Err("expected either `vector` (rad/s, m/s) or `axis` and `point` (m)".into()),
        }
    }
}

/// The library's design variables behind the first four names of [`STEWART_VARIABLES`], in
/// the study's units (lengths, and separations in degrees).
const STEWART_DESIGN_VARIABLES: [StewartDesignVariable; 4] = [
    StewartDesignVariable::BaseRadius,
    StewartDesignVariable::PlatformRadius,
    StewartDesignVariable::BaseSeparationDeg,
    StewartDesignVariable::PlatformSeparationDeg,
];

/// The Stewart–Gough variables a task may optimise, in [`StewartTaskProblem`] slot order.
pub const STEWART_VARIABLES: [&str; 7] = [
    "base_radius",
    "platform_radius",
    "base_separation_deg",
    "platform_separation_deg",
    "x",
    "y",
    "z",
];

/// The 3-UPU variables, in [`UpuProblem`] order.
pub const UPU_VARIABLES: [&str; 14] = [
    "base_radius",
    "platform_radius",
    "beta1_deg",
    "gamma1_deg",
    "beta2_deg",
    "gamma2_deg",
    "beta3_deg",
    "gamma3_deg",
    "x",
    "y",
    "z",
    "rx_deg",
    "ry_deg",
    "rz_deg",
];

/// Park's axes of joint $i$ tilted by $\beta_i$ about the radial $u_2$ and $\gamma_i$ about the
/// tangent $u_1$ (degrees), as in Wolf & Shoham §4.4.
pub fn tilted_axes(tilts: &[f64]) -> [UJointAxes; 3] {
    let park = presets::PARK_AZIMUTHS_DEG.map(|t| UJointAxes::park(t.to_radians()));
    std::array::from_fn(|i| {
        let UJointAxes { u1, u2 } = park[i];
        let tilt = Rotation3::from_axis_angle(&Unit::new_normalize(u2), tilts[2 * i].to_radians())
            * Rotation3::from_axis_angle(&Unit::new_normalize(u1), tilts[2 * i + 1].to_radians());
        UJointAxes {
            u1: tilt * u1,
            u2: tilt * u2,
        }
    })
}

/// What the 3-UPU problem's residuals are.
#[derive(Debug, Clone)]
enum UpuResiduals {
    /// $\sqrt{w_k}\,(L_i \wedge \chi_k)$.
    Task(Vec<(f64, Twist)>),
    /// $\sigma_{min}$.
    SigmaMin,
    /// $\det$.
    Det,
}

/// The 3-UPU over any subset of [`UPU_VARIABLES`].
#[derive(Debug, Clone)]
pub struct UpuProblem {
    values: [f64; 14],
    free: Vec<usize>,
    bounds: Vec<Bounds>,
    residuals: UpuResiduals,
}

impl UpuProblem {
    /// All 14 values at a design vector of the free ones.
    fn full(&self, v: &[f64]) -> [f64; 14] {
        let mut all = self.values;
        for (k, value) in self.free.iter().zip(v) {
            all[*k] = *value;
        }
        all
    }

    /// The mechanism and pose at `v`.
    ///
    /// # Errors
    /// An invalid design or pose (as [`ObjectiveError::Infeasible`]).
    pub fn evaluate(&self, v: &[f64]) -> Result<(ThreeUpu, Isometry3<f64>), ObjectiveError> {
        self.check_dimension(v)?;
        let all = self.full(v);
        let upu = ThreeUpu::new(ThreeUpuDesign {
            base_radius: all[0],
            platform_radius: all[1],
            azimuths: presets::PARK_AZIMUTHS_DEG.map(f64::to_radians),
            upper: tilted_axes(&all[2..8]),
        })?;
        let [x, y, z, rx, ry, rz] = [all[8], all[9], all[10], all[11], all[12], all[13]];
        let (rx, ry, rz) = (rx.to_radians(), ry.to_radians(), rz.to_radians());
        let pose = pose_from_task(&Task::<6>::new(x, y, z, rx, ry, rz)).map_err(ObjectiveError::from)?;
        Ok((upu, pose))
    }

    /// The eq. 18 matrix at `v`.
    ///
    /// # Errors
    /// As [`UpuProblem::evaluate`], or a leg of zero length.
    pub fn wrench_rows(&self, v: &[f64]) -> Result<Matrix6<f64>, ObjectiveError> {
        let (upu, pose) = self.evaluate(v)?;
        upu.wrench_rows(&pose)
            .map_err(ObjectiveError::from)
    }
}

impl Objective for UpuProblem {
    fn dimension(&self) -> usize {
        self.free.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, v: &[f64]) -> Result<f64, ObjectiveError> {
        self.sum_of_squares(v)
    }
}

impl Residuals for UpuProblem {
    fn n_residuals(&self) -> usize {
        match &self.residuals {
            UpuResiduals::Task(t) => 6 * t.len(),
            UpuResiduals::SigmaMin | UpuResiduals::Det => 1,
        }
    }
    fn residuals(&self, v: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        let n = self.n_residuals();
        if r.len() != n {
            return Err(ObjectiveError::Dimension {
                expected: n,
                got: r.len(),
            });
        }
        let rows = self.wrench_rows(v)?;
        match &self.residuals {
            UpuResiduals::Task(twists) => {
                for (chunk, (w, twist)) in r.chunks_mut(6).zip(twists) {
                    let rates = task_residuals(&rows, twist);
                    for (ri, rate) in chunk.iter_mut().zip(rates.iter()) {
                        *ri = w * rate;
                    }
                }
            }
            UpuResiduals::SigmaMin => r[0] = smallest_singular_value(&rows),
            UpuResiduals::Det => r[0] = rows.determinant(),
        }
        Ok(())
    }
}

/// $\sigma_{min}$ of a 6×6 matrix.
fn smallest_singular_value(rows: &Matrix6<f64>) -> f64 {
    rows.singular_values().iter().copied().fold(f64::INFINITY, f64::min)
}

/// The optimised variables of a study among `names`, each with its range, in `names` order;
/// errors at the `[task.variables]` table.
///
/// # Errors
/// [`CliError::Study`] for an unknown name or an invalid range.
fn chosen_variables(
    file: &StudyFile<TaskStudy>,
    names: &[&str],
) -> Result<Vec<(usize, Bounds)>, CliError> {
    let table = &file.study.task.variables;
    let mut chosen = Vec::new();
    for (name, [lo, hi]) in table.get_ref() {
        let k = names.iter().position(|n| n == name).ok_or_else(|| {
            file.error_at(
                table.span(),
                format!(
                    "unknown variable `{name}` for this mechanism: expected one of {} (lengths \
                     in m, *_deg in degrees)",
                    names.join(", ")
                ),
            )
        })?;
        let bounds = Bounds::new(*lo, *hi).map_err(|e| {
            file.error_at(
                table.span(),
                format!("{name} = [{lo}, {hi}]: expected [lower, upper] with lower <= upper ({e})"),
            )
        })?;
        chosen.push((k, bounds));
    }
    chosen.sort_by_key(|(k, _)| *k);
    Ok(chosen)
}

fn design_error(e: impl std::fmt::Display) -> CliError {
    CliError::Invalid(e.to_string())
}

/// The library problem of one twist: the nominal design and pose of the study with the
/// variables `free` (indices into [`STEWART_VARIABLES`]) and, with `max_angle` (radians), the
/// orientation freed.
///
/// # Errors
/// [`CliError::Invalid`] with the library's reason for an invalid design, pose or angle.
pub fn stewart_problem(
    spec: &StewartSpec,
    pose: &PoseSpec,
    free: &[(usize, Bounds)],
    max_angle: Option<f64>,
    twist: Twist,
) -> Result<StewartTaskProblem, CliError> {
    let design = StewartDesign {
        layout: stewart_layout(spec),
        ..StewartDesign::from_deg(
            spec.base_radius.0,
            spec.platform_radius.0,
            spec.base_separation_deg.0,
            spec.platform_separation_deg.0,
        )
    };
    let position = Vector3::from(pose.position.map(|x| x.0));
    let rotation = Vector3::from(pose.rotation_deg.map(Degrees::radians));
    let mut problem =
        StewartTaskProblem::new(design, position, rotation, twist).map_err(design_error)?;
    for &(k, bounds) in free {
        problem = match STEWART_DESIGN_VARIABLES.get(k) {
            Some(&variable) => problem.free_design(variable, bounds),
            None => problem.free_position(k - 4, bounds).map_err(design_error)?,
        };
    }
    if let Some(angle) = max_angle {
        problem = problem.free_rotation(angle).map_err(design_error)?;
    }
    Ok(problem)
}

/// The 3-UPU problem of the study for `goal` and the weighted twists, with the variables
/// `free` (indices into [`UPU_VARIABLES`]).
pub fn upu_problem(
    spec: &UpuSpec,
    pose: &PoseSpec,
    free: &[(usize, Bounds)],
    goal: Goal,
    twists: &[(f64, Twist)],
) -> UpuProblem {
    let [x, y, z] = pose.position.map(|v| v.0);
    let [rx, ry, rz] = pose.rotation_deg.map(|v| v.0);
    let values = [
        spec.base_radius.0,
        spec.platform_radius.0,
        spec.beta1_deg.0,
        spec.gamma1_deg.0,
        spec.beta2_deg.0,
        spec.gamma2_deg.0,
        spec.beta3_deg.0,
        spec.gamma3_deg.0,
        x,
        y,
        z,
        rx,
        ry,
        rz,
    ];
    let residuals = match goal {
        Goal::Maximise | Goal::Minimise => {
            UpuResiduals::Task(twists.iter().map(|(w, t)| (w.sqrt(), *t)).collect())
        }
        Goal::SingularitySigmaMin => UpuResiduals::SigmaMin,
        Goal::SingularityDet => UpuResiduals::Det,
    };
    UpuProblem {
        values,
        free: free.iter().map(|(k, _)| *k).collect(),
        bounds: free.iter().map(|(_, b)| *b).collect(),
        residuals,
    }
}

/// The Levenberg–Marquardt report at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Optimality {
    /// Why the iteration stopped.
    pub termination: String,
    /// Iterations spent.
    pub iterations: usize,
    /// Largest |∂f/∂x_j| over the variables off their bounds (0 at a KKT point).
    pub free_gradient_max: f64,
    /// Variables held on a bound.
    pub active_bounds: usize,
    /// Eigenvalues (ascending) of the Hessian on the free variables: ≤ 0 at a maximum, ≥ 0 at
    /// a minimum.
    pub reduced_hessian_eigenvalues: Vec<f64>,
}

impl From<&LocalOptimum> for Optimality {
    fn from(o: &LocalOptimum) -> Self {
        Self {
            termination: o.termination.to_string(),
            iterations: o.iterations,
            free_gradient_max: o.free_gradient_norm(),
            active_bounds: o.active.iter().filter(|a| **a != ActiveBound::Free).count(),
            reduced_hessian_eigenvalues: o.reduced_hessian_eigenvalues.clone(),
        }
    }
}

/// A pose in the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoseReport {
    /// Position (m).
    pub position: [f64; 3],
    /// Rotation vector $\alpha n$ (degrees).
    pub rotation_deg: [f64; 3],
    /// Unit rotation axis $n$ (z when there is no rotation).
    pub axis: [f64; 3],
    /// Rotation angle $\alpha \ge 0$ (degrees).
    pub angle_deg: f64,
}

impl From<&Isometry3<f64>> for PoseReport {
    fn from(pose: &Isometry3<f64>) -> Self {
        let w = pose.rotation.scaled_axis();
        let angle = w.norm();
        let axis = if angle > 0.0 { w / angle } else { Vector3::z() };
        let array = |v: Vector3<f64>| [v.x, v.y, v.z];
        Self {
            position: array(pose.translation.vector),
            rotation_deg: array(w.map(f64::to_degrees)),
            axis: array(axis),
            angle_deg: angle.to_degrees(),
        }
    }
}

/// The 6×6 matrix of wrench rows at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WrenchMatrix {
    /// Rank of the rows (relative tolerance 1e-9).
    pub rank: usize,
    /// Smallest singular value.
    pub sigma_min: f64,
    /// Determinant.
    pub det: f64,
    /// The unit twist most nearly reciprocal to every row ($[\omega; v]$, rad/s and m/s):
    /// the swapped right singular vector of $\sigma_{min}$.
    pub most_reciprocal_twist: [f64; 6],
    /// Its $F = \sigma_{min}^2$ by the library's task objective.
    pub most_reciprocal_f: f64,
}

/// One twist's $F$ at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TwistValue {
    /// $w_k$.
    pub weight: f64,
    /// $F_k = \sum_i (L_i \wedge \chi_k)^2$ (m²/s²).
    pub f: f64,
}

/// The `result` of `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskResult {
    /// The study's title.
    pub title: Option<String>,
    /// `stewart_gough` or `three_upu`.
    pub mechanism: String,
    /// The goal.
    pub goal: Goal,
    /// The optimised objective at the optimum: $F = \sum_k w_k F_k$ (m²/s²), $\sigma_{min}^2$
    /// or $\det^2$.
    pub objective: f64,
    /// The start it came from (from 0).
    pub best_start: usize,
    /// The optimised variables at the optimum (units of their keys; `u_x`, `u_y`, `u_z`: the
    /// cube coordinates of a free Stewart–Gough orientation).
    pub optimum: BTreeMap<String, f64>,
    /// The design at the optimum (units of its keys).
    pub design: BTreeMap<String, f64>,
    /// The platform pose at the optimum.
    pub pose: PoseReport,
    /// Each twist's $F$ there.
    pub twists: Vec<TwistValue>,
    /// Stewart–Gough: leg lengths (m).
    pub leg_lengths: Option<[f64; 6]>,
    /// The wrench rows there.
    pub wrench_matrix: WrenchMatrix,
    /// The first- and second-order report.
    pub optimality: Optimality,
    /// Starts run.
    pub starts: usize,
}

fn wrench_matrix(
    rows: &Matrix6<f64>,
    objective: impl Fn(&Twist) -> Result<f64, CliError>,
) -> Result<WrenchMatrix, CliError> {
    let lines: Vec<Vector6<f64>> = rows.row_iter().map(|r| r.transpose()).collect();
    let rank = line_set_rank(&lines, 1e-9).map_err(design_error)?;
    let twist = most_reciprocal_twist(rows)
        .ok_or_else(|| CliError::Invalid("the SVD of the wrench rows did not converge".into()))?;
    let v = twist.as_vector();
    Ok(WrenchMatrix {
        rank,
        sigma_min: smallest_singular_value(rows),
        det: rows.determinant(),
        most_reciprocal_twist: [v[0], v[1], v[2], v[3], v[4], v[5]],
        most_reciprocal_f: objective(&twist)?,
    })
}

/// The unit twist most nearly reciprocal to every row: the rows act on the swapped twist
/// ($r = W\,\Delta\chi$), so $\chi$ is the swapped right singular vector of $\sigma_{min}$.
pub fn most_reciprocal_twist(rows: &Matrix6<f64>) -> Option<Twist> {
    let svd = rows.svd(false, true);
    let v_t = svd.v_t?;
    let k = (0..6).min_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]))?;
    let y = v_t.row(k).transpose();
    Some(Twist::from_vector(Vector6::new(
        y[3], y[4], y[5], y[0], y[1], y[2],
    )))
}

/// The study's weighted twists, each error at its `[[task.twists]]` entry.
///
/// # Errors
/// [`CliError::Study`] for an invalid twist or weight.
fn weighted_twists(file: &StudyFile<TaskStudy>) -> Result<Vec<(f64, Twist)>, CliError> {
    file.study
        .task
        .twists
        .iter()
        .map(|t| {
            let spec = t.get_ref();
            if !(spec.weight.0 >= 0.0) {
                return Err(file.error_at(t.span(), "weight: expected a number >= 0"));
            }
            spec.twist()
                .map(|twist| (spec.weight.0, twist))
                .map_err(|m| file.error_at(t.span(), m))
        })
        .collect()
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_study("task", &self.file, context, compute)
    }
}

/// What one mechanism's run found, before the common report.
struct Found {
    names: Vec<String>,
    run: MultistartRun<LocalOptimum>,
    best_start: usize,
    result: TaskResult,
    /// The robot at the optimal pose with the task twists' axes.
    scene: Result<Scene, String>,
}

/// Runs the study in `file`, writing the starts table and figure to `context.out`.
///
/// # Errors
/// Study errors at their line, no successful start, I/O errors, [`CliError::Cancelled`].
pub fn compute(
    file: &StudyFile<TaskStudy>,
    context: &Context,
) -> Result<(TaskResult, Report, Output), CliError> {
    let task = &file.study.task;
    let twists = weighted_twists(file)?;
    if task.goal.is_singularity() != twists.is_empty() {
        let message = if twists.is_empty() {
            "goal = maximise/minimise needs at least one [[task.twists]]"
        } else {
            "a singularity goal takes no [[task.twists]]"
        };
        return Err(file.error_at(task.variables.span(), message));
    }
    let found = match file.study.mechanism.get_ref() {
        TaskMechanismSpec::StewartGough(spec) => stewart(file, spec, &twists, context)?,
        TaskMechanismSpec::ThreeUpu(spec) => upu(file, spec, &twists, context)?,
    };
    let mut out = Output::create(&context.out)?;
    write_starts(&mut out, &found)?;
    let r = &found.result;
    let mut report = Report::default();
    report.line(format!(
        "{} {}: objective {:.6e} from start {} of {} ({})",
        r.mechanism,
        r.goal.name(),
        r.objective, r.best_start, r.starts, r.optimality.termination
    ));
    report.line(format!(
        "optimum: {}",
        r.optimum
            .iter()
            .map(|(n, v)| format!("{n} = {v:.6}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    report.line(format!(
        "pose: p = [{:.6}, {:.6}, {:.6}] m, rotation {:.4}° about [{:.4}, {:.4}, {:.4}]; wrench \
         rows rank {}, sigma_min {:.3e}",
        r.pose.position[0],
        r.pose.position[1],
        r.pose.position[2],
        r.pose.angle_deg,
        r.pose.axis[0],
        r.pose.axis[1],
        r.pose.axis[2],
        r.wrench_matrix.rank,
        r.wrench_matrix.sigma_min
    ));
    report.line(format!(
        "free gradient {:.2e}, {} active bounds, reduced Hessian eigenvalues [{}]",
        r.optimality.free_gradient_max,
        r.optimality.active_bounds,
        r.optimality
            .reduced_hessian_eigenvalues
            .iter()
            .map(|v| format!("{v:.3e}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    let caption = format!("{}: the optimal pose", r.mechanism);
    out.write_robot(&mut report, &caption, found.scene)?;
    report.line(format!("wrote {}", out.dir().join("results.json").display()));
    Ok((found.result, report, out))
}

/// Levenberg–Marquardt from every start of the study, every outcome kept; the best start.
///
/// # Errors
/// Invalid settings or starts (before any start runs), no successful start,
/// [`CliError::Cancelled`].
fn run_starts<P: Residuals>(
    problem: &P,
    sense: Sense,
    task: &TaskSection,
    context: &Context,
) -> Result<(MultistartRun<LocalOptimum>, usize, LocalOptimum), CliError> {
    let settings = task.solver;
    settings.validate()?;
    let starts = task.starts.start_points(problem.bounds())?;
    let run = multistart(starts, &context.progress, |s, cancel| {
        levenberg_marquardt(problem, sense, s, &settings, cancel)
    })?;
    let (best_start, best) = run.best(sense)?;
    let best = best.clone();
    Ok((run, best_start, best))
}

fn stewart(
    file: &StudyFile<TaskStudy>,
    spec: &StewartSpec,
    twists: &[(f64, Twist)],
    context: &Context,
) -> Result<Found, CliError> {
    let task = &file.study.task;
    if task.goal.is_singularity() {
        return Err(file.error_at(
            file.study.mechanism.span(),
            "the singularity goals are for [mechanism.three_upu]",
        ));
    }
    let free = chosen_variables(file, &STEWART_VARIABLES)?;
    let max_angle = task.max_angle_deg.as_ref().map(|a| a.get_ref().radians());
    let parts = twists
        .iter()
        .map(|(w, t)| Ok((*w, stewart_problem(spec, &task.pose, &free, max_angle, *t)?)))
        .collect::<Result<Vec<_>, CliError>>()?;
    let problem = WeightedSum::new(parts)?;
    let sense = task.goal.sense();
    let (run, best_start, best) = run_starts(&problem, sense, task, context)?;
    let (_, first) = problem.parts().next().ok_or_else(|| design_error("no twist"))?;
    let (mechanism, pose) = first.evaluate(&best.design).map_err(design_error)?;
    let mut names: Vec<String> = free
        .iter()
        .map(|(k, _)| STEWART_VARIABLES[*k].to_owned())
        .collect();
    if max_angle.is_some() {
        names.extend(["u_x", "u_y", "u_z"].map(str::to_owned));
    }
    let f = |t: &Twist| -> Result<f64, CliError> {
        mechanism.task_objective(&pose, t).map_err(design_error)
    };
    let result = TaskResult {
        title: file.study.title.clone(),
        mechanism: "stewart_gough".into(),
        goal: task.goal,
        objective: best.value,
        best_start,
        optimum: names.iter().cloned().zip(best.design.iter().copied()).collect(),
        design: STEWART_VARIABLES[..4]
            .iter()
            .map(|n| (*n).to_owned())
            .zip(stewart_design_values(&mechanism.design()))
            .collect(),
        pose: PoseReport::from(&pose),
        twists: twists
            .iter()
            .map(|(w, t)| Ok(TwistValue { weight: *w, f: f(t)? }))
            .collect::<Result<_, CliError>>()?,
        leg_lengths: Some(leg_lengths(&mechanism, &pose)),
        wrench_matrix: wrench_matrix(&mechanism.wrench_rows(&pose).map_err(design_error)?, f)?,
        optimality: Optimality::from(&best),
        starts: run.starts.len(),
    };
    let scene = drawing::task_scene(
        Skeleton::stewart_gough(&mechanism, &pose),
        &pose,
        twists,
        None,
    );
    Ok(Found {
        names,
        run,
        best_start,
        result,
        scene,
    })
}

/// The design in the study's units: radii, then the separations in degrees.
fn stewart_design_values(d: &StewartDesign) -> [f64; 4] {
    [
        d.base_radius,
        d.platform_radius,
        d.base_separation.to_degrees(),
        d.platform_separation.to_degrees(),
    ]
}

fn leg_lengths(mechanism: &StewartGough, pose: &Isometry3<f64>) -> [f64; 6] {
    let l = mechanism.leg_lengths(pose);
    [l[0], l[1], l[2], l[3], l[4], l[5]]
}

fn upu(
    file: &StudyFile<TaskStudy>,
    spec: &UpuSpec,
    twists: &[(f64, Twist)],
    context: &Context,
) -> Result<Found, CliError> {
    let task = &file.study.task;
    if let Some(angle) = &task.max_angle_deg {
        return Err(file.error_at(
            angle.span(),
            "max_angle_deg is for [mechanism.stewart_gough]; free the 3-UPU's orientation with \
             rx_deg, ry_deg, rz_deg in [task.variables]",
        ));
    }
    let free = chosen_variables(file, &UPU_VARIABLES)?;
    let problem = upu_problem(spec, &task.pose, &free, task.goal, twists);
    let sense = task.goal.sense();
    let (run, best_start, best) = run_starts(&problem, sense, task, context)?;
    let (mechanism, pose) = problem.evaluate(&best.design).map_err(design_error)?;
    let rows = mechanism.wrench_rows(&pose).map_err(design_error)?;
    let names: Vec<String> = free
        .iter()
        .map(|(k, _)| UPU_VARIABLES[*k].to_owned())
        .collect();
    let f = |t: &Twist| -> Result<f64, CliError> {
        mechanism.task_objective(&pose, t).map_err(design_error)
    };
    let all = problem.full(&best.design);
    let result = TaskResult {
        title: file.study.title.clone(),
        mechanism: "three_upu".into(),
        goal: task.goal,
        objective: best.value,
        best_start,
        optimum: names.iter().cloned().zip(best.design.iter().copied()).collect(),
        design: UPU_VARIABLES[..8]
            .iter()
            .map(|n| (*n).to_owned())
            .zip(all)
            .collect(),
        pose: PoseReport::from(&pose),
        twists: twists
            .iter()
            .map(|(w, t)| Ok(TwistValue { weight: *w, f: f(t)? }))
            .collect::<Result<_, CliError>>()?,
        leg_lengths: None,
        wrench_matrix: wrench_matrix(&rows, f)?,
        optimality: Optimality::from(&best),
        starts: run.starts.len(),
    };
    let reciprocal = most_reciprocal_twist(&rows);
    let scene = drawing::task_scene(
        Skeleton::three_upu(&mechanism, &pose),
        &pose,
        twists,
        reciprocal,
    );
    Ok(Found {
        names,
        run,
        best_start,
        result,
        scene,
    })
}

/// `starts.csv` (each start and where it ended) and `starts.svg` (the objective reached,
/// best first).
fn write_starts(out: &mut Output, found: &Found) -> Result<(), CliError> {
    let names = &found.names;
    let mut header: Vec<String> = vec!["start".into()];
    header.extend(names.iter().map(|n| format!("start_{n}")));
    header.extend(names.iter().cloned());
    header.extend(["objective".into(), "termination".into()]);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows = found.run.outcomes.iter().enumerate().map(|(k, o)| {
        let mut row = vec![k.to_string()];
        row.extend(found.run.starts[k].iter().map(|v| format!("{v}")));
        match o {
            Ok(r) => {
                row.extend(r.design.iter().map(|v| format!("{v}")));
                row.push(format!("{}", r.value));
                row.push(format!("\"{}\"", r.termination));
            }
            Err(e) => {
                row.extend(std::iter::repeat_n(String::new(), names.len() + 1));
                row.push(format!("\"{}\"", e.to_string().replace('"', "'")));
            }
        }
        row
    });
    out.write_csv("starts.csv", &header, rows)?;
    let maximise = found.result.goal == Goal::Maximise;
    let mut reached: Vec<f64> = found
        .run
        .outcomes
        .iter()
        .filter_map(|o| o.as_ref().ok().map(|r| r.value))
        .collect();
    reached.sort_by(|a, b| if maximise { b.total_cmp(a) } else { a.total_cmp(b) });
    let points: Vec<(f64, f64)> = reached
        .iter()
        .enumerate()
        .map(|(rank, v)| (rank as f64 + 1.0, *v))
        .collect();
    let markers = points
        .first()
        .map(|&(x, y)| Marker {
            x,
            y,
            label: format!("start {}", found.best_start),
        })
        .into_iter()
        .collect();
    let figure = Scatter {
        title: "objective reached from each start".into(),
        x_label: "rank".into(),
        y_label: "objective".into(),
        background: points,
        front: Vec::new(),
        markers,
    };
    out.write_svg("starts.svg", |path| plot::scatter(&figure, path))?;
    Ok(())
}
