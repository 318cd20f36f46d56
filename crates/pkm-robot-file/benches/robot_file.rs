//! IK + J + 1/κ of a general 3-DOF robot from a file against the hand-written model of the same
//! robot: the rotary Delta of Miller 2004 (`examples/robots/rotary_delta.toml` and
//! `pkm_mechanisms::RotaryDelta`), over 256 seeded poses. Numbers go to `docs/performance.md`.

#![allow(missing_docs, clippy::unwrap_used, clippy::expect_used)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Matrix3, Vector3};
use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
use pkm_robot_file::Robot;
use pkm_traits::InverseKinematics;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

fn poses() -> Vec<Vector3<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(18);
    (0..256)
        .map(|_| {
            Vector3::new(
                rng.random_range(-0.1..0.1),
                rng.random_range(-0.1..0.1),
                rng.random_range(-0.85..-0.55),
            )
        })
        .collect()
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
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/robots/rotary_delta.toml"
    );
    let robot = Robot::<3>::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    let hand = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    let xs = poses();
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

criterion_group!(benches, ik_j_kappa);
criterion_main!(benches);
