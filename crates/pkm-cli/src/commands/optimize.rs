//! `pkm optimize FILE`: multistart constrained optimisation of the Tsai platform's workspace
//! volume or global condition index (Stamper, Tsai & Walsh 1997, §5) over any of its design
//! variables $(a, b, d + e, c - r, \phi_2, \phi_3)$, with linear inequality constraints
//! $\sum_j c_j x_j \le u$, by the augmented Lagrangian from seeded uniform starts
//! ([`pkm_optimizers::multistart`], every start kept), and the first- and second-order checks
//! at the optimum ([`pkm_optimizers::kkt::check`] of the minimised $f = -W$ or $-\mathrm{GCI}$
//! with $g_i = c_i \cdot x - u_i$, the solver's multipliers and the relative step
//! `check_step`).

use pkm_traits::Progress as _;
use super::{Context, Report, Run};
use crate::CliError;
use crate::drawing;
use crate::output::Output;
use crate::plot::{self, Marker, Scatter};
use crate::study::mechanism::{MechanismSpec, TsaiSpec};
use crate::study::StudyFile;
use nalgebra::Vector3;
use pkm_mechanisms::{Elbow, Tsai3Dof, TsaiDesign};
use pkm_optimizers::kkt::{self, KktSettings, OptimalityCheck};
use pkm_optimizers::{
    AugmentedLagrangianSettings, ConstrainedResult, Multistart, OptimizeError, Sense,
    augmented_lagrangian, multistart,
};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};
use pkm_workspace_indices::{Sampler, Workspace};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Arguments of `pkm optimize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

/// The study of `pkm optimize`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeStudy {
    /// Free text.
    pub title: Option<String>,
    /// The nominal design (its values hold for the variables that are not optimised).
    pub mechanism: toml::Spanned<MechanismSpec>,
    /// What is optimised and how.
    pub optimize: OptimizeSection,
}

/// The `[optimize]` section.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizeSection {
    /// What is maximised.
    pub objective: TsaiObjective,
    /// Volume: columns per axis of the column quadrature (default 128).
    #[serde(default = "default_columns")]
    pub columns: usize,
    /// GCI: Monte Carlo points in the unit hemisphere, common to every design (default 3000).
    #[serde(default = "default_points")]
    pub points: u64,
    /// GCI: seed of the points (default 999).
    #[serde(default = "default_points_seed")]
    pub points_seed: u64,
    /// The optimised variables and their ranges `[lower, upper]`, in the unit of the key.
    pub variables: toml::Spanned<BTreeMap<String, [f64; 2]>>,
    /// Linear inequalities.
    #[serde(default)]
    pub constraints: Vec<toml::Spanned<LinearConstraint>>,
    /// The multistart.
    pub starts: Multistart,
    /// Augmented-Lagrangian settings (defaults: the library's).
    #[serde(default)]
    pub solver: AugmentedLagrangianSettings,
    /// Finite-difference step of the optimality checks, relative to each variable's range
    /// (default 1e-2).
    #[serde(default = "default_check_step")]
    pub check_step: f64,
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
fn default_check_step() -> f64 {
    1e-2
}

/// What is maximised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TsaiObjective {
    /// Workspace volume $W$ inside the hemisphere of radius $a + b + d + e$ (eq. 3), m³.
    Volume,
    /// Stamper's "global condition index" of eq. 8, the condition integral
    /// $\eta = \int_W 1/\kappa \, dW$, m³.
    Eta,
    /// The Gosselin–Angeles global condition index $\eta / W$, dimensionless.
    Gci,
}

impl TsaiObjective {
    /// Name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Self::Volume => "volume",
            Self::Eta => "eta",
            Self::Gci => "gci",
        }
    }
}

/// $\sum_j c_j x_j \le u$ over the design variables (fixed ones contribute their value).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinearConstraint {
    /// A label for the report.
    pub name: String,
    /// $c_j$ by variable name (unit: 1 / the variable's unit); missing variables have 0.
    pub coefficients: BTreeMap<String, f64>,
    /// $u$.
    pub at_most: f64,
}

/// The Tsai design variables in design-vector order, as named in `[mechanism.tsai]`.
pub const TSAI_VARIABLES: [&str; 6] = ["a", "b", "d_plus_e", "c_minus_r", "phi2_deg", "phi3_deg"];

/// The six values of a `[mechanism.tsai]` table, in [`TSAI_VARIABLES`] order.
pub fn tsai_values(spec: &TsaiSpec) -> [f64; 6] {
    [
        spec.a.0,
        spec.b.0,
        spec.d_plus_e.0,
        spec.c_minus_r.0,
        spec.phi2_deg.0,
        spec.phi3_deg.0,
    ]
}

/// $W$ by columns, or the GCI on the common unit-hemisphere points, of a design.
///
/// # Errors
/// [`ObjectiveError`] for an invalid design or quadrature setting.
pub fn tsai_objective(
    design: &Tsai3Dof,
    objective: TsaiObjective,
    columns: usize,
    points: &[Vector3<f64>],
) -> Result<f64, ObjectiveError> {
    match objective {
        TsaiObjective::Volume => Ok(design.column_volume(columns)?),
        TsaiObjective::Eta | TsaiObjective::Gci => {
            let infeasible = |reason: String| ObjectiveError::infeasible(reason);
            let e = Workspace::new(design, &[[Elbow::Out; 3]], &[])
                .and_then(|w| w.hemisphere_estimate(points, design.reach(), &Silent))
                .map_err(|e| infeasible(e.to_string()))?;
            match objective {
                TsaiObjective::Gci => e
                    .gci()
                    .ok_or_else(|| infeasible("empty workspace: GCI = η/W undefined".into())),
                _ => Ok(e.eta),
            }
        }
    }
}

/// The problem of a study: $f = -W$ or $-\mathrm{GCI}$ over the free variables, $g = Cx - u$.
#[derive(Debug)]
pub struct TsaiProblem {
    nominal: [f64; 6],
    free: Vec<usize>,
    bounds: Vec<Bounds>,
    objective: TsaiObjective,
    columns: usize,
    points: Vec<Vector3<f64>>,
    rows: Vec<[f64; 6]>,
    limits: Vec<f64>,
}

impl TsaiProblem {
    /// The six design values at the free-variable vector `x`.
    pub fn design_values(&self, x: &[f64]) -> [f64; 6] {
        let mut all = self.nominal;
        for (k, v) in self.free.iter().zip(x) {
            all[*k] = *v;
        }
        all
    }

    /// Names of the free variables, in design-vector order.
    pub fn names(&self) -> Vec<&'static str> {
        self.free.iter().map(|&k| TSAI_VARIABLES[k]).collect()
    }
}

impl Objective for TsaiProblem {
    fn dimension(&self) -> usize {
        self.free.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        self.check_dimension(x)?;
        let [a, b, s, h, p2, p3] = self.design_values(x);
        let design = Tsai3Dof::new(TsaiDesign::from_deg(a, b, s, h, p2, p3))?;
        tsai_objective(&design, self.objective, self.columns, &self.points).map(|v| -v)
    }
}

impl Constraints for TsaiProblem {
    fn n_constraints(&self) -> usize {
        self.rows.len()
    }
    fn inequalities(&self, x: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        self.check_dimension(x)?;
        let all = self.design_values(x);
        for ((gi, row), limit) in g.iter_mut().zip(&self.rows).zip(&self.limits) {
            *gi = row.iter().zip(&all).map(|(c, v)| c * v).sum::<f64>() - limit;
        }
        Ok(())
    }
}

/// Builds the problem of `file`, each error at the line of the offending entry.
///
/// # Errors
/// [`CliError::Study`] for a mechanism other than the Tsai platform, an unknown variable, an
/// invalid range or constraint; [`CliError::Index`] for an invalid point count.
pub fn problem_of(file: &StudyFile<OptimizeStudy>) -> Result<TsaiProblem, CliError> {
    let study = &file.study;
    let MechanismSpec::Tsai(spec) = study.mechanism.get_ref() else {
        return Err(file.error_at(
            study.mechanism.span(),
            "pkm optimize optimises the Tsai platform: expected a [mechanism.tsai] table",
        ));
    };
    let o = &study.optimize;
    let position = |name: &str| TSAI_VARIABLES.iter().position(|n| *n == name);
    let unknown = |name: &str| {
        format!(
            "unknown design variable `{name}`: expected one of {} (lengths in m, *_deg in \
             degrees)",
            TSAI_VARIABLES.join(", ")
        )
    };
    let mut chosen = Vec::new();
    for (name, [lo, hi]) in o.variables.get_ref() {
        let k = position(name).ok_or_else(|| file.error_at(o.variables.span(), unknown(name)))?;
        let bounds = Bounds::new(*lo, *hi).map_err(|e| {
            file.error_at(
                o.variables.span(),
                format!("{name} = [{lo}, {hi}]: expected [lower, upper] with lower <= upper ({e})"),
            )
        })?;
        chosen.push((k, bounds));
    }
    chosen.sort_by_key(|(k, _)| *k);
    if chosen.is_empty() {
        return Err(file.error_at(o.variables.span(), "no variable to optimise"));
    }
    let mut rows = Vec::new();
    let mut limits = Vec::new();
    for c in &o.constraints {
        let mut row = [0.0; 6];
        for (name, value) in &c.get_ref().coefficients {
            let k = position(name).ok_or_else(|| file.error_at(c.span(), unknown(name)))?;
            row[k] = *value;
        }
        if !(row.iter().all(|v| v.is_finite()) && c.get_ref().at_most.is_finite()) {
            return Err(file.error_at(c.span(), "coefficients and at_most must be finite"));
        }
        rows.push(row);
        limits.push(c.get_ref().at_most);
    }
    let points = match o.objective {
        TsaiObjective::Eta | TsaiObjective::Gci => Sampler::MonteCarlo {
            seed: o.points_seed,
        }
        .unit_hemisphere_points(o.points)?,
        TsaiObjective::Volume => Vec::new(),
    };
    Ok(TsaiProblem {
        nominal: tsai_values(spec),
        free: chosen.iter().map(|(k, _)| *k).collect(),
        bounds: chosen.iter().map(|(_, b)| *b).collect(),
        objective: o.objective,
        columns: o.columns,
        points,
        rows,
        limits,
    })
}

/// One constraint at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConstraintValue {
    /// Its label.
    pub name: String,
    /// $g_i = c_i \cdot x - u_i$ ($\le 0$ when satisfied).
    pub g: f64,
    /// The solver's multiplier $\mu_i \ge 0$.
    pub multiplier: f64,
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

/// The `result` of `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OptimizeResult {
    /// The study's title.
    pub title: Option<String>,
    /// `volume` (m³) or `gci` (1).
    pub objective: String,
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
    /// The first- and second-order checks.
    pub optimality: OptimalityCheck,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_study("optimize", &self.file, context, compute)
    }
}

/// Runs the study in `file`, writing the starts table and figure to `context.out`.
///
/// # Errors
/// Study errors at their line, no feasible start, I/O errors, [`CliError::Cancelled`].
pub fn compute(
    file: &StudyFile<OptimizeStudy>,
    context: &Context,
) -> Result<(OptimizeResult, Report, Output), CliError> {
    let o = &file.study.optimize;
    let problem = problem_of(file)?;
    let settings = o.solver;
    settings.validate()?;
    let check = KktSettings {
        step: o.check_step,
        active_tolerance: settings.feasibility,
    };
    let check_error =
        |e| CliError::Invalid(format!("optimality check (check_step = {}): {e}", o.check_step));
    check.validate_for(problem.bounds()).map_err(check_error)?;
    let starts = o.starts.start_points(problem.bounds())?;
    let run = multistart(starts, &context.progress, |s, cancel| {
        augmented_lagrangian(&problem, Sense::Minimise, s, &settings, cancel)
    })?;
    let (starts, outcomes) = (&run.starts, &run.outcomes);
    let Ok((best_start, best)) = run.best(Sense::Minimise) else {
        let last = outcomes.iter().rev().find_map(|o| o.as_ref().err());
        return Err(CliError::Invalid(format!(
            "no start reached a feasible design ({} starts); last reason: {}",
            starts.len(),
            last.map_or_else(|| "none".to_owned(), ToString::to_string)
        )));
    };
    context.progress.phase("optimality checks");
    let optimality = kkt::check(
        &problem,
        Sense::Minimise,
        &best.design,
        &best.multipliers,
        &check,
        &context.progress,
    )
    .map_err(|e| match e {
        OptimizeError::Cancelled => CliError::Cancelled,
        e => check_error(e),
    })?;
    let names = problem.names();
    let quantity = o.objective.name();
    let design: BTreeMap<String, f64> = TSAI_VARIABLES
        .iter()
        .zip(problem.design_values(&best.design))
        .map(|(n, v)| ((*n).to_owned(), v))
        .collect();
    let constraints = o
        .constraints
        .iter()
        .enumerate()
        .map(|(i, c)| ConstraintValue {
            name: c.get_ref().name.clone(),
            g: best.constraints[i],
            multiplier: best.multipliers[i],
        })
        .collect();
    let count = |f: &dyn Fn(&Result<ConstrainedResult, OptimizeError>) -> bool| {
        outcomes.iter().filter(|&o| f(o)).count()
    };
    let start_counts = StartCounts {
        total: starts.len(),
        converged: count(&|o| o.as_ref().is_ok_and(|r| r.termination.converged())),
        at_iteration_limit: count(&|o| o.as_ref().is_ok_and(|r| !r.termination.converged())),
        failed: count(&|o| o.is_err()),
    };
    let mut out = Output::create(&context.out)?;
    write_starts(&mut out, &names, quantity, starts, outcomes, best_start)?;
    let mut report = Report::default();
    report.line(format!(
        "max {quantity} = {:.6} from start {best_start} of {} ({}): {}",
        -best.value,
        starts.len(),
        best.termination,
        names
            .iter()
            .zip(&best.design)
            .map(|(n, v)| format!("{n} = {v:.5}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    report.line(format!(
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
    ));
    let scene = drawing::optimum_scene(
        file.study.mechanism.get_ref(),
        TSAI_VARIABLES
            .iter()
            .copied()
            .zip(problem.design_values(&best.design)),
    );
    out.write_robot(&mut report,
        &format!("tsai: the {quantity} optimum"),
        scene,
    )?;
    report.line(format!("wrote {}", out.dir().join("results.json").display()));
    let result = OptimizeResult {
        title: file.study.title.clone(),
        objective: quantity.to_owned(),
        maximum: -best.value,
        variables: names.iter().map(|n| (*n).to_owned()).collect(),
        design,
        best_start,
        termination: best.termination.to_string(),
        constraints,
        starts: start_counts,
        optimality,
    };
    Ok((result, report, out))
}

/// `starts.csv` (each start and where it ended) and `starts.svg` (the values reached, best
/// first).
fn write_starts(
    out: &mut Output,
    names: &[&str],
    quantity: &str,
    starts: &[Vec<f64>],
    outcomes: &[Result<ConstrainedResult, OptimizeError>],
    best_start: usize,
) -> Result<(), CliError> {
    let mut header: Vec<String> = vec!["start".into()];
    header.extend(names.iter().map(|n| format!("start_{n}")));
    header.extend(names.iter().map(|n| (*n).to_owned()));
    header.extend([quantity.into(), "max_violation".into(), "termination".into()]);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let rows = outcomes.iter().enumerate().map(|(k, o)| {
        let mut row = vec![k.to_string()];
        row.extend(starts[k].iter().map(|v| format!("{v}")));
        match o {
            Ok(r) => {
                row.extend(r.design.iter().map(|v| format!("{v}")));
                row.push(format!("{}", -r.value));
                let violation = r.constraints.iter().fold(0.0_f64, |a, g| a.max(*g));
                row.push(format!("{violation}"));
                row.push(format!("\"{}\"", r.termination));
            }
            Err(e) => {
                row.extend(std::iter::repeat_n(String::new(), names.len() + 2));
                row.push(format!("\"{}\"", e.to_string().replace('"', "'")));
            }
        }
        row
    });
    out.write_csv("starts.csv", &header, rows)?;
    let mut reached: Vec<(usize, f64)> = outcomes
        .iter()
        .enumerate()
        .filter_map(|(k, o)| o.as_ref().ok().map(|r| (k, -r.value)))
        .collect();
    reached.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let front: Vec<(f64, f64)> = reached
        .iter()
        .enumerate()
        .map(|(rank, (_, v))| (rank as f64 + 1.0, *v))
        .collect();
    let markers = front
        .first()
        .map(|&(x, y)| Marker {
            x,
            y,
            label: format!("start {best_start}"),
        })
        .into_iter()
        .collect();
    let figure = Scatter {
        title: format!("{quantity} reached from each start"),
        x_label: "rank".into(),
        y_label: quantity.into(),
        background: front,
        front: Vec::new(),
        markers,
    };
    out.write_svg("starts.svg", |path| plot::scatter(&figure, path))?;
    Ok(())
}
