//! Bounded Levenberg–Marquardt for minimising *or maximising* a sum of squares
//! $f(p) = \sum_i r_i(p)^2 = \lVert r(p) \rVert^2$ over a box, with a KKT report at the optimum
//! (Wolf & Shoham §3: "Gauss–Newton").
//!
//! Each iteration solves the damped normal equations on the free variables,
//! $$ (A^\top A + \mu I)\,\delta = \sigma A^\top r, \qquad A = \partial r / \partial p, $$
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
use crate::multistart::{run_multistart, uniform_start_points};
use crate::termination::Termination;
use faer::Mat;
use faer::Side;
use faer::linalg::solvers::Solve;
use pkm_traits::{Bounds, ObjectiveError, Residuals};

/// Initial damping relative to the largest diagonal entry of $A^\top A$:
/// $\mu_0 = 10^{-3} \max_k (A^\top A)_{kk}$ (Marquardt's usual scale).
const INITIAL_DAMPING_SCALE: f64 = 1e-3;
/// Floor of $\max_k (A^\top A)_{kk}$ in $\mu_0$, so a vanishing Jacobian still starts with
/// $\mu_0 > 0$.
const MIN_NORMAL_DIAGONAL: f64 = 1e-12;
/// $\mu \leftarrow \mu / 3$ after a successful step.
const DAMPING_DECREASE: f64 = 3.0;
/// $\mu \leftarrow 4 \mu$ after a rejected step.
const DAMPING_INCREASE: f64 = 4.0;
/// Damping at which the search for an improving step gives up ([`Termination::Stalled`]): the
/// step $\delta \approx \sigma A^\top r / \mu$ is then negligible.
const MAX_DAMPING: f64 = 1e16;

/// Whether the sum of squares is minimised or maximised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    /// Find the smallest $\lVert r \rVert^2$.
    Minimise,
    /// Find the largest $\lVert r \rVert^2$.
    Maximise,
}

impl Sense {
    fn sign(self) -> f64 {
        match self {
            Self::Minimise => -1.0,
            Self::Maximise => 1.0,
        }
    }
}

/// Where a variable sits at the reported optimum.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActiveBound {
    /// Strictly inside its interval.
    Free,
    /// On its lower bound.
    Lower,
    /// On its upper bound.
    Upper,
}

/// Settings of [`levenberg_marquardt`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmSettings {
    /// Largest number of iterations.
    pub max_iterations: usize,
    /// Stop when the projected gradient's largest entry, scaled by the interval width, is below
    /// this, or when a step changes $f$ by less than this relative amount.
    pub tolerance: f64,
    /// Finite-difference step, relative to each interval width (for problems without
    /// [`Residuals::residual_jacobian`]).
    pub fd_step: f64,
}

impl Default for LmSettings {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            tolerance: 1e-12,
            fd_step: 1e-6,
        }
    }
}

/// A local optimum with the first- and second-order checks the paper reports.
#[derive(Debug, Clone, PartialEq)]
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
    /// Why the iteration stopped: [`Termination::Converged`] with criterion
    /// `"projected gradient"`, `"every variable held on a bound"` or `"relative change in f"`;
    /// [`Termination::MaxIterations`] after [`LmSettings::max_iterations`] iterations; or
    /// [`Termination::Stalled`] when the damping reached its limit without an improving step.
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

/// Runs bounded Levenberg–Marquardt from `start` (clamped into the box).
///
/// # Errors
/// [`OptimizeError::InvalidSetting`] for a non-positive tolerance or step, or a start of the
/// wrong length; [`OptimizeError::Objective`] when the residuals fail;
/// [`OptimizeError::Numerical`] when the damped normal matrix is not positive definite or the
/// eigenvalues of the reduced Hessian do not converge.
///
/// # Example
/// ```
/// use pkm_optimizers::{LmSettings, Sense, levenberg_marquardt};
/// use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals};
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
/// let max = levenberg_marquardt(&problem, Sense::Maximise, &[0.5, 0.4], &LmSettings::default()).unwrap();
/// assert!((max.value - 8.0).abs() < 1e-9);
/// let min = levenberg_marquardt(&problem, Sense::Minimise, &[0.5, 0.4], &LmSettings::default()).unwrap();
/// assert!(min.value < 1e-12);
/// ```
pub fn levenberg_marquardt<P: Residuals + ?Sized>(
    problem: &P,
    sense: Sense,
    start: &[f64],
    settings: &LmSettings,
) -> Result<LocalOptimum, OptimizeError> {
    validate(problem, start, settings)?;
    let bounds = problem.bounds();
    let sign = sense.sign();
    let mut p: Vec<f64> = start.iter().zip(bounds).map(|(x, b)| b.clamp(*x)).collect();
    let mut f = sum_of_squares(problem, &p)?;
    let mut mu = 0.0;
    let mut iterations = 0;
    let mut termination = Termination::MaxIterations;
    while iterations < settings.max_iterations {
        iterations += 1;
        let (r, a) = residuals_and_jacobian(problem, &p, settings.fd_step)?;
        let grad = gradient_from(&r, &a);
        let free = free_set(&p, &grad, bounds, sign);
        let projected = free
            .iter()
            .map(|&j| (grad[j] * bounds[j].width()).abs())
            .fold(0.0, f64::max);
        if free.is_empty() {
            termination = Termination::Converged {
                criterion: "every variable held on a bound",
            };
            break;
        }
        if projected <= settings.tolerance * (1.0 + f.abs()) {
            termination = Termination::Converged {
                criterion: "projected gradient",
            };
            break;
        }
        let (ata, atr) = normal_equations(&r, &a, &free);
        if mu == 0.0 {
            mu = INITIAL_DAMPING_SCALE
                * (0..free.len()).fold(MIN_NORMAL_DIAGONAL, |m, i| f64::max(m, ata[(i, i)]));
        }
        // Why to stop after this iteration, if at all: stalled unless an improving step is found.
        let mut stop = Some(Termination::Stalled);
        while mu < MAX_DAMPING {
            let delta = solve_damped(&ata, &atr, mu, sign)?;
            let mut trial = p.clone();
            for (k, &j) in free.iter().enumerate() {
                trial[j] = bounds[j].clamp(p[j] + delta[k]);
            }
            let f_trial = sum_of_squares(problem, &trial)?;
            if sign * (f_trial - f) > 0.0 {
                let gain = (f_trial - f).abs();
                p = trial;
                f = f_trial;
                mu /= DAMPING_DECREASE;
                stop = (gain <= settings.tolerance * (1.0 + f.abs())).then_some(
                    Termination::Converged {
                        criterion: "relative change in f",
                    },
                );
                break;
            }
            mu *= DAMPING_INCREASE;
        }
        if let Some(reason) = stop {
            termination = reason;
            break;
        }
    }
    report(problem, p, f, iterations, termination, settings)
}

/// Multistart [`levenberg_marquardt`]: `n_starts` seeded uniform starts in the box (plus
/// `extra_starts`, run first), in parallel; returns the best optimum in the sense of `sense`
/// (ties broken by start order, so the result is independent of the thread count).
///
/// # Errors
/// As [`levenberg_marquardt`]; [`OptimizeError::NoFeasibleDesign`] when every start fails;
/// [`OptimizeError::InvalidSetting`] for more than [`crate::MAX_STARTS`] starts.
pub fn multistart_levenberg_marquardt<P: Residuals + ?Sized>(
    problem: &P,
    sense: Sense,
    extra_starts: &[Vec<f64>],
    n_starts: usize,
    seed: u64,
    settings: &LmSettings,
) -> Result<LocalOptimum, OptimizeError> {
    let mut starts = extra_starts.to_vec();
    starts.extend(uniform_start_points(problem.bounds(), n_starts, seed)?);
    let outcomes = run_multistart(&starts, |s| {
        levenberg_marquardt(problem, sense, s, settings)
    });
    let mut best: Option<LocalOptimum> = None;
    let mut last_error = None;
    for outcome in outcomes {
        match outcome {
            Ok(o) => {
                if best
                    .as_ref()
                    .is_none_or(|b| sense.sign() * (o.value - b.value) > 0.0)
                {
                    best = Some(o);
                }
            }
            Err(OptimizeError::Objective(ObjectiveError::Infeasible { reason })) => {
                last_error = Some(reason);
            }
            Err(e) => return Err(e),
        }
    }
    best.ok_or(OptimizeError::NoFeasibleDesign {
        evaluations: starts.len(),
        last_reason: last_error.unwrap_or_else(|| "no starts".to_owned()),
    })
}

fn validate<P: Residuals + ?Sized>(
    problem: &P,
    start: &[f64],
    settings: &LmSettings,
) -> Result<(), OptimizeError> {
    let invalid = |setting, value: f64, requirement| {
        Err(OptimizeError::InvalidSetting {
            setting,
            value,
            requirement,
        })
    };
    if !(settings.tolerance > 0.0) {
        return invalid("tolerance", settings.tolerance, "must be > 0");
    }
    if !(settings.fd_step > 0.0 && settings.fd_step < 0.1) {
        return invalid("fd_step", settings.fd_step, "must be in (0, 0.1)");
    }
    problem.check_dimension(start)?;
    if start.iter().any(|x| !x.is_finite()) {
        return invalid("start", f64::NAN, "must be finite");
    }
    Ok(())
}

fn sum_of_squares<P: Residuals + ?Sized>(problem: &P, p: &[f64]) -> Result<f64, OptimizeError> {
    let mut r = vec![0.0; problem.n_residuals()];
    problem.residuals(p, &mut r)?;
    let f: f64 = r.iter().map(|x| x * x).sum();
    if f.is_finite() {
        Ok(f)
    } else {
        Err(ObjectiveError::NonFinite { value: f }.into())
    }
}

/// $r(p)$ and $A = \partial r / \partial p$: the problem's own Jacobian when
/// [`Residuals::residual_jacobian`] provides one, else central differences (one-sided where a
/// side leaves the box, see [`Bounds::difference_points`]).
fn residuals_and_jacobian<P: Residuals + ?Sized>(
    problem: &P,
    p: &[f64],
    rel: f64,
) -> Result<(Vec<f64>, Mat<f64>), OptimizeError> {
    let (m, n) = (problem.n_residuals(), p.len());
    let mut r = vec![0.0; m];
    let mut analytic = vec![0.0; m * n];
    if problem.residual_jacobian(p, &mut r, &mut analytic)? {
        if let Some(value) = analytic.iter().copied().find(|v| !v.is_finite()) {
            return Err(ObjectiveError::NonFinite { value }.into());
        }
        return Ok((r, Mat::from_fn(m, n, |i, j| analytic[i * n + j])));
    }
    problem.residuals(p, &mut r)?;
    let mut a = Mat::<f64>::zeros(m, n);
    let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
    let mut q = p.to_vec();
    for (j, b) in problem.bounds().iter().enumerate() {
        let (hi, lo) = b.difference_points(p[j], rel);
        if !(hi > lo) {
            // A variable fixed by its bounds (lower = upper): its column stays zero.
            continue;
        }
        q[j] = hi;
        problem.residuals(&q, &mut rp)?;
        q[j] = lo;
        problem.residuals(&q, &mut rm)?;
        q[j] = p[j];
        for i in 0..m {
            a[(i, j)] = (rp[i] - rm[i]) / (hi - lo);
        }
    }
    Ok((r, a))
}

fn gradient_from(r: &[f64], a: &Mat<f64>) -> Vec<f64> {
    (0..a.ncols())
        .map(|j| 2.0 * (0..r.len()).map(|i| a[(i, j)] * r[i]).sum::<f64>())
        .collect()
}

fn at_bound(b: &Bounds, x: f64) -> ActiveBound {
    let eps = 1e-12 * (1.0 + b.width());
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

fn normal_equations(r: &[f64], a: &Mat<f64>, free: &[usize]) -> (Mat<f64>, Mat<f64>) {
    let n = free.len();
    let ata = Mat::from_fn(n, n, |k, l| {
        (0..r.len())
            .map(|i| a[(i, free[k])] * a[(i, free[l])])
            .sum()
    });
    let atr = Mat::from_fn(n, 1, |k, _| {
        (0..r.len()).map(|i| a[(i, free[k])] * r[i]).sum()
    });
    (ata, atr)
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
    problem: &P,
    design: Vec<f64>,
    value: f64,
    iterations: usize,
    termination: Termination,
    settings: &LmSettings,
) -> Result<LocalOptimum, OptimizeError> {
    let bounds = problem.bounds();
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
    let hessian = free_hessian(problem, &design, &free)?;
    let reduced_hessian_eigenvalues = if free.is_empty() {
        Vec::new()
    } else {
        hessian
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
        termination,
    })
}

/// Central second differences of $f$ over the free variables, step $10^{-4}$ of each width.
fn free_hessian<P: Residuals + ?Sized>(
    problem: &P,
    p: &[f64],
    free: &[usize],
) -> Result<Mat<f64>, OptimizeError> {
    let bounds = problem.bounds();
    let h: Vec<f64> = free
        .iter()
        .map(|&j| 1e-4 * bounds[j].width().max(1e-8))
        .collect();
    let f_at = |shifts: &[(usize, f64)]| {
        let mut q = p.to_vec();
        for &(k, s) in shifts {
            q[free[k]] += s * h[k];
        }
        sum_of_squares(problem, &q)
    };
    let n = free.len();
    let f0 = f_at(&[])?;
    let mut hess = Mat::<f64>::zeros(n, n);
    for k in 0..n {
        for l in k..n {
            let v = if k == l {
                (f_at(&[(k, 1.0)])? - 2.0 * f0 + f_at(&[(k, -1.0)])?) / (h[k] * h[k])
            } else {
                (f_at(&[(k, 1.0), (l, 1.0)])?
                    - f_at(&[(k, 1.0), (l, -1.0)])?
                    - f_at(&[(k, -1.0), (l, 1.0)])?
                    + f_at(&[(k, -1.0), (l, -1.0)])?)
                    / (4.0 * h[k] * h[l])
            };
            hess[(k, l)] = v;
            hess[(l, k)] = v;
        }
    }
    Ok(hess)
}
