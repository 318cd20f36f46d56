//! The optimisation of a robot file in its own task space: its `[parameters]` are the design
//! variables, the objective a workspace index of its `[task_space]` (the measure $W$,
//! $\eta = \int 1/\kappa\,dW$, GCI $= \eta/W$, the singularity-free volume connected to the
//! start, or $\sum_k w_k I_k$ of them) on the points of `[sampling]`, common to every design.
//!
//! On common random numbers the Monte Carlo estimate is piecewise constant in the design (a
//! point enters or leaves the workspace), so finite differences are 0 or jumps and a
//! gradient method has nothing to follow. Each start therefore runs a compass search
//! ([`pkm_optimizers::compass_search`]): it needs only comparisons of values, and stops at a
//! design that no coordinate step of its final size improves. Linear inequalities
//! $\sum_j c_j x_j \le u$ and designs without a model or a workspace are infeasible designs (the
//! extreme barrier); a start that violates them is a failed start.

use super::{
    ConstraintValue, OptimizeObjective, OptimizeResult, OptimizeStudy, SearchSummary, StartCounts,
    no_feasible, refused, starts_artifacts, summarise,
};
use crate::outcome::Outcome;
use crate::registry::StudyMechanism;
use crate::schema::robot_file::RobotFileSpec;
use crate::starts;
use crate::task_space::{TaskSpaceEvaluator, TaskSpaceIndices, robot_at_home};
use crate::workspace::constraints_of;
use crate::{Infeasible, KeyPath, StudyError};
use pkm_optimizers::{
    CompassResult, CompassSettings, MultistartRun, Sense, compass_search, multistart,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Progress, Silent, WorkspaceConstraint};

/// The indices an objective combines, in weight order.
const INDICES: [OptimizeObjective; 4] = [
    OptimizeObjective::Volume,
    OptimizeObjective::Eta,
    OptimizeObjective::Gci,
    OptimizeObjective::SingularityFreeVolume,
];

/// A linear inequality over the free variables: $c \cdot x \le u$ (the fixed parameters'
/// terms moved into $u$).
struct Row {
    name: String,
    coefficients: Vec<f64>,
    at_most: f64,
}

/// The objective $\sum_k w_k I_k$ over the robot file's free parameters.
struct RobotFileObjective<'a> {
    base: &'a RobotFileSpec,
    names: Vec<String>,
    bounds: Vec<Bounds>,
    rows: Vec<Row>,
    weights: [f64; 4],
    evaluator: TaskSpaceEvaluator,
    constraints: Vec<WorkspaceConstraint>,
}

impl RobotFileObjective<'_> {
    /// The robot file with the free parameters at `x`.
    fn design(&self, x: &[f64]) -> Result<RobotFileSpec, Infeasible> {
        let mut robot = self.base.clone();
        for (name, value) in self.names.iter().zip(x) {
            robot.set(name, *value).map_err(Infeasible::Variable)?;
        }
        Ok(robot)
    }

    /// Every index at `x`, or why the design has none.
    fn indices(&self, x: &[f64]) -> Result<TaskSpaceIndices, ObjectiveError> {
        let robot = self.design(x)?;
        let with_singularity_free = self.weights[3] > 0.0;
        let constraints = &self.constraints;
        match self
            .evaluator
            .indices(&robot, constraints, with_singularity_free, &Silent)
        {
            Ok(Ok(indices)) => Ok(indices),
            Ok(Err(reason)) => Err(reason.into()),
            Err(StudyError::Cancelled) => Err(ObjectiveError::Cancelled),
            Err(e) => Err(ObjectiveError::infeasible(e.to_string())),
        }
    }

    /// The first violated inequality at `x`, as the reason the design is infeasible.
    fn violation(&self, x: &[f64]) -> Option<Infeasible> {
        self.rows.iter().find_map(|row| {
            let g = dot(&row.coefficients, x) - row.at_most;
            (g > 0.0).then(|| Infeasible::Inequality {
                name: row.name.clone(),
                g,
            })
        })
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

impl Objective for RobotFileObjective<'_> {
    fn dimension(&self) -> usize {
        self.names.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        self.check_dimension(x)?;
        if let Some(reason) = self.violation(x) {
            return Err(reason.into());
        }
        let indices = self.indices(x)?;
        let values = index_values(&indices);
        let mut sum = 0.0;
        for (k, &w) in self.weights.iter().enumerate() {
            if w > 0.0 {
                let index = INDICES[k].name();
                let v = values[k].ok_or(Infeasible::EmptyWorkspace { index })?;
                sum += w * v;
            }
        }
        Ok(sum)
    }
}

/// The four indices in [`INDICES`] order (GCI none for an empty workspace, the
/// singularity-free volume none when not computed).
fn index_values(i: &TaskSpaceIndices) -> [Option<f64>; 4] {
    [
        Some(i.volume),
        Some(i.eta),
        i.gci,
        i.singularity_free_volume,
    ]
}

/// The weights of the study's objective, checked.
fn weights<M>(study: &OptimizeStudy<M>) -> Result<[f64; 4], StudyError> {
    let o = &study.optimize;
    let path = KeyPath::parse("optimize.weights");
    if o.objective != OptimizeObjective::Weighted {
        if !o.weights.is_empty() {
            let m = "weights belong to objective = \"weighted\"";
            return Err(StudyError::invalid(path, m));
        }
        let k = INDICES.iter().position(|i| *i == o.objective);
        return Ok(std::array::from_fn(
            |j| if Some(j) == k { 1.0 } else { 0.0 },
        ));
    }
    let mut weights = [0.0; 4];
    for (index, &w) in &o.weights {
        let at = path.clone().field(index.name());
        let k = INDICES.iter().position(|i| i == index).ok_or_else(|| {
            StudyError::invalid(
                at.clone(),
                "expected volume, eta, gci or singularity_free_volume",
            )
        })?;
        if !(w.is_finite() && w >= 0.0) {
            return Err(StudyError::invalid(
                at,
                format!("{w}: a finite weight >= 0"),
            ));
        }
        weights[k] = w;
    }
    if weights.iter().all(|w| *w == 0.0) {
        let m = "a weighted objective needs at least one positive weight";
        return Err(StudyError::invalid(path, m));
    }
    Ok(weights)
}

/// The free parameters and their bounds, in the order of `[optimize.variables]`.
fn variables<M: StudyMechanism>(
    study: &OptimizeStudy<M>,
) -> Result<Vec<(String, Bounds)>, StudyError> {
    let mut free = Vec::new();
    for (name, [lo, hi]) in &study.optimize.variables {
        let path = KeyPath::parse("optimize.variables").field(name.as_str());
        if study.mechanism.get(name).is_none() {
            return Err(StudyError::invalid(
                path,
                not_a_parameter(&study.mechanism, name),
            ));
        }
        free.push((name.clone(), starts::variable_bounds(path, name, *lo, *hi)?));
    }
    if free.is_empty() {
        return Err(StudyError::invalid(
            "optimize.variables",
            "no variable to optimise",
        ));
    }
    Ok(free)
}

fn not_a_parameter<M: StudyMechanism>(mechanism: &M, name: &str) -> String {
    let known: Vec<String> = mechanism
        .variables()
        .iter()
        .map(|v| v.name.to_string())
        .collect();
    format!(
        "`{name}` is not a parameter of the robot file: expected one of [{}] (its \
         [parameters] table)",
        known.join(", ")
    )
}

/// The linear inequalities over the free variables (fixed parameters moved to the bound).
fn rows<M: StudyMechanism>(
    study: &OptimizeStudy<M>,
    names: &[String],
) -> Result<Vec<Row>, StudyError> {
    let mut rows = Vec::new();
    for (i, c) in study.optimize.constraints.iter().enumerate() {
        let path = KeyPath::parse("optimize.constraints").index(i);
        let mut row = Row {
            name: c.name.clone(),
            coefficients: vec![0.0; names.len()],
            at_most: c.at_most,
        };
        for (name, &value) in &c.coefficients {
            let at = path.clone().field("coefficients").field(name.as_str());
            match (
                names.iter().position(|n| n == name),
                study.mechanism.get(name),
            ) {
                (Some(k), _) => row.coefficients[k] = value,
                (None, Some(fixed)) => row.at_most -= value * fixed,
                (None, None) => {
                    return Err(StudyError::invalid(
                        at,
                        not_a_parameter(&study.mechanism, name),
                    ));
                }
            }
        }
        let finite = row.coefficients.iter().all(|v| v.is_finite()) && row.at_most.is_finite();
        if !finite {
            return Err(StudyError::invalid(
                path,
                "coefficients and at_most must be finite",
            ));
        }
        rows.push(row);
    }
    Ok(rows)
}

/// The problem of `study`, every setting checked, and its starts.
fn problem<'a, M: StudyMechanism>(
    study: &OptimizeStudy<M>,
    robot: &'a RobotFileSpec,
) -> Result<(RobotFileObjective<'a>, Vec<Vec<f64>>), StudyError> {
    let spec = study.task_space.as_ref().ok_or_else(|| {
        let m = "an optimize study of a robot file measures its objective in the robot's task \
                 space: give [task_space] (its kind and box, as in a workspace study)";
        StudyError::invalid("task_space", m)
    })?;
    let sampling = study.sampling.as_ref().ok_or_else(|| {
        let m = "the objective is estimated on common points: give [sampling] (points, seed)";
        StudyError::invalid("sampling", m)
    })?;
    for (path, given) in [
        ("optimize.solver", study.optimize.solver.is_some()),
        ("optimize.check_step", study.optimize.check_step.is_some()),
    ] {
        if given {
            let m = "the augmented Lagrangian and its checks need a smooth objective; a robot \
                     file is optimised by compass search ([optimize.search])";
            return Err(StudyError::invalid(path, m));
        }
    }
    let constraints = constraints_of(&study.mechanism, study.constraints.as_ref())?;
    let weights = weights(study)?;
    if weights[3] > 0.0 && spec.singularity_free.is_none() {
        let m = "the singularity-free volume needs [task_space.singularity_free] with its \
                 min_direct_margin";
        return Err(StudyError::invalid("task_space.singularity_free", m));
    }
    let (names, bounds): (Vec<String>, Vec<Bounds>) = variables(study)?.into_iter().unzip();
    let rows = rows(study, &names)?;
    let search = study.optimize.search.unwrap_or_default();
    search
        .validate()
        .map_err(|e| refused("optimize.search", e))?;
    let starts = study
        .optimize
        .starts
        .start_points(&bounds)
        .map_err(|e| refused("optimize.starts", e))?;
    let evaluator = TaskSpaceEvaluator::new(robot, spec, sampling)?;
    let objective = RobotFileObjective {
        base: robot,
        names,
        bounds,
        rows,
        weights,
        evaluator,
        constraints,
    };
    Ok((objective, starts))
}

/// Runs the optimisation of a robot file (module documentation): a compass search from every
/// start, the indices at the best design, the starts as a table and a chart, the optimum drawn
/// at its home pose.
///
/// # Errors
/// As [`super::optimize`]: a setting at its key path (every one checked before the first
/// start), no feasible start (at `optimize.starts`), cancellation.
pub(super) fn optimize<M: StudyMechanism>(
    study: &OptimizeStudy<M>,
    robot: &RobotFileSpec,
    progress: &dyn Progress,
) -> Result<Outcome<OptimizeResult>, StudyError> {
    let (problem, starts) = problem(study, robot)?;
    let settings: CompassSettings = study.optimize.search.unwrap_or_default();
    let run = multistart(starts, progress, |s, cancel| {
        compass_search(&problem, Sense::Maximise, s, &settings, cancel)
    })?;
    let (best_start, best) = run.best(Sense::Maximise).map_err(|_| no_feasible(&run))?;
    let optimum = problem
        .design(&best.design)
        .map_err(|m| StudyError::invalid("optimize.variables", m.to_string()))?;
    let indices = problem.indices(&best.design).map_err(|e| match e {
        ObjectiveError::Cancelled => StudyError::Cancelled,
        e => StudyError::invalid("optimize", format!("the optimum: {e}")),
    })?;
    let result = result_of(
        study,
        &problem,
        &run,
        (best_start, best),
        &optimum,
        &indices,
    );
    let names: Vec<&str> = problem.names.iter().map(String::as_str).collect();
    let mut outcome = Outcome::new(result);
    summarise(&mut outcome, &names, best);
    summarise_indices(&mut outcome);
    let evaluations = ("evaluations", |r: &CompassResult| r.evaluations as f64);
    let artifacts = starts_artifacts(&names, &outcome.result, &run, evaluations);
    outcome.artifacts.extend(artifacts);
    let caption = format!("the {} optimum at home", study.optimize.objective.name());
    outcome.robot(caption, robot_at_home(&optimum));
    Ok(outcome)
}

/// The result: the best start's design (every parameter), the inequalities there, the start
/// counts and the search summary with every index at the optimum.
fn result_of<M: StudyMechanism>(
    study: &OptimizeStudy<M>,
    problem: &RobotFileObjective<'_>,
    run: &MultistartRun<CompassResult>,
    (best_start, best): (usize, &CompassResult),
    optimum: &RobotFileSpec,
    indices: &TaskSpaceIndices,
) -> OptimizeResult {
    let design = optimum
        .variables()
        .iter()
        .filter_map(|v| Some((v.name.to_string(), optimum.get(&v.name)?)))
        .collect();
    let constraints = problem
        .rows
        .iter()
        .map(|row| ConstraintValue {
            name: row.name.clone(),
            g: dot(&row.coefficients, &best.design) - row.at_most,
            multiplier: None,
        })
        .collect();
    let ok = run.outcomes.iter().filter_map(|o| o.as_ref().ok());
    let indices = INDICES
        .iter()
        .zip(index_values(indices))
        .filter_map(|(i, v)| Some((i.name().to_owned(), v?)))
        .collect();
    OptimizeResult {
        title: study.title.clone(),
        objective: study.optimize.objective.name().to_owned(),
        unit: problem.evaluator.unit().to_owned(),
        maximum: best.value,
        variables: problem.names.clone(),
        design,
        best_start,
        termination: best.termination.to_string(),
        constraints,
        starts: StartCounts::of(run),
        optimality: None,
        search: Some(SearchSummary {
            method: "compass".to_owned(),
            evaluations: ok.clone().map(|r| r.evaluations).sum(),
            infeasible: ok.map(|r| r.infeasible).sum(),
            final_step: best.final_step,
            indices,
        }),
    }
}

/// The indices at the optimum and the search's counts, one line.
fn summarise_indices(outcome: &mut Outcome<OptimizeResult>) {
    let r = &outcome.result;
    let Some(search) = &r.search else {
        return;
    };
    let indices: Vec<String> = search
        .indices
        .iter()
        .map(|(name, v)| format!("{name} = {v:.6e}"))
        .collect();
    let line = format!(
        "at the optimum: {} ({} for volume and eta); compass search: {} evaluations, {} \
         infeasible, last step {:.2e} of each range",
        indices.join(", "),
        r.unit,
        search.evaluations,
        search.infeasible,
        search.final_step
    );
    outcome.line(line);
}
