//! `[task_space]`: the workspace of a robot file in its own task coordinates, whatever its task
//! (Merlet, *Parallel Robots*, 2nd ed. 2006, ch. 6): the reachable task set, the
//! constant-orientation, orientation and dexterous (total-orientation) workspaces, each with its
//! measure ± standard error, $\eta = \int 1/\kappa(J_h)$, GCI $= \eta/W$, and the
//! singularity-free part connected to home.
//!
//! **Coordinates.** The box, the fixed values and the start of the singularity-free search
//! name task coordinates as the robot file does (`x`, `tilt_x`, `rz`, ...): lengths in metres
//! under their name, angles in degrees under the name with `_deg` (`tilt_x_deg`); the library
//! receives radians. The measure of a region is the product of its sides in those units (m for
//! a length, rad for an angle): a 3-PRS in $(z, \theta_x, \theta_y)$ is in m·rad².
//!
//! **Kinds.** What is sampled and what is held:
//! - `reachable`: every task coordinate is sampled in the box;
//! - `constant_orientation`: the position coordinates are sampled, the orientation coordinates
//!   held at `fixed` (home by default);
//! - `orientation`: the orientation coordinates are sampled, the position held;
//! - `dexterous`: the position coordinates are sampled and a position belongs when the robot
//!   reaches it with every orientation of the set `orientations` (tilt up to $\theta_{\max}$ at
//!   every azimuth, torsion in a range: [`OrientationSet`]).
//!
//! **The dexterous rule.** "Every orientation" of a continuous set is tested on nested grids
//! of levels $1, 2, 4, \dots, 2^{L-1}$ ([`OrientationSet::grid`]; each holds its predecessor's
//! orientations), and the measure is reported at every level: the sets shrink with the level,
//! and the change between the last two levels says how far the finest grid is from the
//! continuous answer. The reported workspace is the finest level's, an upper bound of the
//! true dexterous workspace that converges to it as the grid refines (a point where some
//! orientation between grid nodes is unreachable can still be counted). Its local index is the
//! least $1/\kappa(J_h)$ over the first level's orientations.
//!
//! **The singularity-free workspace** is the part of the workspace (in the sampled
//! coordinates) whose direct (type II) singularity margin stays at or above a threshold and
//! that is connected to the home pose (or a given one) on a grid of `cells` per side
//! ([`connected_task_volume`]): the region the robot can move through from home without
//! crossing a type II singularity.

use crate::estimate::Estimate;
use crate::outcome::{Artifact, Outcome};
use crate::schema::robot_file::{RobotFileSpec, robot_skeleton};
use crate::schema::sampling::{SamplerKind, SamplingSpec};
use crate::{Infeasible, KeyPath, StudyError};

mod maps;
pub(crate) use maps::grid_table;
pub use maps::{MAX_MAP_CELLS, MapIndex, TaskMapResult, TaskMapSpec};
use pkm_draw::Scene;
use pkm_draw::chart::{self, Chart};
use pkm_robot_file::{
    MarginLimits, OrientationLevels, OrientationSet, RobotFileError, RobotModel, TaskWorkspace,
    WorkingMode,
};
use pkm_traits::{Progress, WorkspaceConstraint};
use pkm_workspace_indices::{
    ConnectedVolume, Sampler, TaskBox, TaskPoints, VolumeEstimate, connected_task_volume,
    nested_task_volumes,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The key path of the section.
const KEY: &str = "task_space";

/// Most nested orientation grids of a dexterous workspace (the finest is level $2^{L-1}$).
pub const MAX_ORIENTATION_LEVELS: u32 = 5;

/// Which workspace of the task space a study measures (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WorkspaceKind {
    /// Every task coordinate sampled.
    #[default]
    Reachable,
    /// The positions at one orientation.
    ConstantOrientation,
    /// The orientations at one position.
    Orientation,
    /// The positions reachable with every orientation of a set.
    Dexterous,
}

impl WorkspaceKind {
    fn key(self) -> &'static str {
        match self {
            Self::Reachable => "reachable",
            Self::ConstantOrientation => "constant_orientation",
            Self::Orientation => "orientation",
            Self::Dexterous => "dexterous",
        }
    }
}

/// The `[task_space]` section of a workspace study (module documentation).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TaskSpaceSpec {
    /// The workspace kind (default `reachable`).
    #[serde(default)]
    pub kind: WorkspaceKind,
    /// `[lo, hi]` of every sampled coordinate, by name (m; degrees under `<name>_deg`).
    #[serde(rename = "box")]
    pub bounds: BTreeMap<String, [f64; 2]>,
    /// Values of coordinates that are held, by name (default: their home values).
    #[serde(default)]
    pub fixed: BTreeMap<String, f64>,
    /// The orientation set of a dexterous workspace.
    pub orientations: Option<OrientationsSpec>,
    /// Least inverse-kinematic singularity margin of a member.
    pub min_inverse_margin: Option<f64>,
    /// Least direct (type II) singularity margin of a member.
    pub min_direct_margin: Option<f64>,
    /// Least constraint singularity margin of a member.
    pub min_constraint_margin: Option<f64>,
    /// The singularity-free workspace connected to home.
    pub singularity_free: Option<SingularityFreeSpec>,
    /// Maps of a local index on planes of two sampled coordinates (workspace studies).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub maps: Vec<TaskMapSpec>,
}

/// `[task_space.orientations]`: tilt up to `max_tilt_deg` at every azimuth, torsion in
/// `torsion_deg`, tested on `levels` nested grids.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OrientationsSpec {
    /// Largest tilt (degrees, 0 to 180).
    pub max_tilt_deg: f64,
    /// Torsion range (degrees, within ±180; default `[0, 0]`).
    #[serde(default)]
    pub torsion_deg: [f64; 2],
    /// Nested grids (1 to [`MAX_ORIENTATION_LEVELS`], default 3).
    #[serde(default = "default_levels")]
    pub levels: u32,
}

fn default_levels() -> u32 {
    3
}

/// `[task_space.singularity_free]`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SingularityFreeSpec {
    /// Least direct singularity margin of the region.
    pub min_direct_margin: f64,
    /// Grid cells per sampled coordinate (default 24).
    #[serde(default = "default_cells")]
    pub cells: u32,
    /// The start of the search, by name (default: the home pose).
    #[serde(default)]
    pub from: BTreeMap<String, f64>,
}

fn default_cells() -> u32 {
    24
}

/// A workspace study in a robot file's task space: the estimate, the measure of the sampled
/// box and what the task space adds; the study wraps it in its
/// [`WorkspaceResult`](crate::workspace::WorkspaceResult).
#[derive(Debug, Clone, PartialEq)]
pub struct TaskSpaceRun {
    /// Measure of the sampled box (the unit of [`TaskSpaceResult::unit`]).
    pub domain_volume: f64,
    /// The estimate (on the finest orientation grid of a dexterous workspace).
    pub estimate: Estimate,
    /// What the task space adds.
    pub task_space: TaskSpaceResult,
}

/// What a task-space workspace study reports beside its [`Estimate`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskSpaceResult {
    /// The workspace kind.
    pub kind: WorkspaceKind,
    /// The sampled coordinates with their units (`"tilt_x (rad)"`).
    pub coordinates: Vec<String>,
    /// The unit of the measure (`"m·rad²"`).
    pub unit: String,
    /// The held coordinates and their values (m, rad).
    pub fixed: BTreeMap<String, f64>,
    /// A dexterous workspace's estimate on each orientation grid, coarsest first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub orientation_levels: Vec<OrientationLevelResult>,
    /// The singularity-free workspace connected to the start pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub singularity_free: Option<SingularityFreeResult>,
    /// The maps, in the order of the section.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub maps: Vec<TaskMapResult>,
}

/// A dexterous workspace on one orientation grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrientationLevelResult {
    /// The grid level (1, 2, 4, ...).
    pub grid_level: u32,
    /// Orientations on the grid.
    pub orientations: usize,
    /// The measure of the positions reaching every one of them.
    pub volume: f64,
    /// Its standard error.
    pub volume_se: f64,
}

/// The singularity-free workspace.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SingularityFreeResult {
    /// The least direct margin.
    pub min_direct_margin: f64,
    /// Cells per side of the grid.
    pub cells: u32,
    /// The start (sampled coordinates, m and rad).
    pub from: Vec<f64>,
    /// Measure of the cells in the workspace with the margin, connected or not.
    pub volume_above_margin: f64,
    /// Measure of those connected to the start: the singularity-free workspace.
    pub volume_connected: f64,
    /// The figure's artifact name (two sampled coordinates and more).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub svg: Option<String>,
}

/// A checked `[task_space]` section bound to a robot.
struct Setup {
    kind: WorkspaceKind,
    /// Task indices of the sampled coordinates, in task order.
    sampled: Vec<usize>,
    region: TaskBox,
    /// The full task vector of the held values (radians).
    base: Vec<f64>,
    levels: Option<OrientationLevels>,
    margins: MarginLimits,
}

impl Setup {
    /// The task vector of sampled values `u`.
    fn pose(&self, u: &[f64]) -> Vec<f64> {
        let mut x = self.base.clone();
        for (&k, &v) in self.sampled.iter().zip(u) {
            x[k] = v;
        }
        x
    }
}

fn invalid(key: impl AsRef<str>, message: impl Into<String>) -> StudyError {
    StudyError::invalid(format!("{KEY}.{}", key.as_ref()).as_str(), message)
}

/// A robot-file error of a `[task_space]` setting at its key path.
fn located(e: RobotFileError) -> StudyError {
    match e {
        RobotFileError::Invalid {
            key,
            value,
            requirement,
        } => invalid(key, format!("{value}: {requirement}")),
        e => StudyError::invalid(KEY, e.to_string()),
    }
}

/// The task index of the coordinate keyed `key` and the factor to SI units and radians.
fn coordinate(model: &RobotModel, at: &str, key: &str) -> Result<(usize, f64), StudyError> {
    task_coordinate(model, &format!("{KEY}.{at}"), key)
}

/// The index of the task coordinate that the study key `key` names (`z`, or `tilt_x_deg` for
/// an angle in degrees) and the factor from the key's unit to the library's (1, or π/180).
///
/// # Errors
/// [`StudyError::Invalid`] at `<at>.<key>` for a name that is not in the task, an angle not
/// in degrees or a length in degrees.
pub(crate) fn task_coordinate(
    model: &RobotModel,
    at: &str,
    key: &str,
) -> Result<(usize, f64), StudyError> {
    let names = model.task_names();
    let path = KeyPath::parse(at).field(key);
    let (name, degrees) = key
        .strip_suffix("_deg")
        .map_or((key, false), |name| (name, true));
    let k = names.iter().position(|n| *n == name).ok_or_else(|| {
        let m = format!("not a task coordinate of this robot: its task is {names:?}");
        StudyError::invalid(path.clone(), m)
    })?;
    match (model.task_is_angle(k), degrees) {
        (true, true) => Ok((k, std::f64::consts::PI / 180.0)),
        (false, false) => Ok((k, 1.0)),
        (true, false) => Err(StudyError::invalid(
            path,
            format!("`{name}` is an angle: give it in degrees as `{name}_deg`"),
        )),
        (false, true) => Err(StudyError::invalid(
            path,
            format!("`{name}` is a length: give it in metres as `{name}`"),
        )),
    }
}

/// A finite value of coordinate `k` (radians), angles within ±π.
fn checked_value(model: &RobotModel, at: &str, value: f64, k: usize) -> Result<f64, StudyError> {
    let limit = if model.task_is_angle(k) {
        std::f64::consts::PI * (1.0 + 1e-12)
    } else {
        1e6
    };
    if value.is_finite() && value.abs() <= limit {
        Ok(value)
    } else {
        Err(invalid(
            at,
            format!(
                "{value}: a finite value within ±{}",
                if model.task_is_angle(k) {
                    "180°"
                } else {
                    "1e6 m"
                }
            ),
        ))
    }
}

/// Refuses a box whose orientation coordinates leave the robot file's chart of one turn
/// (`OrientationKind::rotation_angle` at most π: a rotation vector of norm ≤ π, a tilt ≤ π):
/// the robot file refuses such poses, so they would count as outside the workspace although
/// they are rotations the chart already holds. The angle is a convex function of the
/// coordinates (a norm, or the larger of a norm and an absolute value), so its largest value
/// over the box is at a corner.
///
/// # Errors
/// [`StudyError::Invalid`] at `task_space.box` naming the corner and its angle.
fn within_one_turn(
    model: &RobotModel,
    sampled: &[usize],
    base: &[f64],
    lower: &[f64],
    upper: &[f64],
) -> Result<(), StudyError> {
    let kind = model.orientation();
    let pose_names = kind.coordinate_names();
    let task_names = model.task_names();
    let mut task = base.to_vec();
    for corner in 0..1_usize << sampled.len() {
        for (i, &k) in sampled.iter().enumerate() {
            task[k] = if corner >> i & 1 == 0 {
                lower[i]
            } else {
                upper[i]
            };
        }
        let mut pose = model.home();
        for (k, name) in task_names.iter().enumerate() {
            if let Some(j) = pose_names.iter().position(|n| n == name) {
                pose[j] = task[k];
            }
        }
        let angle = kind.rotation_angle(&nalgebra::Vector3::new(pose[3], pose[4], pose[5]));
        if angle > std::f64::consts::PI * (1.0 + 1e-12) {
            let at: Vec<String> = sampled
                .iter()
                .map(|&k| match model.task_is_angle(k) {
                    true => format!("{} = {:.2}°", task_names[k], task[k].to_degrees()),
                    false => format!("{} = {} m", task_names[k], task[k]),
                })
                .collect();
            return Err(invalid(
                "box",
                format!(
                    "the corner ({}) turns {:.2}°: orientation coordinates describe one turn \
                     (rotation or tilt angle at most 180°), and poses beyond it are refused by \
                     the robot, not outside its workspace; shrink the box (for rotation \
                     vectors: corners within a norm of 180°)",
                    at.join(", "),
                    angle.to_degrees()
                ),
            ));
        }
    }
    Ok(())
}

/// The sampled task indices of `kind` for `model`.
fn sampled_of(model: &RobotModel, kind: WorkspaceKind) -> Result<Vec<usize>, StudyError> {
    let n = model.task_names().len();
    let (angles, lengths): (Vec<usize>, Vec<usize>) = (0..n).partition(|&k| model.task_is_angle(k));
    let task = model.task_names();
    let need = |ok: bool, what: &str| {
        if ok {
            Ok(())
        } else {
            Err(invalid(
                "kind",
                format!(
                    "a {} workspace needs {what}: this robot's task is {task:?}",
                    kind.key()
                ),
            ))
        }
    };
    match kind {
        WorkspaceKind::Reachable => Ok((0..n).collect()),
        WorkspaceKind::Orientation => {
            need(!angles.is_empty(), "orientation coordinates in the task")?;
            Ok(angles)
        }
        WorkspaceKind::ConstantOrientation | WorkspaceKind::Dexterous => {
            need(!angles.is_empty(), "orientation coordinates in the task")?;
            need(!lengths.is_empty(), "position coordinates in the task")?;
            Ok(lengths)
        }
    }
}

impl TaskSpaceSpec {
    /// The checked setup of this section for `model`, before any computation.
    fn setup(&self, model: &RobotModel) -> Result<Setup, StudyError> {
        let sampled = sampled_of(model, self.kind)?;
        let mut base = model.home_task();
        let (mut lower, mut upper) = (vec![f64::NAN; sampled.len()], vec![f64::NAN; sampled.len()]);
        for (key, &[lo, hi]) in &self.bounds {
            let (k, scale) = coordinate(model, "box", key)?;
            let at = format!("box.{key}");
            let Some(i) = sampled.iter().position(|&s| s == k) else {
                return Err(invalid(
                    at,
                    format!(
                        "not sampled in a {} workspace: give a held coordinate in `fixed`",
                        self.kind.key()
                    ),
                ));
            };
            lower[i] = checked_value(model, &at, lo * scale, k)?;
            upper[i] = checked_value(model, &at, hi * scale, k)?;
            if lower[i] >= upper[i] {
                return Err(invalid(at, "[lo, hi] with lo < hi"));
            }
        }
        let names = model.task_names();
        if let Some(i) = lower.iter().position(|v| v.is_nan()) {
            return Err(invalid(
                "box",
                format!(
                    "no bounds for `{}`: a {} workspace samples {:?}",
                    names[sampled[i]],
                    self.kind.key(),
                    sampled.iter().map(|&k| names[k]).collect::<Vec<_>>()
                ),
            ));
        }
        for (key, &value) in &self.fixed {
            let (k, scale) = coordinate(model, "fixed", key)?;
            let at = format!("fixed.{key}");
            let quantified = self.kind == WorkspaceKind::Dexterous && model.task_is_angle(k);
            if sampled.contains(&k) || quantified {
                return Err(invalid(
                    at,
                    "this coordinate is not held in this kind (sampled, or set by `orientations`)",
                ));
            }
            base[k] = checked_value(model, &at, value * scale, k)?;
        }
        within_one_turn(model, &sampled, &base, &lower, &upper)?;
        let region = TaskBox::new(lower, upper)?;
        let levels = self.orientation_levels(model)?;
        let margins = MarginLimits {
            inverse: self.min_inverse_margin,
            direct: self.min_direct_margin,
            constraint: self.min_constraint_margin,
        };
        Ok(Setup {
            kind: self.kind,
            sampled,
            region,
            base,
            levels,
            margins,
        })
    }

    /// The nested orientation grids of a dexterous workspace (`None` for another kind).
    fn orientation_levels(
        &self,
        model: &RobotModel,
    ) -> Result<Option<OrientationLevels>, StudyError> {
        let spec = match (&self.orientations, self.kind) {
            (Some(spec), WorkspaceKind::Dexterous) => spec,
            (None, WorkspaceKind::Dexterous) => {
                return Err(invalid(
                    "orientations",
                    "a dexterous workspace needs its orientation set: max_tilt_deg (and \
                     torsion_deg, levels)",
                ));
            }
            (Some(_), kind) => {
                return Err(invalid(
                    "orientations",
                    format!(
                        "an orientation set belongs to a dexterous workspace, not to a {} one",
                        kind.key()
                    ),
                ));
            }
            (None, _) => return Ok(None),
        };
        if !(1..=MAX_ORIENTATION_LEVELS).contains(&spec.levels) {
            return Err(invalid(
                "orientations.levels",
                format!(
                    "{}: 1 to {MAX_ORIENTATION_LEVELS} nested grids",
                    spec.levels
                ),
            ));
        }
        let radians = std::f64::consts::PI / 180.0;
        let torsion = spec.torsion_deg.map(|d| d * radians);
        let set = OrientationSet::new(spec.max_tilt_deg * radians, torsion).map_err(|e| {
            let RobotFileError::Invalid {
                key,
                value,
                requirement,
            } = e
            else {
                return invalid("orientations", e.to_string());
            };
            invalid(
                format!("orientations.{key}_deg"),
                format!("{value} rad: {requirement}"),
            )
        })?;
        Ok(Some(
            model
                .orientation_levels(&set, spec.levels)
                .map_err(located)?,
        ))
    }
}

/// The sampler of `[sampling]` for task points (no `region`, one sector).
fn task_points(sampling: &SamplingSpec, region: TaskBox) -> Result<TaskPoints, StudyError> {
    if sampling.region.is_some() || sampling.symmetry_folds != 1 {
        return Err(StudyError::invalid(
            "sampling",
            "a [task_space] study samples its `box`: [sampling] gives no region and no symmetry \
             sector",
        ));
    }
    let (sampler, points, replicates) = match sampling.sampler {
        SamplerKind::Sobol => (
            Sampler::Sobol {
                seed: sampling.seed,
            },
            sampling.points,
            sampling.replicates,
        ),
        SamplerKind::MonteCarlo => (
            Sampler::MonteCarlo {
                seed: sampling.seed,
            },
            sampling.points,
            sampling.replicates,
        ),
        SamplerKind::Grid => (
            Sampler::Grid {
                per_axis: sampling.per_axis,
            },
            0,
            1,
        ),
    };
    TaskPoints::new(region, sampler, points, replicates).map_err(|e| sampling.count_error(e))
}

/// The measure unit of the sampled coordinates (`m·rad²`).
fn measure_unit(model: &RobotModel, sampled: &[usize]) -> String {
    let lengths = sampled.iter().filter(|&&k| !model.task_is_angle(k)).count();
    let angles = sampled.len() - lengths;
    let power = |base: &str, n: usize| match n {
        0 => None,
        1 => Some(base.to_owned()),
        n => Some(format!(
            "{base}{}",
            ["", "", "²", "³", "⁴", "⁵", "⁶"][n.min(6)]
        )),
    };
    [power("m", lengths), power("rad", angles)]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join("·")
}

/// Runs a workspace study of a robot file in its task space (module documentation).
///
/// # Errors
/// [`StudyError::Invalid`] at the key path of a setting that does not fit the robot (checked
/// before any computation); [`StudyError::Index`] when the estimator refuses its input;
/// [`StudyError::Cancelled`] when `progress` asks to stop.
pub fn workspace(
    robot: &RobotFileSpec,
    spec: &TaskSpaceSpec,
    sampling: &SamplingSpec,
    constraints: &[WorkspaceConstraint],
    progress: &dyn Progress,
) -> Result<Outcome<TaskSpaceRun>, StudyError> {
    let model = robot.model()?;
    let modes = robot.working_modes(&model)?;
    let setup = spec.setup(&model)?;
    let plans = maps::plans(&model, &setup, &spec.maps)?;
    let points = task_points(sampling, setup.region.clone())?;
    let ws = TaskWorkspace::new(&model, &modes, constraints, setup.margins).map_err(located)?;
    let start = singularity_free_start(&model, &setup, spec)?;
    progress.phase("task-space points");
    progress.start("workspace points", points.total());
    let estimates = estimate(&ws, &setup, &points, progress);
    progress.finish();
    let estimates = estimates?;
    let finest = estimates
        .last()
        .ok_or(StudyError::invalid(KEY, "no estimate"))?;
    let mut artifacts = Vec::new();
    let singularity_free = match (&spec.singularity_free, start) {
        (Some(sf), Some(from)) => Some(singularity_free(
            &model,
            &modes,
            constraints,
            &setup,
            sf,
            from,
            progress,
            &mut artifacts,
        )?),
        _ => None,
    };
    progress.phase("maps");
    let mut maps = Vec::with_capacity(plans.len());
    for (k, plan) in plans.iter().enumerate() {
        progress.check()?;
        maps.push(maps::map(&model, &ws, &setup, plan, k + 1, &mut artifacts));
    }
    let names = model.task_names();
    let unit_of = |k: usize| if model.task_is_angle(k) { "rad" } else { "m" };
    let result = TaskSpaceResult {
        kind: setup.kind,
        coordinates: setup
            .sampled
            .iter()
            .map(|&k| format!("{} ({})", names[k], unit_of(k)))
            .collect(),
        unit: measure_unit(&model, &setup.sampled),
        fixed: (0..names.len())
            .filter(|k| !setup.sampled.contains(k))
            .filter(|&k| !(setup.kind == WorkspaceKind::Dexterous && model.task_is_angle(k)))
            .map(|k| (names[k].to_owned(), setup.base[k]))
            .collect(),
        orientation_levels: orientation_level_results(setup.levels.as_ref(), &estimates),
        singularity_free,
        maps,
    };
    let mut outcome = Outcome::new(TaskSpaceRun {
        domain_volume: setup.region.measure(),
        estimate: Estimate::from(finest),
        task_space: result,
    });
    outcome.artifacts = artifacts;
    summarise(&mut outcome);
    outcome.robot(
        format!("{} at home", model.name()),
        home_scene(&model, modes.first().copied()),
    );
    Ok(outcome)
}

/// The estimate(s): one, or one per orientation grid of a dexterous workspace.
fn estimate(
    ws: &TaskWorkspace<'_>,
    setup: &Setup,
    points: &TaskPoints,
    progress: &dyn Progress,
) -> Result<Vec<VolumeEstimate>, StudyError> {
    let estimates = match &setup.levels {
        None => nested_task_volumes(points, 1, progress, |u| {
            match ws.inverse_condition(&setup.pose(u)) {
                Some(f) => (1, Some(f)),
                None => (0, None),
            }
        })?,
        Some(levels) => nested_task_volumes(points, levels.grid_levels.len(), progress, |u| {
            let x = setup.pose(u);
            let held = ws.dexterous_levels(&x, levels);
            let f = (held > 0)
                .then(|| ws.dexterous_inverse_condition(&x, levels))
                .flatten();
            (held, f)
        })?,
    };
    Ok(estimates)
}

fn orientation_level_results(
    levels: Option<&OrientationLevels>,
    estimates: &[VolumeEstimate],
) -> Vec<OrientationLevelResult> {
    let Some(levels) = levels else {
        return Vec::new();
    };
    levels
        .grid_levels
        .iter()
        .zip(&levels.orientations)
        .zip(estimates)
        .map(|((&grid_level, &orientations), e)| OrientationLevelResult {
            grid_level,
            orientations,
            volume: e.volume,
            volume_se: e.volume_se,
        })
        .collect()
}

/// The start of the singularity-free search in sampled coordinates (home unless `from`).
fn singularity_free_start(
    model: &RobotModel,
    setup: &Setup,
    spec: &TaskSpaceSpec,
) -> Result<Option<Vec<f64>>, StudyError> {
    let Some(sf) = &spec.singularity_free else {
        return Ok(None);
    };
    if !(sf.min_direct_margin.is_finite() && sf.min_direct_margin >= 0.0) {
        return Err(invalid(
            "singularity_free.min_direct_margin",
            format!("{}: a finite margin of at least 0", sf.min_direct_margin),
        ));
    }
    if !(2..=4096).contains(&sf.cells) {
        return Err(invalid(
            "singularity_free.cells",
            format!("{}: 2 to 4096 cells per side", sf.cells),
        ));
    }
    let mut start: Vec<f64> = setup.sampled.iter().map(|&k| setup.base[k]).collect();
    for (key, &value) in &sf.from {
        let (k, scale) = coordinate(model, "singularity_free.from", key)?;
        let at = format!("singularity_free.from.{key}");
        let i = setup
            .sampled
            .iter()
            .position(|&s| s == k)
            .ok_or_else(|| invalid(&at, "the start gives sampled coordinates only"))?;
        start[i] = checked_value(model, &at, value * scale, k)?;
    }
    let inside = start
        .iter()
        .zip(setup.region.lower().iter().zip(setup.region.upper()))
        .all(|(v, (lo, hi))| lo <= v && v <= hi);
    if !inside {
        return Err(invalid(
            "singularity_free.from",
            format!("the start {start:?} (m, rad) lies outside the box"),
        ));
    }
    Ok(Some(start))
}

/// The singularity-free workspace connected to `from` and its figure.
#[allow(clippy::too_many_arguments)]
fn singularity_free(
    model: &RobotModel,
    modes: &[WorkingMode],
    constraints: &[WorkspaceConstraint],
    setup: &Setup,
    sf: &SingularityFreeSpec,
    from: Vec<f64>,
    progress: &dyn Progress,
    artifacts: &mut Vec<Artifact>,
) -> Result<SingularityFreeResult, StudyError> {
    let ws = singularity_free_workspace(model, modes, constraints, setup, sf)?;
    progress.phase("singularity-free region");
    let connected = connected_region(&ws, setup, sf, &from, progress)?;
    let svg = (setup.sampled.len() >= 2).then(|| {
        let name = "singularity-free.svg".to_owned();
        artifacts.push(Artifact::Chart {
            name: name.clone(),
            chart: Box::new(singularity_free_chart(model, setup, sf, &from, &ws)),
        });
        name
    });
    Ok(SingularityFreeResult {
        min_direct_margin: sf.min_direct_margin,
        cells: sf.cells,
        from,
        volume_above_margin: connected.volume_inside,
        volume_connected: connected.volume_connected,
        svg,
    })
}

/// The workspace of `setup` with the direct margin of `sf` (or the setup's own, if larger).
fn singularity_free_workspace<'m>(
    model: &'m RobotModel,
    modes: &[WorkingMode],
    constraints: &[WorkspaceConstraint],
    setup: &Setup,
    sf: &SingularityFreeSpec,
) -> Result<TaskWorkspace<'m>, StudyError> {
    let margins = MarginLimits {
        direct: Some(
            setup
                .margins
                .direct
                .map_or(sf.min_direct_margin, |d| d.max(sf.min_direct_margin)),
        ),
        ..setup.margins
    };
    TaskWorkspace::new(model, modes, constraints, margins).map_err(located)
}

/// The cells of `ws` (every orientation of the set held, for a dexterous workspace) connected
/// to `from` on the grid of `sf` ([`connected_task_volume`]).
fn connected_region(
    ws: &TaskWorkspace<'_>,
    setup: &Setup,
    sf: &SingularityFreeSpec,
    from: &[f64],
    progress: &dyn Progress,
) -> Result<ConnectedVolume, StudyError> {
    let member = |u: &[f64]| {
        let x = setup.pose(u);
        match &setup.levels {
            None => ws.contains(&x),
            Some(levels) => ws.dexterous_levels(&x, levels) == levels.grid_levels.len(),
        }
    };
    Ok(connected_task_volume(
        &setup.region,
        sf.cells,
        from,
        progress,
        member,
    )?)
}

/// The direct margin on the plane of the first two sampled coordinates through the start
/// (blank outside the workspace), on the search grid's cells.
fn singularity_free_chart(
    model: &RobotModel,
    setup: &Setup,
    sf: &SingularityFreeSpec,
    from: &[f64],
    ws: &TaskWorkspace<'_>,
) -> Chart {
    let n = sf.cells.min(96) as usize;
    let axis = |i: usize| -> Vec<f64> {
        let (lo, hi) = (setup.region.lower()[i], setup.region.upper()[i]);
        (0..n)
            .map(|c| lo + (hi - lo) * (c as f64 + 0.5) / n as f64)
            .collect()
    };
    let (u, v) = (axis(0), axis(1));
    let mut values = Vec::with_capacity(n * n);
    let mut point = from.to_vec();
    for &b in &v {
        for &a in &u {
            point[0] = a;
            point[1] = b;
            values.push(ws.margins(&setup.pose(&point)).map(|m| m.direct));
        }
    }
    let names = model.task_names();
    let label = |i: usize| {
        let k = setup.sampled[i];
        format!(
            "{} ({})",
            names[k],
            if model.task_is_angle(k) { "rad" } else { "m" }
        )
    };
    let field = chart::Heatmap {
        colour_axis: "direct margin".into(),
        x: u,
        y: v,
        values,
    };
    let title = format!(
        "direct singularity margin ≥ {} through the start",
        sf.min_direct_margin
    );
    Chart::heatmap(title, label(0), label(1), field)
}

/// The drawing of `robot` at its home pose in its first working mode, or why there is none.
pub(crate) fn robot_at_home(robot: &RobotFileSpec) -> Result<Scene, String> {
    let model = robot.model().map_err(|e| e.to_string())?;
    let modes = robot.working_modes(&model).map_err(|e| e.to_string())?;
    home_scene(&model, modes.first().copied())
}

fn home_scene(model: &RobotModel, mode: Option<WorkingMode>) -> Result<Scene, String> {
    let mode = mode.ok_or("no working mode")?;
    let config = model
        .inverse_kinematics_configuration(&model.home_task(), mode)
        .map_err(|e| format!("the robot at home: {e}"))?;
    Ok(Scene::new(robot_skeleton(model, &config)))
}

fn summarise(outcome: &mut Outcome<TaskSpaceRun>) {
    let r = &outcome.result;
    let (t, e) = (&r.task_space, &r.estimate);
    let mut lines = vec![
        format!(
            "{} workspace in ({}): W = {:.6e} ± {:.2e} {u}, η = {:.6e} ± {:.2e} {u}, GCI = {}",
            t.kind.key(),
            t.coordinates.join(", "),
            e.volume,
            e.volume_se,
            e.eta,
            e.eta_se,
            e.gci.map_or("-".into(), |g| format!("{g:.5}")),
            u = t.unit,
        ),
        format!(
            "{} of {} points inside ({}); box {:.6e} {}",
            e.n_inside, e.n_points, e.error_model, r.domain_volume, t.unit
        ),
    ];
    for level in &t.orientation_levels {
        lines.push(format!(
            "orientation grid level {} ({} orientations): W = {:.6e} ± {:.2e} {}",
            level.grid_level, level.orientations, level.volume, level.volume_se, t.unit
        ));
    }
    if let Some(sf) = &t.singularity_free {
        lines.push(format!(
            "singularity-free (direct margin ≥ {}, {} cells per side): {:.6e} {} connected to the start, {:.6e} above the margin",
            sf.min_direct_margin, sf.cells, sf.volume_connected, t.unit, sf.volume_above_margin
        ));
    }
    lines.extend(e.resolution_warning(r.domain_volume, &t.unit));
    for map in &t.maps {
        lines.push(format!(
            "map of {} over ({}): {:.1} % inside, largest {}",
            map.index_key(),
            map.axes.join(", "),
            100.0 * map.inside_fraction,
            map.max_value.map_or("-".into(), |v| format!("{v:.4}"))
        ));
    }
    outcome.summary.extend(lines);
}

/// W and η of the designs of a grid study in a robot file's task space: the `[task_space]`
/// section checked on the base design, and its common points (the same for every design, so
/// the designs are compared on common random numbers).
#[derive(Debug, Clone)]
pub struct TaskSpaceEvaluator {
    spec: TaskSpaceSpec,
    points: TaskPoints,
    unit: String,
}

impl TaskSpaceEvaluator {
    /// The evaluator of `spec` with the points of `sampling`, checked on the base design
    /// `robot`.
    ///
    /// # Errors
    /// As [`workspace`]: a setting that does not fit the base design, at its key path.
    pub fn new(
        robot: &RobotFileSpec,
        spec: &TaskSpaceSpec,
        sampling: &SamplingSpec,
    ) -> Result<Self, StudyError> {
        if !spec.maps.is_empty() {
            let m = "maps belong to a workspace study of one design";
            return Err(invalid("maps", m));
        }
        let model = robot.model()?;
        let setup = spec.setup(&model)?;
        singularity_free_start(&model, &setup, spec)?;
        let unit = measure_unit(&model, &setup.sampled);
        let points = task_points(sampling, setup.region)?;
        Ok(Self {
            spec: spec.clone(),
            points,
            unit,
        })
    }

    /// The unit of the volume and η (`m·rad²`), the base design's.
    pub fn unit(&self) -> &str {
        &self.unit
    }

    /// The indices of the design `robot` under `constraints` (the singularity-free volume
    /// only when `with_singularity_free`), or why the design has none (its model or its
    /// settings refused).
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at `task_space.singularity_free` when it is asked for and the
    /// section has none; [`StudyError::Cancelled`] when `progress` asks to stop, an estimator
    /// error.
    pub fn indices(
        &self,
        robot: &RobotFileSpec,
        constraints: &[WorkspaceConstraint],
        with_singularity_free: bool,
        progress: &dyn Progress,
    ) -> Result<Result<TaskSpaceIndices, Infeasible>, StudyError> {
        let sf = match (&self.spec.singularity_free, with_singularity_free) {
            (Some(sf), true) => Some(sf),
            (None, true) => return Err(invalid("singularity_free", NO_SINGULARITY_FREE)),
            (_, false) => None,
        };
        let design = || -> Result<_, StudyError> {
            let model = robot.model()?;
            let modes = robot.working_modes(&model)?;
            let setup = self.spec.setup(&model)?;
            let start = singularity_free_start(&model, &setup, &self.spec)?;
            Ok((model, modes, setup, start))
        };
        let (model, modes, setup, start) = match design() {
            Ok(design) => design,
            Err(e) => return Ok(Err(Infeasible::robot_file(e))),
        };
        let ws = match TaskWorkspace::new(&model, &modes, constraints, setup.margins) {
            Ok(ws) => ws,
            Err(e) => return Ok(Err(Infeasible::robot_file(located(e)))),
        };
        let estimates = estimate(&ws, &setup, &self.points, progress)?;
        let Some(finest) = estimates.last() else {
            return Err(invalid(
                "orientations",
                "no orientation grid to estimate on",
            ));
        };
        let singularity_free_volume = match (sf, start) {
            (Some(sf), Some(from)) => {
                let ws = singularity_free_workspace(&model, &modes, constraints, &setup, sf)?;
                Some(connected_region(&ws, &setup, sf, &from, progress)?.volume_connected)
            }
            _ => None,
        };
        Ok(Ok(TaskSpaceIndices {
            volume: finest.volume,
            eta: finest.eta.unwrap_or(0.0),
            gci: finest.gci(),
            singularity_free_volume,
        }))
    }
}

/// The refusal of a singularity-free objective without its section.
const NO_SINGULARITY_FREE: &str = "the singularity-free volume needs \
    [task_space.singularity_free] with its min_direct_margin";

/// The indices of one design in its task space (units: [`TaskSpaceResult::unit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskSpaceIndices {
    /// The measure W of the workspace.
    pub volume: f64,
    /// η = ∫ 1/κ dW.
    pub eta: f64,
    /// GCI = η/W; `None` for an empty workspace.
    pub gci: Option<f64>,
    /// The singularity-free volume connected to the start, when asked for.
    pub singularity_free_volume: Option<f64>,
}
