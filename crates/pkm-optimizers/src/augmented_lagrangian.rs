//! Augmented-Lagrangian (Powell–Hestenes–Rockafellar) method for smooth objectives with bounds
//! and inequality constraints $g(p) \le 0$ ([`pkm_traits::Constraints`]):
//! $$ \mathcal{L}_\rho(p, \mu) = f(p) + \frac{1}{2\rho}\sum_i
//!    \big(\max(0, \mu_i + \rho g_i(p))^2 - \mu_i^2\big), $$
//! minimised over the box by a spectral projected gradient with central-difference gradients
//! in the scaled variables $z_j = x_j / s_j$ of [`crate::scaling`] (by default $s_j$ = the
//! width of the box side, so lengths in metres and angles in degrees move alike), then $\mu_i \leftarrow \max(0, \mu_i + \rho g_i)$; $\rho$ grows
//! by [`PENALTY_GROWTH`] up to [`MAX_PENALTY`] when the violation exceeds the feasibility
//! tolerance and did not shrink by [`REQUIRED_VIOLATION_DECREASE`].
//!
//! The first penalty is set at the start $x_0$ (multipliers 0) from the scaled gradients
//! $\nabla_z = S \nabla_x$ (central differences):
//! $$ \rho_0 = \min\Big(\rho_{\max}, \max\big(\rho_{\min}, \max_i
//!    \frac{-\nabla_z f \cdot \nabla_z g_i}{\delta\, \lVert \nabla_z g_i \rVert^3}\big)\Big), $$
//! $\delta =$ [`FIRST_VIOLATION_TARGET`], $\rho_{\min} =$ [`INITIAL_PENALTY`],
//! $\rho_{\max} =$ [`MAX_PENALTY`]. On the linear model along the normal of constraint $i$,
//! the first subproblem $\min f + \tfrac{\rho}{2} g_i^2$ stops at the scaled distance
//! $t = -\nabla_z f \cdot \nabla_z g_i / (\rho \lVert \nabla_z g_i \rVert^3)$ outside the
//! constraint when $f$ pushes across it, and $\rho_0$ keeps $t \le \delta$. A fixed first
//! penalty does not: where $f$ grows faster than the quadratic penalty across a constraint
//! (a volume $\propto R^3$ beyond a reach limit $R \le 1$) the first subproblem runs to the far
//! corner of the box, and the scaled steps carry every other variable across its whole range on
//! the way, so the run loses the basin of its start (issue 20: Stamper's antiparallel legs). A maximisation ([`Sense::Maximise`]) minimises $-f$. (argmin offers no constrained SQP; the `cobyla` crate is
//! derivative-free and slower on these smooth 6-D problems, so neither was taken.)

use crate::OptimizeError;
use crate::finite_differences::{self, RELATIVE_STEP};
use crate::multistart::LocalResult;
use crate::scaling::{CharacteristicScale, variable_scales};
use crate::sense::Sense;
use crate::spg::{InnerSettings, minimise_in_box, project};
use crate::termination::Termination;
use pkm_traits::{Constraints, InvalidInput, ObjectiveError, Progress};
use serde::{Deserialize, Serialize};
use std::cell::Cell;

/// Smallest penalty $\rho$ of the first outer iteration (the rule of the module docs may start
/// higher).
pub const INITIAL_PENALTY: f64 = 10.0;
/// Violation, as a distance in scaled units (box widths under the default scaling), that the
/// first outer iteration's penalty allows along each constraint's normal (the first-penalty
/// rule of the module docs).
pub const FIRST_VIOLATION_TARGET: f64 = 1e-2;
/// Factor by which $\rho$ grows after an outer iteration that did not shrink the violation
/// enough.
pub const PENALTY_GROWTH: f64 = 10.0;
/// Largest penalty: beyond it the augmented Lagrangian is too ill-conditioned for the inner
/// solver.
pub const MAX_PENALTY: f64 = 1e10;
/// $\rho$ grows unless the largest violation shrinks to this fraction of the previous one or
/// is within [`AugmentedLagrangianSettings::feasibility`].
pub const REQUIRED_VIOLATION_DECREASE: f64 = 0.25;
/// The multipliers have settled when no $\mu_i$ changed by more than this relative amount
/// $(1 + \max_i \mu_i)$ in the last outer iteration.
pub const MULTIPLIER_TOLERANCE: f64 = 1e-6;
/// Outer iterations in a row at [`MAX_PENALTY`] whose violation did not shrink below
/// $(1 - $ [`STALL_DECREASE`]$)$ times the previous one, or that left the design and the
/// multipliers unchanged, after which the run has stalled: the penalty cannot grow any more,
/// so further iterations cannot make the design feasible (an infeasible set), whatever
/// [`AugmentedLagrangianSettings::max_outer`] allows.
pub const MAX_STALLED_OUTER: usize = 5;
/// Relative decrease of the largest violation that counts as progress at [`MAX_PENALTY`].
pub const STALL_DECREASE: f64 = 1e-3;

/// Settings of [`augmented_lagrangian`]. In a study file (e.g. `[optimize.solver]`) every key
/// is optional, with the defaults below.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, default)]
pub struct AugmentedLagrangianSettings {
    /// Relative finite-difference step (times each box width). Default
    /// [`crate::finite_differences::RELATIVE_STEP`]; use ~1e-3 for Monte Carlo objectives on
    /// common random numbers.
    pub fd_step: f64,
    /// Inner stopping tolerance on the projected step $\lVert S^{-1} d \rVert_\infty$, in scaled
    /// units (box widths under the default scaling). Default 1e-9.
    pub tolerance: f64,
    /// Largest admissible constraint violation of the returned design. Default 1e-6.
    pub feasibility: f64,
    /// Outer (multiplier) iterations. Default 30.
    pub max_outer: usize,
    /// Inner iterations per outer one. Default 200.
    pub max_inner: usize,
    /// Characteristic scale of each variable, in its unit (e.g. `scale = [1e-3, 1e3]`); one
    /// value per variable, finite and $> 0$. Default: none, each variable scaled by the width
    /// of its box side ([`crate::scaling`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<CharacteristicScale>,
}

impl Default for AugmentedLagrangianSettings {
    fn default() -> Self {
        Self {
            fd_step: RELATIVE_STEP,
            tolerance: 1e-9,
            feasibility: 1e-6,
            max_outer: 30,
            max_inner: 200,
            scale: None,
        }
    }
}

/// A constrained optimum.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConstrainedResult {
    /// The design.
    pub design: Vec<f64>,
    /// $f$ at the design.
    pub value: f64,
    /// $g$ at the design (all $\le$ the feasibility tolerance).
    pub constraints: Vec<f64>,
    /// Multiplier estimates $\mu_i \ge 0$; positive for active constraints.
    pub multipliers: Vec<f64>,
    /// Why the outer iteration stopped: [`Termination::Converged`] (criterion
    /// `"feasible with settled multipliers"`), [`Termination::MaxIterations`] after
    /// [`AugmentedLagrangianSettings::max_outer`] outer iterations with a feasible but
    /// possibly unsettled design, or [`Termination::Stalled`] after [`MAX_STALLED_OUTER`] outer
    /// iterations without progress. When the last outer iterate is infeasible, the design is the
    /// last feasible outer iterate (with its constraints and multipliers), as NLopt's AUGLAG
    /// keeps its best feasible point; a run that never reached a feasible outer iterate is an
    /// error instead.
    pub termination: Termination,
    /// Outer (multiplier) iterations spent.
    pub outer_iterations: usize,
    /// Inner (projected-gradient) iterations spent over all outer ones.
    pub inner_iterations: usize,
    /// Evaluations of the objective value (each with its constraints) over the whole run.
    pub evaluations: usize,
}

impl LocalResult for ConstrainedResult {
    fn design(&self) -> &[f64] {
        &self.design
    }
    fn value(&self) -> f64 {
        self.value
    }
    fn termination(&self) -> Termination {
        self.termination
    }
}

/// Minimises (or, with [`Sense::Maximise`], maximises) `problem` from `start` subject to its
/// bounds and inequalities.
///
/// `progress` hears one task of [`AugmentedLagrangianSettings::max_outer`] units, advanced
/// once per outer iteration, and is asked for cancellation before every inner iteration.
///
/// # Errors
/// [`OptimizeError::Invalid`] for a start of the wrong length, settings that fail
/// [`AugmentedLagrangianSettings::validate`] or a `scale` without one value per variable;
/// [`OptimizeError::NoFeasibleDesign`] when no outer iterate met every constraint within
/// `settings.feasibility` (an infeasible constraint set, or too few outer iterations: no
/// design is returned);
/// [`OptimizeError::Objective`] for an objective failure other than infeasibility, and for a
/// constraint or final value that is NaN or infinite; [`OptimizeError::Cancelled`] once
/// `progress` is cancelled.
///
/// # Example
/// ```
/// use pkm_optimizers::{AugmentedLagrangianSettings, Sense, augmented_lagrangian};
/// use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};
/// // min x² + y² s.t. x + y >= 1: optimum (½, ½).
/// struct P([Bounds; 2]);
/// impl Objective for P {
///     fn dimension(&self) -> usize { 2 }
///     fn bounds(&self) -> &[Bounds] { &self.0 }
///     fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> { Ok(p[0] * p[0] + p[1] * p[1]) }
/// }
/// impl Constraints for P {
///     fn n_constraints(&self) -> usize { 1 }
///     fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
///         g[0] = 1.0 - p[0] - p[1];
///         Ok(())
///     }
/// }
/// let b = Bounds::new(-5.0, 5.0).unwrap();
/// let settings = AugmentedLagrangianSettings::default();
/// let r = augmented_lagrangian(&P([b, b]), Sense::Minimise, &[2.0, -1.0], &settings, &Silent)
///     .unwrap();
/// assert!((r.design[0] - 0.5).abs() < 1e-5 && (r.multipliers[0] - 1.0).abs() < 1e-3);
/// assert!(r.termination.converged());
/// ```
pub fn augmented_lagrangian<P: Constraints>(
    problem: &P,
    sense: Sense,
    start: &[f64],
    settings: &AugmentedLagrangianSettings,
    progress: &dyn Progress,
) -> Result<ConstrainedResult, OptimizeError> {
    check_start(problem, start)?;
    settings.validate()?;
    let scale = variable_scales(problem.bounds(), settings.scale.as_ref())?;
    progress.start("augmented Lagrangian", settings.max_outer as u64);
    let result = solve(problem, sense, start, settings, scale, progress);
    progress.finish();
    result
}

fn solve<P: Constraints>(
    problem: &P,
    sense: Sense,
    start: &[f64],
    settings: &AugmentedLagrangianSettings,
    scale: Vec<f64>,
    progress: &dyn Progress,
) -> Result<ConstrainedResult, OptimizeError> {
    let bounds = problem.bounds();
    let m = problem.n_constraints();
    let mut x = start.to_vec();
    project(bounds, &mut x);
    let mut mu = vec![0.0; m];
    let mut g = vec![0.0; m];
    let mut violation = f64::INFINITY;
    let mut termination = Termination::MaxIterations;
    let mut last_feasible: Option<FeasibleIterate> = None;
    let evaluations = Cell::new(0_usize);
    let objective = |p: &[f64]| -> Result<f64, ObjectiveError> {
        evaluations.set(evaluations.get() + 1);
        Ok(sense.minimised(problem.value(p)?))
    };
    let mut rho = initial_penalty(problem, &objective, &x, settings.fd_step, &scale)?;
    let inner = InnerSettings {
        fd_step: settings.fd_step,
        tolerance: settings.tolerance,
        max_iterations: settings.max_inner,
        scale,
    };
    let (mut outer_iterations, mut inner_iterations) = (0, 0);
    let mut stalled = 0;
    while outer_iterations < settings.max_outer {
        progress.check()?;
        outer_iterations += 1;
        progress.advance(1);
        let lagrangian = |p: &[f64]| -> Result<f64, ObjectiveError> {
            let mut gp = vec![0.0; m];
            problem.inequalities(p, &mut gp)?;
            let penalty: f64 = gp
                .iter()
                .zip(&mu)
                .map(|(gi, mi)| (mi + rho * gi).max(0.0).powi(2) - mi * mi)
                .sum();
            Ok(objective(p)? + penalty / (2.0 * rho))
        };
        let (previous_x, previous_mu) = (x.clone(), mu.clone());
        let (_, spent) = minimise_in_box(&lagrangian, bounds, &mut x, &inner, progress)?;
        inner_iterations += spent;
        problem.inequalities(&x, &mut g)?;
        // `f64::max` drops a NaN: a NaN constraint must not read as satisfied.
        if let Some(&value) = g.iter().find(|gi| !gi.is_finite()) {
            return Err(ObjectiveError::NonFinite { value }.into());
        }
        let new_violation = g.iter().fold(0.0_f64, |v, gi| v.max(*gi));
        let step: f64 = mu
            .iter_mut()
            .zip(&g)
            .map(|(mi, gi)| {
                let next = (*mi + rho * gi).max(0.0);
                let change = (next - *mi).abs();
                *mi = next;
                change
            })
            .fold(0.0, f64::max);
        if new_violation <= settings.feasibility {
            last_feasible = Some(FeasibleIterate {
                design: x.clone(),
                constraints: g.clone(),
                multipliers: mu.clone(),
            });
        }
        if new_violation <= settings.feasibility
            && step <= MULTIPLIER_TOLERANCE * (1.0 + mu.iter().fold(0.0, |a: f64, b| a.max(*b)))
        {
            violation = new_violation;
            termination = Termination::Converged {
                criterion: "feasible with settled multipliers",
            };
            break;
        }
        let fixed_point = x == previous_x && mu == previous_mu;
        let no_progress =
            rho >= MAX_PENALTY && !(new_violation < (1.0 - STALL_DECREASE) * violation);
        stalled = if fixed_point || no_progress {
            stalled + 1
        } else {
            0
        };
        // A design already within the feasibility tolerance needs no larger penalty: growing
        // it there only amplifies the inner solve's error in the multiplier update.
        if new_violation > settings.feasibility
            && new_violation > REQUIRED_VIOLATION_DECREASE * violation
        {
            rho = (rho * PENALTY_GROWTH).min(MAX_PENALTY);
        }
        violation = new_violation;
        if stalled >= MAX_STALLED_OUTER {
            termination = Termination::Stalled;
            break;
        }
    }
    if !(violation <= settings.feasibility) {
        let Some(feasible) = last_feasible else {
            let after = match termination {
                Termination::Stalled => format!(
                    "the outer iteration stalled at the largest penalty ({MAX_STALLED_OUTER} \
                     iterations without progress)"
                ),
                _ => "the last outer iteration".to_owned(),
            };
            return Err(OptimizeError::NoFeasibleDesign {
                evaluations: evaluations.get(),
                last_reason: format!("largest constraint violation {violation:.3e} after {after}"),
            });
        };
        (x, g, mu) = (feasible.design, feasible.constraints, feasible.multipliers);
    }
    let value = problem.value(&x)?;
    if !value.is_finite() {
        return Err(ObjectiveError::NonFinite { value }.into());
    }
    Ok(ConstrainedResult {
        value,
        design: x,
        constraints: g,
        multipliers: mu,
        termination,
        outer_iterations,
        inner_iterations,
        evaluations: evaluations.get() + 1,
    })
}

/// An outer iterate within the feasibility tolerance: the fallback result when a later one
/// is not ([`ConstrainedResult::termination`]).
struct FeasibleIterate {
    design: Vec<f64>,
    constraints: Vec<f64>,
    multipliers: Vec<f64>,
}

/// The penalty of the first outer iteration at the start `x` (multipliers 0): $\rho_0$ of the
/// module docs.
fn initial_penalty<P: Constraints, F>(
    problem: &P,
    objective: &F,
    x: &[f64],
    fd_step: f64,
    scale: &[f64],
) -> Result<f64, OptimizeError>
where
    F: Fn(&[f64]) -> Result<f64, ObjectiveError>,
{
    let (bounds, m, n) = (problem.bounds(), problem.n_constraints(), x.len());
    if m == 0 {
        return Ok(INITIAL_PENALTY);
    }
    let gradient = finite_differences::gradient(objective, bounds, x, objective(x)?, fd_step)?;
    let jacobian = finite_differences::jacobian(
        &|p: &[f64], out: &mut [f64]| problem.inequalities(p, out),
        bounds,
        x,
        m,
        fd_step,
    )?;
    let rho = jacobian
        .chunks_exact(n)
        .map(|row| {
            let (push, norm2) = row
                .iter()
                .zip(&gradient)
                .zip(scale)
                .fold((0.0, 0.0), |(push, norm2), ((dg, df), s)| {
                    (push - s * s * df * dg, norm2 + (s * dg).powi(2))
                });
            push / (FIRST_VIOLATION_TARGET * norm2 * norm2.sqrt())
        })
        .filter(|r| r.is_finite())
        .fold(INITIAL_PENALTY, f64::max);
    Ok(rho.min(MAX_PENALTY))
}

fn check_start<P: Constraints>(problem: &P, start: &[f64]) -> Result<(), OptimizeError> {
    if start.len() != problem.dimension() || problem.bounds().len() != start.len() {
        return Err(InvalidInput::new(
            "start.len()",
            start.len() as f64,
            "must equal the problem dimension",
        )
        .into());
    }
    Ok(())
}

impl AugmentedLagrangianSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for a step, tolerance or feasibility that is not finite
    /// and positive, a step of 0.1 or more, or no outer or inner iteration.
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::AugmentedLagrangianSettings;
    /// assert!(AugmentedLagrangianSettings::default().validate().is_ok());
    /// let s = AugmentedLagrangianSettings { feasibility: -1.0, ..Default::default() };
    /// assert!(s.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), OptimizeError> {
        for (setting, value) in [
            ("fd_step", self.fd_step),
            ("tolerance", self.tolerance),
            ("feasibility", self.feasibility),
        ] {
            InvalidInput::require_positive(setting, value)?;
        }
        if !((finite_differences::MIN_RELATIVE_STEP..0.1).contains(&self.fd_step)) {
            return Err(InvalidInput::new(
                "fd_step",
                self.fd_step,
                "must be in [f64::EPSILON, 0.1)",
            )
            .into());
        }
        InvalidInput::require_nonzero_count("max_outer", self.max_outer)?;
        InvalidInput::require_nonzero_count("max_inner", self.max_inner)?;
        Ok(())
    }
}
