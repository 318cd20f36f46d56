//! IK + J + 1/κ of a general 3-DOF robot from a file against the hand-written model of the same
//! robot: the rotary Delta of Miller 2004 (`examples/robots/rotary_delta.toml` and
//! `pkm_mechanisms::RotaryDelta`), over 256 seeded poses; and forward kinematics from a guess
//! (the pose plus 0.01 m per coordinate) on the Delta and Tsai files against their hand-written
//! models; and one inverse-dynamics sample of the Delta file (Miller's masses) against the
//! hand-written Lagrange torques, and of the Stewart–Gough file. Numbers go to
//! `docs/performance.md`.

#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Matrix3, Vector3};
use pkm_mechanisms::{Elbow, ElbowMode, Placement, RotaryDelta, Tsai3Dof, presets};
use pkm_robot_file::Robot;
use pkm_traits::{ForwardKinematics, InverseKinematics, NewtonSettings};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

/// 256 seeded poses in the box `x, y ∈ [-0.1, 0.1]`, `z ∈ z_range`.
fn poses(z_range: std::ops::Range<f64>) -> Vec<Vector3<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(18);
    (0..256)
        .map(|_| {
            Vector3::new(
                rng.random_range(-0.1..0.1),
                rng.random_range(-0.1..0.1),
                rng.random_range(z_range.clone()),
            )
        })
        .collect()
}

fn robot(file: &str) -> Robot<3> {
    let path = format!(
        "{}/../../examples/robots/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    Robot::<3>::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn inverse_condition(j: &Matrix3<f64>) -> f64 {
    let sv = j.singular_values();
    sv.min() / sv.max()
}

/// Sum of 1/κ over the poses: IK, then J, then its singular values.
fn sweep<M: InverseKinematics<3, 3>>(m: &M, mode: M::WorkingMode, xs: &[Vector3<f64>]) -> f64 {
    xs.iter()
        .filter_map(|x| {
            let q = m.inverse_kinematics(x, mode).ok()?;
            black_box(q);
            m.velocity_jacobian_at(x, mode).ok()
        })
        .map(|j| inverse_condition(&j))
        .sum()
}

fn ik_j_kappa(c: &mut Criterion) {
    let robot = robot("rotary_delta.toml");
    let hand = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    let xs = poses(-0.85..-0.55);
    let mut group = c.benchmark_group("robot_file/rotary_delta");
    group.throughput(Throughput::Elements(xs.len() as u64));
    group.sample_size(20);
    group.bench_function("ik_j_inverse_kappa/general", |b| {
        b.iter(|| sweep(&robot, robot.model().home_mode(), black_box(&xs)))
    });
    group.bench_function("ik_j_inverse_kappa/hand_written", |b| {
        b.iter(|| sweep(&hand, ElbowMode::Out, black_box(&xs)))
    });
    group.finish();
}

/// The actuators of each pose in `mode`, with the guess `x + 0.01`.
fn fk_rows<M: InverseKinematics<3, 3>>(
    m: &M,
    mode: M::WorkingMode,
    xs: &[Vector3<f64>],
) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    xs.iter()
        .filter_map(|x| Some((m.inverse_kinematics(x, mode).ok()?, x.add_scalar(0.01))))
        .collect()
}

/// Sum of the solved coordinates over the rows (every row must converge).
fn solve_all<M: ForwardKinematics<3>>(m: &M, rows: &[(Vector3<f64>, Vector3<f64>)]) -> f64 {
    let settings = NewtonSettings::default();
    rows.iter()
        .map(|(q, guess)| m.forward_kinematics(q, guess, &settings).unwrap().sum())
        .sum()
}

fn forward_kinematics(c: &mut Criterion) {
    let delta = (
        robot("rotary_delta.toml"),
        RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap(),
    );
    let tsai = (
        robot("tsai.toml"),
        Tsai3Dof::new(presets::stamper_max_gci()).unwrap(),
    );
    let delta_rows = fk_rows(&delta.1, ElbowMode::Out, &poses(-0.85..-0.55));
    let tsai_rows = fk_rows(&tsai.1, [Elbow::Out; 3], &poses(0.35..0.55));
    let mut group = c.benchmark_group("robot_file/forward_kinematics");
    group.sample_size(20);
    group.throughput(Throughput::Elements(delta_rows.len() as u64));
    group.bench_function("rotary_delta/general", |b| {
        b.iter(|| solve_all(&delta.0, black_box(&delta_rows)))
    });
    group.bench_function("rotary_delta/hand_written", |b| {
        b.iter(|| solve_all(&delta.1, black_box(&delta_rows)))
    });
    group.throughput(Throughput::Elements(tsai_rows.len() as u64));
    group.bench_function("tsai/general", |b| {
        b.iter(|| solve_all(&tsai.0, black_box(&tsai_rows)))
    });
    group.bench_function("tsai/hand_written", |b| {
        b.iter(|| solve_all(&tsai.1, black_box(&tsai_rows)))
    });
    group.finish();
}

/// One inverse-dynamics sample on Miller's cycle at t = 0.136 s: the Delta file against the
/// hand-written extended-space Lagrange torques; and the Stewart–Gough file at a pose 2 cm and
/// 0.05 rad from home moving at 0.1 m/s and 0.5 rad/s.
fn inverse_dynamics(c: &mut Criterion) {
    use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
    use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
    let file = robot("rotary_delta.toml").model().clone();
    let hand = ExtendedModel::new(
        RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap(),
        &MassParameters::miller2004(),
    )
    .unwrap();
    let m = miller_pick_and_place(0.5).unwrap().sample(0.136);
    let mut group = c.benchmark_group("robot_file/inverse_dynamics");
    group.sample_size(20);
    group.bench_function("rotary_delta/general", |b| {
        b.iter(|| {
            file.inverse_dynamics(
                black_box(m.p.as_slice()),
                m.v.as_slice(),
                m.a.as_slice(),
                file.home_mode(),
            )
            .unwrap()
            .efforts
        })
    });
    group.bench_function("rotary_delta/hand_written", |b| {
        b.iter(|| {
            let s = hand.joint_motion(black_box(&m.p), &m.v, &m.a).unwrap();
            hand.at(&s.q).lagrange_torques(&s.qd, &s.qdd).unwrap()
        })
    });
    let path = format!(
        "{}/../../examples/robots/stewart_gough.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let sg =
        pkm_robot_file::RobotModel::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    let x = [0.02, -0.01, 0.31, 0.05, -0.03, 0.02];
    let v = [0.1, 0.0, -0.05, 0.5, 0.0, 0.2];
    let a = [1.0, -2.0, 0.5, 3.0, 1.0, -1.0];
    group.bench_function("stewart_gough/general", |b| {
        b.iter(|| {
            sg.inverse_dynamics(black_box(&x), &v, &a, sg.home_mode())
                .unwrap()
                .efforts
        })
    });
    group.bench_function("stewart_gough/efforts", |b| {
        b.iter(|| sg.actuator_efforts(black_box(&x), &v, &a, sg.home_mode()))
    });
    group.bench_function("rotary_delta/efforts", |b| {
        b.iter(|| {
            file.actuator_efforts(
                black_box(m.p.as_slice()),
                m.v.as_slice(),
                m.a.as_slice(),
                file.home_mode(),
            )
        })
    });
    group.finish();
}

/// Every assembly mode of Dietmaier's Stewart–Gough design (40 real) by homotopy: 40 paths from
/// the cached generic solutions (the monodromy runs once, before the measurement), on the
/// machine's threads and on one.
fn assembly_modes(c: &mut Criterion) {
    let path = format!(
        "{}/../../examples/robots/dietmaier_40.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let model =
        pkm_robot_file::RobotModel::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    let q = [1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071];
    assert_eq!(model.forward_kinematics_all(&q).unwrap().report.real, 40);
    let mut group = c.benchmark_group("robot_file/assembly_modes");
    group.sample_size(10);
    let all = |q: &[f64]| model.forward_kinematics_all(q).unwrap().report.real;
    group.bench_function("dietmaier_40/homotopy", |b| b.iter(|| all(black_box(&q))));
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    group.bench_function("dietmaier_40/homotopy_1_thread", |b| {
        b.iter(|| one.install(|| all(black_box(&q))))
    });
    group.finish();
}

criterion_group!(
    benches,
    ik_j_kappa,
    forward_kinematics,
    inverse_dynamics,
    assembly_modes
);
criterion_main!(benches);
