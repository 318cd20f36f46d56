//! The estimators on the lane kernels against the same estimators point by point: the volume
//! counts (`Workspace::count_inside`, `Workspace::volume`, `sweep_workspace_volumes`) are the
//! point test's, exactly, whatever the constraints, the vector path and the thread count;
//! $1/\kappa$ and the estimates built on it (`volume_and_eta`, `hemisphere_estimate`) agree to
//! rounding.

use nalgebra::Vector3;
use pkm_mechanisms::{Elbow, ElbowMode, Placement, RotaryDelta, Tsai3Dof, presets};
use pkm_traits::{ConstrainedWorkspace, Lanes, Silent, WorkspaceConstraint};
use pkm_workspace_indices::{
    BlockKernel, Domain, LANES, PointSet, Region, Sampler, VectorPath, Workspace,
    hemisphere_estimate, run_block_on, sweep_volumes, sweep_workspace_volumes, workspace_volume,
    workspace_volume_and_eta,
};

fn nuwar() -> RotaryDelta {
    RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap()
}

/// A sector of the cylinder that holds the NUWAR's workspace, in 2 replicates.
fn sector_points(per_replicate: u64) -> PointSet {
    let region = Region::axial_cylinder(0.9, -1.3, 0.3);
    let domain = Domain::new(region).unwrap().with_sector(3, 0.0).unwrap();
    PointSet::new(domain, Sampler::Sobol { seed: 11 }, per_replicate, 2).unwrap()
}

/// `f` on a pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(f)
}

/// Every constraint kind the Delta evaluates, alone and together.
fn constraint_sets() -> Vec<Vec<WorkspaceConstraint>> {
    let below = WorkspaceConstraint::below(0.0).unwrap();
    let range = WorkspaceConstraint::joint_range(-1.0, 1.4).unwrap();
    let cone = WorkspaceConstraint::passive_cone(0.6).unwrap();
    let clearance = WorkspaceConstraint::leg_clearance(0.05).unwrap();
    vec![
        vec![],
        vec![below],
        vec![below, range],
        vec![below, cone],
        vec![clearance],
        vec![range, cone, clearance],
    ]
}

#[test]
fn counts_are_the_point_tests_for_every_constraint_and_mode_set() {
    let m = nuwar();
    let mut points = sector_points(3001).points().to_vec();
    points.extend(crate::lane_kernels::hostile());
    for constraints in constraint_sets() {
        let mut inside = 0;
        for modes in [
            &[ElbowMode::Out][..],
            &[ElbowMode::In],
            &[ElbowMode::In, ElbowMode::Out],
        ] {
            let ws = Workspace::new(&m, modes, &constraints).unwrap();
            let one_by_one = points.iter().filter(|x| ws.contains(x)).count() as u64;
            assert_eq!(
                ws.count_inside(&points),
                one_by_one,
                "{constraints:?} {modes:?}"
            );
            inside += one_by_one;
        }
        assert!(
            inside > 100,
            "{constraints:?}: an empty workspace tests nothing"
        );
    }
}

#[test]
fn volumes_and_sweeps_are_bit_identical_to_the_point_by_point_estimators() {
    let m = nuwar();
    let other = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    let points = sector_points(2500);
    for constraints in constraint_sets() {
        let modes = [ElbowMode::Out, ElbowMode::In];
        let ws = [
            Workspace::new(&m, &modes, &constraints).unwrap(),
            Workspace::new(&other, &modes, &constraints).unwrap(),
        ];
        let slow = workspace_volume(&points, &Silent, |x| ws[0].contains(x)).unwrap();
        assert_eq!(
            ws[0].volume(&points, &Silent).unwrap(),
            slow,
            "{constraints:?}"
        );
        let sweep = sweep_workspace_volumes(&ws, &points, &Silent).unwrap();
        assert_eq!(
            sweep,
            sweep_volumes(&ws, &points, &Silent, |w, x| w.contains(x)).unwrap()
        );
        assert_eq!(sweep[0], slow);
        for threads in [1, 2] {
            let again = on_threads(threads, || sweep_workspace_volumes(&ws, &points, &Silent));
            assert_eq!(again.unwrap(), sweep);
        }
    }
}

/// The Delta's lane reachability over groups of points, as one block kernel.
struct Reachability<'a>(&'a RotaryDelta, &'a [[Lanes<LANES>; 3]]);

impl BlockKernel for Reachability<'_> {
    type Output = Vec<bool>;
    #[inline(always)]
    fn run(&self) -> Vec<bool> {
        let modes = [ElbowMode::Out];
        self.1
            .iter()
            .flat_map(|g| self.0.reachable_in_any_lanes(g, &modes))
            .collect()
    }
}

#[test]
fn the_lane_reachability_is_the_point_test_on_every_vector_path() {
    let m = nuwar();
    let mut points = sector_points(4000).points().to_vec();
    points.extend(crate::lane_kernels::hostile());
    points.truncate(points.len() / LANES * LANES);
    let groups: Vec<[Lanes<LANES>; 3]> = points
        .chunks_exact(LANES)
        .map(|c| Lanes::coordinates(&std::array::from_fn(|l| c[l])))
        .collect();
    let want: Vec<bool> = points
        .iter()
        .map(|p| m.reachable(p, ElbowMode::Out))
        .collect();
    for path in VectorPath::available() {
        assert_eq!(
            run_block_on(path, &Reachability(&m, &groups)),
            want,
            "{path:?}"
        );
    }
}

/// Lanes and points agree on membership except within `band` of the boundary, and on $1/\kappa$
/// to `tolerance`; returns how many points were inside.
fn lanes_agree<M>(ws: &Workspace<'_, M>, points: &[Vector3<f64>], tolerance: f64) -> usize
where
    M: ConstrainedWorkspace<3, 3> + Sync,
{
    let mut inside = 0;
    for chunk in points.chunks_exact(LANES) {
        let group: [Vector3<f64>; LANES] = std::array::from_fn(|l| chunk[l]);
        for (x, lane) in group.iter().zip(ws.inverse_condition_lanes(&group)) {
            let one = ws.inverse_condition(x);
            assert_eq!(lane.is_some(), one.is_some(), "membership at {x:?}");
            if let (Some(a), Some(b)) = (lane, one) {
                assert!((a - b).abs() <= tolerance, "1/κ at {x:?}: {a} vs {b}");
                inside += 1;
            }
        }
    }
    inside
}

#[test]
fn lane_inverse_condition_agrees_with_the_point_by_point_one() {
    let m = nuwar();
    let points = sector_points(3000).points().to_vec();
    for modes in [&[ElbowMode::Out][..], &[ElbowMode::In, ElbowMode::Out]] {
        let ws = Workspace::new(&m, modes, &[WorkspaceConstraint::below(0.0).unwrap()]).unwrap();
        let inside = lanes_agree(&ws, &points, 1e-9);
        assert!(inside > 300, "{inside}");
    }
    let tsai = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let unit = Sampler::Sobol { seed: 3 }
        .unit_hemisphere_points(6000)
        .unwrap();
    let points: Vec<_> = unit.iter().map(|p| p * tsai.reach()).collect();
    let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
    let inside = lanes_agree(&ws, &points, 1e-9);
    assert!(inside > 500, "{inside}");
    // A mode without a lane kernel, and a constraint on the joints: point by point, exactly.
    let ws = Workspace::new(&tsai, &[[Elbow::In; 3], [Elbow::Out; 3]], &[]).unwrap();
    lanes_agree(&ws, &points, 0.0);
    let range = WorkspaceConstraint::joint_range(-3.0, 3.0).unwrap();
    let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[range]).unwrap();
    lanes_agree(&ws, &points, 0.0);
}

#[test]
fn eta_estimates_on_lanes_agree_with_the_point_by_point_ones_to_rounding() {
    let tsai = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[]).unwrap();
    let unit = Sampler::Sobol { seed: 5 }
        .unit_hemisphere_points(20_000)
        .unwrap();
    let lanes = ws
        .hemisphere_estimate(&unit, tsai.reach(), &Silent)
        .unwrap();
    let slow =
        hemisphere_estimate(&unit, tsai.reach(), &Silent, |x| ws.inverse_condition(x)).unwrap();
    assert_eq!((lanes.n_inside, lanes.volume), (slow.n_inside, slow.volume));
    assert!(
        (lanes.eta / slow.eta - 1.0).abs() < 1e-12,
        "{} vs {}",
        lanes.eta,
        slow.eta
    );
    let m = nuwar();
    let ws = Workspace::new(
        &m,
        &[ElbowMode::Out],
        &[WorkspaceConstraint::below(0.0).unwrap()],
    )
    .unwrap();
    let points = sector_points(4000);
    let lanes = ws.volume_and_eta(&points, &Silent).unwrap();
    let slow = workspace_volume_and_eta(&points, &Silent, |x| ws.inverse_condition(x)).unwrap();
    assert_eq!(lanes.n_inside, slow.n_inside);
    let (a, b) = (lanes.eta.unwrap(), slow.eta.unwrap());
    assert!((a / b - 1.0).abs() < 1e-12, "{a} vs {b}");
    for threads in [1, 2] {
        let again = on_threads(threads, || ws.volume_and_eta(&points, &Silent));
        assert_eq!(again.unwrap(), lanes);
    }
}
