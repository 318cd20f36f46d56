//! Points per second of the GCI kernel (IK + Jacobian of eq. 7 + closed-form 1/κ per point),
//! on one core and on two; scalar (through `hemisphere_estimate`) and lane-parallel.

use crate::delta_kernel::lane_sums;
use criterion::{Criterion, Throughput};
use pkm::mechanisms::{Tsai3Dof, presets};
use pkm::workspace_indices::{
    Sampler, hemisphere_estimate, inverse_condition_number_3x3, inverse_condition_number_3x3_lanes,
};
use pkm_traits::Silent;

pub(crate) fn gci_kernel(c: &mut Criterion) {
    let Ok(design) = Tsai3Dof::new(presets::stamper_max_gci()) else {
        return;
    };
    let Ok(points) = (Sampler::MonteCarlo { seed: 1 }).unit_hemisphere_points(1 << 20) else {
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
                pool.install(|| {
                    hemisphere_estimate(&points, design.reach(), &Silent, |p| {
                        design
                            .jacobian_eq7(p)
                            .map(|j| inverse_condition_number_3x3(&j))
                    })
                })
            })
        });
    }
    group.finish();
}

/// The same kernel lane-parallel ([`Tsai3Dof::jacobian_eq7_lanes`] and
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
                        let j = design.jacobian_eq7_lanes(&unit.map(|p| p * radius));
                        let r = inverse_condition_number_3x3_lanes(&j.jacobian);
                        std::array::from_fn(|l| j.reachable[l].then_some(r[l]))
                    })
                })
            })
        });
    }
    group.finish();
}
