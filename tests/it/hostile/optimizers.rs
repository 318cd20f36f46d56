//! `pkm-optimizers`: grid search, lattice refinement, LM multistart, augmented Lagrangian (and
//! its SPG inner solver), weighted combination.

use super::{all_finite, config, hostile_count, hostile_f64, judge, judge_err};
use pkm::papers::wolf2006::eq15_as_printed;
use pkm_optimizers::{
    AugmentedLagrangianSettings, GridAxis, GridSearch, LatticeLevel, LmSettings, Multistart,
    RefinementSettings, Sense, augmented_lagrangian, grid_search, lattice_refine_from,
    lattice_refined_search, levenberg_marquardt, multistart_levenberg_marquardt,
    refined_grid_search, weighted_combination,
};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Residuals, Silent};
use proptest::prelude::*;

/// $f(p) = \sum_k (p_k - c_k)^2$ with residuals $r_k = p_k - c_k$ and one constraint
/// $p_0 + p_1 \ge 1$ (feasible inside the box).
struct Bowl {
    bounds: Vec<Bounds>,
    centre: Vec<f64>,
}

impl Bowl {
    fn new(n: usize) -> Self {
        Self {
            bounds: vec![Bounds::new(-2.0, 2.0).unwrap(); n],
            centre: (0..n).map(|k| 0.3 - 0.1 * k as f64).collect(),
        }
    }
}

impl Objective for Bowl {
    fn dimension(&self) -> usize {
        self.bounds.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        self.check_dimension(p)?;
        Ok(p.iter()
            .zip(&self.centre)
            .map(|(x, c)| (x - c).powi(2))
            .sum())
    }
}

impl Residuals for Bowl {
    fn n_residuals(&self) -> usize {
        self.bounds.len()
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        self.check_dimension(p)?;
        for ((ri, x), c) in r.iter_mut().zip(p).zip(&self.centre) {
            *ri = x - c;
        }
        Ok(())
    }
}

impl Constraints for Bowl {
    fn n_constraints(&self) -> usize {
        1
    }
    fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        self.check_dimension(p)?;
        g[0] = 1.0 - p[0] - p[1];
        Ok(())
    }
}

fn axis_is_checked(a: &GridAxis) -> bool {
    let first = a.node(0);
    let last = a.node(a.n().saturating_sub(1));
    a.n() >= 1
        && a.step().is_finite()
        && a.step() >= 0.0
        && first.is_finite()
        && last.is_finite()
        && first <= last
}

fn sense(maximise: bool) -> Sense {
    if maximise {
        Sense::Maximise
    } else {
        Sense::Minimise
    }
}

fn grid(axes: Vec<GridAxis>, keep: bool) -> Result<GridSearch, pkm_optimizers::OptimizeError> {
    let grid = GridSearch::new(axes)?;
    Ok(if keep { grid.keeping_landscape() } else { grid })
}

fn design_inside(bounds: &[Bounds], p: &[f64]) -> bool {
    p.len() == bounds.len() && p.iter().zip(bounds).all(|(x, b)| b.contains(*x))
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn grid_axes_are_checked(lower in hostile_f64(), upper in hostile_f64(), n in hostile_count(), step in hostile_f64()) {
        judge("GridAxis::new", || GridAxis::new(lower, upper, n), axis_is_checked)?;
        judge("GridAxis::with_step", || GridAxis::with_step(lower, upper, step), axis_is_checked)?;
    }

    #[test]
    fn grid_search_on_hostile_axes(
        lower in hostile_f64(), upper in hostile_f64(), n in hostile_count(), keep in prop::bool::ANY,
        resolution in hostile_f64(), nodes in hostile_count(), levels in 0..30usize, maximise in prop::bool::ANY,
    ) {
        let bowl = Bowl::new(2);
        let Ok(fixed) = GridAxis::new(0.0, 1.0, 3) else { unreachable!() };
        if let Ok(axis) = GridAxis::new(lower, upper, n) {
            judge("grid_search", || grid(vec![axis, fixed], keep).and_then(|g| grid_search(&bowl, sense(maximise), &g, &Silent)), |r| {
                r.best_value.is_finite() && all_finite(r.best.iter())
            })?;
        }
        let coarse = GridSearch::new(vec![GridAxis::new(-2.0, 2.0, 5).unwrap(); 2]).unwrap();
        let settings = RefinementSettings { nodes_per_axis: nodes, max_levels: levels };
        judge("RefinementSettings::validate", || settings.validate(), |_| (3..=pkm_optimizers::MAX_GRID_NODES).contains(&nodes))?;
        judge("refined_grid_search", || refined_grid_search(&bowl, sense(maximise), &coarse, &[resolution; 2], &settings, &Silent), |r| {
            r.best_value.is_finite() && design_inside(bowl.bounds(), &r.best)
        })?;
    }

    #[test]
    fn lattice_refinement_on_hostile_levels(step in hostile_f64(), half_width in hostile_count()) {
        let bowl = Bowl::new(2);
        let coarse = GridSearch::new(vec![GridAxis::new(-2.0, 2.0, 5).unwrap(); 2]).unwrap();
        let levels = [LatticeLevel { step, half_width }];
        judge("lattice_refined_search", || lattice_refined_search(&bowl, Sense::Minimise, &coarse, &levels, &Silent), |r| {
            r.best_value.is_finite() && design_inside(bowl.bounds(), &r.best)
        })?;
    }

    #[test]
    fn lattice_refinement_from_hostile_starts(
        start in prop::collection::vec(hostile_f64(), 0..4), value in hostile_f64(), n_axes in 0..4usize,
        step in hostile_f64(), half_width in hostile_count(), maximise in prop::bool::ANY,
    ) {
        let bowl = Bowl::new(2);
        let coarse = vec![GridAxis::new(-2.0, 2.0, 5).unwrap(); n_axes];
        let levels = [LatticeLevel { step, half_width }];
        let sense = sense(maximise);
        // Accepted only for one axis and one finite coordinate per variable and a finite value;
        // the incumbent never gets worse than the start.
        judge("lattice_refine_from", || lattice_refine_from(&bowl, sense, &coarse, (start.clone(), value), &levels, &Silent), |r| {
            n_axes == 2 && start.len() == 2 && all_finite(start.iter()) && value.is_finite()
                && r.best_value.is_finite() && r.best.len() == 2 && all_finite(r.best.iter())
                && sense.at_least_as_good(r.best_value, value)
        })?;
    }

    #[test]
    fn levenberg_marquardt_on_hostile_settings(
        start in prop::collection::vec(hostile_f64(), 0..4), tolerance in hostile_f64(), fd_step in hostile_f64(),
        max_iterations in 0..50usize, maximise in prop::bool::ANY, n_starts in hostile_count(), seed in any::<u64>(),
    ) {
        let bowl = Bowl::new(3);
        let settings = LmSettings { max_iterations, tolerance, fd_step };
        let sense = sense(maximise);
        let checked = |o: &pkm_optimizers::LocalOptimum| {
            o.value.is_finite() && design_inside(bowl.bounds(), &o.design) && all_finite(o.gradient.iter())
                && all_finite(o.reduced_hessian_eigenvalues.iter())
                && o.iterations >= 1 && o.iterations <= max_iterations && o.evaluations > o.iterations
        };
        judge("LmSettings::validate", || settings.validate(), |_| {
            max_iterations >= 1 && tolerance.is_finite() && tolerance > 0.0 && fd_step > 0.0 && fd_step < 0.1
        })?;
        judge("levenberg_marquardt", || levenberg_marquardt(&bowl, sense, &start, &settings, &Silent), checked)?;
        let small = n_starts.min(4);
        let multistart = Multistart::new(small, seed).with_extra_starts(vec![start.clone()]);
        judge("multistart_levenberg_marquardt", || multistart_levenberg_marquardt(&bowl, sense, &multistart, &settings, &Silent), |m| {
            checked(&m.best) && m.starts == small + 1 && m.evaluations >= m.best.evaluations
        })?;
    }

    #[test]
    fn multistart_counts_are_checked(starts in hostile_count(), extra in 0..3usize, seed in any::<u64>()) {
        let multistart = Multistart::new(starts, seed).with_extra_starts(vec![vec![0.0; 3]; extra]);
        judge("Multistart::validate", || multistart.validate(), |_| {
            let total = starts.saturating_add(extra);
            (1..=pkm_optimizers::MAX_STARTS).contains(&total)
        })?;
        if starts > 64 {
            // Large counts: refused or (up to MAX_STARTS) accepted, but not run here.
            return Ok(());
        }
        let settings = LmSettings { max_iterations: 3, ..LmSettings::default() };
        judge("multistart_levenberg_marquardt (counts)", || multistart_levenberg_marquardt(&Bowl::new(3), Sense::Minimise, &multistart, &settings, &Silent), |m| {
            m.starts == starts + extra && m.best.value.is_finite()
        })?;
    }

    #[test]
    fn augmented_lagrangian_on_hostile_settings(
        start in prop::collection::vec(hostile_f64(), 0..4), fd_step in hostile_f64(), tolerance in hostile_f64(),
        feasibility in hostile_f64(), max_outer in 0..6usize, max_inner in 0..40usize, maximise in prop::bool::ANY,
    ) {
        let bowl = Bowl::new(2);
        let settings = AugmentedLagrangianSettings { fd_step, tolerance, feasibility, max_outer, max_inner };
        judge("AugmentedLagrangianSettings::validate", || settings.validate(), |_| {
            [fd_step, tolerance, feasibility].iter().all(|v| v.is_finite() && *v > 0.0) && fd_step < 0.1
                && max_outer >= 1 && max_inner >= 1
        })?;
        judge("augmented_lagrangian", || augmented_lagrangian(&bowl, sense(maximise), &start, &settings, &Silent), |r| {
            r.value.is_finite() && design_inside(bowl.bounds(), &r.design) && all_finite(r.constraints.iter())
                && all_finite(r.multipliers.iter()) && r.outer_iterations >= 1 && r.outer_iterations <= max_outer
        })?;
    }

    #[test]
    fn weighted_combination_is_finite(
        optima in prop::collection::vec(prop::collection::vec(hostile_f64(), 2), 0..4),
        weights in prop::collection::vec(hostile_f64(), 0..4), printed in prop::bool::ANY,
    ) {
        if printed {
            judge("eq15_as_printed", || eq15_as_printed(&optima, &weights), |q| all_finite(q.iter()))?;
        } else {
            judge("weighted_combination", || weighted_combination(&optima, &weights), |q| all_finite(q.iter()))?;
        }
    }
}

#[test]
fn huge_counts_are_refused_before_allocating() {
    let bowl = Bowl::new(2);
    for n in [usize::MAX, 1 << 33] {
        super::expect(judge_err("GridAxis::new (huge)", || {
            GridAxis::new(0.0, 1.0, n)
        }));
    }
    super::expect(judge_err("GridAxis::with_step (huge)", || {
        GridAxis::with_step(0.0, 1.0, 1e-300)
    }));
    // Each axis is admissible, their product is not.
    let wide = GridAxis::new(0.0, 1.0, 1 << 13).unwrap();
    for keep in [false, true] {
        super::expect(judge_err("GridSearch::new (huge)", || {
            grid(vec![wide, wide], keep)
        }));
    }
    super::expect(judge_err("GridSearch::new (no axis)", || {
        GridSearch::new(Vec::new())
    }));
    let coarse = GridSearch::new(vec![GridAxis::new(-2.0, 2.0, 5).unwrap(); 2]).unwrap();
    let levels = [LatticeLevel {
        step: 1e-300,
        half_width: usize::MAX,
    }];
    super::expect(judge_err("lattice_refined_search (huge)", || {
        lattice_refined_search(&bowl, Sense::Minimise, &coarse, &levels, &Silent)
    }));
    let settings = RefinementSettings {
        nodes_per_axis: 1 << 20,
        max_levels: 3,
    };
    super::expect(judge_err("refined_grid_search (huge)", || {
        refined_grid_search(
            &bowl,
            Sense::Minimise,
            &coarse,
            &[1e-3; 2],
            &settings,
            &Silent,
        )
    }));
    let settings = LmSettings {
        max_iterations: 5,
        ..LmSettings::default()
    };
    for n in [usize::MAX, 1 << 40] {
        super::expect(judge_err("multistart_levenberg_marquardt (huge)", || {
            multistart_levenberg_marquardt(
                &bowl,
                Sense::Minimise,
                &Multistart::new(n, 1),
                &settings,
                &Silent,
            )
        }));
    }
}
