//! Property tests: analytic derivatives against finite differences, conservation, and the
//! spec's reference numbers (an independent re-implementation).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Vector3, Vector6};
use pkm_dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm_dynamics_hamilton::trajectory::Trajectory;
use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm_mechanisms::{Placement, RotaryDelta, presets};
use proptest::prelude::*;

fn nuwar() -> ExtendedModel {
    ExtendedModel::new(
        RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
        &MassParameters::miller2004(),
    )
    .unwrap()
}

/// Miller's canonical cycle (§3.5, spec `miller-dynamics.md`): 0.25 s each way.
fn ellipse_cycle() -> Trajectory {
    miller_pick_and_place(0.5).unwrap()
}

fn lagrangian(m: &ExtendedModel, q: &Vector6<f64>, qd: &Vector6<f64>) -> f64 {
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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random clothoids: $|dp/ds| = 1$, signed curvature $\kappa_0 + c s$, and the analytic
    /// $p'$, $p''$ against central differences of the quadrature-evaluated $p$; composed with a
    /// motion program, $\dot p$ and $\ddot p$ against central differences in time.
    #[test]
    fn clothoid_derivatives_and_curvature(
        k0 in -10.0..10.0f64,
        c in -50.0..50.0f64,
        length in 0.05..1.0f64,
        t in prop::array::uniform3(-1.0..1.0f64),
        n in prop::array::uniform3(-1.0..1.0f64),
        u in 0.01..0.99f64,
    ) {
        use pkm_dynamics_hamilton::trajectory::{MotionLaw, Path, Segment};
        let (t, n) = (Vector3::from(t), Vector3::from(n));
        prop_assume!(t.cross(&n).norm() > 0.1 * t.norm() * n.norm());
        let path = Path::clothoid(Vector3::new(0.0, 0.0, -0.8), t, n, k0, c, length).unwrap();
        let h = 1e-5;
        let [_, d1, d2] = path.eval(u);
        let [pp, dp, _] = path.eval(u + h);
        let [pm, dm, _] = path.eval(u - h);
        // Truncation ~ h² (κL)² / 6 relative, κL ≤ 60: below 1e-7.
        prop_assert!(((pp - pm) / (2.0 * h) - d1).norm() < 1e-6 * d1.norm());
        prop_assert!(((dp - dm) / (2.0 * h) - d2).norm() < 1e-6 * d2.norm().max(1.0));
        prop_assert!((d1.norm() - length).abs() < 1e-13);
        let kappa = d1.cross(&d2).dot(&t.cross(&n).normalize()) / d1.norm().powi(3);
        prop_assert!((kappa - (k0 + c * u * length)).abs() < 1e-10 * (1.0 + k0.abs() + c.abs()));

        let traj = Trajectory::new(vec![Segment { path, law: MotionLaw::Polynomial345, duration: 0.4, reverse: true }]).unwrap();
        let (time, h) = (0.4 * u, 1e-6);
        let (m, mp, mm) = (traj.sample(time), traj.sample(time + h), traj.sample(time - h));
        prop_assert!(((mp.p - mm.p) / (2.0 * h) - m.v).norm() < 1e-6 * m.v.norm().max(1.0));
        prop_assert!(((mp.v - mm.v) / (2.0 * h) - m.a).norm() < 1e-6 * m.a.norm().max(1.0));
    }
}

#[test]
fn canonical_cycle_reproduces_the_spec_reference_numbers() {
    let m = nuwar();
    let traj = ellipse_cycle();
    let samples = inverse::sample(&m, &traj, 1e-3).unwrap();
    let max_acc = samples
        .iter()
        .map(|(_, s)| s.qdd.fixed_rows::<3>(0).norm())
        .fold(0.0, f64::max);
    assert!((max_acc - 222.07).abs() < 0.01, "{max_acc}");
    let exact = inverse::lagrange(&m, &samples, Accelerations::Exact).unwrap();
    let peak = exact.iter().map(Vector3::amax).fold(0.0, f64::max);
    assert!((peak - 60.91).abs() < 0.05, "NUWAR max torque {peak}");
    let c = Differencing::Central;
    let h = inverse::hamilton(&m, &samples, c).unwrap();
    let l = inverse::lagrange(&m, &samples, Accelerations::Differenced(c)).unwrap();
    let diff = h
        .iter()
        .zip(&l)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    assert!(diff < 0.01, "Hamilton vs Lagrange {diff}");
}

fn dopri(rtol: f64) -> pkm_integrators::DormandPrince54<13> {
    let s = pkm_integrators::AdaptiveSettings::default()
        .with_rtol(rtol)
        .unwrap()
        .with_atol(rtol * 1e-3)
        .unwrap();
    pkm_integrators::DormandPrince54::new(s)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    /// Zero torque, no gravity: $H = T$ is conserved (to the integrator's tolerance) by the
    /// Hamilton form from a random consistent initial velocity.
    #[test]
    fn hamiltonian_is_conserved_without_torque_and_gravity(
        v in prop::array::uniform3(-1.0..1.0f64),
        y in -0.1..0.1f64,
    ) {
        use pkm_dynamics_hamilton::forward::{ForwardForm, HamiltonForm};
        let mass = MassParameters { gravity: 0.0, ..MassParameters::miller2004() };
        let m = ExtendedModel::new(RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(), &mass).unwrap();
        let s = m.joint_motion(&Vector3::new(0.0, y, -0.75), &Vector3::from(v), &Vector3::zeros()).unwrap();
        let form = HamiltonForm::new(&m, |_| Vector3::zeros(), 0.0).unwrap();
        let z0 = form.initial_state(&s.q, &s.qd);
        let out = pkm_integrators::OutputTimes::Uniform(0.01);
        let run = pkm_integrators::integrate(&form, &mut dopri(1e-9), (0.0, 0.1), &z0, &out, &pkm_traits::Silent).unwrap();
        let e0 = form.energy_minus_work(0.0, &z0).unwrap();
        for (t, z) in run.times.iter().zip(&run.states) {
            let e = form.energy_minus_work(*t, z).unwrap();
            prop_assert!((e - e0).abs() <= 1e-6 * e0.abs().max(1e-3), "{e} vs {e0} at {t}");
        }
    }

    /// Exact inverse dynamics of a random smooth (cycloidal, straight-line) move, fed to the
    /// Hamilton forward form, reproduces the move.
    #[test]
    fn inverse_then_forward_reproduces_random_moves(
        a in prop::array::uniform3(-0.1..0.1f64),
        b in prop::array::uniform3(-0.1..0.1f64),
    ) {
        use pkm_dynamics_hamilton::forward::{ForwardForm, HamiltonForm};
        use pkm_dynamics_hamilton::trajectory::{MotionLaw, Path, Segment};
        let m = nuwar();
        let centre = Vector3::new(0.0, 0.0, -0.75);
        let path = Path::Line { start: centre + Vector3::from(a), end: centre + Vector3::from(b) };
        let traj = Trajectory::new(vec![Segment { path, law: MotionLaw::Cycloidal, duration: 0.3, reverse: false }]).unwrap();
        let torque = |t: f64| {
            let c = traj.sample(t);
            let s = m.joint_motion(&c.p, &c.v, &c.a).unwrap();
            inverse::lagrange_torques(&m, &s.q, &s.qd, &s.qdd).unwrap()
        };
        let form = HamiltonForm::new(&m, torque, 20.0).unwrap();
        let s0 = m.joint_motion(&traj.sample(0.0).p, &Vector3::zeros(), &Vector3::zeros()).unwrap();
        let z0 = form.initial_state(&s0.q, &s0.qd);
        let out = pkm_integrators::OutputTimes::Uniform(0.01);
        let run = pkm_integrators::integrate(&form, &mut dopri(1e-9), (0.0, 0.3), &z0, &out, &pkm_traits::Silent).unwrap();
        for (t, z) in run.times.iter().zip(&run.states) {
            let err = (z.fixed_rows::<3>(0) - traj.sample(*t).p).norm();
            prop_assert!(err < 1e-6, "error {err} at {t}");
        }
    }
}

/// Issue 29: `Differencing::apply` returned zeros for fewer than 3 samples (its docs say it
/// needs 3) and divided by any step. Both are typed errors now; 3 samples of a line give its
/// slope exactly.
#[test]
fn differencing_refuses_too_few_samples_and_bad_steps() {
    use nalgebra::Vector6;
    let line = |k: usize| Vector6::repeat(2.0 * k as f64);
    let two = [line(0), line(1)];
    for d in [Differencing::Backward, Differencing::Central] {
        assert!(d.apply(&two, 0.1).is_err());
        assert!(d.apply::<Vector6<f64>>(&[], 0.1).is_err());
        let three = [line(0), line(1), line(2)];
        for dt in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            assert!(d.apply(&three, dt).is_err(), "{dt}");
        }
        let slope = d.apply(&three, 0.5).unwrap();
        assert!(
            slope
                .iter()
                .all(|v| (v - Vector6::repeat(4.0)).amax() < 1e-12)
        );
    }
}
