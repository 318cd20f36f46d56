//! The weighted mean of per-task optima (Wolf & Shoham eq. 15, read as a mean; the form as
//! printed, divided by the number of tasks, is `eq15_as_printed` in the `pkm` facade's `papers::wolf2006`).

use crate::error::OptimizeError;
use pkm_traits::InvalidInput;

/// The weighted mean $Q = \sum_i w_i q_i / \sum_i w_i$ of the optima `optima[i]` (each a design
/// vector) of the tasks, with weights `weights`.
///
/// # Errors
/// [`OptimizeError::Invalid`] when there are no tasks, the lengths differ, a weight is
/// negative or not finite, an optimum is not finite, the weights sum to zero, or the weighted
/// sum overflows.
///
/// # Example
/// ```
/// use pkm_optimizers::weighted_combination;
/// let q = [vec![0.0, 2.0], vec![4.0, 6.0]];
/// let mean = weighted_combination(&q, &[1.0, 3.0]).unwrap();
/// assert_eq!(mean, vec![3.0, 5.0]);
/// // Weights that overflow when summed still give the mean.
/// let huge = weighted_combination(&q, &[f64::MAX, f64::MAX]).unwrap();
/// assert_eq!(huge, vec![2.0, 4.0]);
/// ```
pub fn weighted_combination(
    optima: &[Vec<f64>],
    weights: &[f64],
) -> Result<Vec<f64>, OptimizeError> {
    let first = optima
        .first()
        .ok_or(InvalidInput::new("tasks", 0.0, "need at least one task"))?;
    if weights.len() != optima.len() {
        return Err(
            InvalidInput::new("weights", weights.len() as f64, "one weight per task").into(),
        );
    }
    if let Some(q) = optima.iter().find(|q| q.len() != first.len()) {
        return Err(InvalidInput::new(
            "optimum length",
            q.len() as f64,
            "all optima the same length",
        )
        .into());
    }
    if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        return Err(InvalidInput::new("weight", *w, "must be finite and >= 0").into());
    }
    if let Some(v) = optima.iter().flatten().find(|v| !v.is_finite()) {
        return Err(InvalidInput::new("optimum", *v, "must be finite").into());
    }
    let denominator: f64 = weights.iter().sum();
    if !(denominator > 0.0) {
        return Err(InvalidInput::new("sum of weights", denominator, "must be > 0").into());
    }
    let mean = combine(optima, weights, denominator, first.len());
    if denominator.is_finite() && mean.iter().all(|v| v.is_finite()) {
        return Ok(mean);
    }
    // An overflow of Σ w_i or of a product w_i q_i: the same sum with weights scaled by the
    // largest, exact in exponent; what still overflows has no finite value.
    let w_max = weights.iter().fold(0.0_f64, |m, w| m.max(*w));
    let scaled: Vec<f64> = weights.iter().map(|w| w / w_max).collect();
    let mean = combine(optima, &scaled, scaled.iter().sum(), first.len());
    match mean.iter().find(|v| !v.is_finite()) {
        Some(v) => {
            Err(
                InvalidInput::new("weighted sum", *v, "must be representable (it overflows)")
                    .into(),
            )
        }
        None => Ok(mean),
    }
}

/// $\sum_i w_i q_{ij} / d$ for every component $j$.
fn combine(optima: &[Vec<f64>], weights: &[f64], denominator: f64, len: usize) -> Vec<f64> {
    (0..len)
        .map(|j| {
            optima
                .iter()
                .zip(weights)
                .map(|(q, w)| w * q[j])
                .sum::<f64>()
                / denominator
        })
        .collect()
}
