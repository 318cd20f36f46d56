//! Properties of the shared vocabulary, checked on a planar 2-RPR toy mechanism: two legs of
//! length q_i from base pivots b_i to the platform point x, Φ_i = |x − b_i|² − q_i².
#![allow(clippy::unwrap_used)]

use nalgebra::{Matrix2, Vector2};
use pkm_traits::testkit::{self, ConformanceFailure};
use pkm_traits::{
    Bounds, ClosedChain, DesignError, ForwardKinematics, InverseKinematics, Joints,
    KinematicsError, NewtonSettings, Task,
};
use proptest::prelude::*;

const BASE: [Vector2<f64>; 2] = [Vector2::new(-1.0, 0.0), Vector2::new(1.0, 0.0)];

#[derive(Debug, Clone)]
struct TwoRpr {
    /// Scales the analytic J_x: 1 is correct, anything else is a deliberately wrong model.
    j_x_scale: f64,
}

impl ClosedChain<2, 2> for TwoRpr {
    fn closure(&self, x: &Task<2>, q: &Joints<2>) -> Joints<2> {
        Vector2::from_fn(|i, _| (x - BASE[i]).norm_squared() - q[i] * q[i])
    }
    fn jacobian_x(&self, x: &Task<2>, _: &Joints<2>) -> Matrix2<f64> {
        let r = |i: usize| 2.0 * (x - BASE[i]) * self.j_x_scale;
        Matrix2::from_rows(&[r(0).transpose(), r(1).transpose()])
    }
    fn jacobian_q(&self, _: &Task<2>, q: &Joints<2>) -> Matrix2<f64> {
        Matrix2::from_diagonal(&(-2.0 * q))
    }
}

impl InverseKinematics<2, 2> for TwoRpr {
    type WorkingMode = ();
    fn inverse_kinematics(&self, x: &Task<2>, _: ()) -> Result<Joints<2>, KinematicsError> {
        if x.y.abs() < 1e-3 {
            return Err(KinematicsError::Singular {
                matrix: "J_x",
                sigma_min: x.y.abs(),
            });
        }
        Ok(Vector2::from_fn(|i, _| (x - BASE[i]).norm()))
    }
}

impl ForwardKinematics<2> for TwoRpr {}

const GOOD: TwoRpr = TwoRpr { j_x_scale: 1.0 };

fn poses() -> impl Strategy<Value = Vec<Task<2>>> {
    prop::collection::vec((-2.0..2.0f64, 0.2..2.0f64), 3..12)
        .prop_map(|v| v.into_iter().map(|(x, y)| Vector2::new(x, y)).collect())
}

proptest! {
    #[test]
    fn conformance_checks_pass_on_a_correct_model(poses in poses()) {
        testkit::check_closure(&GOOD, (), &poses, 1e-12).unwrap();
        testkit::check_jacobians_against_central_differences(&GOOD, (), &poses, 1e-6, 1e-7)
            .unwrap();
        testkit::check_ik_fk_round_trip(&GOOD, (), &poses, 0.05, 1e-10).unwrap();
    }

    #[test]
    fn jacobian_check_rejects_a_wrong_model(poses in poses(), scale in 1.01..2.0f64) {
        let wrong = TwoRpr { j_x_scale: scale };
        let result = testkit::check_jacobians_against_central_differences(&wrong, (), &poses, 1e-6, 1e-7);
        let rejected = matches!(result, Err(ConformanceFailure::Exceeded { .. }));
        prop_assert!(rejected);
    }

    #[test]
    fn velocity_jacobian_matches_differentiated_inverse_kinematics(x in -2.0..2.0f64, y in 0.2..2.0f64) {
        let x = Vector2::new(x, y);
        let q = GOOD.inverse_kinematics(&x, ()).unwrap();
        let j = GOOD.jacobian(&x, &q).unwrap();
        let h = 1e-6;
        for k in 0..2 {
            let mut xp = x;
            let mut xm = x;
            xp[k] += h;
            xm[k] -= h;
            let dq = (GOOD.inverse_kinematics(&xp, ()).unwrap() - GOOD.inverse_kinematics(&xm, ()).unwrap()) / (2.0 * h);
            prop_assert!((j.column(k) - dq).amax() < 1e-8);
        }
    }

    #[test]
    fn forward_kinematics_keeps_the_assembly_mode_of_the_guess(x in -2.0..2.0f64, y in 0.2..2.0f64) {
        let up = Vector2::new(x, y);
        let down = Vector2::new(x, -y);
        let q = GOOD.inverse_kinematics(&up, ()).unwrap();
        let settings = NewtonSettings::default();
        let fk_up = GOOD.forward_kinematics(&q, &(up * 1.02), &settings).unwrap();
        let fk_down = GOOD.forward_kinematics(&q, &(down * 1.02), &settings).unwrap();
        prop_assert!((fk_up - up).amax() < 1e-10);
        prop_assert!((fk_down - down).amax() < 1e-10);
    }

    #[test]
    fn design_and_bound_validation_reject_bad_numbers(v in prop::num::f64::ANY) {
        let ok = v.is_finite() && v > 0.0;
        prop_assert_eq!(DesignError::require_positive("a", v).is_ok(), ok);
        prop_assert_eq!(DesignError::require_finite("a", v).is_ok(), v.is_finite());
        prop_assert_eq!(Bounds::new(v, 1.0).is_ok(), v.is_finite() && v <= 1.0);
    }
}

#[test]
fn checks_refuse_to_pass_on_an_empty_or_unreachable_sample() {
    let empty: Vec<Task<2>> = Vec::new();
    let on_singular_line = vec![Vector2::new(0.0, 0.0); 5];
    for sample in [&empty, &on_singular_line] {
        let result = testkit::check_closure(&GOOD, (), sample, 1e-12);
        assert!(matches!(
            result,
            Err(ConformanceFailure::Vacuous { checked: 0, .. })
        ));
    }
}

#[test]
fn forward_kinematics_reports_non_finite_joints_and_non_convergence() {
    let settings = NewtonSettings::default();
    let guess = Vector2::new(0.0, 1.0);
    let nan = GOOD.forward_kinematics(&Vector2::new(f64::NAN, 1.0), &guess, &settings);
    assert!(matches!(nan, Err(KinematicsError::NonFinite { .. })));
    // Legs of length 0.1 from pivots 2 apart cannot meet: Newton cannot converge.
    let apart = GOOD.forward_kinematics(&Vector2::new(0.1, 0.1), &guess, &settings);
    assert!(matches!(
        apart,
        Err(KinematicsError::NotConverged { .. } | KinematicsError::Singular { .. })
    ));
}

proptest! {
    /// An angle range holds an angle exactly when it holds the same angle a whole number of
    /// turns away, and agrees with the plain range for angles inside it.
    #[test]
    fn angle_ranges_hold_angles_modulo_a_turn(
        lower in -10.0_f64..10.0,
        width in 0.0_f64..7.0,
        v in -10.0_f64..10.0,
        turns in -3_i32..=3,
    ) {
        use pkm_traits::WorkspaceConstraint;
        let upper = lower + width;
        let angle = WorkspaceConstraint::angle_range(lower, upper).unwrap();
        let plain = WorkspaceConstraint::joint_range(lower, upper).unwrap();
        let at = |c: &WorkspaceConstraint, q: f64| {
            c.holds_at(&nalgebra::Vector3::zeros(), &[q], || None, || None)
        };
        let shifted = v + f64::from(turns) * std::f64::consts::TAU;
        let tau = std::f64::consts::TAU;
        // Away from the ends (rounding of the shift), the two angles are the same angle.
        let offset = (v - lower).rem_euclid(tau);
        if (offset - width).abs() > 1e-9 && offset > 1e-9 && (tau - offset) > 1e-9 {
            prop_assert_eq!(at(&angle, v), at(&angle, shifted));
        }
        if at(&plain, v) {
            prop_assert!(at(&angle, v));
        }
        if width >= tau {
            prop_assert!(at(&angle, v));
        }
    }
}
