//! Points per second of the §2.1 membership kernel (NUWAR, plate below the motors, every leg
//! reachable: `Workspace::volume`, which counts through the lane test
//! `RotaryDelta::reachable_in_any_lanes`), on one core and on two, and point by point
//! (`Workspace::contains` through the trigonometry-free `RotaryDelta::reachable`); and of one
//! row of the (α, β) sweep (`sweep_workspace_volumes`, and `sweep_volumes` point by point).

use criterion::{Criterion, Throughput};
use nalgebra::Vector3;
use pkm::mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
use pkm::workspace_indices::{
    Domain, PointSet, Region, Sampler, Workspace, sweep_volumes, sweep_workspace_volumes,
    workspace_volume,
};
use pkm_traits::{Silent, WorkspaceConstraint};

fn study_placement() -> Placement {
    Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    }
}

fn sector_points(n: u64) -> Option<PointSet> {
    let region = Region::axial_cylinder(0.904, -0.74, 0.0);
    let domain = Domain::new(region).ok()?.with_sector(3, 0.0).ok()?;
    PointSet::new(domain, Sampler::Sobol { seed: 1 }, n / 4, 4).ok()
}

pub(crate) fn membership_kernel(c: &mut Criterion) {
    let (Ok(nuwar), Ok(below), Some(points)) = (
        RotaryDelta::new(presets::nuwar(study_placement())),
        WorkspaceConstraint::below(0.0),
        sector_points(1 << 20),
    ) else {
        return;
    };
    let Ok(workspace) = Workspace::new(&nuwar, &[ElbowMode::Out, ElbowMode::In], &[below]) else {
        return;
    };
    let mut group = c.benchmark_group("workspace/membership");
    group.sample_size(10);
    group.throughput(Throughput::Elements(points.points().len() as u64));
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return;
        };
        group.bench_function(format!("{threads}_threads"), |b| {
            b.iter(|| pool.install(|| workspace.volume(&points, &Silent)))
        });
        let one_by_one = |x: &Vector3<f64>| workspace.contains(x);
        group.bench_function(format!("point_by_point_{threads}_threads"), |b| {
            b.iter(|| pool.install(|| workspace_volume(&points, &Silent, one_by_one)))
        });
    }
    group.finish();

    // One α-row of the sweep: 91 designs (β = 0..90°) on 4 × 25,000 common points.
    let Some(points) = sector_points(100_000) else {
        return;
    };
    let designs: Vec<RotaryDelta> = (0..=90)
        .filter_map(|b| {
            RotaryDelta::new(presets::miller_prototype(
                0.6,
                f64::from(b).to_radians(),
                study_placement(),
            ))
            .ok()
        })
        .collect();
    let workspaces: Vec<_> = designs
        .iter()
        .filter_map(|d| Workspace::new(d, &[ElbowMode::Out, ElbowMode::In], &[below]).ok())
        .collect();
    let mut group = c.benchmark_group("workspace/sweep_row");
    group.sample_size(10);
    group.throughput(Throughput::Elements(
        workspaces.len() as u64 * points.points().len() as u64,
    ));
    for threads in [1, 2] {
        let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(threads).build() else {
            return;
        };
        group.bench_function(format!("91_designs_{threads}_threads"), |b| {
            b.iter(|| pool.install(|| sweep_workspace_volumes(&workspaces, &points, &Silent)))
        });
        group.bench_function(
            format!("91_designs_point_by_point_{threads}_threads"),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        sweep_volumes(&workspaces, &points, &Silent, |w, x| w.contains(x))
                    })
                })
            },
        );
    }
    group.finish();
}
