//! The multistart keeps every start's outcome in start order, picks its best by the one rule
//! (NaN never best, ties to the lowest start), gives the same bits on 1 and 4 threads, and a
//! cancellation aborts it; the grid's node range evaluation and the weighted sum of problems.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::{
    GridAxis, GridSearch, LmSettings, LocalOptimum, LocalResult, Multistart, MultistartRun,
    OptimizeError, Sense, Termination, WeightedSum, levenberg_marquardt, multistart,
    multistart_levenberg_marquardt,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Progress, Residuals, Silent};
use std::sync::atomic::{AtomicU64, Ordering};

/// $r = (x^2 - 1, y - c)$ on $[-2, 2]^2$: two minima $(\pm 1, c)$ of equal value 0, infeasible
/// for $x > 1.9$.
struct Wells {
    c: f64,
    bounds: [Bounds; 2],
}

impl Wells {
    fn new(c: f64) -> Self {
        Self {
            c,
            bounds: [Bounds::new(-2.0, 2.0).unwrap(); 2],
        }
    }
}

impl Objective for Wells {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        self.sum_of_squares(p)
    }
}

impl Residuals for Wells {
    fn n_residuals(&self) -> usize {
        2
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        if p[0] > 1.9 {
            return Err(ObjectiveError::infeasible("x > 1.9"));
        }
        r[0] = p[0] * p[0] - 1.0;
        r[1] = p[1] - self.c;
        Ok(())
    }
}

fn run(problem: &Wells, starts: &Multistart) -> MultistartRun<LocalOptimum> {
    let points = starts.start_points(problem.bounds()).unwrap();
    let settings = LmSettings::default();
    multistart(points, &Silent, |s, p| {
        levenberg_marquardt(problem, Sense::Minimise, s, &settings, p)
    })
    .unwrap()
}

#[test]
fn every_outcome_is_kept_in_start_order() {
    let problem = Wells::new(0.3);
    let extra = vec![vec![1.95, 0.0], vec![-0.5, 1.0]];
    let starts = Multistart::new(6, 11).with_extra_starts(extra.clone());
    let run = run(&problem, &starts);
    assert_eq!(run.starts.len(), 8);
    assert_eq!(run.starts[..2], extra[..]);
    assert_eq!(run.outcomes.len(), 8);
    // The first start is infeasible and kept as such, as is any other that stepped past 1.9.
    assert!(
        run.outcomes[0]
            .as_ref()
            .is_err_and(OptimizeError::is_infeasible)
    );
    let failed = run.outcomes.iter().filter(|o| o.is_err()).count();
    assert!(run.infeasible() == failed && failed < 8);
    for (start, outcome) in run.starts.iter().zip(&run.outcomes).skip(1) {
        let alone = levenberg_marquardt(
            &problem,
            Sense::Minimise,
            start,
            &LmSettings::default(),
            &Silent,
        );
        assert_eq!(
            outcome, &alone,
            "a start's outcome is its run alone, bit for bit"
        );
    }
    // Both wells have the value 0 up to rounding: the best is the first start of least value.
    let (k, best) = run.best(Sense::Minimise).unwrap();
    let values: Vec<f64> = run
        .outcomes
        .iter()
        .flatten()
        .map(LocalResult::value)
        .collect();
    assert!(values.iter().all(|v| *v >= best.value()));
    assert!(
        run.outcomes[..k]
            .iter()
            .flatten()
            .all(|o| o.value > best.value)
    );
    assert!(best.termination().converged() && (best.design()[1] - 0.3).abs() < 1e-8);
}

#[test]
fn the_outcomes_are_the_same_bits_on_one_and_four_threads() {
    let problem = Wells::new(-0.7);
    let starts = Multistart::new(24, 5);
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| run(&problem, &starts))
    };
    assert_eq!(on(1), on(4));
}

/// A local "solver" that returns a given value per start: the best rule on its own.
#[derive(Debug, Clone, PartialEq)]
struct Fixed(f64);

impl LocalResult for Fixed {
    fn design(&self) -> &[f64] {
        &[]
    }
    fn value(&self) -> f64 {
        self.0
    }
    fn termination(&self) -> Termination {
        Termination::MaxIterations
    }
}

/// Start `i` is the point `[i]`, and its "local result" is `values[i]` (`None`: infeasible).
fn fixed(values: &[Option<f64>]) -> MultistartRun<Fixed> {
    let starts = (0..values.len()).map(|i| vec![i as f64]).collect();
    multistart(starts, &Silent, |s, _| {
        let i = s[0] as usize;
        values[i]
            .map(Fixed)
            .ok_or_else(|| ObjectiveError::infeasible(format!("start {i}")).into())
    })
    .unwrap()
}

#[test]
fn nan_is_never_best_and_ties_go_to_the_lowest_start() {
    let run = fixed(&[
        Some(f64::NAN),
        Some(2.0),
        None,
        Some(1.0),
        Some(1.0),
        Some(f64::NAN),
    ]);
    assert_eq!(run.best(Sense::Minimise).unwrap(), (3, &Fixed(1.0)));
    assert_eq!(run.best(Sense::Maximise).unwrap(), (1, &Fixed(2.0)));
    let none = fixed(&[None, Some(f64::NAN), None]);
    match none.best(Sense::Minimise) {
        Err(OptimizeError::NoFeasibleDesign {
            evaluations,
            last_reason,
        }) => assert_eq!((evaluations, last_reason.as_str()), (3, "start 2")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn without_a_success_the_first_failure_that_is_not_infeasibility_is_the_error() {
    let starts = vec![vec![0.0]; 3];
    let run: MultistartRun<Fixed> = multistart(starts, &Silent, |s, _| {
        if s[0] > 0.0 {
            Ok(Fixed(1.0))
        } else {
            Err(OptimizeError::Numerical { what: "test" })
        }
    })
    .unwrap();
    assert_eq!(
        run.best(Sense::Minimise),
        Err(OptimizeError::Numerical { what: "test" })
    );
}

/// Cancels once `advance` has been called `after` times.
struct CancelAfter(u64, AtomicU64);

impl Progress for CancelAfter {
    fn advance(&self, n: u64) {
        self.1.fetch_add(n, Ordering::Relaxed);
    }
    fn is_cancelled(&self) -> bool {
        self.1.load(Ordering::Relaxed) >= self.0
    }
}

#[test]
fn a_cancelled_start_cancels_the_whole_run() {
    let problem = Wells::new(0.0);
    let points = Multistart::new(64, 3)
        .start_points(problem.bounds())
        .unwrap();
    let settings = LmSettings::default();
    let progress = CancelAfter(2, AtomicU64::new(0));
    let run = multistart(points.clone(), &progress, |s, p| {
        levenberg_marquardt(&problem, Sense::Minimise, s, &settings, p)
    });
    assert_eq!(run, Err(OptimizeError::Cancelled));
    // A start whose objective reports the cancellation itself cancels the run too.
    let run: Result<MultistartRun<Fixed>, _> =
        multistart(
            points,
            &Silent,
            |_, _| Err(ObjectiveError::Cancelled.into()),
        );
    assert_eq!(run, Err(OptimizeError::Cancelled));
}

#[test]
fn multistart_levenberg_marquardt_is_the_best_of_the_multistart() {
    let problem = Wells::new(0.3);
    let starts = Multistart::new(10, 2).with_extra_starts(vec![vec![1.95, 0.0]]);
    let settings = LmSettings::default();
    let best =
        multistart_levenberg_marquardt(&problem, Sense::Minimise, &starts, &settings, &Silent)
            .unwrap();
    let run = run(&problem, &starts);
    let (k, direct) = run.best(Sense::Minimise).unwrap();
    assert_eq!((best.best_start, &best.best), (k, direct));
    assert_eq!(
        (best.starts, best.infeasible_starts),
        (11, run.infeasible())
    );
    assert!(run.infeasible() >= 1);
    let successful: usize = run.outcomes.iter().flatten().map(|o| o.evaluations).sum();
    assert!(
        best.evaluations > successful,
        "the infeasible starts' evaluations count too"
    );
}

#[test]
fn grid_ranges_partition_the_evaluation_in_node_order() {
    let axes = vec![
        GridAxis::new(0.0, 1.0, 3).unwrap(),
        GridAxis::new(0.0, 1.0, 1).unwrap(),
        GridAxis::new(-1.0, 1.0, 4).unwrap(),
    ];
    let grid = GridSearch::new(axes).unwrap();
    assert_eq!(grid.nodes(), 12);
    for flat in 0..grid.nodes() {
        let index = grid.node_index(flat).unwrap();
        assert_eq!(grid.flat_index(&index), Some(flat));
    }
    // The last variable runs fastest.
    assert_eq!(grid.node_index(5), Some(vec![1, 0, 1]));
    let f = |p: &[f64]| Ok::<_, OptimizeError>(p.to_vec());
    let whole = grid.evaluate_range(0..12, &Silent, f).unwrap();
    for cut in 0..=12 {
        let mut parts = grid.evaluate_range(0..cut, &Silent, f).unwrap();
        parts.extend(grid.evaluate_range(cut..12, &Silent, f).unwrap());
        assert_eq!(parts, whole);
    }
    assert_eq!(whole[5], grid.node_design(5).unwrap());
    let past = grid.evaluate_range(3..13, &Silent, f);
    assert!(matches!(past, Err(OptimizeError::Invalid(_))), "{past:?}");
    // The first failing node in node order is the error, whatever the scheduling.
    let failing = |p: &[f64]| {
        if p[2] > 0.0 {
            Err(OptimizeError::Numerical { what: "upper half" })
        } else {
            Ok(p[0])
        }
    };
    assert_eq!(
        grid.evaluate_range(0..12, &Silent, failing),
        Err(OptimizeError::Numerical { what: "upper half" })
    );
    let cancelled = CancelAfter(0, AtomicU64::new(0));
    assert_eq!(
        grid.evaluate_range(0..12, &cancelled, f),
        Err(OptimizeError::Cancelled)
    );
}

#[test]
fn a_weighted_sum_stacks_square_root_weighted_residuals() {
    let (a, b) = (Wells::new(0.3), Wells::new(-0.2));
    let sum = WeightedSum::new(vec![(2.0, Wells::new(0.3)), (0.5, Wells::new(-0.2))]).unwrap();
    assert_eq!(sum.n_residuals(), 4);
    for p in [[0.1, 0.2], [-1.5, 1.0], [0.7, -0.4]] {
        let expected = 2.0 * a.value(&p).unwrap() + 0.5 * b.value(&p).unwrap();
        let got = sum.value(&p).unwrap();
        assert!(
            (got - expected).abs() <= 1e-14 * expected,
            "{got} vs {expected}"
        );
    }
    // One part of weight 1 is that part, bit for bit, through a whole solve.
    let one = WeightedSum::new(vec![(1.0, Wells::new(0.3))]).unwrap();
    let s = LmSettings::default();
    let direct = levenberg_marquardt(&a, Sense::Minimise, &[0.4, 0.0], &s, &Silent);
    let wrapped = levenberg_marquardt(&one, Sense::Minimise, &[0.4, 0.0], &s, &Silent);
    assert_eq!(direct, wrapped);
    // Parts with other variables, no parts, and hostile weights are refused.
    let narrow = Wells {
        bounds: [Bounds::new(-1.0, 1.0).unwrap(); 2],
        ..Wells::new(0.0)
    };
    assert!(WeightedSum::new(vec![(1.0, Wells::new(0.0)), (1.0, narrow)]).is_err());
    assert!(WeightedSum::<Wells>::new(Vec::new()).is_err());
    for w in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(WeightedSum::new(vec![(w, Wells::new(0.0))]).is_err(), "{w}");
    }
}
