//! Progress and cancellation of every solver: a cancelled run returns
//! [`OptimizeError::Cancelled`] after a bounded number of evaluations, the counts that results
//! report are the evaluations the problem saw, and a maximisation is a [`Sense`] everywhere.
#![allow(clippy::unwrap_used, clippy::panic)]

use pkm_optimizers::{
    AugmentedLagrangianSettings, GridAxis, GridSearch, LmSettings, Multistart, OptimizeError,
    Sense, augmented_lagrangian, grid_search, levenberg_marquardt, multistart_levenberg_marquardt,
};
use pkm_traits::{
    Bounds, Constraints, InvalidInput, Objective, ObjectiveError, Progress, Residuals, Silent,
};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

/// Cancels once `advance` has been called `after` times.
struct CancelAfter {
    after: u64,
    advanced: AtomicU64,
    started: AtomicU64,
}

impl CancelAfter {
    fn new(after: u64) -> Self {
        Self {
            after,
            advanced: AtomicU64::new(0),
            started: AtomicU64::new(0),
        }
    }
}

impl Progress for CancelAfter {
    fn start(&self, _label: &str, _total: u64) {
        self.started.fetch_add(1, Ordering::Relaxed);
    }
    fn advance(&self, n: u64) {
        self.advanced.fetch_add(n, Ordering::Relaxed);
    }
    fn is_cancelled(&self) -> bool {
        self.advanced.load(Ordering::Relaxed) >= self.after
    }
}

/// Rosenbrock's residuals $r = (10(p_1 - p_0^2), 1 - p_0)$ on $[-2, 2]^2$, with the constraint
/// $p_0 + p_1 \ge 1$, counting every evaluation of the residuals or the value.
struct Counted {
    bounds: [Bounds; 2],
    evaluations: AtomicUsize,
}

impl Counted {
    fn new() -> Self {
        Self {
            bounds: [Bounds::new(-2.0, 2.0).unwrap(); 2],
            evaluations: AtomicUsize::new(0),
        }
    }
    fn count(&self) -> usize {
        self.evaluations.load(Ordering::Relaxed)
    }
}

impl Objective for Counted {
    fn dimension(&self) -> usize {
        2
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0; 2];
        self.residuals(p, &mut r)?;
        Ok(r[0] * r[0] + r[1] * r[1])
    }
}

impl Residuals for Counted {
    fn n_residuals(&self) -> usize {
        2
    }
    fn residuals(&self, p: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        r.copy_from_slice(&[10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]]);
        Ok(())
    }
}

impl Constraints for Counted {
    fn n_constraints(&self) -> usize {
        1
    }
    fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        g[0] = 1.0 - p[0] - p[1];
        Ok(())
    }
}

const START: [f64; 2] = [-1.2, 1.0];

#[test]
fn a_cancelled_levenberg_marquardt_stops_within_its_iteration() {
    let settings = LmSettings::default();
    let full = Counted::new();
    let done = levenberg_marquardt(&full, Sense::Minimise, &START, &settings, &Silent).unwrap();
    assert!(
        done.termination.converged() && done.iterations > 4,
        "{done:?}"
    );
    assert_eq!(
        done.evaluations,
        full.count(),
        "the reported count is the problem's"
    );
    // Cancelled once 3 iterations have begun: no more work than a run limited to 3 iterations.
    let three = Counted::new();
    let limited = LmSettings {
        max_iterations: 3,
        ..settings.clone()
    };
    let bound = levenberg_marquardt(&three, Sense::Minimise, &START, &limited, &Silent).unwrap();
    let cancelled = Counted::new();
    let progress = CancelAfter::new(3);
    let e = levenberg_marquardt(&cancelled, Sense::Minimise, &START, &settings, &progress);
    assert_eq!(e, Err(OptimizeError::Cancelled));
    assert!(cancelled.count() > 0 && cancelled.count() <= bound.evaluations);
    assert_eq!(progress.advanced.load(Ordering::Relaxed), 3);
    assert_eq!(progress.started.load(Ordering::Relaxed), 1);
}

#[test]
fn a_cancelled_multistart_runs_no_start_after_the_cancellation() {
    let settings = LmSettings::default();
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let (full, done) = one_thread.install(|| {
        let full = Counted::new();
        let m = Multistart::new(3, 5).with_extra_starts(vec![START.to_vec()]);
        let done = multistart_levenberg_marquardt(&full, Sense::Minimise, &m, &settings, &Silent);
        (full, done.unwrap())
    });
    assert_eq!(done.starts, 4);
    assert_eq!(done.evaluations, full.count());
    // 64 starts, cancelled after 4 have finished: on one thread exactly the work of those 4.
    let cancelled = Counted::new();
    let progress = CancelAfter::new(4);
    let e = one_thread.install(|| {
        let m = Multistart::new(63, 5).with_extra_starts(vec![START.to_vec()]);
        multistart_levenberg_marquardt(&cancelled, Sense::Minimise, &m, &settings, &progress)
    });
    assert_eq!(e, Err(OptimizeError::Cancelled));
    assert_eq!(cancelled.count(), full.count());
    // On any number of threads the work stays bounded by the starts in flight.
    let parallel = Counted::new();
    let progress = CancelAfter::new(4);
    let m = Multistart::new(1 << 12, 5);
    let e = multistart_levenberg_marquardt(&parallel, Sense::Minimise, &m, &settings, &progress);
    assert_eq!(e, Err(OptimizeError::Cancelled));
    assert!(
        parallel.count() < 64 * done.evaluations,
        "{}",
        parallel.count()
    );
}

#[test]
fn a_cancelled_augmented_lagrangian_stops_within_its_outer_iteration() {
    let settings = AugmentedLagrangianSettings::default();
    let full = Counted::new();
    let done = augmented_lagrangian(&full, Sense::Minimise, &START, &settings, &Silent).unwrap();
    assert!(
        done.termination.converged() && done.outer_iterations > 1,
        "{done:?}"
    );
    assert_eq!(done.evaluations, full.count());
    assert!(done.inner_iterations >= done.outer_iterations);
    let once = Counted::new();
    let one = AugmentedLagrangianSettings {
        max_outer: 1,
        feasibility: 10.0,
        ..settings.clone()
    };
    let bound = augmented_lagrangian(&once, Sense::Minimise, &START, &one, &Silent).unwrap();
    // Cancelled once the first outer iteration has begun: it stops at its first inner check.
    let cancelled = Counted::new();
    let progress = CancelAfter::new(1);
    let e = augmented_lagrangian(&cancelled, Sense::Minimise, &START, &settings, &progress);
    assert_eq!(e, Err(OptimizeError::Cancelled));
    assert!(
        cancelled.count() <= bound.evaluations,
        "{}",
        cancelled.count()
    );
}

#[test]
fn a_cancelled_grid_search_returns_cancelled_too() {
    let grid = GridSearch::new(vec![GridAxis::new(-2.0, 2.0, 101).unwrap(); 2]).unwrap();
    let problem = Counted::new();
    let progress = CancelAfter::new(10);
    let e = grid_search(&problem, Sense::Minimise, &grid, &progress);
    assert_eq!(e, Err(OptimizeError::Cancelled));
    assert!(problem.count() < grid.nodes());
}

#[test]
fn maximising_is_a_sense_in_every_solver() {
    // max −(x² + y²) s.t. x + y ≥ 1 is min x² + y² there: (½, ½), value −½.
    struct Negated([Bounds; 2]);
    impl Objective for Negated {
        fn dimension(&self) -> usize {
            2
        }
        fn bounds(&self) -> &[Bounds] {
            &self.0
        }
        fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
            Ok(-(p[0] * p[0] + p[1] * p[1]))
        }
    }
    impl Constraints for Negated {
        fn n_constraints(&self) -> usize {
            1
        }
        fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
            g[0] = 1.0 - p[0] - p[1];
            Ok(())
        }
    }
    let b = Bounds::new(-5.0, 5.0).unwrap();
    let problem = Negated([b, b]);
    let settings = AugmentedLagrangianSettings::default();
    let r =
        augmented_lagrangian(&problem, Sense::Maximise, &[2.0, -1.0], &settings, &Silent).unwrap();
    assert!(r.termination.converged(), "{r:?}");
    assert!((r.value + 0.5).abs() < 1e-5, "{r:?}");
    assert!(r.design.iter().all(|x| (x - 0.5).abs() < 1e-5), "{r:?}");
    // The grid's largest value of −(x² + y²) is at the node nearest the origin.
    let grid = GridSearch::new(vec![GridAxis::new(-5.0, 5.0, 11).unwrap(); 2]).unwrap();
    let best = grid_search(&problem, Sense::Maximise, &grid, &Silent).unwrap();
    assert_eq!(best.best, vec![0.0, 0.0]);
    let worst = grid_search(&problem, Sense::Minimise, &grid, &Silent).unwrap();
    assert_eq!(worst.best, vec![-5.0, -5.0]);
    assert!((worst.best_value + 50.0).abs() < 1e-12);
}

#[test]
fn settings_refuse_hostile_values() {
    for bad in [f64::NAN, f64::INFINITY, 0.0, -1.0] {
        let tolerance = LmSettings {
            tolerance: bad,
            ..LmSettings::default()
        };
        let step = LmSettings {
            fd_step: bad,
            ..LmSettings::default()
        };
        let al = AugmentedLagrangianSettings {
            feasibility: bad,
            ..Default::default()
        };
        for e in [tolerance.validate(), step.validate(), al.validate()] {
            assert!(matches!(e, Err(OptimizeError::Invalid(_))), "{bad}: {e:?}");
        }
    }
    let none = LmSettings {
        max_iterations: 0,
        ..LmSettings::default()
    };
    assert!(matches!(
        none.validate(),
        Err(OptimizeError::Invalid(InvalidInput {
            name: "max_iterations",
            ..
        }))
    ));
    for m in [Multistart::new(0, 1), Multistart::new(usize::MAX, 1)] {
        let e = multistart_levenberg_marquardt(
            &Counted::new(),
            Sense::Minimise,
            &m,
            &LmSettings::default(),
            &Silent,
        );
        assert!(
            matches!(
                e,
                Err(OptimizeError::Invalid(InvalidInput { name: "count", .. }))
            ),
            "{e:?}"
        );
    }
}
