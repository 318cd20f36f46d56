//! Property tests: analytic derivatives against finite differences, conservation, and the
//! spec's reference numbers (an independent re-implementation).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Vector3, Vector6};
use pkm_dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm_dynamics_hamilton::trajectory::{CycleReading, Trajectory};
use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm_mechanisms::{Placement, RotaryDelta};
use proptest::prelude::*;

fn nuwar() -> ExtendedModel {
    ExtendedModel::new(
        RotaryDelta::nuwar(Placement::canonical()).unwrap(),
        &MassParameters::miller2004(),
    )
    .unwrap()
}

fn lagrangian(m: &ExtendedModel, q: &Vector6<f64>, qd: &Vector6<f64>) -> f64 {
    use pkm_traits::ExtendedInertia;
    m.kinetic_energy(q, qd) - m.potential(q)
}

fn state() -> impl Strategy<Value = (Vector6<f64>, Vector6<f64>)> {
    (
        prop::array::uniform6(-1.0..1.0f64),
        prop::array::uniform6(-3.0..3.0f64),
    )
        .prop_map(|(q, v)| {
            let q = Vector6::from(q).component_mul(&Vector6::new(0.2, 0.2, 0.2, 1.0, 1.0, 1.0))
                + Vector6::new(0.0, 0.0, -0.7, 0.5, 0.5, 0.5);
            (q, Vector6::from(v))
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn analytic_derivatives_match_central_differences((q, qd) in state()) {
        let m = nuwar();
        let h = 1e-6;
        let phi_q = m.constraint_jacobian(&q);
        let l_q = m.lagrangian_gradient(&q, &qd);
        let mut phi_q_dot_fd = nalgebra::SMatrix::<f64, 3, 6>::zeros();
        let mut mdot = Vector6::zeros();
        for j in 0..6 {
            let e = Vector6::from_fn(|i, _| if i == j { h } else { 0.0 });
            let dphi = (m.constraints(&(q + e)) - m.constraints(&(q - e))) / (2.0 * h);
            prop_assert!((dphi - phi_q.column(j)).amax() < 1e-6);
            let dl = (lagrangian(&m, &(q + e), &qd) - lagrangian(&m, &(q - e), &qd)) / (2.0 * h);
            prop_assert!((dl - l_q[j]).abs() < 1e-6, "L_q[{j}] {dl} vs {}", l_q[j]);
            phi_q_dot_fd += (m.constraint_jacobian(&(q + e)) - m.constraint_jacobian(&(q - e)))
                / (2.0 * h) * qd[j];
            mdot += (m.mass_matrix(&(q + e)) - m.mass_matrix(&(q - e))) / (2.0 * h) * qd[j] * qd;
        }
        prop_assert!((phi_q_dot_fd - m.constraint_jacobian_rate(&q, &qd)).amax() < 1e-5);
        let diff = mdot - m.mass_matrix_rate_times_velocity(&q, &qd);
        prop_assert!(diff.amax() < 1e-6, "{diff}");
    }
}

#[test]
fn canonical_cycle_reproduces_the_spec_reference_numbers() {
    let m = nuwar();
    let traj = Trajectory::pick_and_place(0.5, CycleReading::RoundTrip).unwrap();
    let samples = inverse::sample(&m, &traj, 1e-3).unwrap();
    let max_acc = samples.iter().map(|(_, s)| s.qdd.fixed_rows::<3>(0).norm()).fold(0.0, f64::max);
    assert!((max_acc - 222.07).abs() < 0.01, "{max_acc}");
    let exact = inverse::lagrange(&m, &samples, 1e-3, Accelerations::Exact).unwrap();
    let peak = exact.iter().map(Vector3::amax).fold(0.0, f64::max);
    assert!((peak - 60.91).abs() < 0.05, "NUWAR max torque {peak}");
    let c = Differencing::Central;
    let h = inverse::hamilton(&m, &samples, 1e-3, c).unwrap();
    let l = inverse::lagrange(&m, &samples, 1e-3, Accelerations::Differenced(c)).unwrap();
    let diff = h.iter().zip(&l).map(|(a, b)| (a - b).amax()).fold(0.0, f64::max);
    assert!(diff < 0.01, "Hamilton vs Lagrange {diff}");
}
