//! The task study of a robot file: Wolf & Shoham's objective (2006, eq. 12–14)
//! $F = \sum_k w_k \sum_i (W_i \wedge \chi_k)^2$ over the rows $W_i$ of the robot's wrench
//! system at a pose, its actuation wrenches $J_a$ and every leg's constraint wrenches $J_c$
//! (`pkm_robot_file::ScrewJacobians`: unit forces, or unit couples), or the singularity goals
//! on the same rows ($\sigma_{min}$ of the stacked rows, $\det$ when there are six). For the
//! Stewart–Gough platform the rows are its six unit leg lines and $F$ is the hand-written
//! model's; for a 3-UPU three leg lines and three constraint couples, the matrix of eq. 18.
//!
//! The variables are task coordinates of the robot (by name, angles as `<name>_deg`) and
//! parameters of the file (`[parameters]`, a design changed at every evaluation); the others
//! hold the nominal pose (`[task] at`, by default home) and the file's values. The pose is
//! assembled in the study's first working mode.

use super::report::{Optimality, PoseReport, TaskResult, TwistValue};
use super::{TaskRun, TaskSection, checked_starts, named, run_starts, wrench_matrix};
use crate::registry::StudyMechanism;
use crate::schema::robot_file::{RobotFileSpec, robot_skeleton};
use crate::task::schema::{Goal, PoseSpec};
use crate::task_space::task_coordinate;
use crate::{KeyPath, StudyError, scene};
use nalgebra::{DMatrix, Vector6};
use pkm_robot_file::{Configuration, RobotModel, WorkingMode, platform_pose};
use pkm_screw_theory::Twist;
use pkm_screw_theory::most_reciprocal_twist;
use pkm_traits::{Bounds, Objective, ObjectiveError, Progress, Residuals};

/// A variable of the problem.
#[derive(Debug, Clone)]
enum Variable {
    /// Task coordinate `k`, in the study's unit times `scale` (radians per degree for angles).
    Task { k: usize, scale: f64 },
    /// A parameter of the file, by name.
    Parameter(String),
}

/// What the residuals are.
#[derive(Debug, Clone)]
enum Goal6 {
    /// For every twist $k$ and row $i$ the six numbers
    /// $\sqrt{w_k}\,(W_i \wedge \chi_k)\,W_i/\lVert W_i\rVert$, whose squares sum to
    /// $w_k (W_i \wedge \chi_k)^2$: the sign of a wrench row is arbitrary (a null space of an
    /// SVD), and this block does not change with it, so the residuals are continuous in the
    /// variables and finite differences of them are meaningful. $\sqrt{w_k}$ is stored beside
    /// $\chi_k = [\omega; v]$.
    Task(Vec<(f64, Vector6<f64>)>),
    /// $\sigma_{min}$ of the rows.
    SigmaMin,
    /// $\det$ of the six rows.
    Det,
}

/// The robot at one design and pose: its model, the configuration and the wrench rows.
struct Evaluated {
    model: RobotModel,
    config: Configuration,
    rows: DMatrix<f64>,
}

/// The task problem of a robot file over its chosen variables.
struct RobotFileTask<'a> {
    base: &'a RobotFileSpec,
    names: Vec<String>,
    variables: Vec<Variable>,
    bounds: Vec<Bounds>,
    nominal: Vec<f64>,
    goal: Goal6,
    rows: usize,
}

impl RobotFileTask<'_> {
    /// The file and the task coordinates (radians) at `x`.
    fn at(&self, x: &[f64]) -> Result<(RobotFileSpec, Vec<f64>), String> {
        let mut robot = self.base.clone();
        let mut task = self.nominal.clone();
        for (variable, value) in self.variables.iter().zip(x) {
            match variable {
                Variable::Task { k, scale } => task[*k] = value * scale,
                Variable::Parameter(name) => robot.set(name, *value)?,
            }
        }
        Ok((robot, task))
    }

    /// The robot at `x`, or why it cannot be evaluated there.
    fn evaluate(&self, x: &[f64]) -> Result<Evaluated, ObjectiveError> {
        let infeasible = |e: &dyn std::fmt::Display| ObjectiveError::infeasible(e.to_string());
        let (robot, task) = self.at(x).map_err(|e| infeasible(&e))?;
        let model = robot.model().map_err(|e| infeasible(&e))?;
        let mode = first_mode(&robot, &model).map_err(|e| infeasible(&e))?;
        let config = model
            .inverse_kinematics_configuration(&task, mode)
            .map_err(|e| infeasible(&e))?;
        let jacobians = model.screw_jacobians(&config).map_err(|e| infeasible(&e))?;
        let (a, c) = (&jacobians.j_a, &jacobians.j_c);
        let rows = DMatrix::from_fn(a.nrows() + c.nrows(), 6, |i, j| {
            if i < a.nrows() {
                a[(i, j)]
            } else {
                c[(i - a.nrows(), j)]
            }
        });
        Ok(Evaluated {
            model,
            config,
            rows,
        })
    }
}

/// The study's first working mode of `robot`.
fn first_mode(robot: &RobotFileSpec, model: &RobotModel) -> Result<WorkingMode, StudyError> {
    let modes = robot.working_modes(model)?;
    modes
        .first()
        .copied()
        .ok_or_else(|| StudyError::invalid("mechanism.robot_file.modes", "no working mode"))
}

/// $W \wedge \chi = f \cdot v + m \cdot \omega$ for the wrench $W = [f; m]$ and the twist
/// $\chi = [\omega; v]$.
fn reciprocal(row: &[f64], twist: &Vector6<f64>) -> f64 {
    (0..3)
        .map(|j| row[j] * twist[3 + j] + row[3 + j] * twist[j])
        .sum()
}

impl Objective for RobotFileTask<'_> {
    fn dimension(&self) -> usize {
        self.variables.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        self.sum_of_squares(x)
    }
}

impl Residuals for RobotFileTask<'_> {
    fn n_residuals(&self) -> usize {
        match &self.goal {
            Goal6::Task(twists) => 6 * twists.len() * self.rows,
            Goal6::SigmaMin | Goal6::Det => 1,
        }
    }

    fn residuals(&self, x: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        self.check_dimension(x)?;
        let rows = self.evaluate(x)?.rows;
        if rows.nrows() != self.rows {
            let m = format!(
                "{} wrench rows here, {} at the nominal pose (a change of the constraint system)",
                rows.nrows(),
                self.rows
            );
            return Err(ObjectiveError::infeasible(m));
        }
        match &self.goal {
            Goal6::Task(twists) => {
                let blocks = r.chunks_exact_mut(6);
                let pairs = twists
                    .iter()
                    .flat_map(|t| rows.row_iter().map(move |w| (t, w)));
                for (block, ((root_w, chi), w)) in blocks.zip(pairs) {
                    let w: Vec<f64> = w.iter().copied().collect();
                    let norm = w.iter().map(|v| v * v).sum::<f64>().sqrt();
                    let scale = root_w * reciprocal(&w, chi) / norm;
                    for (slot, wj) in block.iter_mut().zip(&w) {
                        *slot = scale * wj;
                    }
                }
            }
            Goal6::SigmaMin => {
                let (sigma, _) = most_reciprocal_twist(&rows)
                    .ok_or_else(|| ObjectiveError::infeasible("the SVD did not converge"))?;
                r[0] = sigma;
            }
            Goal6::Det => r[0] = rows.determinant(),
        }
        Ok(())
    }
}

/// The variables of `task` (task coordinates or parameters) with their bounds, in the order of
/// `[task.variables]`.
fn variables(
    robot: &RobotFileSpec,
    model: &RobotModel,
    task: &TaskSection,
) -> Result<Vec<(String, Variable, Bounds)>, StudyError> {
    let mut chosen = Vec::new();
    for (name, [lo, hi]) in &task.variables {
        let path = KeyPath::parse("task.variables").field(name.as_str());
        let variable = if robot.get(name).is_some() {
            Variable::Parameter(name.clone())
        } else {
            let (k, scale) = task_coordinate(model, "task.variables", name).map_err(|_| {
                let m = format!(
                    "`{name}` is neither a task coordinate of the robot ({:?}; angles as \
                     <name>_deg) nor one of its [parameters]",
                    model.task_names()
                );
                StudyError::invalid(path.clone(), m)
            })?;
            Variable::Task { k, scale }
        };
        let bounds = crate::starts::variable_bounds(path, name, *lo, *hi)?;
        chosen.push((name.clone(), variable, bounds));
    }
    Ok(chosen)
}

/// The nominal task coordinates: home, with the study's `at` values.
fn nominal(model: &RobotModel, task: &TaskSection) -> Result<Vec<f64>, StudyError> {
    let mut x = model.home_task();
    for (name, value) in &task.at {
        let (k, scale) = task_coordinate(model, "task.at", name)?;
        let v = value * scale;
        if !v.is_finite() {
            let path = KeyPath::parse("task.at").field(name.as_str());
            return Err(StudyError::invalid(
                path,
                format!("{value}: a finite value"),
            ));
        }
        x[k] = v;
    }
    Ok(x)
}

/// Refuses the settings of the papers' models in a robot-file study.
fn no_paper_settings(task: &TaskSection) -> Result<(), StudyError> {
    if task.pose != PoseSpec::default() {
        let m = "a robot file's nominal pose is given by task coordinate in `at` (e.g. \
                 at = { z = 0.5, tilt_x_deg = 10.0 })";
        return Err(StudyError::invalid("task.pose", m));
    }
    if task.max_angle_deg.is_some() {
        let m = "free a robot file's orientation coordinates in [task.variables] by name";
        return Err(StudyError::invalid("task.max_angle_deg", m));
    }
    Ok(())
}

/// The goal's residuals, checked against the number of rows.
fn goal(task: &TaskSection, twists: &[(f64, Twist)], rows: usize) -> Result<Goal6, StudyError> {
    match task.goal {
        Goal::Maximise | Goal::Minimise => Ok(Goal6::Task(
            twists
                .iter()
                .map(|(w, t)| (w.sqrt(), *t.as_vector()))
                .collect(),
        )),
        Goal::SingularitySigmaMin => Ok(Goal6::SigmaMin),
        Goal::SingularityDet if rows == 6 => Ok(Goal6::Det),
        Goal::SingularityDet => Err(StudyError::invalid(
            "task.goal",
            format!(
                "the determinant needs six wrench rows, this robot has {rows}: use singularity_sigma_min"
            ),
        )),
    }
}

/// Runs the task study of `robot` (module documentation).
///
/// # Errors
/// As [`super::task`].
pub(super) fn robot_file_task(
    robot: &RobotFileSpec,
    task: &TaskSection,
    twists: &[(f64, Twist)],
    progress: &dyn Progress,
) -> Result<TaskRun, StudyError> {
    no_paper_settings(task)?;
    let model = robot.model()?;
    let chosen = variables(robot, &model, task)?;
    let nominal = nominal(&model, task)?;
    let mut problem = RobotFileTask {
        base: robot,
        names: chosen.iter().map(|c| c.0.clone()).collect(),
        variables: chosen.iter().map(|c| c.1.clone()).collect(),
        bounds: chosen.iter().map(|c| c.2).collect(),
        nominal,
        goal: Goal6::SigmaMin,
        rows: 0,
    };
    let start_rows = nominal_rows(&problem)?;
    problem.rows = start_rows;
    problem.goal = goal(task, twists, start_rows)?;
    let starts = checked_starts(task, &problem.bounds)?;
    let sense = task.goal.sense();
    let (run, best_start, best) = run_starts(&problem, sense, task, starts, progress)?;
    let at = problem.evaluate(&best.design).map_err(|e| {
        StudyError::invalid(
            "task",
            format!("the optimum cannot be evaluated again: {e}"),
        )
    })?;
    let (optimum, _) = problem
        .at(&best.design)
        .map_err(|m| StudyError::invalid("task.variables", m))?;
    let pose = platform_pose(at.model.orientation(), &at.config.pose());
    let f_of = |t: &Twist| -> Result<f64, StudyError> {
        let chi = t.as_vector();
        Ok(at
            .rows
            .row_iter()
            .map(|row| reciprocal(&row.iter().copied().collect::<Vec<_>>(), chi).powi(2))
            .sum())
    };
    let twist_values = twists
        .iter()
        .map(|(w, t)| {
            Ok(TwistValue {
                weight: *w,
                f: f_of(t)?,
            })
        })
        .collect::<Result<Vec<_>, StudyError>>()?;
    let result = TaskResult {
        title: None,
        mechanism: "robot_file".into(),
        goal: task.goal,
        objective: best.value,
        best_start,
        optimum: named(
            problem.names.iter().map(String::as_str),
            best.design.iter().copied(),
        ),
        design: optimum
            .variables()
            .iter()
            .filter_map(|v| Some((v.name.to_string(), optimum.get(&v.name)?)))
            .collect(),
        pose: PoseReport::from(&pose),
        twists: twist_values,
        leg_lengths: None,
        wrench_matrix: wrench_matrix(&at.rows, f_of)?,
        optimality: Optimality::from(&best),
        starts: run.starts.len(),
    };
    let reciprocal_twist = most_reciprocal_twist(&at.rows).map(|(_, t)| t);
    let skeleton = Ok(robot_skeleton(&at.model, &at.config));
    let scene = scene::task_scene(skeleton, &pose, twists, reciprocal_twist);
    Ok(TaskRun {
        names: problem.names,
        run,
        result,
        scene,
    })
}

/// The number of wrench rows at the nominal design and pose (the centre of every variable's
/// range), at least six.
fn nominal_rows(problem: &RobotFileTask<'_>) -> Result<usize, StudyError> {
    let centre: Vec<f64> = problem
        .bounds
        .iter()
        .map(|b| 0.5 * (b.lower() + b.upper()))
        .collect();
    let rows = problem
        .evaluate(&centre)
        .map_err(|e| {
            let m = format!("the robot at the centre of the variables' ranges: {e}");
            StudyError::invalid("task.variables", m)
        })?
        .rows
        .nrows();
    if rows < 6 {
        let m = format!(
            "{rows} wrench rows: a task study needs the full wrench system (six rows or more)"
        );
        return Err(StudyError::invalid("mechanism.robot_file", m));
    }
    Ok(rows)
}
