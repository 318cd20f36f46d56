//! The task study: task-based synthesis after Wolf & Shoham (2006): the pose and/or geometry of
//! a Stewart–Gough platform or a 3-UPU that maximises or minimises
//! $F = \sum_k w_k \sum_i (L_i \wedge \chi_k)^2$ (eq. 14, 18) for a weighted set of task twists
//! $\chi_k$, by multistart bounded Levenberg–Marquardt with its first- and second-order report;
//! and, for the 3-UPU, the singularity search: the pose or geometry that minimises the smallest
//! singular value (or the determinant) of the $6 \times 6$ matrix of eq. 18 (three leg lines,
//! three constraint couples).
//!
//! Weighted twists enter as the stacked residuals $\sqrt{w_k}\,(L_i \wedge \chi_k)$
//! ([`pkm_optimizers::WeightedSum`]), so the sum of squares is $F$, and one twist of weight 1
//! is exactly the library's problem.
//!
//! Every setting (twists, variables and their ranges, the orientation bound, the solver, the
//! starts) is checked at its key path before the first start runs.

mod problem;
mod report;
mod robot_file;
mod schema;

pub use pkm_design_problems::upu::UPU_VARIABLES;
pub use problem::{STEWART_VARIABLES, stewart_problem, upu_problem};
pub use report::{
    Optimality, PoseReport, TaskResult, TwistValue, WrenchMatrix, most_reciprocal_twist,
};
pub use schema::{Goal, PoseSpec, TaskSection, TaskStudy, TwistSpec, TwistSpecError};

use crate::outcome::Outcome;
use crate::registry::StudyMechanism;
use crate::schema::mechanism::{MechanismSpec, StewartSpec, ThreeUpuSpec};
use crate::schema::robot_file::RobotFileSpec;
use crate::{KeyPath, StudyError, scene};
use nalgebra::{DMatrix, Isometry3, Matrix6};
use pkm_draw::Scene;
use pkm_mechanisms::{Skeleton, StewartDesign, StewartGough, WrenchSystem};
use pkm_optimizers::{
    LocalOptimum, MultistartRun, OptimizeError, Sense, WeightedSum, levenberg_marquardt, multistart,
};
use pkm_screw_theory::Twist;
use pkm_traits::{Bounds, Objective, Progress, Residuals};
use report::{starts_artifacts, summarise, wrench_matrix};
use std::collections::BTreeMap;

/// A mechanism with a wrench system (`pkm_mechanisms::WrenchSystem`): the part of a task study
/// that depends on it. The default refuses at `mechanism`; the Stewart–Gough platform (six leg
/// lines) and the 3-UPU (three leg lines, three constraint couples) run their problems.
///
/// It is a trait of its own, not a method of [`StudyMechanism`], because its types are the task
/// study's and the registry sits below the study kinds. A registry takes part with one impl:
/// `impl TaskMechanism for MyMechanisms {}` refuses every kind, or delegate to the kinds that
/// have a wrench system (as [`MechanismSpec`] does).
pub trait TaskMechanism: StudyMechanism {
    /// The multistart over this mechanism's task problem for `task` and its `twists` (checked),
    /// and its report (without the study's title).
    ///
    /// # Errors
    /// As [`task`]; the default: this mechanism has no wrench system.
    fn task_run(
        &self,
        task: &TaskSection,
        twists: &[(f64, Twist)],
        progress: &dyn Progress,
    ) -> Result<TaskRun, StudyError> {
        let _ = (task, twists, progress);
        Err(no_wrench_system(self.kind(), ""))
    }
}

/// The refusal of a mechanism without a wrench system (`hint`: which kinds have one).
fn no_wrench_system(kind: &str, hint: &str) -> StudyError {
    let message = format!("{kind} has no wrench system for a task study{hint}");
    StudyError::invalid("mechanism", message)
}

impl TaskMechanism for MechanismSpec {
    fn task_run(
        &self,
        task: &TaskSection,
        twists: &[(f64, Twist)],
        progress: &dyn Progress,
    ) -> Result<TaskRun, StudyError> {
        match self {
            Self::StewartGough(spec) => spec.task_run(task, twists, progress),
            Self::ThreeUpu(spec) => spec.task_run(task, twists, progress),
            Self::RobotFile(spec) => spec.task_run(task, twists, progress),
            other => Err(no_wrench_system(
                other.kind(),
                ": expected [mechanism.stewart_gough], [mechanism.three_upu] or \
                 [mechanism.robot_file]",
            )),
        }
    }
}

impl TaskMechanism for StewartSpec {
    fn task_run(
        &self,
        task: &TaskSection,
        twists: &[(f64, Twist)],
        progress: &dyn Progress,
    ) -> Result<TaskRun, StudyError> {
        stewart(self, task, twists, progress)
    }
}

impl TaskMechanism for RobotFileSpec {
    fn task_run(
        &self,
        task: &TaskSection,
        twists: &[(f64, Twist)],
        progress: &dyn Progress,
    ) -> Result<TaskRun, StudyError> {
        robot_file::robot_file_task(self, task, twists, progress)
    }
}

impl TaskMechanism for ThreeUpuSpec {
    fn task_run(
        &self,
        task: &TaskSection,
        twists: &[(f64, Twist)],
        progress: &dyn Progress,
    ) -> Result<TaskRun, StudyError> {
        upu(self, task, twists, progress)
    }
}

/// Runs a task study: the multistart, the report at the best start, the starts as a table and
/// a chart, and the drawing of the robot at the optimal pose with the task twists' axes.
///
/// # Errors
/// [`StudyError::Invalid`] at its key path for a setting that cannot be used (every one checked
/// before the first start) or at `mechanism` for a mechanism without a wrench system;
/// [`StudyError::Optimize`] when no start succeeds; [`StudyError::Cancelled`] when `progress`
/// asks to stop.
pub fn task<M: TaskMechanism>(
    study: &TaskStudy<M>,
    progress: &dyn Progress,
) -> Result<Outcome<TaskResult>, StudyError> {
    if study.mechanism.robot_file().is_none() && !study.task.at.is_empty() {
        let m = "`at` gives a robot file's nominal pose by task coordinate; use [task.pose]";
        return Err(StudyError::invalid("task.at", m));
    }
    let twists = weighted_twists(&study.task)?;
    let mut found = study.mechanism.task_run(&study.task, &twists, progress)?;
    found.result.title.clone_from(&study.title);
    let mut outcome = Outcome::new(found.result);
    summarise(&mut outcome);
    let artifacts = starts_artifacts(&found.names, &outcome.result, &found.run);
    outcome.artifacts.extend(artifacts);
    let caption = format!("{}: the optimal pose", outcome.result.mechanism);
    outcome.robot(caption, found.scene);
    Ok(outcome)
}

/// What one mechanism's run found, before the common report.
#[derive(Debug)]
pub struct TaskRun {
    /// The optimised variables, in design-vector order.
    pub names: Vec<String>,
    /// Every start's outcome.
    pub run: MultistartRun<LocalOptimum>,
    /// The result (its title is the study's, set by [`task`]).
    pub result: TaskResult,
    /// The robot at the optimal pose with the task twists' axes.
    pub scene: Result<Scene, String>,
}

/// The study's weighted twists, each checked at its `task.twists[k]` entry, and their presence
/// checked against the goal.
fn weighted_twists(task: &TaskSection) -> Result<Vec<(f64, Twist)>, StudyError> {
    let twists = task
        .twists
        .iter()
        .enumerate()
        .map(|(k, spec)| {
            let path = KeyPath::parse("task.twists").index(k);
            if !(spec.weight.0 >= 0.0) {
                return Err(StudyError::invalid(
                    path.field("weight"),
                    "expected a number >= 0",
                ));
            }
            let twist = spec
                .twist()
                .map_err(|e| StudyError::invalid(path, e.to_string()))?;
            Ok((spec.weight.0, twist))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if task.goal.is_singularity() != twists.is_empty() {
        let message = if twists.is_empty() {
            "goal = maximise/minimise needs at least one [[task.twists]]"
        } else {
            "a singularity goal takes no [[task.twists]]"
        };
        return Err(StudyError::invalid("task.goal", message));
    }
    Ok(twists)
}

/// The optimised variables of a study among `names`, each with its range, in `names` order;
/// each error at its `task.variables.<name>` key.
fn chosen_variables(
    task: &TaskSection,
    names: &[&str],
) -> Result<Vec<(usize, Bounds)>, StudyError> {
    let mut chosen = Vec::new();
    for (name, [lo, hi]) in &task.variables {
        let path = KeyPath::parse("task.variables").field(name.as_str());
        let k = names.iter().position(|n| n == name).ok_or_else(|| {
            let message = format!(
                "unknown variable `{name}` for this mechanism: expected one of {} (lengths in m, \
                 *_deg in degrees)",
                names.join(", ")
            );
            StudyError::invalid(path.clone(), message)
        })?;
        let bounds = crate::starts::variable_bounds(path, name, *lo, *hi)?;
        chosen.push((k, bounds));
    }
    chosen.sort_by_key(|(k, _)| *k);
    Ok(chosen)
}

/// An optimiser's refusal of the setting at `section` as an error at its key path (the
/// setting's own name appended).
fn refused(section: &str, e: OptimizeError) -> StudyError {
    match e {
        OptimizeError::Invalid(invalid) => {
            let path = KeyPath::parse(section).field(invalid.name);
            StudyError::invalid(path, invalid.to_string())
        }
        e => StudyError::invalid(section, e.to_string()),
    }
}

/// The solver settings and the start points, checked (before any start runs).
fn checked_starts(task: &TaskSection, bounds: &[Bounds]) -> Result<Vec<Vec<f64>>, StudyError> {
    if bounds.is_empty() {
        return Err(StudyError::invalid(
            "task.variables",
            "no variable to optimise",
        ));
    }
    task.solver
        .validate()
        .map_err(|e| refused("task.solver", e))?;
    task.starts
        .start_points(bounds)
        .map_err(|e| refused("task.starts", e))
}

/// Levenberg–Marquardt from every start, every outcome kept; the best start.
///
/// # Errors
/// No successful start, [`StudyError::Cancelled`].
fn run_starts<P: Residuals>(
    problem: &P,
    sense: Sense,
    task: &TaskSection,
    starts: Vec<Vec<f64>>,
    progress: &dyn Progress,
) -> Result<(MultistartRun<LocalOptimum>, usize, LocalOptimum), StudyError> {
    let settings = &task.solver;
    let run = multistart(starts, progress, |s, cancel| {
        levenberg_marquardt(problem, sense, s, settings, cancel)
    })?;
    let (best_start, best) = run.best(sense)?;
    let best = best.clone();
    Ok((run, best_start, best))
}

/// Each twist's $F$ at `pose` of `mechanism`.
fn twist_values(
    mechanism: &impl WrenchSystem,
    pose: &Isometry3<f64>,
    twists: &[(f64, Twist)],
) -> Result<Vec<TwistValue>, StudyError> {
    twists
        .iter()
        .map(|(w, t)| {
            Ok(TwistValue {
                weight: *w,
                f: task_f(mechanism, pose, t)?,
            })
        })
        .collect()
}

/// $F$ of `twist` at `pose` of `mechanism` (eq. 12 of Wolf & Shoham).
fn task_f(
    mechanism: &impl WrenchSystem,
    pose: &Isometry3<f64>,
    twist: &Twist,
) -> Result<f64, StudyError> {
    Ok(mechanism
        .task_objective(pose, twist)
        .map_err(pkm_traits::ObjectiveError::from)?)
}

/// `names` paired with `values`, as the result's maps hold them.
fn named<'a>(
    names: impl IntoIterator<Item = &'a str>,
    values: impl IntoIterator<Item = f64>,
) -> BTreeMap<String, f64> {
    names.into_iter().map(str::to_owned).zip(values).collect()
}

fn stewart(
    spec: &StewartSpec,
    task: &TaskSection,
    twists: &[(f64, Twist)],
    progress: &dyn Progress,
) -> Result<TaskRun, StudyError> {
    if spec.rotation_deg.iter().any(|w| w.0.abs() > 0.0) {
        return Err(StudyError::invalid(
            "mechanism.stewart_gough.rotation_deg",
            "a task study takes the platform's orientation from [task.pose] rotation_deg and \
             max_angle_deg: expected no rotation here",
        ));
    }
    if task.goal.is_singularity() {
        return Err(StudyError::invalid(
            "task.goal",
            "the singularity goals are for [mechanism.three_upu]",
        ));
    }
    let free = chosen_variables(task, &STEWART_VARIABLES)?;
    let max_angle = task.max_angle_deg.map(|a| a.radians());
    let parts = twists
        .iter()
        .map(|(w, t)| Ok((*w, stewart_problem(spec, &task.pose, &free, max_angle, *t)?)))
        .collect::<Result<Vec<_>, StudyError>>()?;
    let problem = WeightedSum::new(parts).map_err(|e| refused("task.twists", e))?;
    let starts = checked_starts(task, problem.bounds())?;
    let sense = task.goal.sense();
    let (run, best_start, best) = run_starts(&problem, sense, task, starts, progress)?;
    let (mechanism, pose) = match problem.parts().next() {
        Some((_, first)) => first.evaluate(&best.design)?,
        None => return Err(StudyError::invalid("task.twists", "no twist")),
    };
    let mut names: Vec<String> = free
        .iter()
        .map(|(k, _)| STEWART_VARIABLES[*k].to_owned())
        .collect();
    if max_angle.is_some() {
        names.extend(["u_x", "u_y", "u_z"].map(str::to_owned));
    }
    let result = TaskResult {
        title: None,
        mechanism: "stewart_gough".into(),
        goal: task.goal,
        objective: best.value,
        best_start,
        optimum: named(
            names.iter().map(String::as_str),
            best.design.iter().copied(),
        ),
        design: named(
            STEWART_VARIABLES[..4].iter().copied(),
            stewart_design_values(&mechanism.design()),
        ),
        pose: PoseReport::from(&pose),
        twists: twist_values(&mechanism, &pose, twists)?,
        leg_lengths: Some(leg_lengths(&mechanism, &pose)),
        wrench_matrix: wrench_matrix(&dynamic(&objective_rows(&mechanism, &pose)?), |t| {
            task_f(&mechanism, &pose, t)
        })?,
        optimality: Optimality::from(&best),
        starts: run.starts.len(),
    };
    let scene = scene::task_scene(
        Skeleton::stewart_gough(&mechanism, &pose),
        &pose,
        twists,
        None,
    );
    Ok(TaskRun {
        names,
        run,
        result,
        scene,
    })
}

/// The wrench rows of `mechanism` at `pose`.
fn objective_rows(
    mechanism: &impl WrenchSystem,
    pose: &Isometry3<f64>,
) -> Result<Matrix6<f64>, StudyError> {
    Ok(mechanism
        .wrench_rows(pose)
        .map_err(pkm_traits::ObjectiveError::from)?)
}

/// The rows of a 6 × 6 wrench matrix as the report takes them.
fn dynamic(rows: &Matrix6<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(6, 6, |i, j| rows[(i, j)])
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
    spec: &ThreeUpuSpec,
    task: &TaskSection,
    twists: &[(f64, Twist)],
    progress: &dyn Progress,
) -> Result<TaskRun, StudyError> {
    if task.max_angle_deg.is_some() {
        return Err(StudyError::invalid(
            "task.max_angle_deg",
            "max_angle_deg is for [mechanism.stewart_gough]; free the 3-UPU's orientation with \
             rx_deg, ry_deg, rz_deg in [task.variables]",
        ));
    }
    let free = chosen_variables(task, &UPU_VARIABLES)?;
    let problem = upu_problem(spec, &task.pose, &free, task.goal, twists);
    let starts = checked_starts(task, problem.bounds())?;
    let sense = task.goal.sense();
    let (run, best_start, best) = run_starts(&problem, sense, task, starts, progress)?;
    let (mechanism, pose) = problem.evaluate(&best.design)?;
    let rows = objective_rows(&mechanism, &pose)?;
    let names: Vec<String> = free
        .iter()
        .map(|(k, _)| UPU_VARIABLES[*k].to_owned())
        .collect();
    let all = problem.full(&best.design);
    let result = TaskResult {
        title: None,
        mechanism: "three_upu".into(),
        goal: task.goal,
        objective: best.value,
        best_start,
        optimum: named(
            names.iter().map(String::as_str),
            best.design.iter().copied(),
        ),
        design: named(UPU_VARIABLES[..8].iter().copied(), all),
        pose: PoseReport::from(&pose),
        twists: twist_values(&mechanism, &pose, twists)?,
        leg_lengths: None,
        wrench_matrix: wrench_matrix(&dynamic(&rows), |t| task_f(&mechanism, &pose, t))?,
        optimality: Optimality::from(&best),
        starts: run.starts.len(),
    };
    let reciprocal = most_reciprocal_twist(&rows);
    let scene = scene::task_scene(
        Skeleton::three_upu(&mechanism, &pose),
        &pose,
        twists,
        reciprocal,
    );
    Ok(TaskRun {
        names,
        run,
        result,
        scene,
    })
}
