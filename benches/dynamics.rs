//! Miller 2004 §3: one inverse-dynamics evaluation (Hamilton vs Lagrange) and the forward
//! simulation of the full pick-and-place cycle.

#![allow(clippy::expect_used)]

use criterion::Criterion;
use pkm::dynamics_hamilton::inverse::{self, lagrange_torques, torques};
use pkm::dynamics_hamilton::trajectory::{CycleReading, Trajectory};
use pkm::dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm::mechanisms::{Placement, RotaryDelta};
use std::hint::black_box;

fn nuwar() -> ExtendedModel {
    let mechanism = RotaryDelta::nuwar(Placement::canonical()).expect("paper design");
    ExtendedModel::new(mechanism, &MassParameters::miller2004()).expect("paper masses")
}

/// One torque evaluation at t = 0.136 s (the peak), per sample as in a sweep over the 1 ms grid.
///
/// * `hamilton_one_sample`: the momentum $p_{k+1} = M(q_{k+1})\dot q_{k+1}$ of the next sample
///   (in a sweep every momentum is formed once and used by both neighbours, so $p_{k-1}$ is
///   given), the central difference and steps 2–3 of §3.3.
/// * `lagrange_one_sample`: $\dot p = M\ddot q + \dot M\dot q$ and the same steps 2–3, with a
///   **precomputed** $\ddot q$ (the trajectory sample's analytic acceleration); it leaves out the
///   acceleration-level inverse kinematics that only Lagrange needs.
/// * `lagrange_one_sample_with_acceleration_ik`: the same plus $\ddot\theta =
///   -\Phi_\theta^{-1}(\Phi_x\ddot p + \gamma)$ from the task acceleration
///   ([`ExtendedModel::joint_accelerations`]): the fair per-sample cost of Lagrange against
///   Hamilton, since both need $(q, \dot q)$ from the position- and velocity-level IK.
///
/// All inputs go through `black_box`.
pub(crate) fn inverse_dynamics(c: &mut Criterion) {
    let model = nuwar();
    let trajectory = Trajectory::pick_and_place(0.5, CycleReading::RoundTrip).expect("cycle");
    let dt = 1e-3;
    let samples = inverse::sample(&model, &trajectory, dt).expect("reachable");
    let (prev, now, next) = (samples[135].1, samples[136].1, samples[137].1);
    let p_prev = model.mass_matrix(&prev.q) * prev.qd;
    let task_acceleration = trajectory.sample(samples[136].0).a;
    let mut group = c.benchmark_group("miller2004_inverse_dynamics");
    group.bench_function("hamilton_one_sample", |b| {
        b.iter(|| {
            let (q, qd) = (black_box(&now.q), black_box(&now.qd));
            let p_next = model.mass_matrix(black_box(&next.q)) * black_box(&next.qd);
            let rate = (p_next - black_box(&p_prev)) / (2.0 * black_box(dt));
            torques(&model, q, qd, &rate)
        })
    });
    group.bench_function("lagrange_one_sample", |b| {
        b.iter(|| {
            lagrange_torques(
                &model,
                black_box(&now.q),
                black_box(&now.qd),
                black_box(&now.qdd),
            )
        })
    });
    group.bench_function("lagrange_one_sample_with_acceleration_ik", |b| {
        b.iter(|| {
            let (q, qd) = (black_box(&now.q), black_box(&now.qd));
            let qdd = model.joint_accelerations(q, qd, black_box(&task_acceleration))?;
            lagrange_torques(&model, q, qd, &qdd)
        })
    });
    group.bench_function("hamilton_full_cycle_1ms", |b| {
        b.iter(|| {
            inverse::hamilton(
                &model,
                black_box(&samples),
                black_box(dt),
                inverse::Differencing::Central,
            )
        })
    });
    group.bench_function("lagrange_exact_full_cycle_1ms", |b| {
        b.iter(|| {
            inverse::lagrange(
                &model,
                black_box(&samples),
                black_box(dt),
                inverse::Accelerations::Exact,
            )
        })
    });
    group.finish();
}

/// The forward simulation of the full cycle as in the Fig. 9 retrace: Hamilton form with
/// Baumgarte κ = 20 /s, fed with the **differenced Hamilton torques** (central differences on the
/// 1 ms grid, Catmull–Rom interpolation; not the exact Lagrange torques), DP54 at rtol 1e-9,
/// atol 1e-12, output every 1 ms.
pub(crate) fn forward_cycle(c: &mut Criterion) {
    use pkm::dynamics_hamilton::forward::{ForwardForm, HamiltonForm, SampledTorques};
    use pkm::integrators::{AdaptiveSettings, DormandPrince54, OutputTimes, integrate};
    let model = nuwar();
    let trajectory = Trajectory::pick_and_place(0.5, CycleReading::RoundTrip).expect("cycle");
    let dt = 1e-3;
    let samples = inverse::sample(&model, &trajectory, dt).expect("reachable");
    let tau =
        inverse::hamilton(&model, &samples, dt, inverse::Differencing::Central).expect("torques");
    let tau = SampledTorques::new(dt, tau).expect("grid");
    let form = HamiltonForm {
        model: &model,
        torque: |t| tau.at(t),
        kappa: 20.0,
    };
    let z0 = form.initial_state(&samples[0].1.q, &samples[0].1.qd);
    let settings = AdaptiveSettings::default()
        .with_rtol(1e-9)
        .and_then(|s| s.with_atol(1e-12))
        .expect("settings");
    let mut group = c.benchmark_group("miller2004_forward");
    group.sample_size(10);
    group.bench_function("hamilton_cycle_rtol_1e-9", |b| {
        b.iter(|| {
            let mut dopri = DormandPrince54::new(settings);
            integrate(
                black_box(&form),
                &mut dopri,
                (0.0, 0.5),
                black_box(&z0),
                &OutputTimes::Uniform(dt),
                &pkm::traits::Silent,
            )
        })
    });
    group.finish();
}
