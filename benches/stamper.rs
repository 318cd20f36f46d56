//! Points per second of the GCI kernel (IK + Jacobian of eq. 7 + closed-form 1/κ per point),
//! on one core and on two: through `Workspace::hemisphere_estimate`, the generic entry point
//! (the lane kernels since they were wired into the estimators), the same estimator asked point
//! by point (`point_by_point_*`), and the bare lane kernels (`gci_kernel_batch`).

use crate::delta_kernel::lane_sums;
use criterion::{Criterion, Throughput};
use nalgebra::Vector3;
use pkm::mechanisms::{Elbow, Tsai3Dof, presets};
use pkm::workspace_indices::{
    LANES, LaneKernel, Sampler, VectorPath, Workspace, hemisphere_estimate,
    inverse_condition_of_reachable_lanes,
};
use pkm_traits::Silent;

pub(crate) fn gci_kernel(c: &mut Criterion) {
    let Ok(design) = Tsai3Dof::new(presets::stamper_max_gci()) else {
        return;
    };
    let Ok(points) = (Sampler::MonteCarlo { seed: 1 }).unit_hemisphere_points(1 << 20) else {
        return;
    };
    let Ok(workspace) = Workspace::new(&design, &[[Elbow::Out; 3]], &[]) else {
        return;
    };
    let mut group = c.benchmark_group("stamper/gci_kernel");
    group.sample_size(10);
    group.throughput(Throughput::Elements(points.len() as u64));
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return;
        };
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| {
                pool.install(|| workspace.hemisphere_estimate(&points, design.reach(), &Silent))
            })
        });
        let one_by_one = |x: &Vector3<f64>| workspace.inverse_condition(x);
        group.bench_function(format!("point_by_point_{threads}_threads"), |b| {
            b.iter(|| {
                pool.install(|| hemisphere_estimate(&points, design.reach(), &Silent, one_by_one))
            })
        });
    }
    group.finish();
}

/// The same kernel lane-parallel ([`Tsai3Dof::velocity_jacobian_elbow_out_lanes`] and
/// `inverse_condition_of_reachable_lanes`) on unit-hemisphere points scaled by `radius`.
struct TsaiIndex {
    design: Tsai3Dof,
    radius: f64,
}

impl LaneKernel for TsaiIndex {
    type Output = [Option<f64>; LANES];
    #[inline(always)]
    fn evaluate(&self, unit: &[Vector3<f64>; LANES]) -> [Option<f64>; LANES] {
        let scaled = unit.map(|p| p * self.radius);
        inverse_condition_of_reachable_lanes(
            &self.design.velocity_jacobian_elbow_out_lanes(&scaled),
        )
    }
}

/// [`TsaiIndex`] over the same points as [`gci_kernel`], same sums, on the vector path
/// selected at run time (`*_threads`) and on the baseline (`baseline_1_threads`).
pub(crate) fn gci_kernel_batch(c: &mut Criterion) {
    let Ok(design) = Tsai3Dof::new(presets::stamper_max_gci()) else {
        return;
    };
    let Ok(points) = (Sampler::MonteCarlo { seed: 1 }).unit_hemisphere_points(1 << 20) else {
        return;
    };
    let radius = design.reach();
    let kernel = TsaiIndex { design, radius };
    let mut group = c.benchmark_group("stamper/gci_kernel_batch");
    group.sample_size(10);
    group.throughput(Throughput::Elements(points.len() as u64));
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return;
        };
        let selected = VectorPath::selected();
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| pool.install(|| lane_sums(&points, &kernel, selected)))
        });
        if threads == 1 {
            group.bench_function("baseline_1_threads", |b| {
                b.iter(|| pool.install(|| lane_sums(&points, &kernel, VectorPath::Baseline)))
            });
        }
    }
    group.finish();
}
