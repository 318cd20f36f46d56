//! Miller 2004 §3: one inverse-dynamics evaluation (Hamilton vs Lagrange) and the forward
//! simulation of the full pick-and-place cycle.

#![allow(clippy::expect_used)]

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{BenchmarkGroup, Criterion};
use pkm::dynamics_hamilton::inverse;
use pkm::dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm::mechanisms::{Placement, RotaryDelta, presets};
use pkm::papers::miller2004::dynamics::{CycleReading, pick_and_place};
use std::hint::black_box;

/// The CPU time of the benchmarking thread (`/proc/thread-self/schedstat`, ns), beside the wall
/// time: on a shared machine the two differ by the time the thread waited for a core.
struct ThreadCpuTime(WallTime);

/// The thread's run time. The kernel brings it up to date on a scheduler tick (4 ms here) or when
/// the thread enters the scheduler, so `yield_now` first (`sched_yield` updates the running
/// task's time); the constant cost of the yield and the read is removed by criterion's linear
/// fit over batches of iterations.
fn thread_cpu_ns() -> u64 {
    std::thread::yield_now();
    let stat = std::fs::read_to_string("/proc/thread-self/schedstat").expect("Linux schedstat");
    stat.split_whitespace()
        .next()
        .and_then(|ns| ns.parse().ok())
        .expect("run time in ns")
}

impl Measurement for ThreadCpuTime {
    type Intermediate = u64;
    type Value = u64;

    fn start(&self) -> u64 {
        thread_cpu_ns()
    }
    fn end(&self, start: u64) -> u64 {
        thread_cpu_ns() - start
    }
    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }
    fn zero(&self) -> u64 {
        0
    }
    fn to_f64(&self, ns: &u64) -> f64 {
        *ns as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        self.0.formatter()
    }
}

/// A criterion that measures thread CPU time, configured from the same command line.
fn cpu_criterion() -> Criterion<ThreadCpuTime> {
    Criterion::default()
        .with_measurement(ThreadCpuTime(WallTime))
        .configure_from_args()
}

fn nuwar() -> ExtendedModel {
    let mechanism = RotaryDelta::new(presets::nuwar(Placement::canonical())).expect("paper design");
    ExtendedModel::new(mechanism, &MassParameters::miller2004()).expect("paper masses")
}

/// One torque evaluation at t = 0.136 s (the peak), per sample as in a sweep over the 1 ms grid.
/// Every variant forms the sample's [`Configuration`](pkm::dynamics_hamilton::Configuration)
/// (three `sin_cos` and the per-leg vectors) once; in a sweep it serves the sample's momentum and
/// its torques.
///
/// * `hamilton_one_sample`: the configuration and momentum $p_{k+1} = M(q_{k+1})\dot q_{k+1}$ of
///   the next sample, the central difference with $p_{k-1}$, and steps 2–3 of §3.3 at sample
///   $k$, whose configuration was formed when it was the next sample (given): the per-sample
///   cost of [`inverse::hamilton`].
/// * `lagrange_one_sample`: the configuration, $\dot p = M\ddot q + \dot M\dot q$ and the same
///   steps 2–3, with a **precomputed** $\ddot q$ (the trajectory sample's analytic acceleration).
/// * `lagrange_one_sample_with_acceleration_ik`: the same plus $\ddot\theta =
///   -\Phi_\theta^{-1}(\Phi_x\ddot p + \gamma)$ from the task acceleration: the fair per-sample
///   cost of Lagrange against Hamilton, since both need $(q, \dot q)$ from the position- and
///   velocity-level IK.
///
/// All inputs go through `black_box`.
pub(crate) fn inverse_dynamics(c: &mut Criterion) {
    inverse_benches(&mut c.benchmark_group("miller2004_inverse_dynamics"));
    inverse_benches(&mut cpu_criterion().benchmark_group("miller2004_inverse_dynamics_cpu"));
}

fn inverse_benches<M: Measurement>(group: &mut BenchmarkGroup<'_, M>) {
    let model = nuwar();
    let trajectory = pick_and_place(0.5, CycleReading::RoundTrip).expect("cycle");
    let dt = 1e-3;
    let samples = inverse::sample(&model, &trajectory, dt).expect("reachable");
    let (prev, now, next) = (samples[135].1, samples[136].1, samples[137].1);
    let p_prev = model.at(&prev.q).momentum(&prev.qd);
    let now_at = model.at(&now.q);
    let task_acceleration = trajectory.sample(samples[136].0).a;
    group.bench_function("hamilton_one_sample", |b| {
        b.iter(|| {
            let next_at = model.at(black_box(&next.q));
            let p_next = next_at.momentum(black_box(&next.qd));
            let rate = (p_next - black_box(&p_prev)) * (0.5 / black_box(dt));
            black_box(&now_at).hamilton_torques(black_box(&now.qd), &rate)
        })
    });
    group.bench_function("lagrange_one_sample", |b| {
        b.iter(|| {
            let at = model.at(black_box(&now.q));
            at.lagrange_torques(black_box(&now.qd), black_box(&now.qdd))
        })
    });
    group.bench_function("lagrange_one_sample_with_acceleration_ik", |b| {
        b.iter(|| {
            let at = model.at(black_box(&now.q));
            let qd = black_box(&now.qd);
            let qdd = at.joint_accelerations(qd, black_box(&task_acceleration))?;
            at.lagrange_torques(qd, &qdd)
        })
    });
    group.bench_function("hamilton_full_cycle_1ms", |b| {
        b.iter(|| inverse::hamilton(&model, black_box(&samples), inverse::Differencing::Central))
    });
    group.bench_function("lagrange_exact_full_cycle_1ms", |b| {
        b.iter(|| inverse::lagrange(&model, black_box(&samples), inverse::Accelerations::Exact))
    });
}

/// The forward simulation of the full cycle as in the Fig. 9 retrace: Hamilton form with
/// Baumgarte κ = 20 /s, fed with the **differenced Hamilton torques** (central differences on the
/// 1 ms grid, Catmull–Rom interpolation; not the exact Lagrange torques), DP54 at rtol 1e-9,
/// atol 1e-12, output every 1 ms; and one right-hand side of each forward form.
pub(crate) fn forward_cycle(c: &mut Criterion) {
    forward_benches(&mut c.benchmark_group("miller2004_forward"));
    forward_benches(&mut cpu_criterion().benchmark_group("miller2004_forward_cpu"));
}

fn forward_benches<M: Measurement>(group: &mut BenchmarkGroup<'_, M>) {
    use nalgebra::SVector;
    use pkm::dynamics_hamilton::forward::{
        AccelerationForm, ForwardForm, HamiltonForm, SampledTorques,
    };
    use pkm::integrators::{AdaptiveSettings, DormandPrince54, OutputTimes, integrate};
    use pkm::traits::VectorField;
    let model = nuwar();
    let trajectory = pick_and_place(0.5, CycleReading::RoundTrip).expect("cycle");
    let dt = 1e-3;
    let samples = inverse::sample(&model, &trajectory, dt).expect("reachable");
    let tau = inverse::hamilton(&model, &samples, inverse::Differencing::Central).expect("torques");
    let tau = SampledTorques::new(dt, tau).expect("grid");
    let form = HamiltonForm::new(&model, |t| tau.at(t), 20.0).expect("gain");
    let z0 = form.initial_state(&samples[0].1.q, &samples[0].1.qd);
    let settings = AdaptiveSettings::default()
        .with_rtol(1e-9)
        .and_then(|s| s.with_atol(1e-12))
        .expect("settings");
    // One right-hand side at the peak (t = 0.136 s) of the commanded cycle: eq. 19 by the Schur
    // complement, then eq. 17 (Hamilton form); the acceleration form with Baumgarte ω = 20 /s.
    let peak = &samples[136].1;
    let z_peak = form.initial_state(&peak.q, &peak.qd);
    group.bench_function("hamilton_rhs", |b| {
        let mut dz = SVector::<f64, 13>::zeros();
        b.iter(|| {
            form.rhs(black_box(0.136), black_box(&z_peak), &mut dz)
                .map(|()| dz)
        })
    });
    let acceleration = AccelerationForm::new(&model, |t| tau.at(t), 20.0).expect("gain");
    let z_peak_acceleration = acceleration.initial_state(&peak.q, &peak.qd);
    group.bench_function("acceleration_form_rhs", |b| {
        let mut dz = SVector::<f64, 13>::zeros();
        b.iter(|| {
            acceleration
                .rhs(black_box(0.136), black_box(&z_peak_acceleration), &mut dz)
                .map(|()| dz)
        })
    });
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
}
