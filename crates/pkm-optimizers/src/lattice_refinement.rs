//! Coarse-to-fine exhaustive search on nested lattices: the design study of Miller 2004, §2.2.3
//! (exhaustive grid, then exhaustive local grids at finer steps, e.g. 0.05 then 0.01).
//!
//! Unlike [`crate::refined_grid_search`], whose spacing halves per level, every level here lies
//! on the lattice of its own step, so the optimum is reported on the same lattice as a paper
//! that tabulates its designs to two decimals.

use crate::{GridAxis, GridResult, GridSearch, OptimizeError, Sense, Termination, grid_search};
use pkm_traits::{Bounds, Objective, Progress};

/// One refinement level of [`lattice_refined_search`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeLevel {
    /// The lattice step of this level (applied to every axis that has more than one node).
    pub step: f64,
    /// The window spans this many steps either side of the incumbent (clipped to the bounds).
    pub half_width: usize,
}

/// Exhaustive search on `coarse`, then on every level a window of `2·half_width + 1` lattice
/// nodes per axis around the incumbent; a level is repeated (at most `max_repeats` times) while
/// its optimum lies on the window's edge but not on a bound, so that the reported optimum is a
/// local optimum of the finest lattice. Axes with a single coarse node stay fixed.
///
/// The landscape, if `coarse` keeps it, is the coarse one.
///
/// # Errors
/// As [`grid_search`]; [`OptimizeError::InvalidSetting`] for a step that is not positive.
pub fn lattice_refined_search<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    coarse: &GridSearch,
    levels: &[LatticeLevel],
    progress: &dyn Progress,
) -> Result<GridResult, OptimizeError> {
    let mut result = grid_search(objective, sense, coarse, progress)?;
    let coarse = coarse.axes();
    // Whether some level's window still moved after its last repeat.
    let mut exhausted = false;
    for level in levels {
        if !(level.step > 0.0 && level.step.is_finite()) {
            return Err(OptimizeError::InvalidSetting {
                setting: "step",
                value: level.step,
                requirement: "must be finite and > 0",
            });
        }
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
/// `bounds`; axes of `axes` with a single node are kept as they are.
///
/// # Errors
/// [`OptimizeError::InvalidSetting`] for a step that is not finite and positive, a centre that
/// is not finite, or a window of more than [`crate::MAX_GRID_NODES`] nodes on one axis.
pub fn lattice_window(
    bounds: &[Bounds],
    axes: &[GridAxis],
    centre: &[f64],
    level: &LatticeLevel,
) -> Result<Vec<GridAxis>, OptimizeError> {
    if !(level.step > 0.0 && level.step.is_finite()) {
        return Err(invalid("step", level.step, "must be finite and > 0"));
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
                return Err(invalid("centre", c, "must be finite"));
            }
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

fn invalid(setting: &'static str, value: f64, requirement: &'static str) -> OptimizeError {
    OptimizeError::InvalidSetting {
        setting,
        value,
        requirement,
    }
}

fn on_open_edge(axes: &[GridAxis], best: &[f64], bounds: &[Bounds], step: f64) -> bool {
    let near = |a: f64, b: f64| (a - b).abs() < 1e-9 * (1.0 + step);
    axes.iter().zip(best).zip(bounds).any(|((axis, &x), b)| {
        axis.n() > 1
            && ((near(x, axis.lower()) && x - step >= b.lower() - 1e-12)
                || (near(x, axis.upper()) && x + step <= b.upper() + 1e-12))
    })
}
