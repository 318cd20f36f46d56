//! First- and second-order optimality check (Karush–Kuhn–Tucker) at a design of any problem
//! with bounds and inequality constraints $g(x) \le 0$ ([`Constraints`]), given multiplier
//! estimates $\mu \ge 0$ (e.g. [`crate::ConstrainedResult::multipliers`]).
//!
//! With $\phi = f$ to minimise and $\phi = -f$ to maximise ([`Sense`]) and the Lagrangian
//! $\mathcal L(x) = \phi(x) + \sum_i \mu_i g_i(x)$ (Nocedal & Wright, *Numerical
//! Optimization*, 2nd ed., eq. 12.33):
//! - *first order* (Theorem 12.1): the projected gradient of $\mathcal L$ (on a lower bound
//!   only $\min(0, \partial_j\mathcal L)$ counts, on an upper bound only
//!   $\max(0, \partial_j\mathcal L)$), and the stationarity residual
//!   $\nabla\phi + \sum_{i\,\mathrm{active}} \hat\mu_i \nabla g_i$ over the variables off their
//!   bounds with least-squares multipliers $\hat\mu$; each entry times the variable's range, so
//!   both are 0 at a KKT point;
//! - *second order* (Theorem 12.5): the eigenvalues of the Hessian of $\mathcal L$ over the free
//!   variables (more than one difference step from both bounds), and of that Hessian on the null
//!   space $Z$ of the active constraints' gradients, $Z^\top \nabla^2\mathcal L\, Z$: all
//!   $\ge 0$ at a minimum of $\phi$, up to finite-difference noise. An empty null space (as many
//!   independent active constraints as free variables, or no free variable) has no eigenvalue.
//!
//! Every derivative is a [`crate::finite_differences`] difference with the relative step
//! [`KktSettings::step`]: the gradient and the constraint Jacobian central and clamped into the
//! box ([`finite_differences::gradient`], [`finite_differences::jacobian`]), the Hessian by
//! [`finite_differences::hessian`]. A constraint is active when its multiplier is positive or
//! $g_i \ge -$[`KktSettings::active_tolerance`].
//!
//! The check never panics and never reports a NaN: a step outside $(0, 0.5)$ or too small to
//! move the designs of the box ([`KktSettings::validate_for`], which a caller can run before
//! the optimisation) is an [`OptimizeError::Invalid`], a difference that is not finite an
//! [`OptimizeError::NonFiniteDerivative`], and a decomposition that fails an
//! [`OptimizeError::Numerical`]. The dense algebra uses nalgebra (least squares by SVD,
//! symmetric eigen-decompositions).

mod algebra;

use crate::finite_differences;
use crate::{OptimizeError, Sense};
use nalgebra::{DMatrix, DVector};
use pkm_traits::{Bounds, Constraints, InvalidInput, ObjectiveError, Progress};
use serde::{Deserialize, Serialize};

/// Settings of [`check`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, default)]
pub struct KktSettings {
    /// Difference step relative to each variable's range, in $(0, 0.5)$ (at $0.5$ and above no
    /// variable is a step away from both bounds). Default $10^{-2}$.
    pub step: f64,
    /// A constraint is active when $g_i \ge -$this (or its multiplier is positive); finite and
    /// $\ge 0$. Default $10^{-6}$, the default feasibility of the augmented Lagrangian.
    pub active_tolerance: f64,
}

impl Default for KktSettings {
    fn default() -> Self {
        Self {
            step: 1e-2,
            active_tolerance: 1e-6,
        }
    }
}

impl KktSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for a step outside $(0, 0.5)$ (NaN included) or an active
    /// tolerance that is not finite and $\ge 0$.
    pub fn validate(&self) -> Result<(), OptimizeError> {
        if !(self.step > 0.0 && self.step < 0.5) {
            return Err(InvalidInput::new("step", self.step, "must be in (0, 0.5)").into());
        }
        if !(self.active_tolerance.is_finite() && self.active_tolerance >= 0.0) {
            let value = self.active_tolerance;
            return Err(InvalidInput::new("active_tolerance", value, "finite and >= 0").into());
        }
        Ok(())
    }

    /// Checks the settings for the box `bounds`, before any design is known: as
    /// [`KktSettings::validate`], and the step must move every design in the box, i.e. for every
    /// variable with a range, $h$ = step × range must satisfy $m \pm h \ne m$ for the largest
    /// magnitude $m$ of its bounds (then $x \pm h \ne x$ for every $x$ in the interval) and
    /// $h^2$ must be a normal number (the second differences divide by it).
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] as [`KktSettings::validate`], or for a step too small for
    /// the box.
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::kkt::KktSettings;
    /// use pkm_traits::Bounds;
    /// let b = [Bounds::new(0.02, 1.0).unwrap()];
    /// assert!(KktSettings { step: 1e-6, ..Default::default() }.validate_for(&b).is_ok());
    /// for step in [1e300, 0.9, 1e-300, 5e-324] {
    ///     assert!(KktSettings { step, ..Default::default() }.validate_for(&b).is_err());
    /// }
    /// ```
    pub fn validate_for(&self, bounds: &[Bounds]) -> Result<(), OptimizeError> {
        self.validate()?;
        for b in bounds.iter().filter(|b| b.width() > 0.0) {
            let h = finite_differences::step(b, self.step);
            let m = b.lower().abs().max(b.upper().abs());
            if !(m + h > m && m - h < m && (h * h).is_normal()) {
                return Err(InvalidInput::new(
                    "step",
                    self.step,
                    "too small for the box: x ± step·range must differ from x, with a normal \
                     (step·range)²",
                )
                .into());
            }
        }
        Ok(())
    }
}

/// Where a variable sits at the checked design.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VariableStatus {
    /// On its lower bound (within $10^{-9}$ of its range).
    Lower,
    /// On its upper bound.
    Upper,
    /// Inside, but within one difference step of a bound (left out of the Hessian).
    NearBound,
    /// Inside, more than one difference step from both bounds.
    Free,
}

/// The first- and second-order checks of the module docs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OptimalityCheck {
    /// $\nabla\mathcal L$ with the given multipliers (central differences, one-sided at a
    /// bound), per variable.
    pub lagrangian_gradient: Vec<f64>,
    /// Each variable's status.
    pub status: Vec<VariableStatus>,
    /// Largest |projected entry of $\nabla\mathcal L$| × range.
    pub projected_gradient_max: f64,
    /// Indices of the active constraints.
    pub active_constraints: Vec<usize>,
    /// Multipliers of the active constraints that best cancel $\nabla\phi$ on the variables off
    /// their bounds (least squares).
    pub least_squares_multipliers: Vec<f64>,
    /// Largest |entry| × range of $\nabla\phi + \sum_{active}\hat\mu_i\nabla g_i$ with those
    /// multipliers, over the variables off their bounds (0 at a KKT point).
    pub stationarity_residual: f64,
    /// Eigenvalues (ascending) of the Hessian of $\mathcal L$ on the free variables.
    pub hessian_eigenvalues: Vec<f64>,
    /// Eigenvalues (ascending) of that Hessian on the null space of the active constraints
    /// (none when the null space is empty).
    pub reduced_hessian_eigenvalues: Vec<f64>,
}

/// A variable lies on a bound within this fraction of its range.
const ON_BOUND: f64 = 1e-9;

/// The checks of the module docs at `design` with multipliers `multipliers` (one per
/// constraint), for the problem optimised in the sense `sense`.
///
/// `progress` is asked for cancellation before every evaluation of the problem.
///
/// # Errors
/// [`OptimizeError::Invalid`] for settings that fail [`KktSettings::validate_for`] the
/// problem's bounds, a design that is not finite, or multipliers that are not one finite value
/// $\ge 0$ per constraint; [`OptimizeError::Objective`] for a design of the wrong length, a
/// failed or non-finite evaluation; [`OptimizeError::NonFiniteDerivative`] for a difference
/// that is not finite; [`OptimizeError::Numerical`] for a decomposition that fails;
/// [`OptimizeError::Cancelled`] once `progress` is cancelled.
///
/// # Example
/// $\min x^2 + y^2$ subject to $x + y \ge 1$ at its optimum $(\frac12, \frac12)$, $\mu = 1$:
/// ```
/// use pkm_optimizers::kkt::{self, KktSettings, VariableStatus};
/// use pkm_optimizers::Sense;
/// use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};
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
/// let problem = P([Bounds::new(-5.0, 5.0)?; 2]);
/// let settings = KktSettings::default();
/// let c = kkt::check(&problem, Sense::Minimise, &[0.5, 0.5], &[1.0], &settings, &Silent)?;
/// assert_eq!(c.status, [VariableStatus::Free; 2]);
/// assert!(c.projected_gradient_max < 1e-9 && c.stationarity_residual < 1e-9);
/// assert_eq!(c.active_constraints, [0]);
/// assert!((c.least_squares_multipliers[0] - 1.0).abs() < 1e-9);
/// // ∇²L = 2I; on the line x + y = 1 one direction remains, of curvature 2.
/// assert!((c.reduced_hessian_eigenvalues[0] - 2.0).abs() < 1e-6);
/// // A step that cannot work is refused, never a NaN.
/// let hostile = KktSettings { step: 1e-300, ..settings };
/// assert!(kkt::check(&problem, Sense::Minimise, &[0.5, 0.5], &[1.0], &hostile, &Silent).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check<P: Constraints + ?Sized>(
    problem: &P,
    sense: Sense,
    design: &[f64],
    multipliers: &[f64],
    settings: &KktSettings,
    progress: &dyn Progress,
) -> Result<OptimalityCheck, OptimizeError> {
    settings.validate_for(problem.bounds())?;
    validate_point(problem, design, multipliers)?;
    let (x, bounds, mu, step) = (design, problem.bounds(), multipliers, settings.step);
    let (n, m) = (x.len(), problem.n_constraints());
    let constraints = |p: &[f64], g: &mut [f64]| {
        progress.check()?;
        problem.inequalities(p, g)
    };
    let lagrangian = |p: &[f64]| -> Result<f64, ObjectiveError> {
        progress.check()?;
        let mut g = vec![0.0; m];
        problem.inequalities(p, &mut g)?;
        let penalty: f64 = g.iter().zip(mu).map(|(g, m)| g * m).sum();
        Ok(sense.minimised(problem.value(p)?) + penalty)
    };
    let l0 = lagrangian(x)?;
    if !l0.is_finite() {
        return Err(ObjectiveError::NonFinite { value: l0 }.into());
    }
    let gradient = finite_differences::gradient(&lagrangian, bounds, x, l0, step)?;
    require_finite("gradient", n, &gradient)?;
    let jacobian = finite_differences::jacobian(&constraints, bounds, x, m, step)?;
    require_finite("constraint Jacobian", n, &jacobian)?;
    let jacobian = DMatrix::from_row_slice(m, n, &jacobian);
    let mut g = vec![0.0; m];
    constraints(x, &mut g)?;
    let status: Vec<VariableStatus> = (0..n)
        .map(|j| status_of(&bounds[j], x[j], finite_differences::step(&bounds[j], step)))
        .collect();
    let projected: Vec<f64> = (0..n)
        .map(|j| {
            let projected = match status[j] {
                VariableStatus::Lower => gradient[j].min(0.0),
                VariableStatus::Upper => gradient[j].max(0.0),
                VariableStatus::NearBound | VariableStatus::Free => gradient[j],
            };
            (projected * bounds[j].width()).abs()
        })
        .collect();
    let projected_gradient_max = largest("scaled projected gradient", n, &projected)?;
    let active: Vec<usize> = (0..m)
        .filter(|&i| mu[i] > 0.0 || g[i] >= -settings.active_tolerance)
        .collect();
    let (least_squares_multipliers, stationarity_residual) =
        least_squares_stationarity(&gradient, &jacobian, mu, &active, &status, bounds)?;
    let free: Vec<usize> = (0..n)
        .filter(|&j| status[j] == VariableStatus::Free)
        .collect();
    let hessian = finite_differences::hessian(&lagrangian, bounds, x, &free, l0, step)?;
    require_finite("Hessian", free.len(), &hessian)?;
    let hessian = DMatrix::from_row_slice(free.len(), free.len(), &hessian);
    let active_gradients = DMatrix::from_fn(active.len(), free.len(), |r, c| {
        jacobian[(active[r], free[c])]
    });
    let basis = algebra::null_space(&active_gradients)?;
    let reduced = basis.transpose() * &hessian * &basis;
    let result = OptimalityCheck {
        lagrangian_gradient: gradient,
        status,
        projected_gradient_max,
        active_constraints: active,
        least_squares_multipliers,
        stationarity_residual,
        hessian_eigenvalues: algebra::ascending_eigenvalues(hessian)?,
        reduced_hessian_eigenvalues: algebra::ascending_eigenvalues(reduced)?,
    };
    result.check_finite()?;
    Ok(result)
}

impl OptimalityCheck {
    /// `Err(Numerical)` unless every number of the check is finite (the guarantee of [`check`]).
    fn check_finite(&self) -> Result<(), OptimizeError> {
        let numbers = self
            .lagrangian_gradient
            .iter()
            .chain(&self.least_squares_multipliers)
            .chain(&self.hessian_eigenvalues)
            .chain(&self.reduced_hessian_eigenvalues)
            .chain([&self.projected_gradient_max, &self.stationarity_residual]);
        if numbers.into_iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(OptimizeError::Numerical {
                what: "the optimality check overflows",
            })
        }
    }
}

/// Checks the design and multipliers.
fn validate_point<P: Constraints + ?Sized>(
    problem: &P,
    design: &[f64],
    multipliers: &[f64],
) -> Result<(), OptimizeError> {
    problem.check_dimension(design)?;
    let bounds = problem.bounds();
    if bounds.len() != design.len() {
        let got = bounds.len() as f64;
        return Err(InvalidInput::new("bounds", got, "one interval per design variable").into());
    }
    if let Some(&x) = design.iter().find(|x| !x.is_finite()) {
        return Err(InvalidInput::new("design", x, "must be finite").into());
    }
    if multipliers.len() != problem.n_constraints() {
        let got = multipliers.len() as f64;
        return Err(InvalidInput::new("multipliers", got, "one per constraint").into());
    }
    if let Some(&mu) = multipliers
        .iter()
        .find(|mu| !(mu.is_finite() && **mu >= 0.0))
    {
        return Err(InvalidInput::new("multipliers", mu, "each finite and >= 0").into());
    }
    Ok(())
}

/// `Err(NonFiniteDerivative)` at the first entry of `values` (row-major, `n` columns) that is
/// not finite.
fn require_finite(quantity: &'static str, n: usize, values: &[f64]) -> Result<(), OptimizeError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(k) => Err(OptimizeError::NonFiniteDerivative {
            quantity,
            variable: k % n.max(1),
            value: values[k],
        }),
    }
}

/// The largest of `values` (0 for none), refused when one is NaN or infinite: `f64::max` would
/// drop a NaN and report the others' maximum.
fn largest(quantity: &'static str, n: usize, values: &[f64]) -> Result<f64, OptimizeError> {
    require_finite(quantity, n, values)?;
    Ok(values.iter().copied().fold(0.0, f64::max))
}

fn status_of(b: &Bounds, x: f64, h: f64) -> VariableStatus {
    let tol = ON_BOUND * b.width();
    if !(x > b.lower() + tol) {
        VariableStatus::Lower
    } else if !(x < b.upper() - tol) {
        VariableStatus::Upper
    } else if x - h <= b.lower() || x + h >= b.upper() {
        VariableStatus::NearBound
    } else {
        VariableStatus::Free
    }
}

/// $\nabla\phi = \nabla\mathcal L - J^\top\mu$ on the variables off their bounds, the
/// least-squares multipliers of the active constraints there, and the scaled residual.
fn least_squares_stationarity(
    lagrangian_gradient: &[f64],
    jacobian: &DMatrix<f64>,
    mu: &[f64],
    active: &[usize],
    status: &[VariableStatus],
    bounds: &[Bounds],
) -> Result<(Vec<f64>, f64), OptimizeError> {
    let off: Vec<usize> = (0..status.len())
        .filter(|&j| matches!(status[j], VariableStatus::Free | VariableStatus::NearBound))
        .collect();
    let grad_f = DVector::from_iterator(
        off.len(),
        off.iter().map(|&j| {
            let correction: f64 = (0..mu.len()).map(|i| jacobian[(i, j)] * mu[i]).sum();
            lagrangian_gradient[j] - correction
        }),
    );
    let a_t = DMatrix::from_fn(off.len(), active.len(), |r, c| {
        jacobian[(active[c], off[r])]
    });
    let multipliers = algebra::least_squares(&a_t, &(-&grad_f))?;
    let residual = grad_f + &a_t * &multipliers;
    let scaled: Vec<f64> = off
        .iter()
        .zip(residual.iter())
        .map(|(&j, r)| (r * bounds[j].width()).abs())
        .collect();
    let scaled = largest("scaled stationarity residual", scaled.len(), &scaled)?;
    Ok((multipliers.as_slice().to_vec(), scaled))
}
