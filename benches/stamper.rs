//! Points per second of the GCI kernel (IK + Jacobian of eq. 7 + closed-form 1/κ per point),
//! on one core and on two; scalar (through `Workspace::hemisphere_estimate`, the generic entry
//! point) and lane-parallel.

use crate::delta_kernel::lane_sums;
use criterion::{Criterion, Throughput};
use pkm::mechanisms::{Elbow, Tsai3Dof, presets};
use pkm::workspace_indices::{Sampler, Workspace, inverse_condition_number_3x3_lanes};
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
    }
    group.finish();
}

/// The same kernel lane-parallel ([`Tsai3Dof::velocity_jacobian_elbow_out_lanes`] and
/// `inverse_condition_number_3x3_lanes`), same points, same sums.
pub(crate) fn gci_kernel_batch(c: &mut Criterion) {
    let Ok(design) = Tsai3Dof::new(presets::stamper_max_gci()) else {
        return;
    };
    let Ok(points) = (Sampler::MonteCarlo { seed: 1 }).unit_hemisphere_points(1 << 20) else {
        return;
    };
    let radius = design.reach();
    let mut group = c.benchmark_group("stamper/gci_kernel_batch");
    group.sample_size(10);
    group.throughput(Throughput::Elements(points.len() as u64));
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return;
        };
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| {
                pool.install(|| {
                    lane_sums(&points, |unit| {
                        let j = design.velocity_jacobian_elbow_out_lanes(&unit.map(|p| p * radius));
                        let r = inverse_condition_number_3x3_lanes(&j.jacobian);
                        std::array::from_fn(|l| j.reachable[l].then_some(r[l]))
                    })
                })
            })
        });
    }
    group.finish();
}
