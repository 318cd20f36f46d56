//! Augmented-Lagrangian (Powell–Hestenes–Rockafellar) method for smooth objectives with bounds
//! and inequality constraints $g(p) \le 0$ ([`pkm_traits::Constraints`]):
//! $$ \mathcal{L}_\rho(p, \mu) = f(p) + \frac{1}{2\rho}\sum_i
//!    \big(\max(0, \mu_i + \rho g_i(p))^2 - \mu_i^2\big), $$
//! minimised over the box by a spectral projected gradient with central-difference gradients,
//! then $\mu_i \leftarrow \max(0, \mu_i + \rho g_i)$; $\rho$ grows tenfold when the violation
//! does not shrink by 4. (argmin offers no constrained SQP; the `cobyla` crate is
//! derivative-free and slower on these smooth 6-D problems, so neither was taken.)

use crate::OptimizeError;
use crate::spg::{minimise_in_box, project};
use crate::termination::Termination;
use pkm_traits::{Constraints, ObjectiveError};

/// Settings of [`augmented_lagrangian`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AugmentedLagrangianSettings {
    /// Relative finite-difference step (times each box width). Default 1e-6; use ~1e-3 for
    /// Monte Carlo objectives on common random numbers.
    pub fd_step: f64,
    /// Inner stopping tolerance on the projected step, in box widths. Default 1e-9.
    pub tolerance: f64,
    /// Largest admissible constraint violation of the returned design. Default 1e-6.
    pub feasibility: f64,
    /// Outer (multiplier) iterations. Default 30.
    pub max_outer: usize,
    /// Inner iterations per outer one. Default 200.
    pub max_inner: usize,
}

impl Default for AugmentedLagrangianSettings {
    fn default() -> Self {
        Self {
            fd_step: 1e-6,
            tolerance: 1e-9,
            feasibility: 1e-6,
            max_outer: 30,
            max_inner: 200,
        }
    }
}

/// A constrained optimum.
#[derive(Debug, Clone, PartialEq)]
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
    /// `"feasible with settled multipliers"`) or [`Termination::MaxIterations`] after
    /// [`AugmentedLagrangianSettings::max_outer`] outer iterations with a feasible but
    /// possibly unsettled design (an infeasible one is an error instead).
    pub termination: Termination,
}

/// Minimises `problem` from `start` subject to its bounds and inequalities.
///
/// # Errors
/// [`OptimizeError::InvalidSetting`] for a start of the wrong length or non-positive settings;
/// [`OptimizeError::NoFeasibleDesign`] when the final design still violates a constraint by
/// more than `settings.feasibility` (an infeasible constraint set: no design is returned);
/// [`OptimizeError::Objective`] for an objective failure other than infeasibility, and for a
/// constraint or final value that is NaN or infinite.
///
/// # Example
/// ```
/// use pkm_optimizers::{AugmentedLagrangianSettings, augmented_lagrangian};
/// use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError};
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
/// let r = augmented_lagrangian(&P([b, b]), &[2.0, -1.0], &Default::default()).unwrap();
/// assert!((r.design[0] - 0.5).abs() < 1e-5 && (r.multipliers[0] - 1.0).abs() < 1e-3);
/// ```
pub fn augmented_lagrangian<P: Constraints>(
    problem: &P,
    start: &[f64],
    settings: &AugmentedLagrangianSettings,
) -> Result<ConstrainedResult, OptimizeError> {
    check_settings(problem, start, settings)?;
    let bounds = problem.bounds();
    let m = problem.n_constraints();
    let mut x = start.to_vec();
    project(bounds, &mut x);
    let mut mu = vec![0.0; m];
    let mut rho = 10.0;
    let mut g = vec![0.0; m];
    let mut violation = f64::INFINITY;
    let mut termination = Termination::MaxIterations;
    for _ in 0..settings.max_outer {
        let lagrangian = |p: &[f64]| -> Result<f64, ObjectiveError> {
            let mut gp = vec![0.0; m];
            problem.inequalities(p, &mut gp)?;
            let penalty: f64 = gp
                .iter()
                .zip(&mu)
                .map(|(gi, mi)| (mi + rho * gi).max(0.0).powi(2) - mi * mi)
                .sum();
            Ok(problem.value(p)? + penalty / (2.0 * rho))
        };
        minimise_in_box(
            &lagrangian,
            bounds,
            &mut x,
            settings.fd_step,
            settings.tolerance,
            settings.max_inner,
        )?;
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
        if new_violation <= settings.feasibility
            && step <= 1e-6 * (1.0 + mu.iter().fold(0.0, |a: f64, b| a.max(*b)))
        {
            violation = new_violation;
            termination = Termination::Converged {
                criterion: "feasible with settled multipliers",
            };
            break;
        }
        if new_violation > 0.25 * violation {
            rho = (rho * 10.0).min(1e10);
        }
        violation = new_violation;
    }
    if !(violation <= settings.feasibility) {
        return Err(OptimizeError::NoFeasibleDesign {
            evaluations: settings.max_outer,
            last_reason: format!(
                "largest constraint violation {violation:.3e} after the last outer iteration"
            ),
        });
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
    })
}

fn check_settings<P: Constraints>(
    problem: &P,
    start: &[f64],
    s: &AugmentedLagrangianSettings,
) -> Result<(), OptimizeError> {
    let invalid = |setting, value, requirement| {
        Err(OptimizeError::InvalidSetting {
            setting,
            value,
            requirement,
        })
    };
    if start.len() != problem.dimension() || problem.bounds().len() != start.len() {
        return invalid(
            "start.len()",
            start.len() as f64,
            "must equal the problem dimension",
        );
    }
    for (setting, value) in [
        ("fd_step", s.fd_step),
        ("tolerance", s.tolerance),
        ("feasibility", s.feasibility),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return invalid(setting, value, "must be finite and > 0");
        }
    }
    if s.max_outer == 0 || s.max_inner == 0 {
        return invalid("max_outer/max_inner", 0.0, "must be >= 1");
    }
    Ok(())
}
