//! The optimality check against closed forms (a quadratic with a linear constraint, whose
//! gradient, multiplier and reduced Hessian are known exactly), and its promise for every step
//! in the whole float range: a finite check or a typed error, never a panic or a NaN.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::kkt::{self, KktSettings, OptimalityCheck, VariableStatus};
use pkm_optimizers::{AugmentedLagrangianSettings, OptimizeError, Sense, augmented_lagrangian};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};
use proptest::prelude::*;

/// $f = a x^2 + b y^2 + c z^2$ on `bounds`, with $g = 1 - x - y \le 0$ (x + y ≥ 1), maximised
/// through a negated copy when `negated`.
struct Quadratic {
    curvature: [f64; 3],
    bounds: [Bounds; 3],
    negated: bool,
}

impl Quadratic {
    fn new(curvature: [f64; 3]) -> Self {
        Self {
            curvature,
            bounds: [Bounds::new(-2.0, 2.0).unwrap(); 3],
            negated: false,
        }
    }
}

impl Objective for Quadratic {
    fn dimension(&self) -> usize {
        3
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        let f: f64 = p.iter().zip(&self.curvature).map(|(x, a)| a * x * x).sum();
        Ok(if self.negated { -f } else { f })
    }
}

impl Constraints for Quadratic {
    fn n_constraints(&self) -> usize {
        1
    }
    fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        g[0] = 1.0 - p[0] - p[1];
        Ok(())
    }
}

/// The optimum of min a x² + b y² + c z² s.t. x + y ≥ 1: x = b/(a+b), y = a/(a+b), z = 0, with
/// multiplier μ = 2ab/(a+b); on the line x + y = 1 the reduced Hessian has the eigenvalues
/// 2c (along z) and a + b (along (1, −1)/√2).
fn optimum([a, b, _]: [f64; 3]) -> ([f64; 3], f64) {
    ([b / (a + b), a / (a + b), 0.0], 2.0 * a * b / (a + b))
}

fn check(problem: &Quadratic, sense: Sense, x: &[f64], mu: f64, step: f64) -> OptimalityCheck {
    let settings = KktSettings {
        step,
        ..KktSettings::default()
    };
    kkt::check(problem, sense, x, &[mu], &settings, &Silent).unwrap()
}

#[test]
fn the_check_at_a_known_optimum_matches_the_closed_form() {
    let curvature = [1.0, 3.0, 0.5];
    let problem = Quadratic::new(curvature);
    let (x, mu) = optimum(curvature);
    let c = check(&problem, Sense::Minimise, &x, mu, 1e-3);
    assert_eq!(c.status, [VariableStatus::Free; 3]);
    assert_eq!(c.active_constraints, [0]);
    // ∇L = ∇f − μ(1, 1, 0) = 0; central differences of a quadratic are exact up to rounding.
    assert!(
        c.lagrangian_gradient.iter().all(|g| g.abs() < 1e-9),
        "{c:?}"
    );
    assert!(c.projected_gradient_max < 1e-8 && c.stationarity_residual < 1e-8);
    assert!((c.least_squares_multipliers[0] - mu).abs() < 1e-8);
    let mut want = [2.0 * curvature[0], 2.0 * curvature[1], 2.0 * curvature[2]];
    want.sort_by(f64::total_cmp);
    for (got, want) in c.hessian_eigenvalues.iter().zip(want) {
        assert!((got - want).abs() < 1e-5, "{got} vs {want}");
    }
    let reduced = [2.0 * curvature[2], curvature[0] + curvature[1]];
    assert_eq!(c.reduced_hessian_eigenvalues.len(), 2);
    for (got, want) in c.reduced_hessian_eigenvalues.iter().zip(reduced) {
        assert!((got - want).abs() < 1e-5, "{got} vs {want}");
    }
}

#[test]
fn a_maximisation_is_checked_as_the_minimisation_of_its_negation() {
    let curvature = [2.0, 1.0, 1.0];
    let (x, mu) = optimum(curvature);
    let min = check(&Quadratic::new(curvature), Sense::Minimise, &x, mu, 1e-2);
    let negated = Quadratic {
        negated: true,
        ..Quadratic::new(curvature)
    };
    let max = check(&negated, Sense::Maximise, &x, mu, 1e-2);
    assert_eq!(
        min, max,
        "negation is exact, so the checks agree bit for bit"
    );
}

#[test]
fn the_check_agrees_with_the_augmented_lagrangian_it_follows() {
    let problem = Quadratic::new([1.0, 3.0, 0.5]);
    let settings = AugmentedLagrangianSettings::default();
    let r = augmented_lagrangian(
        &problem,
        Sense::Minimise,
        &[1.5, 1.5, 1.0],
        &settings,
        &Silent,
    )
    .unwrap();
    let c = check(&problem, Sense::Minimise, &r.design, r.multipliers[0], 1e-2);
    assert!(c.stationarity_residual < 1e-4, "{c:?}");
    assert!((c.least_squares_multipliers[0] - r.multipliers[0]).abs() < 1e-3);
    assert!(c.reduced_hessian_eigenvalues.iter().all(|v| *v > 0.0));
}

#[test]
fn a_design_on_its_bounds_has_an_empty_null_space_and_no_reduced_eigenvalue() {
    // Minimise x + y + z on [1, 2]³ with x + y ≥ 1 inactive: every variable on its lower bound,
    // no free variable, so no Hessian and no null space.
    struct Linear([Bounds; 3]);
    impl Objective for Linear {
        fn dimension(&self) -> usize {
            3
        }
        fn bounds(&self) -> &[Bounds] {
            &self.0
        }
        fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
            Ok(p.iter().sum())
        }
    }
    impl Constraints for Linear {
        fn n_constraints(&self) -> usize {
            1
        }
        fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
            g[0] = 1.0 - p[0] - p[1];
            Ok(())
        }
    }
    let problem = Linear([Bounds::new(1.0, 2.0).unwrap(); 3]);
    let settings = KktSettings::default();
    let c = kkt::check(
        &problem,
        Sense::Minimise,
        &[1.0; 3],
        &[0.0],
        &settings,
        &Silent,
    )
    .unwrap();
    assert_eq!(c.status, [VariableStatus::Lower; 3]);
    assert!(c.active_constraints.is_empty());
    assert!(
        !(c.projected_gradient_max > 0.0),
        "the gradient pushes outward only"
    );
    assert!(c.hessian_eigenvalues.is_empty() && c.reduced_hessian_eigenvalues.is_empty());
    // Active constraints on no free variable: still no eigenvalue, and no panic.
    let active = kkt::check(
        &problem,
        Sense::Minimise,
        &[1.0; 3],
        &[1.0],
        &settings,
        &Silent,
    );
    assert!(active.unwrap().reduced_hessian_eigenvalues.is_empty());
}

#[test]
fn the_steps_of_the_issue_are_refused_with_typed_errors() {
    let curvature = [1.0, 3.0, 0.5];
    let problem = Quadratic::new(curvature);
    let (x, mu) = optimum(curvature);
    for step in [
        1e300,
        0.9,
        0.5,
        1e-300,
        5e-324,
        0.0,
        -1e-2,
        f64::NAN,
        f64::INFINITY,
    ] {
        let settings = KktSettings {
            step,
            ..KktSettings::default()
        };
        let e = kkt::check(&problem, Sense::Minimise, &x, &[mu], &settings, &Silent);
        assert!(
            matches!(&e, Err(OptimizeError::Invalid(i)) if i.name == "step"),
            "{step}: {e:?}"
        );
    }
}

#[test]
fn hostile_designs_and_multipliers_are_refused() {
    let problem = Quadratic::new([1.0, 1.0, 1.0]);
    let s = KktSettings::default();
    for (x, mu) in [
        (vec![0.5, 0.5], vec![1.0]),
        (vec![f64::NAN, 0.5, 0.0], vec![1.0]),
        (vec![0.5, 0.5, 0.0], vec![]),
        (vec![0.5, 0.5, 0.0], vec![-1.0]),
        (vec![0.5, 0.5, 0.0], vec![f64::INFINITY]),
    ] {
        let e = kkt::check(&problem, Sense::Minimise, &x, &mu, &s, &Silent);
        assert!(e.is_err(), "{x:?} {mu:?}: {e:?}");
    }
    let tolerance = KktSettings {
        active_tolerance: f64::NAN,
        ..s
    };
    assert!(tolerance.validate().is_err());
}

/// Every number of a check is finite.
fn finite(c: &OptimalityCheck) -> bool {
    c.lagrangian_gradient
        .iter()
        .chain(&c.least_squares_multipliers)
        .chain(&c.hessian_eigenvalues)
        .chain(&c.reduced_hessian_eigenvalues)
        .chain([&c.projected_gradient_max, &c.stationarity_residual])
        .all(|v| v.is_finite())
}

/// `Ok` with every number finite, or one of the documented typed errors.
fn acceptable(outcome: &Result<OptimalityCheck, OptimizeError>) -> bool {
    match outcome {
        Ok(c) => finite(c),
        Err(e) => matches!(
            e,
            OptimizeError::Invalid(_)
                | OptimizeError::NonFiniteDerivative { .. }
                | OptimizeError::Numerical { .. }
        ),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any f64 as the step (NaN, infinities, subnormals and every magnitude, by bit pattern):
    /// a finite check or a typed error, at the optimum and at a point on a bound, for a
    /// problem whose values grow like 1e200.
    #[test]
    fn every_step_gives_a_finite_check_or_a_typed_error(
        bits in any::<u64>(),
        scale in prop::sample::select(vec![1.0, 1e-300, 1e200]),
        on_bound in any::<bool>(),
    ) {
        let step = f64::from_bits(bits);
        let curvature = [scale, 3.0 * scale, 0.5 * scale];
        let problem = Quadratic::new(curvature);
        let (mut x, mu) = optimum(curvature);
        if on_bound {
            x[2] = 2.0;
        }
        let settings = KktSettings { step, ..KktSettings::default() };
        let outcome = kkt::check(&problem, Sense::Minimise, &x, &[mu], &settings, &Silent);
        prop_assert!(acceptable(&outcome), "step {step:e}: {outcome:?}");
    }

    /// The same over steps spread evenly in magnitude, from 5e-324 to 1e308.
    #[test]
    fn every_magnitude_of_step_gives_a_finite_check_or_a_typed_error(exponent in -323.5f64..308.0) {
        let problem = Quadratic::new([1.0, 3.0, 0.5]);
        let (x, mu) = optimum([1.0, 3.0, 0.5]);
        let settings = KktSettings { step: 10f64.powf(exponent), ..KktSettings::default() };
        let outcome = kkt::check(&problem, Sense::Minimise, &x, &[mu], &settings, &Silent);
        prop_assert!(acceptable(&outcome), "step 1e{exponent}: {outcome:?}");
        if (1e-6..0.3).contains(&settings.step) {
            prop_assert!(outcome.is_ok(), "a reasonable step must work: {outcome:?}");
        }
    }
}
