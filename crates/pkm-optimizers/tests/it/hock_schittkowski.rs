//! The augmented-Lagrangian optimiser on Hock–Schittkowski problems 21, 35 and 43, and an
//! infeasible constraint set.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_optimizers::{
    AugmentedLagrangianSettings, OptimizeError, Sense, Termination, augmented_lagrangian,
};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};

type Fun = fn(&[f64]) -> f64;

struct Problem {
    bounds: Vec<Bounds>,
    f: Fun,
    g: Vec<Fun>,
}

impl Objective for Problem {
    fn dimension(&self) -> usize {
        self.bounds.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
        Ok((self.f)(p))
    }
}

impl Constraints for Problem {
    fn n_constraints(&self) -> usize {
        self.g.len()
    }
    fn inequalities(&self, p: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        for (gi, fi) in g.iter_mut().zip(&self.g) {
            *gi = fi(p);
        }
        Ok(())
    }
}

fn b(lo: f64, hi: f64) -> Bounds {
    Bounds::new(lo, hi).unwrap()
}

#[test]
fn hs21() {
    let p = Problem {
        bounds: vec![b(2.0, 50.0), b(-50.0, 50.0)],
        f: |x| 0.01 * x[0] * x[0] + x[1] * x[1] - 100.0,
        g: vec![|x| 10.0 - 10.0 * x[0] + x[1]],
    };
    let r = augmented_lagrangian(
        &p,
        Sense::Minimise,
        &[-1.0, -1.0],
        &Default::default(),
        &Silent,
    )
    .unwrap();
    assert!((r.value + 99.96).abs() < 1e-6, "{r:?}");
    assert!((r.design[0] - 2.0).abs() < 1e-5 && r.design[1].abs() < 1e-4);
}

#[test]
fn hs35() {
    let p = Problem {
        bounds: vec![b(0.0, 10.0); 3],
        f: |x| {
            9.0 - 8.0 * x[0] - 6.0 * x[1] - 4.0 * x[2]
                + 2.0 * x[0] * x[0]
                + 2.0 * x[1] * x[1]
                + x[2] * x[2]
                + 2.0 * x[0] * x[1]
                + 2.0 * x[0] * x[2]
        },
        g: vec![|x| x[0] + x[1] + 2.0 * x[2] - 3.0],
    };
    let r = augmented_lagrangian(
        &p,
        Sense::Minimise,
        &[0.5, 0.5, 0.5],
        &Default::default(),
        &Silent,
    )
    .unwrap();
    let expected = [4.0 / 3.0, 7.0 / 9.0, 4.0 / 9.0];
    assert!((r.value - 1.0 / 9.0).abs() < 1e-7, "{r:?}");
    assert!(
        r.design
            .iter()
            .zip(expected)
            .all(|(a, e)| (a - e).abs() < 1e-4)
    );
    assert!((r.multipliers[0] - 2.0 / 9.0).abs() < 1e-3);
}

#[test]
fn hs43_rosen_suzuki() {
    let p = Problem {
        bounds: vec![b(-10.0, 10.0); 4],
        f: |x| {
            x[0] * x[0] + x[1] * x[1] + 2.0 * x[2] * x[2] + x[3] * x[3]
                - 5.0 * x[0]
                - 5.0 * x[1]
                - 21.0 * x[2]
                + 7.0 * x[3]
        },
        g: vec![
            |x| {
                -(8.0 - x[0] * x[0] - x[1] * x[1] - x[2] * x[2] - x[3] * x[3] - x[0] + x[1] - x[2]
                    + x[3])
            },
            |x| {
                -(10.0 - x[0] * x[0] - 2.0 * x[1] * x[1] - x[2] * x[2] - 2.0 * x[3] * x[3]
                    + x[0]
                    + x[3])
            },
            |x| -(5.0 - 2.0 * x[0] * x[0] - x[1] * x[1] - x[2] * x[2] - 2.0 * x[0] + x[1] + x[3]),
        ],
    };
    let r =
        augmented_lagrangian(&p, Sense::Minimise, &[0.0; 4], &Default::default(), &Silent).unwrap();
    let expected = [0.0, 1.0, 2.0, -1.0];
    assert!((r.value + 44.0).abs() < 1e-5, "{r:?}");
    assert!(
        r.design
            .iter()
            .zip(expected)
            .all(|(a, e)| (a - e).abs() < 1e-3)
    );
}

#[test]
fn infeasible_constraint_set_returns_no_design() {
    // x >= 2 and x <= 1 cannot both hold.
    let p = Problem {
        bounds: vec![b(-5.0, 5.0)],
        f: |x| x[0] * x[0],
        g: vec![|x| 2.0 - x[0], |x| x[0] - 1.0],
    };
    let r = augmented_lagrangian(&p, Sense::Minimise, &[0.0], &Default::default(), &Silent);
    assert!(
        matches!(r, Err(OptimizeError::NoFeasibleDesign { .. })),
        "{r:?}"
    );
}

#[test]
fn bad_settings_are_typed_errors() {
    let p = Problem {
        bounds: vec![b(-1.0, 1.0)],
        f: |x| x[0],
        g: vec![],
    };
    assert!(
        augmented_lagrangian(
            &p,
            Sense::Minimise,
            &[0.0, 1.0],
            &Default::default(),
            &Silent
        )
        .is_err()
    );
    let s = AugmentedLagrangianSettings {
        fd_step: f64::NAN,
        ..Default::default()
    };
    assert!(augmented_lagrangian(&p, Sense::Minimise, &[0.0], &s, &Silent).is_err());
}

#[test]
fn termination_tells_convergence_from_the_outer_iteration_limit() {
    // min x² + y² s.t. x + y >= 1. With μ = 0 and ρ = 10 the first inner problem
    // 2t² + 5(1 − 2t)² gives x = y = 5/11, a violation 1/11 and a multiplier step 10/11.
    let p = Problem {
        bounds: vec![b(-5.0, 5.0); 2],
        f: |x| x[0] * x[0] + x[1] * x[1],
        g: vec![|x| 1.0 - x[0] - x[1]],
    };
    let converged = augmented_lagrangian(
        &p,
        Sense::Minimise,
        &[2.0, -1.0],
        &Default::default(),
        &Silent,
    )
    .unwrap();
    assert_eq!(
        converged.termination,
        Termination::Converged {
            criterion: "feasible with settled multipliers"
        },
        "{converged:?}"
    );
    let one = AugmentedLagrangianSettings {
        max_outer: 1,
        feasibility: 0.5,
        ..Default::default()
    };
    let cut = augmented_lagrangian(&p, Sense::Minimise, &[2.0, -1.0], &one, &Silent).unwrap();
    assert_eq!(cut.termination, Termination::MaxIterations, "{cut:?}");
    assert!((cut.constraints[0] - 1.0 / 11.0).abs() < 1e-6, "{cut:?}");
    assert!((cut.multipliers[0] - 10.0 / 11.0).abs() < 1e-5, "{cut:?}");
}
