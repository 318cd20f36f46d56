//! Compass search (Kolda, Lewis & Torczon 2003, Algorithm 3.2) against problems of known
//! optimum: a smooth bowl with its optimum inside and on a bound, a staircase (piecewise
//! constant, as a Monte Carlo estimate on common random numbers), an infeasible region
//! (the extreme barrier), the evaluation budget, and refused settings.

#![allow(clippy::float_cmp)] // exact values: a bound reached by clipping, a plateau

use pkm_optimizers::{CompassSettings, OptimizeError, Sense, Termination, compass_search};
use pkm_traits::{Bounds, Objective, ObjectiveError, Silent};
use std::sync::atomic::{AtomicUsize, Ordering};

/// $f(x) = -\sum_j (x_j - c_j)^2$ on a box, counting its evaluations, infeasible where
/// $x_0 + x_1 > $ `cut`.
struct Bowl {
    centre: Vec<f64>,
    bounds: Vec<Bounds>,
    cut: f64,
    calls: AtomicUsize,
}

impl Bowl {
    fn new(centre: &[f64], lower: f64, upper: f64) -> Self {
        Self {
            centre: centre.to_vec(),
            bounds: vec![Bounds::new(lower, upper).unwrap(); centre.len()],
            cut: f64::INFINITY,
            calls: AtomicUsize::new(0),
        }
    }
}

impl Objective for Bowl {
    fn dimension(&self) -> usize {
        self.centre.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        if x[0] + x.get(1).unwrap_or(&0.0) > self.cut {
            return Err(ObjectiveError::infeasible("beyond the cut"));
        }
        Ok(-x
            .iter()
            .zip(&self.centre)
            .map(|(a, c)| (a - c).powi(2))
            .sum::<f64>())
    }
}

fn fine() -> CompassSettings {
    CompassSettings {
        min_step: 1e-7,
        ..CompassSettings::default()
    }
}

#[test]
fn compass_search_finds_an_interior_optimum_and_one_on_a_bound() {
    // Interior: (0.3, -0.1, 0.7); the poll is complete, so the final design is within one
    // final step (2·Δ box widths, Δ < 1e-7, width 2) of the optimum.
    let bowl = Bowl::new(&[0.3, -0.1, 0.7], -1.0, 1.0);
    let r = compass_search(&bowl, Sense::Maximise, &[0.0; 3], &fine(), &Silent).unwrap();
    for (x, c) in r.design.iter().zip(&bowl.centre) {
        assert!((x - c).abs() < 4e-7, "{x} vs {c}");
    }
    assert!(r.termination.converged() && r.final_step < 1e-7);
    assert_eq!(r.evaluations, bowl.calls.load(Ordering::Relaxed));
    // Centre outside the box: the optimum is the bound x0 = 1 exactly (clipped poll points).
    let bowl = Bowl::new(&[1.5, 0.2], -1.0, 1.0);
    let r = compass_search(&bowl, Sense::Maximise, &[-0.5, 0.9], &fine(), &Silent).unwrap();
    assert_eq!(r.design[0], 1.0);
    assert!((r.design[1] - 0.2).abs() < 4e-7);
}

/// A staircase $f(x) = -\lfloor 10 |x - 0.62| \rfloor$: flat almost everywhere, so every
/// finite difference is 0; its top plateau, $f = 0$, is $|x - 0.62| < 0.1$.
struct Staircase([Bounds; 1]);

impl Objective for Staircase {
    fn dimension(&self) -> usize {
        1
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        Ok(-(10.0 * (x[0] - 0.62).abs()).floor())
    }
}

#[test]
fn compass_search_climbs_a_piecewise_constant_objective_to_its_top_plateau() {
    let problem = Staircase([Bounds::new(0.0, 1.0).unwrap()]);
    for start in [0.0, 0.05, 0.97, 1.0] {
        let r = compass_search(
            &problem,
            Sense::Maximise,
            &[start],
            &CompassSettings::default(),
            &Silent,
        )
        .unwrap();
        assert_eq!(r.value, 0.0, "from {start}: {r:?}");
        assert!((r.design[0] - 0.62).abs() < 0.1);
    }
}

#[test]
fn compass_search_stops_at_an_infeasible_region_without_entering_it() {
    // Optimum (0.8, 0.8) beyond x0 + x1 <= 1: the barrier stops the search on the cut, never
    // inside the infeasible region, and counts the infeasible poll points.
    let mut bowl = Bowl::new(&[0.8, 0.8], 0.0, 1.0);
    bowl.cut = 1.0;
    let r = compass_search(&bowl, Sense::Maximise, &[0.1, 0.1], &fine(), &Silent).unwrap();
    let sum = r.design[0] + r.design[1];
    assert!(sum <= 1.0 && sum > 1.0 - 1e-6, "{r:?}");
    assert!(r.infeasible > 0);
    // From an infeasible start there is nothing to compare with: a typed error.
    let e = compass_search(&bowl, Sense::Maximise, &[0.9, 0.9], &fine(), &Silent).unwrap_err();
    assert!(e.is_infeasible(), "{e}");
}

#[test]
fn compass_search_keeps_to_its_budget_and_says_so() {
    let bowl = Bowl::new(&[0.3, -0.1], -1.0, 1.0);
    let budget = CompassSettings {
        max_evaluations: 7,
        ..fine()
    };
    let r = compass_search(&bowl, Sense::Maximise, &[0.0, 0.0], &budget, &Silent).unwrap();
    assert_eq!(r.evaluations, 7);
    assert_eq!(bowl.calls.load(Ordering::Relaxed), 7);
    assert_eq!(r.termination, Termination::MaxIterations);
}

#[test]
fn compass_search_refuses_settings_and_starts_that_cannot_work() {
    let bowl = Bowl::new(&[0.0], -1.0, 1.0);
    let run = |s: CompassSettings, start: &[f64]| {
        compass_search(&bowl, Sense::Minimise, start, &s, &Silent).unwrap_err()
    };
    let d = CompassSettings::default();
    for (settings, name) in [
        (
            CompassSettings {
                initial_step: 0.0,
                ..d
            },
            "initial_step",
        ),
        (
            CompassSettings {
                initial_step: f64::NAN,
                ..d
            },
            "initial_step",
        ),
        (
            CompassSettings {
                initial_step: 1.5,
                ..d
            },
            "initial_step",
        ),
        (CompassSettings { min_step: 0.5, ..d }, "min_step"),
        (
            CompassSettings {
                min_step: -1.0,
                ..d
            },
            "min_step",
        ),
        (
            CompassSettings {
                max_evaluations: 0,
                ..d
            },
            "max_evaluations",
        ),
        (
            CompassSettings {
                max_evaluations: usize::MAX,
                ..d
            },
            "max_evaluations",
        ),
    ] {
        match run(settings, &[0.0]) {
            OptimizeError::Invalid(e) => assert_eq!(e.name, name),
            e => panic!("{name}: {e}"),
        }
    }
    for start in [&[2.0][..], &[f64::NAN], &[0.0, 0.0]] {
        assert!(
            matches!(run(d, start), OptimizeError::Invalid(_)),
            "{start:?}"
        );
    }
}
