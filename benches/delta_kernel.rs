//! Points per second of the rotary Delta design-index kernel (IK + $J_x$ + $J_\theta$ +
//! $1/\kappa(J_\theta^{-1}J_x)$), scalar and lane-parallel, on one core and on two, over the
//! point set of the NumPy peer (`shared/peers/numpy_delta_gci.py`): $2^{20}$ points uniform in
//! the box $[-0.2, 0.2]^2 \times [-0.65, -0.25]$ m of the paper's Delta with the motors in the
//! plane $z = 0$ and motor 1 at azimuth 0 (the peer's frame). Sums go through
//! `chunked_reduce`, so the result is the same for any thread count.
//!
//! The batch kernel runs on the vector path selected at run time (`batch/*`, AVX2 where the
//! processor has it) and, for comparison, on the baseline (`batch_baseline/*`); both give the
//! same sums bit for bit.
//!
//! Also the shared drivers of the batch benches: [`scalar_sums`] and [`lane_sums`].

use criterion::{Criterion, Throughput};
use nalgebra::Vector3;
use pkm::mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
use pkm::workspace_indices::{
    Accumulator, LANES, LaneKernel, Sampler, VectorPath, chunked_reduce, evaluate_on,
    inverse_condition_number_3x3, inverse_condition_of_reachable_lanes,
};
use pkm_traits::{ClosedChain, InverseKinematics, Silent};

/// Count, sum and sum of squares of a local index over the points where it is defined (what
/// `hemisphere_estimate` accumulates).
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub(crate) struct Sums {
    inside: u64,
    f: f64,
    f2: f64,
}

impl Sums {
    fn add(&mut self, f: Option<f64>) {
        if let Some(f) = f {
            let f = if f.is_finite() { f } else { 0.0 };
            self.inside += 1;
            self.f += f;
            self.f2 += f * f;
        }
    }
}

impl Accumulator for Sums {
    fn merge(&mut self, later: Self) {
        self.inside += later.inside;
        self.f += later.f;
        self.f2 += later.f2;
    }
}

/// [`Sums`] of `local` over `points`, one point at a time, deterministic chunks.
pub(crate) fn scalar_sums<F>(points: &[Vector3<f64>], local: F) -> Option<Sums>
where
    F: Fn(&Vector3<f64>) -> Option<f64> + Sync,
{
    chunked_reduce(points.len() as u64, &Silent, |acc: &mut Sums, i| {
        acc.add(local(&points[i as usize]));
    })
    .ok()
}

/// [`Sums`] of a batch kernel over `points` on the vector path `path`, [`LANES`] points at a
/// time (the last group padded with its last point, whose extra lanes are not counted),
/// deterministic chunks of groups. Full groups are borrowed from `points`, not copied.
pub(crate) fn lane_sums<K>(points: &[Vector3<f64>], kernel: &K, path: VectorPath) -> Option<Sums>
where
    K: LaneKernel<Output = [Option<f64>; LANES]>,
{
    let groups = points.len().div_ceil(LANES) as u64;
    chunked_reduce(groups, &Silent, |acc: &mut Sums, g| {
        let start = g as usize * LANES;
        let valid = (points.len() - start).min(LANES);
        let values = match points[start..start + valid].try_into() {
            Ok(group) => evaluate_on(path, kernel, group),
            Err(_) => {
                let padded = std::array::from_fn(|l| points[start + l.min(valid - 1)]);
                evaluate_on(path, kernel, &padded)
            }
        };
        for f in &values[..valid] {
            acc.add(*f);
        }
    })
    .ok()
}

/// The paper's Delta in the peer's frame.
pub(crate) fn peer_delta() -> Option<RotaryDelta> {
    RotaryDelta::new(presets::miller_delta(Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    }))
    .ok()
}

/// The peer's box, $2^{20}$ seeded points.
pub(crate) fn peer_points() -> Vec<Vector3<f64>> {
    let (lo, hi) = (
        Vector3::new(-0.2, -0.2, -0.65),
        Vector3::new(0.2, 0.2, -0.25),
    );
    let sampler = Sampler::MonteCarlo { seed: 20240601 };
    (0..1 << 20).map(|i| sampler.in_box(i, &lo, &hi)).collect()
}

/// The scalar kernel: IK, $J = -J_q^{-1}J_x$, closed-form $1/\kappa$.
pub(crate) fn delta_scalar(delta: &RotaryDelta, p: &Vector3<f64>) -> Option<f64> {
    let q = delta.inverse_kinematics(p, ElbowMode::Out).ok()?;
    let j = delta.jacobian(p, &q).ok()?;
    Some(inverse_condition_number_3x3(&j))
}

/// The batch kernel: $1/\kappa$ where the point is reachable (elbow out).
struct DeltaIndex(RotaryDelta);

impl LaneKernel for DeltaIndex {
    type Output = [Option<f64>; LANES];
    #[inline(always)]
    fn evaluate(&self, points: &[Vector3<f64>; LANES]) -> [Option<f64>; LANES] {
        inverse_condition_of_reachable_lanes(&self.0.jacobian_lanes(points, ElbowMode::Out))
    }
}

pub(crate) fn delta_kernel(c: &mut Criterion) {
    let Some(delta) = peer_delta() else {
        return;
    };
    let points = peer_points();
    let kernel = DeltaIndex(delta.clone());
    let mut group = c.benchmark_group("delta_kernel");
    group.sample_size(10);
    group.throughput(Throughput::Elements(points.len() as u64));
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return;
        };
        group.bench_function(format!("scalar/{threads}_threads"), |b| {
            b.iter(|| pool.install(|| scalar_sums(&points, |p| delta_scalar(&delta, p))))
        });
        let selected = VectorPath::selected();
        group.bench_function(format!("batch/{threads}_threads"), |b| {
            b.iter(|| pool.install(|| lane_sums(&points, &kernel, selected)))
        });
        if threads == 1 {
            group.bench_function("batch_baseline/1_threads", |b| {
                b.iter(|| pool.install(|| lane_sums(&points, &kernel, VectorPath::Baseline)))
            });
        }
    }
    group.finish();
}
