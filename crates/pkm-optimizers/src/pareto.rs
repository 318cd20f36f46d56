//! The Pareto front of designs scored on $k \ge 2$ objectives, each with its [`Sense`], and
//! for two objectives what a weighted sum hides: the interval of weights that selects each
//! design of the front.
//!
//! Write $\gamma_{pk} = f_{pk}$ for an objective maximised and $-f_{pk}$ for one minimised, so
//! that larger is better everywhere. Design $p$ *dominates* $q$ when $\gamma_{pk} \ge
//! \gamma_{qk}$ for every $k$ and $>$ for some $k$; the front is the set of designs that no
//! design dominates (equal designs do not dominate each other, so both stay). For two
//! objectives, the weight $w \in [0, 1]$ *selects* $p$ when $p$ maximises
//! $u_w = w\gamma_1 + (1 - w)\gamma_2$ (for two minimised objectives: minimises
//! $w f_1 + (1 - w) f_2$). That is the case for $w$ in the intersection over every other
//! design $q$ of the half-lines $w\,(\Delta_1 - \Delta_2) \ge -\Delta_2$,
//! $\Delta_k = \gamma_{pk} - \gamma_{qk}$: an interval $[w_{\min}, w_{\max}]$, empty for a
//! design on a non-convex part of the front, which no weighting finds.

use crate::OptimizeError;
use crate::sense::Sense;
use pkm_traits::InvalidInput;
use serde::{Deserialize, Serialize};

/// The front of [`pareto_front`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParetoFront {
    /// The non-dominated designs, as ascending indices into the values given.
    pub members: Vec<usize>,
    /// For two objectives, the weights $[w_{\min}, w_{\max}]$ for which each member (in the
    /// order of `members`) maximises $w\gamma_1 + (1 - w)\gamma_2$ among all designs (module
    /// docs; computed against the other members, which is equivalent, as a design dominated by
    /// a member scores at most as much for every $w$), `None` for a member that no weight
    /// selects; `None` altogether for more than two
    /// objectives (the regions are then polytopes of the weight simplex).
    pub weight_intervals: Option<Vec<Option<(f64, f64)>>>,
}

/// The Pareto front of `values` (design $p$ scored `values[p][k]` on objective $k$, in the
/// sense `senses[k]`), with the weight intervals for two objectives (module docs).
///
/// The designs are visited in decreasing lexicographic order of $\gamma$ (ties by index), so
/// a dominated design is always dominated by a member found before it: the cost is
/// $O(N \cdot |\text{front}|)$ comparisons.
///
/// # Errors
/// [`OptimizeError::Invalid`] for fewer than two objectives, a design without one value per
/// objective, or a value that is not finite.
///
/// # Example
/// Two maximised objectives: (0.6, 0.6) is selected by the weights in [0.4, 0.6], (0.45, 0.45)
/// is dominated, and (0.7, 0.4) lies under the chord from (1, 0) to (0.6, 0.6), so no weight
/// selects it.
/// ```
/// use pkm_optimizers::{Sense, pareto_front};
/// let values = [[1.0, 0.0], [0.6, 0.6], [0.45, 0.45], [0.0, 1.0], [0.7, 0.4]];
/// let front = pareto_front(&values, &[Sense::Maximise; 2])?;
/// assert_eq!(front.members, [0, 1, 3, 4]);
/// let w = front.weight_intervals.unwrap();
/// let (lo, hi) = w[1].unwrap();
/// assert!((lo - 0.4).abs() < 1e-12 && (hi - 0.6).abs() < 1e-12);
/// assert_eq!(w[3], None);
/// # Ok::<(), pkm_optimizers::OptimizeError>(())
/// ```
pub fn pareto_front<V: AsRef<[f64]>>(
    values: &[V],
    senses: &[Sense],
) -> Result<ParetoFront, OptimizeError> {
    let k = senses.len();
    if k < 2 {
        return Err(InvalidInput::new("senses", k as f64, "at least two objectives").into());
    }
    let gamma = oriented(values, senses)?;
    let members = non_dominated(&gamma);
    let weight_intervals = (k == 2).then(|| {
        members
            .iter()
            .map(|&p| {
                let others = members.iter().filter(|&&q| q != p).map(|&q| &gamma[q]);
                weight_interval(&gamma[p], others)
            })
            .collect()
    });
    Ok(ParetoFront {
        members,
        weight_intervals,
    })
}

/// $\gamma$ of the module docs, checked: one finite value per objective.
fn oriented<V: AsRef<[f64]>>(
    values: &[V],
    senses: &[Sense],
) -> Result<Vec<Vec<f64>>, OptimizeError> {
    values
        .iter()
        .map(|v| {
            let v = v.as_ref();
            if v.len() != senses.len() {
                let got = v.len() as f64;
                return Err(InvalidInput::new("values", got, "one value per objective").into());
            }
            if let Some(&bad) = v.iter().find(|x| !x.is_finite()) {
                return Err(InvalidInput::new("values", bad, "must be finite").into());
            }
            Ok(v.iter().zip(senses).map(|(x, s)| s.goodness(*x)).collect())
        })
        .collect()
}

fn dominates(a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).all(|(x, y)| x >= y) && a.iter().zip(b).any(|(x, y)| x > y)
}

/// Ascending indices of the designs no other dominates.
fn non_dominated(gamma: &[Vec<f64>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..gamma.len()).collect();
    order.sort_by(|&i, &j| {
        gamma[j]
            .iter()
            .zip(&gamma[i])
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
            .then(i.cmp(&j))
    });
    let mut front: Vec<usize> = Vec::new();
    for i in order {
        if !front.iter().any(|&f| dominates(&gamma[f], &gamma[i])) {
            front.push(i);
        }
    }
    front.sort_unstable();
    front
}

/// $[w_{\min}, w_{\max}] \subset [0, 1]$ of the weights for which `p` maximises
/// $w\gamma_1 + (1 - w)\gamma_2$ among `others`; `None` when empty.
fn weight_interval<'a>(
    p: &[f64],
    others: impl Iterator<Item = &'a Vec<f64>>,
) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for q in others {
        let (da, db) = (p[0] - q[0], p[1] - q[1]);
        let c = da - db;
        if c > 0.0 {
            lo = lo.max(-db / c);
        } else if c < 0.0 {
            hi = hi.min(-db / c);
        } else if db < 0.0 {
            return None;
        }
    }
    (lo <= hi).then_some((lo, hi))
}
