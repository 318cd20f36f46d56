//! `pkm-optimizers`: grid search, lattice refinement, LM multistart, augmented Lagrangian (and
//! its SPG inner solver), weighted combination.

use super::{all_finite, config, hostile_count, hostile_f64, judge, judge_err, judge_value};
use pkm::papers::wolf2006::eq15_as_printed;
use pkm_optimizers::kkt::{self, KktSettings};
use pkm_optimizers::{
    AugmentedLagrangianSettings, GridAxis, GridSearch, LatticeLevel, LmSettings, Multistart,
    OptimizeError, RefinementSettings, Sense, WeightedSum, augmented_lagrangian, grid_search,
    lattice_refine_from, lattice_refined_search, levenberg_marquardt,
    multistart_levenberg_marquardt, pareto_front, refined_grid_search, weighted_combination,
};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Residuals, Silent};
use proptest::prelude::*;

/// $f(p) = \sum_k (p_k - c_k)^2$ with residuals $r_k = p_k - c_k$ and one constraint
/// $p_0 + p_1 \ge 1$ (feasible inside the box).
#[derive(Debug)]
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

fn grid(axes: Vec<GridAxis>, keep: bool) -> Result<GridSearch, OptimizeError> {
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
        let settings = LmSettings { max_iterations, tolerance, fd_step, ..LmSettings::default() };
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
        let settings = AugmentedLagrangianSettings { fd_step, tolerance, feasibility, max_outer, max_inner, scale: None };
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

proptest! {
    #![proptest_config(config())]

    #[test]
    fn optimality_checks_are_finite_or_typed(
        design in prop::collection::vec(hostile_f64(), 0..4), multipliers in prop::collection::vec(hostile_f64(), 0..3),
        step in hostile_f64(), active_tolerance in hostile_f64(), maximise in prop::bool::ANY,
    ) {
        let bowl = Bowl::new(3);
        let settings = KktSettings { step, active_tolerance };
        judge("KktSettings::validate", || settings.validate(), |_| {
            step > 0.0 && step < 0.5 && active_tolerance.is_finite() && active_tolerance >= 0.0
        })?;
        judge("kkt::check", || kkt::check(&bowl, sense(maximise), &design, &multipliers, &settings, &Silent), |c| {
            design.len() == 3 && multipliers.len() == 1
                && all_finite(c.lagrangian_gradient.iter().chain(&c.least_squares_multipliers))
                && all_finite(c.hessian_eigenvalues.iter().chain(&c.reduced_hessian_eigenvalues))
                && c.projected_gradient_max.is_finite() && c.stationarity_residual.is_finite()
        })?;
    }

    #[test]
    fn pareto_fronts_are_checked(
        values in prop::collection::vec(prop::collection::vec(hostile_f64(), 0..4), 0..6),
        k in 0..4usize, maximise in prop::bool::ANY,
    ) {
        let senses = vec![sense(maximise); k];
        judge("pareto_front", || pareto_front(&values, &senses), |front| {
            k >= 2 && front.members.iter().all(|&i| i < values.len())
                && front.weight_intervals.as_ref().is_none_or(|w| {
                    w.len() == front.members.len()
                        && w.iter().flatten().all(|(lo, hi)| 0.0 <= *lo && lo <= hi && *hi <= 1.0)
                })
        })?;
    }

    #[test]
    fn the_best_of_hostile_values_is_a_number(values in prop::collection::vec(prop::option::of(hostile_f64()), 0..8), maximise in prop::bool::ANY) {
        judge_value("Sense::best", || sense(maximise).best(values.iter().copied()), |best| {
            best.is_none_or(|(k, v)| !v.is_nan() && values.get(k).copied().flatten().is_some_and(|x| x.to_bits() == v.to_bits()))
        })?;
    }

    #[test]
    fn grid_ranges_and_indices_are_checked(n in hostile_count(), start in hostile_count(), end in hostile_count(), flat in hostile_count()) {
        let Ok(axis) = GridAxis::new(-1.0, 1.0, n.min(1 << 12)) else { return Ok(()) };
        let grid = GridSearch::new(vec![axis, GridAxis::new(0.0, 1.0, 3).unwrap()]).unwrap();
        let range = start.min(1 << 16)..end.min(1 << 16);
        judge("GridSearch::evaluate_range", || grid.evaluate_range(range.clone(), &Silent, |p| Ok::<_, OptimizeError>(p[0] + p[1])), |v| {
            range.end <= grid.nodes() && v.len() == range.len() && all_finite(v.iter())
        })?;
        judge_value("GridSearch::node_index", || grid.node_index(flat), |i| {
            i.as_ref().is_none_or(|i| grid.flat_index(i) == Some(flat))
        })?;
        judge_value("GridSearch::node_design", || grid.node_design(flat), |d| {
            d.as_ref().is_none_or(|d| design_inside(&grid.bounds(), d))
        })?;
    }

    #[test]
    fn start_points_and_weighted_sums_are_checked(
        extra in prop::collection::vec(prop::collection::vec(hostile_f64(), 0..4), 0..3), count in 0..4usize,
        weights in prop::collection::vec(hostile_f64(), 0..3),
    ) {
        let bowl = Bowl::new(3);
        let starts = Multistart::new(count, 7).with_extra_starts(extra.clone());
        judge("Multistart::start_points", || starts.start_points(bowl.bounds()), |points| {
            points.len() == count + extra.len() && points.iter().all(|p| p.len() == 3 && all_finite(p.iter()))
        })?;
        let parts = weights.iter().map(|w| (*w, Bowl::new(3))).collect();
        judge("WeightedSum::new", || WeightedSum::new(parts), |sum| {
            sum.parts().all(|(w, _)| w.is_finite() && w >= 0.0) && sum.value(&[0.1, 0.2, 0.3]).is_ok_and(f64::is_finite)
        })?;
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
