//! The structured kernels (per-leg quantities, Cramer's rule, the 3×3 Schur complement of the
//! saddle-point system) against the straightforward formulation: the 6×6 $M$, $L_q$, $\dot M\dot q$,
//! $\Phi_q$, $\dot\Phi_q$ of `ExtendedModel`, an LU solve of $\Phi_x^\top\lambda$ and a dense 9×9 LU
//! of eq. 19, on random states.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Matrix3, SMatrix, SVector, Vector3, Vector6};
use pkm_dynamics_hamilton::forward::{AccelerationForm, HamiltonForm};
use pkm_dynamics_hamilton::{ConfigurationError, ExtendedModel, MassParameters};
use pkm_mechanisms::{Placement, RotaryDelta, presets};
use pkm_traits::VectorField;
use proptest::prelude::*;

fn models() -> [ExtendedModel; 2] {
    let mass = MassParameters::miller2004();
    [
        ExtendedModel::new(
            RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
            &mass,
        )
        .unwrap(),
        ExtendedModel::new(
            RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap(),
            &mass,
        )
        .unwrap(),
    ]
}

/// A random extended state near the workspace (not on the constraint manifold: the identities
/// checked here are algebraic).
fn state() -> impl Strategy<Value = (Vector6<f64>, Vector6<f64>, Vector6<f64>)> {
    (
        prop::array::uniform6(-1.0..1.0f64),
        prop::array::uniform6(-3.0..3.0f64),
        prop::array::uniform6(-300.0..300.0f64),
    )
        .prop_map(|(q, v, a)| {
            let q = Vector6::from(q).component_mul(&Vector6::new(0.2, 0.2, 0.2, 1.0, 1.0, 1.0))
                + Vector6::new(0.0, 0.0, -0.7, 0.5, 0.5, 0.5);
            (q, Vector6::from(v), Vector6::from(a))
        })
}

/// Steps 2–3 as first written: $\Phi_x^\top\lambda = L_{q,x} - \dot p_x$ by LU,
/// $\tau = \dot p_\theta - L_{q,\theta} + \Phi_\theta^\top\lambda$.
fn reference_torques(
    m: &ExtendedModel,
    q: &Vector6<f64>,
    qd: &Vector6<f64>,
    p_rate: &Vector6<f64>,
) -> Vector3<f64> {
    let l_q = m.lagrangian_gradient(q, qd);
    let phi_q = m.constraint_jacobian(q);
    let phi_x_t: Matrix3<f64> = phi_q.fixed_view::<3, 3>(0, 0).transpose();
    let rhs = l_q.fixed_rows::<3>(0) - p_rate.fixed_rows::<3>(0);
    let lambda = phi_x_t.lu().solve(&rhs).unwrap();
    Vector3::from_fn(|i, _| p_rate[3 + i] - l_q[3 + i] + phi_q[(i, 3 + i)] * lambda[i])
}

/// Eq. 19 as a dense 9×9 LU.
fn dense_saddle(
    m: &ExtendedModel,
    q: &Vector6<f64>,
    r1: &Vector6<f64>,
    r2: &Vector3<f64>,
) -> (Vector6<f64>, Vector3<f64>) {
    let phi_q = m.constraint_jacobian(q);
    let mut a = SMatrix::<f64, 9, 9>::zeros();
    a.fixed_view_mut::<6, 6>(0, 0).copy_from(&m.mass_matrix(q));
    a.fixed_view_mut::<6, 3>(0, 6).copy_from(&phi_q.transpose());
    a.fixed_view_mut::<3, 6>(6, 0).copy_from(&phi_q);
    let rhs = SVector::<f64, 9>::from_iterator(r1.iter().chain(r2.iter()).copied());
    let x = a.lu().solve(&rhs).unwrap();
    (x.fixed_rows::<6>(0).into(), x.fixed_rows::<3>(6).into())
}

fn close<const N: usize>(a: &SVector<f64, N>, b: &SVector<f64, N>, rel: f64) -> bool {
    (a - b).amax() <= rel * b.amax().max(1.0)
}

fn torque(t: f64) -> Vector3<f64> {
    Vector3::new(10.0 * t.sin(), -5.0, 20.0 * t.cos())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn inverse_dynamics_kernels_match_the_matrix_formulation((q, qd, qdd) in state(), rate in prop::array::uniform6(-50.0..50.0f64)) {
        for m in &models() {
            let at = m.at(&q);
            prop_assert!(close(&at.momentum(&qd), &(m.mass_matrix(&q) * qd), 1e-13));
            prop_assert!(close(&at.constraints(), &m.constraints(&q), 1e-13));
            let rate = Vector6::from(rate);
            let fast = at.hamilton_torques(&qd, &rate).unwrap();
            prop_assert!(close(&fast, &reference_torques(m, &q, &qd, &rate), 1e-11), "{fast}");
            let lagrange_rate = m.mass_matrix(&q) * qdd + m.mass_matrix_rate_times_velocity(&q, &qd);
            let fast = at.lagrange_torques(&qd, &qdd).unwrap();
            prop_assert!(close(&fast, &reference_torques(m, &q, &qd, &lagrange_rate), 1e-11), "{fast}");
            // Acceleration- and velocity-level IK: Φ_q q̈ + γ = 0 and Φ_q q̇ = 0.
            let a: Vector3<f64> = qdd.fixed_rows::<3>(0).into();
            let acc = at.joint_accelerations(&qd, &a).unwrap();
            let residual = m.constraint_jacobian(&q) * acc + m.gamma(&q, &qd);
            prop_assert!(residual.amax() <= 1e-11 * (m.constraint_jacobian(&q) * acc).amax().max(1.0), "{residual}");
            let v: Vector3<f64> = qd.fixed_rows::<3>(0).into();
            let vel = at.joint_velocities(&v).unwrap();
            prop_assert!((m.constraint_jacobian(&q) * vel).amax() <= 1e-12 * v.amax().max(1.0));
        }
    }

    /// The Schur-complement solve of eq. 19 (both forms) against a dense 9×9 LU, and the whole
    /// right-hand sides against the matrix formulation of eqs. 17 and the acceleration form.
    #[test]
    fn schur_solve_matches_dense_lu((q, qd, _) in state(), p in prop::array::uniform6(-2.0..2.0f64), t in 0.0..1.0f64) {
        for m in &models() {
            let p = Vector6::from(p);
            let kappa = 20.0;
            let h = HamiltonForm::new(m, torque, kappa).unwrap();
            let z = SVector::<f64, 13>::from_iterator(q.iter().chain(p.iter()).copied().chain([0.0]));
            let (qd_fast, sigma_fast) = h.solve(t, &z).unwrap();
            let (qd_dense, minus_sigma) = dense_saddle(m, &q, &p, &(-m.constraints(&q) * kappa));
            prop_assert!(close(&qd_fast, &qd_dense, 1e-12), "{qd_fast} vs {qd_dense}");
            prop_assert!(close(&sigma_fast, &(-minus_sigma), 1e-12));
            let mut dz = SVector::<f64, 13>::zeros();
            h.rhs(t, &z, &mut dz).unwrap();
            let tau = torque(t);
            let q_force = Vector6::new(0.0, 0.0, 0.0, tau.x, tau.y, tau.z);
            let pd = m.lagrangian_gradient(&q, &qd_dense) + q_force
                + m.constraint_jacobian_rate(&q, &qd_dense).transpose() * minus_sigma;
            let dz_ref = SVector::<f64, 13>::from_iterator(
                qd_dense.iter().chain(pd.iter()).copied().chain([tau.dot(&qd_dense.fixed_rows::<3>(3))]),
            );
            prop_assert!(close(&dz, &dz_ref, 1e-11), "{dz} vs {dz_ref}");

            let omega = 20.0;
            let a = AccelerationForm::new(m, torque, omega).unwrap();
            let z = SVector::<f64, 13>::from_iterator(q.iter().chain(qd.iter()).copied().chain([0.0]));
            let (qdd_fast, lambda_fast) = a.solve(t, &z, &tau).unwrap();
            let r1 = m.lagrangian_gradient(&q, &qd) + q_force - m.mass_matrix_rate_times_velocity(&q, &qd);
            let r2 = -m.gamma(&q, &qd) - m.constraint_jacobian(&q) * qd * (2.0 * omega)
                - m.constraints(&q) * (omega * omega);
            let (qdd_dense, lambda_dense) = dense_saddle(m, &q, &r1, &r2);
            prop_assert!(close(&qdd_fast, &qdd_dense, 1e-12), "{qdd_fast} vs {qdd_dense}");
            prop_assert!(close(&lambda_fast, &lambda_dense, 1e-12));
        }
    }
}

/// A direct-kinematic singularity of steps 2–3 ($\det\Phi_x = 0$: all three forearms parallel to a
/// plane, here the horizontal one) is a typed error.
#[test]
fn a_singular_phi_x_is_a_typed_error() {
    // Delta, arms horizontal (θ = 0) and the plate at the motor plane: each v_i is horizontal.
    let m = &models()[1];
    let q = Vector6::new(
        0.0,
        0.0,
        Placement::canonical().motor_plane_z,
        0.0,
        0.0,
        0.0,
    );
    let e = m
        .at(&q)
        .hamilton_torques(&Vector6::zeros(), &Vector6::zeros())
        .unwrap_err();
    assert!(
        matches!(
            e,
            ConfigurationError::Singular {
                matrix: "Phi_x^T",
                ..
            }
        ),
        "{e:?}"
    );
}
