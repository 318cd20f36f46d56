//! Bounded Levenberg–Marquardt for minimising *or maximising* a sum of squares
//! $f(p) = \sum_i r_i(p)^2 = \lVert r(p) \rVert^2$ over a box, with a KKT report at the optimum
//! (Wolf & Shoham §3: "Gauss–Newton").
//!
//! Each iteration solves the damped normal equations on the free variables in the scaled
//! variables $z = S^{-1} p$ of [`crate::scaling`] ($S = \mathrm{diag}(s)$, by default the box
//! widths),
//! $$ (A_z^\top A_z + \mu I)\,\delta_z = \sigma A_z^\top r, \qquad A_z = A S, \quad
//!    A = \partial r / \partial p, \quad \delta = S \delta_z, $$
//! that is Marquardt's $(A^\top A + \mu S^{-2})\,\delta = \sigma A^\top r$, so the damping
//! treats a variable in degrees over 345 and one in metres over 0.3 alike,
//! ($A$ from [`Residuals::residual_jacobian`] when the problem provides it, else central
//! differences of the residuals with step [`LmSettings::fd_step`]),
//! with $\sigma = -1$ to minimise and $\sigma = +1$ to maximise (for a maximisation the
//! Gauss–Newton matrix is a positive preconditioner of the ascent direction $A^\top r$), then
//! projects $p + \delta$ onto the box. A variable on a bound whose gradient pushes outward is
//! held there (the active set). $\mu$ follows the Levenberg–Marquardt rule: divided on success,
//! multiplied on failure.
//!
//! Hand-written because argmin's Gauss–Newton and Levenberg–Marquardt-style solvers are
//! unconstrained and minimise only; the box projection, the maximisation and the KKT report
//! (gradient, active bounds, reduced-Hessian eigenvalues) are what the paper's checks need.
//! The dynamic-size normal equations and the Hessian eigenvalues use faer.

use crate::error::OptimizeError;
use crate::finite_differences::{self, HESSIAN_RELATIVE_STEP, RELATIVE_STEP};
use crate::multistart::{LocalResult, Multistart, multistart};
use crate::scaling::{CharacteristicScale, variable_scales};
use crate::sense::Sense;
use crate::termination::Termination;
use faer::Mat;
use faer::Side;
use faer::linalg::solvers::Solve;
use pkm_traits::{Bounds, InvalidInput, ObjectiveError, Progress, Residuals};
use serde::{Deserialize, Serialize};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Initial damping relative to the largest diagonal entry of $A_z^\top A_z$ (scaled variables):
/// $\mu_0 = 10^{-3} \max_k (A_z^\top A_z)_{kk}$ (Marquardt's usual scale).
pub const INITIAL_DAMPING_SCALE: f64 = 1e-3;
/// Floor of $\max_k (A^\top A)_{kk}$ in $\mu_0$, so a vanishing Jacobian still starts with
/// $\mu_0 > 0$.
pub const MIN_NORMAL_DIAGONAL: f64 = 1e-12;
/// $\mu \leftarrow \mu / 3$ after a successful step.
pub const DAMPING_DECREASE: f64 = 3.0;
/// $\mu \leftarrow 4 \mu$ after a rejected step.
pub const DAMPING_INCREASE: f64 = 4.0;
/// Damping at which the search for an improving step gives up ([`Termination::Stalled`]): the
/// step $\delta \approx \sigma A^\top r / \mu$ is then negligible.
pub const MAX_DAMPING: f64 = 1e16;
/// A variable within $10^{-12}(1 + w)$ of a bound ($w$ the interval width) sits on it
/// ([`ActiveBound`]).
pub const BOUND_TOLERANCE: f64 = 1e-12;

/// Where a variable sits at the reported optimum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ActiveBound {
    /// Strictly inside its interval.
    Free,
    /// On its lower bound.
    Lower,
    /// On its upper bound.
    Upper,
}

/// Settings of [`levenberg_marquardt`]. In a study file (e.g. `[task.solver]`) every key is
/// optional, with the defaults below: `max_iterations = 200`, `tolerance = 1e-12`,
/// `gradient_tolerance = 1e-6`, `fd_step = 1e-6`, no `scale` (the box widths).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, default)]
pub struct LmSettings {
    /// Largest number of iterations (at least 1).
    pub max_iterations: usize,
    /// Stop when a step changes $f$ by less than this relative amount, $|\Delta f| \le
    /// \tau (1 + |f|)$, and the projected gradient at the new point does not already meet
    /// [`LmSettings::gradient_tolerance`] (finite and $> 0$).
    pub tolerance: f64,
    /// Stop when the projected gradient in scaled variables is small,
    /// $\max_{j\ \text{free}} |s_j\, \partial f / \partial p_j| \le \tau_g (1 + |f|)$
    /// (finite and $> 0$). Default $10^{-6} = \sqrt{10^{-12}}$: near an optimum
    /// $|f - f^*| \approx \tfrac12 g_z^\top H_z^{-1} g_z$, so this gradient matches the change
    /// in $f$ of the default [`LmSettings::tolerance`] for a Hessian of order 1 in scaled
    /// variables, and it lies well above the rounding noise of a central difference with the
    /// default step ($\approx \varepsilon_{\mathrm{mach}} / 10^{-6} \approx 2 \times 10^{-10}$
    /// relative to $f$), so the test fires with finite-difference Jacobians too.
    pub gradient_tolerance: f64,
    /// Finite-difference step, relative to each interval width (for problems without
    /// [`Residuals::residual_jacobian`]); in $(0, 0.1)$. Default
    /// [`finite_differences::RELATIVE_STEP`].
    pub fd_step: f64,
    /// Characteristic scale $s_j$ of each variable, in its unit (e.g. `scale = [1e-3, 1e3]`);
    /// one value per variable, finite and $> 0$. Default: none, each variable scaled by the
    /// width of its box side ([`crate::scaling`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale: Option<CharacteristicScale>,
}

impl Default for LmSettings {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            tolerance: 1e-12,
            gradient_tolerance: 1e-6,
            fd_step: RELATIVE_STEP,
            scale: None,
        }
    }
}

impl LmSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for no iteration, a tolerance that is not finite and
    /// positive, or a step outside $(0, 0.1)$. (A `scale` is checked against the problem's
    /// dimension when a solver starts.)
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::LmSettings;
    /// assert!(LmSettings::default().validate().is_ok());
    /// assert!(LmSettings { tolerance: f64::NAN, ..LmSettings::default() }.validate().is_err());
    /// assert!(LmSettings { max_iterations: 0, ..LmSettings::default() }.validate().is_err());
    /// ```
    pub fn validate(&self) -> Result<(), OptimizeError> {
        InvalidInput::require_nonzero_count("max_iterations", self.max_iterations)?;
        InvalidInput::require_positive("tolerance", self.tolerance)?;
        InvalidInput::require_positive("gradient_tolerance", self.gradient_tolerance)?;
        if !((finite_differences::MIN_RELATIVE_STEP..0.1).contains(&self.fd_step)) {
            return Err(InvalidInput::new(
                "fd_step",
                self.fd_step,
                "must be in [f64::EPSILON, 0.1)",
            )
            .into());
        }
        Ok(())
    }
}

/// A local optimum with the first- and second-order checks the paper reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LocalOptimum {
    /// The design.
    pub design: Vec<f64>,
    /// $f = \lVert r \rVert^2$ there.
    pub value: f64,
    /// $\nabla f = 2 A^\top r$, with $A$ from [`Residuals::residual_jacobian`] when the problem
    /// provides it, else from central differences.
    pub gradient: Vec<f64>,
    /// Which bound each variable sits on.
    pub active: Vec<ActiveBound>,
    /// Eigenvalues (ascending) of the Hessian of $f$ restricted to the free variables: all
    /// $\le 0$ at a maximum, $\ge 0$ at a minimum, up to finite-difference noise.
    pub reduced_hessian_eigenvalues: Vec<f64>,
    /// Iterations spent.
    pub iterations: usize,
    /// Evaluations of the residuals (a call of [`Residuals::residuals`], or of
    /// [`Residuals::residual_jacobian`] that provided a Jacobian), including those of the final
    /// report (gradient and reduced Hessian).
    pub evaluations: usize,
    /// Why the iteration stopped: [`Termination::Converged`] with criterion
    /// `"projected gradient"`, `"every variable held on a bound"` or `"relative change in f"`;
    /// [`Termination::MaxIterations`] after [`LmSettings::max_iterations`] iterations; or
    /// [`Termination::Stalled`] when the damping reached [`MAX_DAMPING`] without an improving
    /// step.
    pub termination: Termination,
}

impl LocalOptimum {
    /// Largest $|\partial f/\partial p_j|$ over the free variables (zero at a KKT point).
    pub fn free_gradient_norm(&self) -> f64 {
        self.gradient
            .iter()
            .zip(&self.active)
            .filter(|(_, a)| **a == ActiveBound::Free)
            .fold(0.0, |m, (g, _)| m.max(g.abs()))
    }
}

impl LocalResult for LocalOptimum {
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

/// Runs bounded Levenberg–Marquardt from `start` (clamped into the box), toward the smallest or
/// the largest $\lVert r \rVert^2$ as `sense` says.
///
/// `progress` hears one task of [`LmSettings::max_iterations`] units, advanced once per
/// iteration, and is asked for cancellation before every evaluation of a trial step.
///
/// # Errors
/// [`OptimizeError::Invalid`] for settings that fail [`LmSettings::validate`], a `scale`
/// without one value per variable, or a start that is not finite; [`OptimizeError::Objective`] for a start of the wrong length; [`OptimizeError::Objective`] when the residuals fail;
/// [`OptimizeError::Numerical`] when the damped normal matrix is not positive definite or the
/// eigenvalues of the reduced Hessian do not converge; [`OptimizeError::Cancelled`] once
/// `progress` is cancelled (a cancelled run returns no design, as every solver of this crate).
///
/// # Example
/// ```
/// use pkm_optimizers::{LmSettings, Sense, levenberg_marquardt};
/// use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals, Silent};
/// struct Paraboloid([Bounds; 2]);
/// impl Objective for Paraboloid {
///     fn dimension(&self) -> usize { 2 }
///     fn bounds(&self) -> &[Bounds] { &self.0 }
///     fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> { Ok(p[0] * p[0] + p[1] * p[1]) }
/// }
/// impl Residuals for Paraboloid {
///     fn n_residuals(&self) -> usize { 2 }
///     fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
///         r.copy_from_slice(p);
///         Ok(())
///     }
/// }
/// let b = Bounds::new(-1.0, 2.0).unwrap();
/// let problem = Paraboloid([b, b]);
/// let settings = LmSettings::default();
/// let max = levenberg_marquardt(&problem, Sense::Maximise, &[0.5, 0.4], &settings, &Silent).unwrap();
/// assert!((max.value - 8.0).abs() < 1e-9);
/// let min = levenberg_marquardt(&problem, Sense::Minimise, &[0.5, 0.4], &settings, &Silent).unwrap();
/// assert!(min.value < 1e-12 && min.termination.converged());
/// ```
pub fn levenberg_marquardt<P: Residuals + ?Sized>(
    problem: &P,
    sense: Sense,
    start: &[f64],
    settings: &LmSettings,
    progress: &dyn Progress,
) -> Result<LocalOptimum, OptimizeError> {
    settings.validate()?;
    progress.start("Levenberg-Marquardt", settings.max_iterations as u64);
    let counted = Counted::new(problem);
    let result = run(&counted, sense, start, settings, progress);
    progress.finish();
    result
}

/// The problem with a count of its residual evaluations.
struct Counted<'a, P: ?Sized> {
    problem: &'a P,
    evaluations: Cell<usize>,
}

impl<'a, P: Residuals + ?Sized> Counted<'a, P> {
    fn new(problem: &'a P) -> Self {
        Self {
            problem,
            evaluations: Cell::new(0),
        }
    }

    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        self.evaluations.set(self.evaluations.get() + 1);
        self.problem.residuals(p, r)
    }

    fn residual_jacobian(
        &self,
        p: &[f64],
        r: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, ObjectiveError> {
        let provided = self.problem.residual_jacobian(p, r, jacobian)?;
        if provided {
            self.evaluations.set(self.evaluations.get() + 1);
        }
        Ok(provided)
    }
}

fn run<P: Residuals + ?Sized>(
    problem: &Counted<'_, P>,
    sense: Sense,
    start: &[f64],
    settings: &LmSettings,
    progress: &dyn Progress,
) -> Result<LocalOptimum, OptimizeError> {
    validate_start(problem.problem, start)?;
    let bounds = problem.problem.bounds();
    let scale = variable_scales(bounds, settings.scale.as_ref())?;
    progress.check()?;
    let sign = sense.sign();
    let mut p: Vec<f64> = start.iter().zip(bounds).map(|(x, b)| b.clamp(*x)).collect();
    let mut f = sum_of_squares(problem, &p)?;
    let mut mu = 0.0;
    let mut iterations = 0;
    // Why to stop once the projected gradient at `p` is known not to be small: a small change
    // in f is declared only after the gradient test at the new point had its chance (in the
    // next iteration, when one is left).
    let mut pending: Option<Termination> = None;
    let mut termination = None;
    while iterations < settings.max_iterations {
        progress.check()?;
        iterations += 1;
        progress.advance(1);
        let (r, a) = residuals_and_jacobian(problem, &p, settings.fd_step)?;
        let grad = gradient_from(&r, &a);
        let free = free_set(&p, &grad, bounds, sign);
        // max over the free variables of |∂f/∂z_j| = |s_j ∂f/∂p_j|.
        let projected = free
            .iter()
            .map(|&j| (grad[j] * scale[j]).abs())
            .fold(0.0, f64::max);
        termination = if free.is_empty() {
            Some(Termination::Converged {
                criterion: "every variable held on a bound",
            })
        } else if projected <= settings.gradient_tolerance * (1.0 + f.abs()) {
            Some(Termination::Converged {
                criterion: "projected gradient",
            })
        } else {
            pending
        };
        if termination.is_some() {
            break;
        }
        let system = NormalSystem::new(&r, &a, free, &scale, sign);
        if mu == 0.0 {
            mu = INITIAL_DAMPING_SCALE * system.largest_diagonal();
        }
        let Some(gain) = damped_step(problem, &system, (&mut p, &mut f), &mut mu, progress)? else {
            termination = Some(Termination::Stalled);
            break;
        };
        pending =
            (gain <= settings.tolerance * (1.0 + f.abs())).then_some(Termination::Converged {
                criterion: "relative change in f",
            });
    }
    let termination = termination
        .or(pending)
        .unwrap_or(Termination::MaxIterations);
    report(problem, p, f, iterations, termination, settings)
}

/// One Levenberg–Marquardt step: raises $\mu$ until a damped step in scaled variables improves
/// $f$ in the direction of the system's sign, then moves `p` there and lowers $\mu$. Returns the
/// gain $|\Delta f|$, or `None` when $\mu$ reached [`MAX_DAMPING`] without an improving step.
fn damped_step<P: Residuals + ?Sized>(
    problem: &Counted<'_, P>,
    system: &NormalSystem<'_>,
    (p, f): (&mut Vec<f64>, &mut f64),
    mu: &mut f64,
    progress: &dyn Progress,
) -> Result<Option<f64>, OptimizeError> {
    let bounds = problem.problem.bounds();
    while *mu < MAX_DAMPING {
        progress.check()?;
        let delta = solve_damped(&system.ata, &system.atr, *mu, system.sign)?;
        let mut trial = p.clone();
        for (k, &j) in system.free.iter().enumerate() {
            // δp_j = s_j δz_j.
            trial[j] = bounds[j].clamp(p[j] + system.scale[j] * delta[k]);
        }
        let f_trial = sum_of_squares(problem, &trial)?;
        if system.sign * (f_trial - *f) > 0.0 {
            let gain = (f_trial - *f).abs();
            *p = trial;
            *f = f_trial;
            *mu /= DAMPING_DECREASE;
            return Ok(Some(gain));
        }
        *mu *= DAMPING_INCREASE;
    }
    Ok(None)
}

/// The best of the local optima of a multistart, with the counts of the whole run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MultistartOptimum {
    /// The best local optimum (its [`LocalOptimum::termination`] says why that run stopped).
    pub best: LocalOptimum,
    /// The start it came from (from 0, in [`Multistart::start_points`] order).
    pub best_start: usize,
    /// Starts run.
    pub starts: usize,
    /// Starts that ended on an infeasible design ([`ObjectiveError::Infeasible`]).
    pub infeasible_starts: usize,
    /// Residual evaluations over all starts, failed ones included.
    pub evaluations: usize,
}

/// Multistart [`levenberg_marquardt`] over the starts of `starts`, in parallel
/// ([`multistart()`]); returns the best optimum by [`crate::MultistartRun::best`] (in the sense of
/// `sense`, ties to the earlier start, independent of the thread count). For every start's
/// outcome, call [`multistart()`] with [`levenberg_marquardt`] directly.
///
/// `progress` hears one task with a unit per start, advanced as each start finishes, and is
/// asked for cancellation inside every start as in [`levenberg_marquardt`].
///
/// # Errors
/// [`OptimizeError::Invalid`] when `starts` fails [`Multistart::start_points`] or
/// `settings` [`LmSettings::validate`] (before any start runs); when no start succeeded, the
/// first failure that is not an infeasible design, else [`OptimizeError::NoFeasibleDesign`];
/// [`OptimizeError::Cancelled`] once `progress` is cancelled.
pub fn multistart_levenberg_marquardt<P: Residuals + ?Sized>(
    problem: &P,
    sense: Sense,
    starts: &Multistart,
    settings: &LmSettings,
    progress: &dyn Progress,
) -> Result<MultistartOptimum, OptimizeError> {
    let points = starts.start_points(problem.bounds())?;
    settings.validate()?;
    let evaluations = AtomicUsize::new(0);
    let run = multistart(points, progress, |start, cancel| {
        let counted = Counted::new(problem);
        let outcome = run(&counted, sense, start, settings, cancel);
        evaluations.fetch_add(counted.evaluations.get(), Ordering::Relaxed);
        outcome
    })?;
    let (best_start, best) = run.best(sense)?;
    Ok(MultistartOptimum {
        best: best.clone(),
        best_start,
        starts: run.starts.len(),
        infeasible_starts: run.infeasible(),
        evaluations: evaluations.into_inner(),
    })
}

fn validate_start<P: Residuals + ?Sized>(problem: &P, start: &[f64]) -> Result<(), OptimizeError> {
    problem.check_dimension(start)?;
    if let Some(&x) = start.iter().find(|x| !x.is_finite()) {
        return Err(InvalidInput::new("start", x, "must be finite").into());
    }
    Ok(())
}

fn sum_of_squares<P: Residuals + ?Sized>(
    problem: &Counted<'_, P>,
    p: &[f64],
) -> Result<f64, ObjectiveError> {
    let mut r = vec![0.0; problem.problem.n_residuals()];
    problem.residuals(p, &mut r)?;
    let f: f64 = r.iter().map(|x| x * x).sum();
    if f.is_finite() {
        Ok(f)
    } else {
        Err(ObjectiveError::NonFinite { value: f })
    }
}

/// $r(p)$ and $A = \partial r / \partial p$: the problem's own Jacobian when
/// [`Residuals::residual_jacobian`] provides one, else [`finite_differences::jacobian`].
fn residuals_and_jacobian<P: Residuals + ?Sized>(
    problem: &Counted<'_, P>,
    p: &[f64],
    rel: f64,
) -> Result<(Vec<f64>, Mat<f64>), OptimizeError> {
    let (m, n) = (problem.problem.n_residuals(), p.len());
    let mut r = vec![0.0; m];
    let mut analytic = vec![0.0; m * n];
    if problem.residual_jacobian(p, &mut r, &mut analytic)? {
        if let Some(value) = analytic.iter().copied().find(|v| !v.is_finite()) {
            return Err(ObjectiveError::NonFinite { value }.into());
        }
        return Ok((r, Mat::from_fn(m, n, |i, j| analytic[i * n + j])));
    }
    problem.residuals(p, &mut r)?;
    let bounds = problem.problem.bounds();
    let a = finite_differences::jacobian(
        &|q: &[f64], out: &mut [f64]| problem.residuals(q, out),
        bounds,
        p,
        m,
        rel,
    )?;
    Ok((r, Mat::from_fn(m, n, |i, j| a[i * n + j])))
}

fn gradient_from(r: &[f64], a: &Mat<f64>) -> Vec<f64> {
    (0..a.ncols())
        .map(|j| 2.0 * (0..r.len()).map(|i| a[(i, j)] * r[i]).sum::<f64>())
        .collect()
}

fn at_bound(b: &Bounds, x: f64) -> ActiveBound {
    let eps = BOUND_TOLERANCE * (1.0 + b.width());
    if x <= b.lower() + eps {
        ActiveBound::Lower
    } else if x >= b.upper() - eps {
        ActiveBound::Upper
    } else {
        ActiveBound::Free
    }
}

/// Variables that may move: inside the box, or on a bound with the improving direction inward.
fn free_set(p: &[f64], grad: &[f64], bounds: &[Bounds], sign: f64) -> Vec<usize> {
    (0..p.len())
        .filter(|&j| match at_bound(&bounds[j], p[j]) {
            ActiveBound::Free => true,
            ActiveBound::Lower => sign * grad[j] > 0.0,
            ActiveBound::Upper => sign * grad[j] < 0.0,
        })
        .collect()
}

/// The normal equations of one iteration in scaled variables: $A_z^\top A_z$ and
/// $A_z^\top r$ over the free columns of $A_z = A S$.
struct NormalSystem<'s> {
    ata: Mat<f64>,
    atr: Mat<f64>,
    free: Vec<usize>,
    scale: &'s [f64],
    /// $\sigma$: $-1$ to minimise, $+1$ to maximise.
    sign: f64,
}

impl<'s> NormalSystem<'s> {
    fn new(r: &[f64], a: &Mat<f64>, free: Vec<usize>, scale: &'s [f64], sign: f64) -> Self {
        let n = free.len();
        let az = Mat::from_fn(r.len(), n, |i, k| a[(i, free[k])] * scale[free[k]]);
        let ata = Mat::from_fn(n, n, |k, l| {
            (0..r.len()).map(|i| az[(i, k)] * az[(i, l)]).sum()
        });
        let atr = Mat::from_fn(n, 1, |k, _| (0..r.len()).map(|i| az[(i, k)] * r[i]).sum());
        Self {
            ata,
            atr,
            free,
            scale,
            sign,
        }
    }

    /// $\max_k (A_z^\top A_z)_{kk}$, at least [`MIN_NORMAL_DIAGONAL`].
    fn largest_diagonal(&self) -> f64 {
        (0..self.free.len()).fold(MIN_NORMAL_DIAGONAL, |m, i| f64::max(m, self.ata[(i, i)]))
    }
}

fn solve_damped(
    ata: &Mat<f64>,
    atr: &Mat<f64>,
    mu: f64,
    sign: f64,
) -> Result<Vec<f64>, OptimizeError> {
    let n = ata.nrows();
    let damped = Mat::from_fn(n, n, |k, l| ata[(k, l)] + if k == l { mu } else { 0.0 });
    let llt = damped
        .llt(Side::Lower)
        .map_err(|_| OptimizeError::Numerical {
            what: "the damped normal matrix is not positive definite",
        })?;
    let x = llt.solve(atr);
    Ok((0..n).map(|k| sign * x[(k, 0)]).collect())
}

fn report<P: Residuals + ?Sized>(
    problem: &Counted<'_, P>,
    design: Vec<f64>,
    value: f64,
    iterations: usize,
    termination: Termination,
    settings: &LmSettings,
) -> Result<LocalOptimum, OptimizeError> {
    let bounds = problem.problem.bounds();
    let (r, a) = residuals_and_jacobian(problem, &design, settings.fd_step)?;
    let gradient = gradient_from(&r, &a);
    let active: Vec<ActiveBound> = design
        .iter()
        .zip(bounds)
        .map(|(x, b)| at_bound(b, *x))
        .collect();
    let free: Vec<usize> = (0..design.len())
        .filter(|&j| active[j] == ActiveBound::Free)
        .collect();
    let f = |q: &[f64]| sum_of_squares(problem, q);
    let n = free.len();
    let h = finite_differences::hessian(&f, bounds, &design, &free, value, HESSIAN_RELATIVE_STEP)?;
    let reduced_hessian_eigenvalues = if free.is_empty() {
        Vec::new()
    } else {
        Mat::from_fn(n, n, |k, l| h[k * n + l])
            .self_adjoint_eigenvalues(Side::Lower)
            .map_err(|_| OptimizeError::Numerical {
                what: "the eigenvalues of the reduced Hessian did not converge",
            })?
    };
    Ok(LocalOptimum {
        design,
        value,
        gradient,
        active,
        reduced_hessian_eigenvalues,
        iterations,
        evaluations: problem.evaluations.get(),
        termination,
    })
}
