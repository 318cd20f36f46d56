//! Spectral projected gradient (Birgin, Martínez & Raydan 2000) with central-difference
//! gradients ([`crate::finite_differences::gradient`]): the bound-constrained inner solver of
//! [`crate::augmented_lagrangian`].
//!
//! It iterates in the scaled variables $z = S^{-1} x$ of [`crate::scaling`]: with
//! $g = \nabla_x f$, the trial direction is
//! $$ d = P(x - \lambda S^2 g) - x \qquad (z - \lambda \nabla_z f \text{ mapped back}), $$
//! $\lambda_0 = 1 / \lVert S g \rVert_\infty$, the spectral step
//! $\lambda = \lVert S^{-1} \Delta x \rVert^2 / (\Delta x^\top \Delta g)$, and the stop
//! $\lVert S^{-1} d \rVert_\infty <$ tolerance.

use crate::OptimizeError;
use crate::finite_differences;
use pkm_traits::{Bounds, ObjectiveError, Progress};

/// Armijo constant of the (monotone) backtracking line search: accept $t$ when
/// $f(x + t d) \le f(x) + 10^{-4}\, t\, \nabla f \cdot d$.
const ARMIJO: f64 = 1e-4;
/// The line search halves $t$ until it accepts or $t$ drops below this.
const MIN_STEP_FRACTION: f64 = 1e-10;
/// The spectral step length $\lambda = s^\top s / s^\top y$ is kept in
/// $[\lambda_{\min}, \lambda_{\max}] = [10^{-10}, 10^{10}]$.
const MIN_SPECTRAL_STEP: f64 = 1e-10;
/// See [`MIN_SPECTRAL_STEP`].
const MAX_SPECTRAL_STEP: f64 = 1e10;
/// Floor of the largest gradient entry in the first step length $\lambda_0 = 1/\max_k |g_k|$.
const MIN_FIRST_GRADIENT: f64 = 1e-12;

/// Projects `x` onto the box.
pub(crate) fn project(bounds: &[Bounds], x: &mut [f64]) {
    for (v, b) in x.iter_mut().zip(bounds) {
        *v = b.clamp(*v);
    }
}

/// Settings of one inner solve.
pub(crate) struct InnerSettings {
    /// Relative finite-difference step.
    pub fd_step: f64,
    /// Stop when the projected-gradient step is below this, in scaled units.
    pub tolerance: f64,
    /// The characteristic scale $s_j$ of each variable ([`crate::scaling`]).
    pub scale: Vec<f64>,
    /// Iteration limit.
    pub max_iterations: usize,
}

/// Minimises `f` over the box from `x` (projected), stopping when the projected-gradient step
/// is below the tolerance (in scaled units) or after the iteration limit. Returns
/// $f(x)$ and the iterations spent.
///
/// # Errors
/// An objective error other than a recorded infeasibility, which the line search treats as
/// $+\infty$; [`OptimizeError::Cancelled`] once `progress` is cancelled (checked every
/// iteration).
pub(crate) fn minimise_in_box<F>(
    f: &F,
    bounds: &[Bounds],
    x: &mut Vec<f64>,
    settings: &InnerSettings,
    progress: &dyn Progress,
) -> Result<(f64, usize), OptimizeError>
where
    F: Fn(&[f64]) -> Result<f64, ObjectiveError>,
{
    project(bounds, x);
    let h = settings.fd_step;
    let mut fx = f(x)?;
    let scale = &settings.scale;
    let mut g = finite_differences::gradient(f, bounds, x, fx, h)?;
    let mut lambda = 1.0
        / g.iter()
            .zip(scale)
            .map(|(v, s)| (s * v).abs())
            .fold(MIN_FIRST_GRADIENT, f64::max);
    let mut iterations = 0;
    while iterations < settings.max_iterations {
        progress.check()?;
        iterations += 1;
        let mut d: Vec<f64> = x
            .iter()
            .zip(&g)
            .zip(scale)
            .map(|((xi, gi), si)| xi - lambda * (si * si * gi))
            .collect();
        project(bounds, &mut d);
        d.iter_mut().zip(x.iter()).for_each(|(di, xi)| *di -= xi);
        let size = d
            .iter()
            .zip(scale)
            .map(|(di, si)| (di / si).abs())
            .fold(0.0, f64::max);
        if size < settings.tolerance {
            break;
        }
        let slope: f64 = d.iter().zip(&g).map(|(a, b)| a * b).sum();
        let mut t = 1.0;
        let accepted = loop {
            let trial: Vec<f64> = x.iter().zip(&d).map(|(xi, di)| xi + t * di).collect();
            match f(&trial) {
                Ok(ft) if ft <= fx + ARMIJO * t * slope => break Some((trial, ft)),
                Ok(_) | Err(ObjectiveError::Infeasible { .. }) => {}
                Err(e) => return Err(e.into()),
            }
            t *= 0.5;
            if t < MIN_STEP_FRACTION {
                break None;
            }
        };
        let Some((trial, ft)) = accepted else { break };
        let g_new = finite_differences::gradient(f, bounds, &trial, ft, h)?;
        let s: Vec<f64> = trial.iter().zip(x.iter()).map(|(a, b)| a - b).collect();
        let y: Vec<f64> = g_new.iter().zip(&g).map(|(a, b)| a - b).collect();
        let sy: f64 = s.iter().zip(&y).map(|(a, b)| a * b).sum();
        let ss: f64 = s.iter().zip(scale).map(|(v, si)| (v / si).powi(2)).sum();
        lambda = if sy > 0.0 {
            (ss / sy).clamp(MIN_SPECTRAL_STEP, MAX_SPECTRAL_STEP)
        } else {
            MAX_SPECTRAL_STEP.min(lambda * 10.0)
        };
        *x = trial;
        fx = ft;
        g = g_new;
    }
    Ok((fx, iterations))
}
