//! The optimize study: multistart constrained optimisation of the Tsai platform's workspace
//! volume, $\eta$ or GCI (Stamper, Tsai & Walsh 1997, §5) over any of its design variables
//! $(a, b, d + e, c - r, \phi_2, \phi_3)$, with linear inequality constraints
//! $\sum_j c_j x_j \le u$, by the augmented Lagrangian from seeded uniform starts
//! ([`pkm_optimizers::multistart`], every start kept), and the first- and second-order checks
//! at the optimum ([`pkm_optimizers::kkt::check`] of the maximised criterion with
//! $g_i = c_i \cdot x - u_i$, the solver's multipliers and the relative step `check_step`).
//!
//! A robot file ([`crate::schema::robot_file`]) is optimised in its own task space instead:
//! its `[parameters]` are the design variables, the objective a workspace index of its
//! `[task_space]` on common random points, and each start a derivative-free compass search
//! (`optimize/robot_file.rs`).
//!
//! Every setting is checked before the first start runs, each at its key path.

mod robot_file;

use crate::outcome::{Artifact, Outcome};
use crate::registry::StudyMechanism;
use crate::scene;
use crate::schema::mechanism::{ConstraintsSpec, MechanismSpec};
use crate::schema::sampling::SamplingSpec;
use crate::starts::{self, Reached, ranked_chart};
use crate::task_space::TaskSpaceSpec;
use crate::{KeyPath, StudyError};
use nalgebra::Vector3;
use pkm_design_problems::DesignProblem;
use pkm_design_problems::tsai::{LinearInequality, TSAI_VARIABLES, TsaiCriterion, TsaiProblem};
use pkm_optimizers::kkt::{self, KktSettings, OptimalityCheck};
use pkm_optimizers::{
    AugmentedLagrangianSettings, CompassSettings, ConstrainedResult, LocalResult, Multistart,
    MultistartRun, OptimizeError, Sense, augmented_lagrangian, multistart,
};
use pkm_traits::{Bounds, Progress};
use pkm_workspace_indices::Sampler;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// An optimize study of a mechanism of the registry `M` (the papers' mechanisms by default);
/// a mechanism takes part through [`StudyMechanism::design_problem`].
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeStudy<M = MechanismSpec> {
    /// Free text.
    pub title: Option<String>,
    /// The nominal design (its values hold for the variables that are not optimised).
    pub mechanism: M,
    /// Robot files: the workspace limits of every design (as in a workspace study).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constraints: Option<ConstraintsSpec>,
    /// Robot files: the task space the objective is measured in ([`crate::task_space`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub task_space: Option<TaskSpaceSpec>,
    /// Robot files: the points of the objective, common to every design.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampling: Option<SamplingSpec>,
    /// What is optimised and how.
    pub optimize: OptimizeSection,
}

/// The `[optimize]` section.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeSection {
    /// What is maximised.
    pub objective: OptimizeObjective,
    /// `objective = "weighted"` (robot files): the weight $w_k \ge 0$ of each index in
    /// $\sum_k w_k I_k$, by name (`volume`, `eta`, `gci`, `singularity_free_volume`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub weights: BTreeMap<OptimizeObjective, f64>,
    /// Volume: columns per axis of the column quadrature (default 128).
    #[serde(default = "default_columns")]
    pub columns: usize,
    /// η and GCI: Monte Carlo points in the unit hemisphere, common to every design (default
    /// 3000).
    #[serde(default = "default_points")]
    pub points: u64,
    /// η and GCI: seed of the points (default 999).
    #[serde(default = "default_points_seed")]
    pub points_seed: u64,
    /// The optimised variables and their ranges `[lower, upper]`, in the unit of the key.
    pub variables: BTreeMap<String, [f64; 2]>,
    /// Linear inequalities.
    #[serde(default)]
    pub constraints: Vec<LinearConstraint>,
    /// The multistart.
    pub starts: Multistart,
    /// The Tsai platform: augmented-Lagrangian settings (defaults: the library's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<AugmentedLagrangianSettings>,
    /// The Tsai platform: finite-difference step of the optimality checks, relative to each
    /// variable's range, in $(0, 0.5)$ and large enough to move every design in the box
    /// (default 1e-2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check_step: Option<f64>,
    /// Robot files: the compass search of each start (defaults: the library's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<CompassSettings>,
}

fn default_columns() -> usize {
    128
}
fn default_points() -> u64 {
    3000
}
fn default_points_seed() -> u64 {
    999
}
/// The step of the optimality checks when the study gives none.
const DEFAULT_CHECK_STEP: f64 = 1e-2;

/// What is maximised. For the Tsai platform the volume, η and GCI are Stamper's; for a robot
/// file they are measured in its task space, in the unit of its sampled coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OptimizeObjective {
    /// Workspace volume $W$ (Tsai: inside the hemisphere of radius $a + b + d + e$, eq. 3, m³).
    Volume,
    /// Stamper's "global condition index" of eq. 8, the condition integral
    /// $\eta = \int_W 1/\kappa \, dW$.
    Eta,
    /// The Gosselin–Angeles global condition index $\eta / W$, dimensionless.
    Gci,
    /// Robot files: the singularity-free volume connected to the start pose
    /// (`[task_space.singularity_free]`).
    SingularityFreeVolume,
    /// Robot files: $\sum_k w_k I_k$ with the study's `weights`.
    Weighted,
}

impl OptimizeObjective {
    /// Name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Self::Volume => "volume",
            Self::Eta => "eta",
            Self::Gci => "gci",
            Self::SingularityFreeVolume => "singularity_free_volume",
            Self::Weighted => "weighted",
        }
    }
}

/// $\sum_j c_j x_j \le u$ over the design variables (fixed ones contribute their value).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinearConstraint {
    /// A label for the report.
    pub name: String,
    /// $c_j$ by variable name (unit: 1 / the variable's unit); missing variables have 0.
    pub coefficients: BTreeMap<String, f64>,
    /// $u$.
    pub at_most: f64,
}

/// One constraint at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConstraintValue {
    /// Its label.
    pub name: String,
    /// $g_i = c_i \cdot x - u_i$ ($\le 0$ when satisfied).
    pub g: f64,
    /// The solver's multiplier $\mu_i \ge 0$ (the augmented Lagrangian's; none for a compass
    /// search, which treats constraints as a barrier).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub multiplier: Option<f64>,
}

/// How the starts ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StartCounts {
    /// Starts run.
    pub total: usize,
    /// Feasible and converged.
    pub converged: usize,
    /// Feasible at the iteration limit.
    pub at_iteration_limit: usize,
    /// No feasible design (or another failure).
    pub failed: usize,
}

impl StartCounts {
    /// How the starts of `run` ended.
    fn of<R: LocalResult>(run: &MultistartRun<R>) -> Self {
        let ok = run.outcomes.iter().filter_map(|o| o.as_ref().ok());
        let converged = ok.clone().filter(|r| r.termination().converged()).count();
        let succeeded = ok.count();
        Self {
            total: run.starts.len(),
            converged,
            at_iteration_limit: succeeded - converged,
            failed: run.outcomes.len() - succeeded,
        }
    }
}

/// The result of an optimize study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OptimizeResult {
    /// The study's title.
    pub title: Option<String>,
    /// `volume`, `eta`, `gci`, `singularity_free_volume` or `weighted`.
    pub objective: String,
    /// The unit of the volume and η (`m³`, or a robot file's task-space unit such as
    /// `m·rad²`).
    pub unit: String,
    /// Its largest value found.
    pub maximum: f64,
    /// The optimised variables, in order.
    pub variables: Vec<String>,
    /// The optimum of every design variable (the unit of its key).
    pub design: BTreeMap<String, f64>,
    /// The start the optimum came from (from 0).
    pub best_start: usize,
    /// Why the augmented Lagrangian stopped there.
    pub termination: String,
    /// The constraints there.
    pub constraints: Vec<ConstraintValue>,
    /// How the starts ended.
    pub starts: StartCounts,
    /// The first- and second-order checks (the Tsai platform's smooth objective; a Monte
    /// Carlo objective has no derivatives to check).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub optimality: Option<OptimalityCheck>,
    /// Robot files: the compass search and every index at the optimum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<SearchSummary>,
}

/// How the compass searches of a robot-file optimisation went, and the optimum's indices.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SearchSummary {
    /// `"compass"`.
    pub method: String,
    /// Objective evaluations over every start.
    pub evaluations: usize,
    /// Designs of the polls that were infeasible (a linear constraint, no model, no workspace).
    pub infeasible: usize,
    /// The best start's last step (a fraction of each variable's range).
    pub final_step: f64,
    /// The indices at the optimum, by name (the volume and η in [`OptimizeResult::unit`]).
    pub indices: BTreeMap<String, f64>,
}

/// Every setting of a study, checked: the problem's pieces, the start points and the solver
/// and check settings.
struct Checked {
    nominal: [f64; 6],
    free: Vec<(usize, Bounds)>,
    criterion: TsaiCriterion,
    points: Vec<Vector3<f64>>,
    inequalities: Vec<LinearInequality>,
    starts: Vec<Vec<f64>>,
    solver: AugmentedLagrangianSettings,
    check: KktSettings,
}

/// An optimiser's refusal of the setting at `section` as an error at its key path (the
/// setting's own name appended when the library names one).
fn refused(section: &str, e: OptimizeError) -> StudyError {
    match e {
        OptimizeError::Invalid(invalid) => {
            let path = KeyPath::parse(section);
            let path = if section.ends_with(invalid.name) {
                path
            } else {
                path.field(invalid.name)
            };
            StudyError::invalid(path, invalid.to_string())
        }
        e => StudyError::invalid(section, e.to_string()),
    }
}

/// The refusal of a mechanism without a smooth design problem.
fn no_smooth_objective(kind: &str) -> StudyError {
    StudyError::invalid(
        "mechanism",
        format!(
            "{kind} has no objective that is smooth in the design: its Monte Carlo workspace \
             volume is piecewise constant in the design variables; use a sweep or pareto study"
        ),
    )
}

fn unknown_variable(name: &str) -> String {
    format!(
        "unknown design variable `{name}`: expected one of {} (lengths in m, *_deg in degrees)",
        TSAI_VARIABLES.join(", ")
    )
}

fn variable_index(path: KeyPath, name: &str) -> Result<usize, StudyError> {
    TSAI_VARIABLES
        .iter()
        .position(|n| *n == name)
        .ok_or_else(|| StudyError::invalid(path, unknown_variable(name)))
}

/// The free variables with their bounds, in design-vector order.
fn free_variables(o: &OptimizeSection) -> Result<Vec<(usize, Bounds)>, StudyError> {
    let mut chosen = Vec::new();
    for (name, [lo, hi]) in &o.variables {
        let path = KeyPath::parse("optimize.variables").field(name.as_str());
        let k = variable_index(path.clone(), name)?;
        let bounds = starts::variable_bounds(path, name, *lo, *hi)?;
        chosen.push((k, bounds));
    }
    chosen.sort_by_key(|(k, _)| *k);
    if chosen.is_empty() {
        return Err(StudyError::invalid(
            "optimize.variables",
            "no variable to optimise",
        ));
    }
    Ok(chosen)
}

/// The linear inequalities, each checked.
fn inequalities(o: &OptimizeSection) -> Result<Vec<LinearInequality>, StudyError> {
    let mut rows = Vec::new();
    for (i, c) in o.constraints.iter().enumerate() {
        let path = KeyPath::parse("optimize.constraints").index(i);
        let mut coefficients = [0.0; 6];
        for (name, value) in &c.coefficients {
            let at = path.clone().field("coefficients").field(name.as_str());
            coefficients[variable_index(at, name)?] = *value;
        }
        if !(coefficients.iter().all(|v| v.is_finite()) && c.at_most.is_finite()) {
            return Err(StudyError::invalid(
                path,
                "coefficients and at_most must be finite",
            ));
        }
        rows.push(LinearInequality {
            coefficients,
            at_most: c.at_most,
        });
    }
    Ok(rows)
}

/// The criterion and its common points, the quadrature settings checked.
fn criterion(o: &OptimizeSection) -> Result<(TsaiCriterion, Vec<Vector3<f64>>), StudyError> {
    let criterion = match o.objective {
        OptimizeObjective::Volume => TsaiCriterion::Volume { columns: o.columns },
        OptimizeObjective::Eta => TsaiCriterion::Eta,
        OptimizeObjective::Gci => TsaiCriterion::Gci,
        other => return Err(robot_files_only("optimize.objective", other.name())),
    };
    if o.objective == OptimizeObjective::Volume
        && !(1..=pkm_mechanisms::Tsai3Dof::MAX_COLUMN_GRID).contains(&o.columns)
    {
        return Err(StudyError::invalid(
            "optimize.columns",
            format!(
                "expected a count of columns per axis in 1..={}",
                pkm_mechanisms::Tsai3Dof::MAX_COLUMN_GRID
            ),
        ));
    }
    let points = match o.objective {
        OptimizeObjective::Eta | OptimizeObjective::Gci => Sampler::MonteCarlo {
            seed: o.points_seed,
        }
        .unit_hemisphere_points(o.points)
        .map_err(|e| StudyError::invalid("optimize.points", e.to_string()))?,
        _ => Vec::new(),
    };
    Ok((criterion, points))
}

/// The refusal of a robot-file setting in a study of the Tsai platform.
fn robot_files_only(path: &str, what: &str) -> StudyError {
    StudyError::invalid(
        path,
        format!("{what} belongs to the optimisation of a robot file ([mechanism.robot_file])"),
    )
}

/// Refuses the settings of a robot-file optimisation in a study of the Tsai platform.
fn no_robot_file_settings<M>(study: &OptimizeStudy<M>) -> Result<(), StudyError> {
    let given = [
        ("constraints", study.constraints.is_some()),
        ("task_space", study.task_space.is_some()),
        ("sampling", study.sampling.is_some()),
        ("optimize.weights", !study.optimize.weights.is_empty()),
        ("optimize.search", study.optimize.search.is_some()),
    ];
    match given.into_iter().find(|(_, given)| *given) {
        Some((path, _)) => Err(robot_files_only(path, "this setting")),
        None => Ok(()),
    }
}

/// Checks every setting of `study` (before any start runs).
fn check<M: StudyMechanism>(study: &OptimizeStudy<M>) -> Result<Checked, StudyError> {
    let nominal = match study.mechanism.design_problem() {
        Some(DesignProblem::Tsai { nominal }) => nominal,
        _ => return Err(no_smooth_objective(study.mechanism.kind())),
    };
    no_robot_file_settings(study)?;
    let o = &study.optimize;
    let free = free_variables(o)?;
    let inequalities = inequalities(o)?;
    let solver = o.solver.clone().unwrap_or_default();
    solver
        .validate()
        .map_err(|e| refused("optimize.solver", e))?;
    let bounds: Vec<Bounds> = free.iter().map(|(_, b)| *b).collect();
    let check = KktSettings {
        step: o.check_step.unwrap_or(DEFAULT_CHECK_STEP),
        active_tolerance: solver.feasibility,
    };
    check
        .validate_for(&bounds)
        .map_err(|e| refused("optimize.check_step", e))?;
    let starts = o
        .starts
        .start_points(&bounds)
        .map_err(|e| refused("optimize.starts", e))?;
    let (criterion, points) = criterion(o)?;
    Ok(Checked {
        nominal,
        free,
        criterion,
        points,
        inequalities,
        starts,
        solver,
        check,
    })
}

/// Runs an optimize study: the multistart, the optimality checks at the best start, the starts
/// as a table and a chart, and the drawing of the optimum.
///
/// # Errors
/// [`StudyError::Invalid`] at its key path for a setting that cannot be used (every one checked
/// before the first start), or when no start reaches a feasible design (at `optimize.starts`)
/// or the optimality check fails (at `optimize.check_step`); [`StudyError::Cancelled`] when
/// `progress` asks to stop.
pub fn optimize<M: StudyMechanism>(
    study: &OptimizeStudy<M>,
    progress: &dyn Progress,
) -> Result<Outcome<OptimizeResult>, StudyError> {
    if let Some(robot) = study.mechanism.robot_file() {
        return robot_file::optimize(study, robot, progress);
    }
    let c = check(study)?;
    let problem = TsaiProblem::new(c.nominal, c.free, c.criterion, &c.points, c.inequalities);
    let settings = &c.solver;
    let run = multistart(c.starts, progress, |s, cancel| {
        augmented_lagrangian(&problem, Sense::Maximise, s, settings, cancel)
    })?;
    let (best_start, best) = run.best(Sense::Maximise).map_err(|_| no_feasible(&run))?;
    progress.phase("optimality checks");
    let optimality = kkt::check(
        &problem,
        Sense::Maximise,
        &best.design,
        &best.multipliers,
        &c.check,
        progress,
    )
    .map_err(|e| match e {
        OptimizeError::Cancelled => StudyError::Cancelled,
        e => StudyError::invalid("optimize.check_step", format!("optimality check: {e}")),
    })?;
    let result = result_of(study, &problem, &run, (best_start, best), optimality);
    let mut outcome = Outcome::new(result);
    summarise(&mut outcome, &problem.names(), best);
    outcome.artifacts.extend(starts_artifacts(
        &problem.names(),
        &outcome.result,
        &run,
        ("max_violation", |r: &ConstrainedResult| {
            r.constraints.iter().fold(0.0_f64, |a, g| a.max(*g))
        }),
    ));
    let scene = scene::optimum_scene(
        &study.mechanism,
        TSAI_VARIABLES
            .iter()
            .copied()
            .zip(problem.design_values(&best.design)),
    );
    let quantity = study.optimize.objective.name();
    let kind = study.mechanism.kind();
    outcome.robot(format!("{kind}: the {quantity} optimum"), scene);
    Ok(outcome)
}

/// The error when no start reached a feasible design, with the last start's reason.
fn no_feasible<R>(run: &MultistartRun<R>) -> StudyError {
    let last = run.outcomes.iter().rev().find_map(|o| o.as_ref().err());
    StudyError::invalid(
        "optimize.starts",
        format!(
            "no start reached a feasible design ({} starts); last reason: {}",
            run.starts.len(),
            last.map_or_else(|| "none".to_owned(), ToString::to_string)
        ),
    )
}

/// The result: the best start's design, constraints and termination, the start counts and the
/// checks.
fn result_of<M>(
    study: &OptimizeStudy<M>,
    problem: &TsaiProblem<'_>,
    run: &MultistartRun<ConstrainedResult>,
    (best_start, best): (usize, &ConstrainedResult),
    optimality: OptimalityCheck,
) -> OptimizeResult {
    let o = &study.optimize;
    let design = TSAI_VARIABLES
        .iter()
        .zip(problem.design_values(&best.design))
        .map(|(n, v)| ((*n).to_owned(), v))
        .collect();
    let constraints = o
        .constraints
        .iter()
        .enumerate()
        .map(|(i, c)| ConstraintValue {
            name: c.name.clone(),
            g: best.constraints[i],
            multiplier: Some(best.multipliers[i]),
        })
        .collect();
    OptimizeResult {
        title: study.title.clone(),
        objective: o.objective.name().to_owned(),
        unit: "m³".to_owned(),
        maximum: best.value,
        variables: problem.names().iter().map(|n| (*n).to_owned()).collect(),
        design,
        best_start,
        termination: best.termination.to_string(),
        constraints,
        starts: StartCounts::of(run),
        optimality: Some(optimality),
        search: None,
    }
}

/// The two summary lines: the optimum, and the first- and second-order checks.
fn summarise<R: LocalResult>(outcome: &mut Outcome<OptimizeResult>, names: &[&str], best: &R) {
    let r = &outcome.result;
    let unit = match r.objective.as_str() {
        "volume" | "eta" | "singularity_free_volume" => format!(" {}", r.unit),
        _ => String::new(),
    };
    let optimum = format!(
        "max {} = {:.6}{unit} from start {} of {} ({}): {}",
        r.objective,
        best.value(),
        r.best_start,
        r.starts.total,
        best.termination(),
        names
            .iter()
            .zip(best.design())
            .map(|(n, v)| format!("{n} = {v:.5}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    outcome.summary.push(optimum);
    let Some(optimality) = &outcome.result.optimality else {
        return;
    };
    let checks = format!(
        "first order: projected gradient {:.2e} (solver multipliers), stationarity {:.2e} \
         (least-squares multipliers); second order: reduced Hessian eigenvalues [{}]",
        optimality.projected_gradient_max,
        optimality.stationarity_residual,
        optimality
            .reduced_hessian_eigenvalues
            .iter()
            .map(|v| format!("{v:.3e}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    outcome.summary.push(checks);
}

/// `starts.csv` (each start, where it ended, the value and a second number `extra` names and
/// computes) and `starts.svg` (the values reached, best first).
fn starts_artifacts<R: LocalResult>(
    names: &[&str],
    result: &OptimizeResult,
    run: &MultistartRun<R>,
    (extra, number): (&str, impl Fn(&R) -> f64),
) -> [Artifact; 2] {
    let quantity = result.objective.as_str();
    let rows = starts::start_rows(run, names.len() + 2, |r| Reached {
        design: r.design(),
        numbers: vec![r.value(), number(r)],
        termination: r.termination(),
    });
    let values = run
        .outcomes
        .iter()
        .filter_map(|o| o.as_ref().ok().map(R::value));
    let chart = ranked_chart(
        format!("{quantity} reached from each start"),
        quantity,
        values.collect(),
        true,
        result.best_start,
    );
    starts::starts_artifacts(names, &[quantity, extra], rows, chart)
}
