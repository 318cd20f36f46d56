//! Lattice refinement of a sweep's grid optimum (`pkm_optimizers::lattice_refine_from`, the
//! grid is not evaluated twice): each `[[sweep.refine]]` level searches a window of
//! ±`half_width` steps of `step` around the optimum so far, re-centred while the optimum
//! improves on the window's open edge. A level that overrides index settings (e.g. a finer η1
//! rule) starts a new stage: a grid on its window with the new settings, whose optimum replaces
//! the old one (values under different settings are not compared), then the level itself, as
//! the Linear Delta search of Miller 2004 §2.2.3 does.

use super::utility;
use crate::StudyError;
use crate::grid::Prepared;
use crate::registry::StudyMechanism;
use crate::schema::grid::{IndexName, IndexSettings, RefineLevel};
use pkm_optimizers::{
    GridSearch, LatticeLevel, Sense, grid_search, lattice_refine_from, lattice_window,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Progress};

/// The lattice of a level.
fn lattice(level: &RefineLevel) -> LatticeLevel {
    LatticeLevel {
        step: level.step,
        half_width: level.half_width,
    }
}

/// The settings from `level` on, when it overrides any.
fn overrides(level: &RefineLevel, current: IndexSettings) -> Option<IndexSettings> {
    (level.eta1_points.is_some() || level.eta1_paper_grid.is_some()).then(|| IndexSettings {
        eta1_points: level.eta1_points.unwrap_or(current.eta1_points),
        eta1_paper_grid: level.eta1_paper_grid.unwrap_or(current.eta1_paper_grid),
    })
}

/// Checks every level before any computation: a positive finite step, a Gauss–Legendre order
/// in range.
///
/// # Errors
/// [`StudyError::Invalid`] at `sweep.refine[k].step` or `sweep.refine[k].eta1_points`.
pub(super) fn check_levels(levels: &[RefineLevel]) -> Result<(), StudyError> {
    for (k, level) in levels.iter().enumerate() {
        let path = format!("sweep.refine[{k}]");
        if !(level.step > 0.0 && level.step.is_finite()) {
            return Err(StudyError::invalid(
                format!("{path}.step").as_str(),
                "expected a positive lattice step (in every variable's unit)",
            ));
        }
        if let Some(points) = level.eta1_points {
            crate::grid::check_eta1_points(points, &path)?;
        }
    }
    Ok(())
}

/// The utility of a design as an [`Objective`] (negated: the searches minimise).
struct UtilityObjective<'a, M> {
    prepared: &'a Prepared<M>,
    terms: &'a [(IndexName, f64)],
    indices: Vec<IndexName>,
    settings: IndexSettings,
    bounds: Vec<Bounds>,
}

impl<M: StudyMechanism> Objective for UtilityObjective<'_, M> {
    fn dimension(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn value(&self, design: &[f64]) -> Result<f64, ObjectiveError> {
        match self
            .prepared
            .evaluator
            .evaluate(design, &self.indices, self.settings)
        {
            Ok(Ok(values)) => Ok(-utility(self.terms, &self.indices, &values)),
            Ok(Err(reason)) => Err(reason.into()),
            Err(StudyError::Cancelled) => Err(ObjectiveError::Cancelled),
            Err(e) => Err(ObjectiveError::infeasible(e.to_string())),
        }
    }
}

/// The refined optimum: its design, the settings of the last stage, and the designs evaluated.
pub(super) struct Refined {
    pub best: Vec<f64>,
    pub settings: IndexSettings,
    pub evaluations: usize,
}

/// Refines `(best, best_value)` (the grid optimum and its negated utility) through `levels`.
///
/// # Errors
/// The searches' errors; [`StudyError::Cancelled`].
pub(super) fn refine<M: StudyMechanism>(
    prepared: &Prepared<M>,
    terms: &[(IndexName, f64)],
    mut settings: IndexSettings,
    levels: &[RefineLevel],
    (mut best, mut best_value): (Vec<f64>, f64),
    progress: &dyn Progress,
) -> Result<Refined, StudyError> {
    let grid_axes = prepared.grid.axes();
    let bounds = prepared.grid.search.bounds();
    let indices: Vec<IndexName> = terms.iter().map(|(i, _)| *i).collect();
    let mut coarse = grid_axes.to_vec();
    let mut evaluations = 0;
    for level in levels {
        let lattice = lattice(level);
        let overrides = overrides(level, settings);
        settings = overrides.unwrap_or(settings);
        let objective = UtilityObjective {
            prepared,
            terms,
            indices: indices.clone(),
            settings,
            bounds: bounds.clone(),
        };
        if overrides.is_some() {
            let window = lattice_window(&bounds, grid_axes, &best, &lattice)?;
            let search = GridSearch::new(window.clone())?;
            let stage = grid_search(&objective, Sense::Minimise, &search, progress)?;
            evaluations += stage.evaluations;
            (best, best_value) = (stage.best, stage.best_value);
            coarse = window;
        }
        let refined = lattice_refine_from(
            &objective,
            Sense::Minimise,
            &coarse,
            (best, best_value),
            &[lattice],
            progress,
        )?;
        evaluations += refined.evaluations;
        (best, best_value) = (refined.best, refined.best_value);
    }
    if let Some(last) = levels.last() {
        for (v, axis) in best.iter_mut().zip(grid_axes) {
            if axis.upper() > axis.lower() {
                *v = on_lattice(*v, last.step);
            }
        }
    }
    Ok(Refined {
        best,
        settings,
        evaluations,
    })
}

/// `v` on the lattice of `step` when `1/step` is an integer (0.1, 0.05, 0.01, …): removes the
/// round-off of `lower + i·step`; unchanged otherwise.
fn on_lattice(v: f64, step: f64) -> f64 {
    let scale = (1.0 / step).round();
    if scale >= 1.0 && ((1.0 / step) - scale).abs() < 1e-9 * scale {
        (v * scale).round() / scale
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_values_lose_their_round_off() {
        assert_eq!(
            on_lattice(1.4 + 6.0 * 0.1, 0.1).to_bits(),
            2.0_f64.to_bits()
        );
        assert_eq!(
            on_lattice(0.123_456, 0.3).to_bits(),
            0.123_456_f64.to_bits()
        );
    }

    #[test]
    fn levels_are_checked_before_any_search() {
        let level = |step: f64, eta1_points| RefineLevel {
            step,
            half_width: 1,
            eta1_points,
            eta1_paper_grid: None,
        };
        assert!(check_levels(&[level(0.05, Some(16))]).is_ok());
        let at = |levels: &[RefineLevel]| match check_levels(levels) {
            Err(e) => e.path().map(ToString::to_string),
            Ok(()) => None,
        };
        assert_eq!(
            at(&[level(0.05, None), level(-0.01, None)]).as_deref(),
            Some("sweep.refine[1].step")
        );
        assert_eq!(
            at(&[level(f64::NAN, None)]).as_deref(),
            Some("sweep.refine[0].step")
        );
        assert_eq!(
            at(&[level(0.01, Some(0))]).as_deref(),
            Some("sweep.refine[0].eta1_points")
        );
    }
}
