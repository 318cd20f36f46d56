//! Spectral projected gradient (Birgin, Martínez & Raydan 2000) with central-difference
//! gradients: the bound-constrained inner solver of [`crate::augmented_lagrangian`].

use pkm_traits::{Bounds, ObjectiveError};

/// Projects `x` onto the box.
pub(crate) fn project(bounds: &[Bounds], x: &mut [f64]) {
    for (v, b) in x.iter_mut().zip(bounds) {
        *v = b.clamp(*v);
    }
}

/// Central-difference gradient with step `h` scaled by each box width, one-sided at a bound.
/// An infeasible neighbour counts as $+\infty$, so the gradient points back inside.
pub(crate) fn gradient<F>(
    f: &F,
    bounds: &[Bounds],
    x: &[f64],
    h: f64,
) -> Result<Vec<f64>, ObjectiveError>
where
    F: Fn(&[f64]) -> Result<f64, ObjectiveError>,
{
    let mut g = vec![0.0; x.len()];
    let mut probe = x.to_vec();
    let f0 = f(x)?;
    for k in 0..x.len() {
        let step = h * bounds[k].width().max(1e-12);
        let hi = bounds[k].clamp(x[k] + step);
        let lo = bounds[k].clamp(x[k] - step);
        let mut at = |v: f64| {
            probe[k] = v;
            let r = if (v - x[k]).abs() > 0.0 {
                f(&probe)
            } else {
                Ok(f0)
            };
            probe[k] = x[k];
            r
        };
        let (fp, fm) = (at(hi)?, at(lo)?);
        g[k] = if hi > lo { (fp - fm) / (hi - lo) } else { 0.0 };
    }
    Ok(g)
}

/// Minimises `f` over the box from `x` (projected), stopping when the projected-gradient step
/// is below `tolerance` (in units of the box widths) or after `max_iterations`.
///
/// # Errors
/// An objective error other than a recorded infeasibility, which the line search treats as
/// $+\infty$.
pub(crate) fn minimise_in_box<F>(
    f: &F,
    bounds: &[Bounds],
    x: &mut Vec<f64>,
    h: f64,
    tolerance: f64,
    max_iterations: usize,
) -> Result<f64, ObjectiveError>
where
    F: Fn(&[f64]) -> Result<f64, ObjectiveError>,
{
    project(bounds, x);
    let mut fx = f(x)?;
    let mut g = gradient(f, bounds, x, h)?;
    let mut lambda = 1.0 / g.iter().map(|v| v.abs()).fold(1e-12, f64::max);
    for _ in 0..max_iterations {
        let mut d: Vec<f64> = x.iter().zip(&g).map(|(xi, gi)| xi - lambda * gi).collect();
        project(bounds, &mut d);
        d.iter_mut().zip(x.iter()).for_each(|(di, xi)| *di -= xi);
        let size = d
            .iter()
            .zip(bounds)
            .map(|(di, b)| (di / b.width().max(1e-12)).abs())
            .fold(0.0, f64::max);
        if size < tolerance {
            break;
        }
        let slope: f64 = d.iter().zip(&g).map(|(a, b)| a * b).sum();
        let mut t = 1.0;
        let accepted = loop {
            let trial: Vec<f64> = x.iter().zip(&d).map(|(xi, di)| xi + t * di).collect();
            match f(&trial) {
                Ok(ft) if ft <= fx + 1e-4 * t * slope => break Some((trial, ft)),
                Ok(_) | Err(ObjectiveError::Infeasible { .. }) => {}
                Err(e) => return Err(e),
            }
            t *= 0.5;
            if t < 1e-10 {
                break None;
            }
        };
        let Some((trial, ft)) = accepted else { break };
        let g_new = gradient(f, bounds, &trial, h)?;
        let s: Vec<f64> = trial.iter().zip(x.iter()).map(|(a, b)| a - b).collect();
        let y: Vec<f64> = g_new.iter().zip(&g).map(|(a, b)| a - b).collect();
        let sy: f64 = s.iter().zip(&y).map(|(a, b)| a * b).sum();
        let ss: f64 = s.iter().map(|v| v * v).sum();
        lambda = if sy > 0.0 {
            (ss / sy).clamp(1e-10, 1e10)
        } else {
            1e10_f64.min(lambda * 10.0)
        };
        *x = trial;
        fx = ft;
        g = g_new;
    }
    Ok(fx)
}
