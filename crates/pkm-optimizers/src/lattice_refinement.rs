//! Coarse-to-fine exhaustive search on nested lattices: the design study of Miller 2004, §2.2.3
//! (exhaustive grid, then exhaustive local grids at finer steps, e.g. 0.05 then 0.01).
//!
//! Unlike [`crate::refined_grid_search`], whose spacing halves per level, every level here lies
//! on the lattice of its own step, so the optimum is reported on the same lattice as a paper
//! that tabulates its designs to two decimals.

use crate::{GridAxis, GridResult, GridSearch, OptimizeError, Sense, Termination, grid_search};
use pkm_traits::{Bounds, InvalidInput, Objective, Progress};
use serde::{Deserialize, Serialize};

/// One refinement level of [`lattice_refined_search`] (in a study file `{ step, half_width }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub struct LatticeLevel {
    /// The lattice step of this level (applied to every axis that has more than one node).
    pub step: f64,
    /// The window spans this many steps either side of the incumbent (clipped to the bounds).
    pub half_width: usize,
}

/// Exhaustive search on `coarse`, then on every level a window of `2·half_width + 1` lattice
/// nodes per axis around the incumbent; a level is repeated (at most eight times) while
/// its optimum lies on the window's edge but not on a bound, so that the reported optimum is a
/// local optimum of the finest lattice. Axes with a single coarse node stay fixed.
///
/// This is [`grid_search`] on `coarse` followed by [`lattice_refine_from`] from its optimum;
/// evaluations and infeasible designs are summed over both. The landscape, if `coarse` keeps
/// it, is the coarse one.
///
/// # Errors
/// As [`grid_search`]; [`OptimizeError::Invalid`] for a step that is not positive.
pub fn lattice_refined_search<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    coarse: &GridSearch,
    levels: &[LatticeLevel],
    progress: &dyn Progress,
) -> Result<GridResult, OptimizeError> {
    let GridResult {
        best,
        best_value,
        evaluations,
        infeasible,
        landscape,
        ..
    } = grid_search(objective, sense, coarse, progress)?;
    let refined = lattice_refine_from(
        objective,
        sense,
        coarse.axes(),
        (best, best_value),
        levels,
        progress,
    )?;
    Ok(GridResult {
        evaluations: evaluations + refined.evaluations,
        infeasible: infeasible + refined.infeasible,
        landscape,
        ..refined
    })
}

/// The refinement of [`lattice_refined_search`] from a known optimum `start = (x₀, f(x₀))` of
/// the grid `coarse` (e.g. a coarse grid already evaluated for its landscape or in shards).
///
/// Level ℓ, of step $h_\ell$ and half-width $w_\ell$, searches exhaustively the window
/// $W_\ell(c) = \prod_k \{c_k + i\,h_\ell : -b_k \le i \le a_k\}$ around the incumbent
/// $c$, where $b_k = \min(w_\ell, \lfloor (c_k - l_k)/h_\ell \rfloor)$ and
/// $a_k = \min(w_\ell, \lfloor (u_k - c_k)/h_\ell \rfloor)$ clip it to the bounds
/// $[l_k, u_k]$ ([`lattice_window`]); axes of `coarse` with a single node keep it. The window's
/// best node $x^\ast$ becomes the incumbent when $f(x^\ast)$ is at least as good as $f(c)$ (a
/// tie moves to the window's first best node, in row-major order), and the level is repeated
/// around it, at most 8 times, while $f(x^\ast)$ strictly improves and $x^\ast$ lies on an
/// edge of the window that the bounds leave room to pass. The levels run in order, each from
/// the incumbent of the one before.
///
/// The result holds the final incumbent, the evaluations and infeasible designs of the windows
/// only (not those of `coarse`), no landscape, and [`Termination::Converged`] with criterion
/// `"optimum inside every window"`, or [`Termination::MaxIterations`] when some level's window
/// still moved after its last repeat. Without levels it is `start`, with no evaluation.
///
/// # Errors
/// [`OptimizeError::Invalid`] when `coarse` or `start.0` does not have one entry per
/// design variable, `start.0` or `start.1` is not finite, `start.0` lies outside the
/// objective's bounds (a window around it would too), or for a level as in
/// [`lattice_window`]; otherwise as [`grid_search`] on a window.
pub fn lattice_refine_from<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    coarse: &[GridAxis],
    (best, best_value): (Vec<f64>, f64),
    levels: &[LatticeLevel],
    progress: &dyn Progress,
) -> Result<GridResult, OptimizeError> {
    let dimension = objective.dimension();
    if coarse.len() != dimension {
        return Err(
            InvalidInput::new("axes", coarse.len() as f64, "one axis per design variable").into(),
        );
    }
    if best.len() != dimension {
        return Err(
            InvalidInput::new("start", best.len() as f64, "one value per design variable").into(),
        );
    }
    if let Some(&x) = best.iter().find(|x| !x.is_finite()) {
        return Err(InvalidInput::new("start", x, "must be finite").into());
    }
    if let Some((&x, _)) = best
        .iter()
        .zip(objective.bounds())
        .find(|(x, b)| !b.contains(**x))
    {
        return Err(InvalidInput::new("start", x, "must lie in the objective's bounds").into());
    }
    if !best_value.is_finite() {
        return Err(InvalidInput::new("start value", best_value, "must be finite").into());
    }
    let mut result = GridResult {
        best,
        best_value,
        evaluations: 0,
        infeasible: 0,
        landscape: None,
        termination: Termination::MaxIterations,
    };
    // Whether some level's window still moved after its last repeat.
    let mut exhausted = false;
    for level in levels {
        let mut window_moved = false;
        for _ in 0..MAX_REPEATS {
            let axes = lattice_window(objective.bounds(), coarse, &result.best, level)?;
            let local = grid_search(objective, sense, &GridSearch::new(axes.clone())?, progress)?;
            result.evaluations += local.evaluations;
            result.infeasible += local.infeasible;
            let improved = sense.improves(local.best_value, result.best_value);
            if sense.at_least_as_good(local.best_value, result.best_value) {
                result.best_value = local.best_value;
                result.best = local.best;
            }
            window_moved =
                improved && on_open_edge(&axes, &result.best, objective.bounds(), level.step);
            if !window_moved {
                break;
            }
        }
        exhausted |= window_moved;
    }
    result.termination = if exhausted {
        Termination::MaxIterations
    } else {
        Termination::Converged {
            criterion: "optimum inside every window",
        }
    };
    Ok(result)
}

/// Re-centred windows per level at most: a window that keeps moving is a search along a ridge.
const MAX_REPEATS: usize = 8;

/// The window of `level` around `centre`: `2·half_width + 1` lattice nodes per axis, clipped to
/// `bounds` (a centre beyond its bounds is taken at the nearest one, so the window always lies
/// within them); axes of `axes` with a single node are kept as they are.
///
/// # Errors
/// [`OptimizeError::Invalid`] for a step that is not finite and positive, `axes` or `centre`
/// of another length than `bounds`, a centre that is not finite, or a window
/// of more than [`crate::MAX_GRID_NODES`] nodes on one axis.
pub fn lattice_window(
    bounds: &[Bounds],
    axes: &[GridAxis],
    centre: &[f64],
    level: &LatticeLevel,
) -> Result<Vec<GridAxis>, OptimizeError> {
    if !(level.step > 0.0 && level.step.is_finite()) {
        return Err(InvalidInput::new("step", level.step, "must be finite and > 0").into());
    }
    for (name, len) in [("axes", axes.len()), ("centre", centre.len())] {
        if len != bounds.len() {
            let requirement = "must have one entry per bound";
            return Err(InvalidInput::new(name, len as f64, requirement).into());
        }
    }
    // At most this many steps either side, so that `below + above + 1` cannot overflow.
    let half_width = level.half_width.min(crate::MAX_GRID_NODES);
    axes.iter()
        .zip(bounds)
        .zip(centre)
        .map(|((axis, b), &c)| {
            if axis.n() == 1 {
                return Ok(*axis);
            }
            if !c.is_finite() {
                return Err(InvalidInput::new("centre", c, "must be finite").into());
            }
            // A centre beyond its bounds is taken at the nearest bound.
            let c = c.clamp(b.lower(), b.upper());
            // The float-to-usize cast saturates; the `min` keeps the count small.
            let room = |d: f64| ((d / level.step + 1e-9).floor().max(0.0) as usize).min(half_width);
            let below = room(c - b.lower());
            let above = room(b.upper() - c);
            let lower = c - below as f64 * level.step;
            let upper = c + above as f64 * level.step;
            GridAxis::new(lower, upper, below + above + 1)
        })
        .collect()
}

fn on_open_edge(axes: &[GridAxis], best: &[f64], bounds: &[Bounds], step: f64) -> bool {
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9 * (1.0 + step);
    axes.iter().zip(best).zip(bounds).any(|((axis, &x), b)| {
        axis.n() > 1
            && ((near(x, axis.lower()) && x - step >= b.lower() - 1e-12)
                || (near(x, axis.upper()) && x + step <= b.upper() + 1e-12))
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use pkm_traits::{ObjectiveError, Silent};

    /// A tilted bowl $\sum_k (x_k - c_k)^2 + 0.3\,x_0 x_1$ on $[-1, 1]^2 \times \{0.25\}$,
    /// infeasible for $x_0 + x_1 > 1.05$ (so that windows count infeasible nodes).
    struct TiltedBowl([Bounds; 3]);

    impl Objective for TiltedBowl {
        fn dimension(&self) -> usize {
            3
        }
        fn bounds(&self) -> &[Bounds] {
            &self.0
        }
        fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
            if p[0] + p[1] > 1.05 {
                return Err(ObjectiveError::infeasible("x0 + x1 > 1.05"));
            }
            Ok((p[0] - 0.713).powi(2) + (p[1] - 0.437).powi(2) + 0.3 * p[0] * p[1] + p[2])
        }
    }

    #[test]
    fn lattice_refined_search_is_grid_search_then_lattice_refine_from_bit_for_bit() {
        let unit = Bounds::new(-1.0, 1.0).unwrap();
        let objective = TiltedBowl([unit, unit, Bounds::new(0.25, 0.25).unwrap()]);
        let axes = vec![
            GridAxis::new(-1.0, 1.0, 5).unwrap(),
            GridAxis::new(-1.0, 1.0, 5).unwrap(),
            GridAxis::new(0.25, 0.25, 1).unwrap(),
        ];
        let coarse = GridSearch::new(axes).unwrap().keeping_landscape();
        // Half-width 1 at 0.1 must re-centre to walk from the coarse node (0.5, 0.5).
        let levels = [
            LatticeLevel {
                step: 0.1,
                half_width: 1,
            },
            LatticeLevel {
                step: 0.01,
                half_width: 3,
            },
        ];
        for sense in [Sense::Minimise, Sense::Maximise] {
            let whole =
                lattice_refined_search(&objective, sense, &coarse, &levels, &Silent).unwrap();
            let grid = grid_search(&objective, sense, &coarse, &Silent).unwrap();
            let start = (grid.best.clone(), grid.best_value);
            let refined =
                lattice_refine_from(&objective, sense, coarse.axes(), start, &levels, &Silent)
                    .unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&whole.best), bits(&refined.best));
            assert_eq!(whole.best_value.to_bits(), refined.best_value.to_bits());
            assert_eq!(whole.evaluations, grid.evaluations + refined.evaluations);
            assert_eq!(whole.infeasible, grid.infeasible + refined.infeasible);
            assert_eq!(whole.termination, refined.termination);
            assert_eq!(whole.landscape, grid.landscape);
            assert!(refined.landscape.is_none());
            // Minimising, the refinement did work: more than one 3×3 window at 0.1 and, near
            // the minimum (0.66, 0.34), infeasible nodes; maximising, it stays in the corner
            // (−1, −1).
            if sense == Sense::Minimise {
                assert!(refined.evaluations > 9 + 49, "{}", refined.evaluations);
                assert!(refined.infeasible > 0, "{refined:?}");
            } else {
                assert!(
                    refined.best[..2]
                        .iter()
                        .all(|x| x.to_bits() == (-1.0f64).to_bits())
                );
            }
        }
    }

    #[test]
    fn lattice_refine_from_without_levels_returns_the_start() {
        let unit = Bounds::new(-1.0, 1.0).unwrap();
        let objective = TiltedBowl([unit, unit, Bounds::new(0.25, 0.25).unwrap()]);
        let axes = [GridAxis::new(-1.0, 1.0, 5).unwrap(); 3];
        let start = (vec![0.5, 0.5, 0.25], 1.5);
        let result = lattice_refine_from(
            &objective,
            Sense::Minimise,
            &axes,
            start.clone(),
            &[],
            &Silent,
        )
        .unwrap();
        assert_eq!(
            (result.best, result.best_value.to_bits()),
            (start.0, start.1.to_bits())
        );
        assert_eq!(result.evaluations, 0);
    }
}
