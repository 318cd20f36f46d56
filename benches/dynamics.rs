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

/// One torque evaluation at t = 0.136 s (the peak): Hamilton from the momenta at the two
/// neighbouring samples (steps 1–3), Lagrange from $(q, \dot q, \ddot q)$.
pub(crate) fn inverse_dynamics(c: &mut Criterion) {
    let model = nuwar();
    let trajectory = Trajectory::pick_and_place(0.5, CycleReading::RoundTrip).expect("cycle");
    let dt = 1e-3;
    let samples = inverse::sample(&model, &trajectory, dt).expect("reachable");
    let (prev, now, next) = (samples[135].1, samples[136].1, samples[137].1);
    let mut group = c.benchmark_group("miller2004_inverse_dynamics");
    group.bench_function("hamilton_one_sample", |b| {
        b.iter(|| {
            let p_prev = model.mass_matrix(&prev.q) * prev.qd;
            let p_next = model.mass_matrix(&next.q) * next.qd;
            let rate = (p_next - p_prev) / (2.0 * dt);
            torques(&model, black_box(&now.q), black_box(&now.qd), &rate)
        })
    });
    group.bench_function("lagrange_one_sample", |b| {
        b.iter(|| lagrange_torques(&model, black_box(&now.q), black_box(&now.qd), &now.qdd))
    });
    group.bench_function("hamilton_full_cycle_1ms", |b| {
        b.iter(|| {
            inverse::hamilton(
                &model,
                black_box(&samples),
                dt,
                inverse::Differencing::Central,
            )
        })
    });
    group.finish();
}

/// The forward simulation of the full cycle (Hamilton form, exact torques sampled at 1 ms,
/// DP54 at rtol 1e-9).
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
                &form,
                &mut dopri,
                (0.0, 0.5),
                &z0,
                &OutputTimes::Uniform(dt),
                &pkm::traits::Silent,
            )
        })
    });
    group.finish();
}
