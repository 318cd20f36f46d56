//! The six mechanisms through the one generic path of `examples/six_mechanisms.rs` (the traits of
//! `pkm-traits`, `local_indices`, `Workspace`), each result checked against an independent
//! computation: the forward kinematics against the pose it started from, the velocity Jacobian
//! against central differences of the inverse kinematics, the local indices against the SVD of
//! that finite-difference Jacobian, and the Tsai volume against its deterministic column
//! integral.

use nalgebra::{SMatrix, Vector3, Vector6};
use pkm_mechanisms::{
    Elbow, ElbowMode, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios,
    Placement, RotaryDelta, StewartGough, ThreeUpu, Tsai3Dof, presets,
};
use pkm_traits::{ForwardKinematics, InverseKinematics, NewtonSettings, Silent, Task};
use pkm_workspace_indices::{
    Dim, Domain, FixedSvd, PointSet, Region, Sampler, Workspace, local_indices,
};

/// $(q(x + h e_j) - q(x - h e_j)) / 2h$ for every column $j$.
fn central_difference_jacobian<M, const N: usize>(
    mechanism: &M,
    mode: M::WorkingMode,
    x: &Task<N>,
    h: f64,
) -> SMatrix<f64, N, N>
where
    M: InverseKinematics<N, N>,
{
    let mut j = SMatrix::<f64, N, N>::zeros();
    for k in 0..N {
        let mut step = Task::<N>::zeros();
        step[k] = h;
        let forward = mechanism.inverse_kinematics(&(x + step), mode).unwrap();
        let backward = mechanism.inverse_kinematics(&(x - step), mode).unwrap();
        j.set_column(k, &((forward - backward) / (2.0 * h)));
    }
    j
}

/// IK → FK round trip, `velocity_jacobian_at` against central differences (step `length`·1e-6,
/// `length` the mechanism's size) and `local_indices` against the SVD of the difference
/// Jacobian, all at `x` in `mode`.
fn check_kinematics<M, const N: usize>(
    name: &str,
    mechanism: &M,
    mode: M::WorkingMode,
    x: &Task<N>,
    length: f64,
) where
    M: InverseKinematics<N, N> + ForwardKinematics<N>,
    Dim<N>: FixedSvd<N>,
{
    let q = mechanism.inverse_kinematics(x, mode).unwrap();
    let guess = x + x.map(|v| 0.01 * v);
    let x_fk = mechanism
        .forward_kinematics(&q, &guess, &NewtonSettings::default())
        .unwrap();
    let round_trip = (x_fk - x).amax();
    assert!(round_trip < 1e-9, "{name}: |x_fk - x| = {round_trip:e}");

    let j = mechanism.velocity_jacobian_at(x, mode).unwrap();
    let j_fd = central_difference_jacobian(mechanism, mode, x, 1e-6 * length);
    let relative = (j - j_fd).amax() / j_fd.amax();
    assert!(
        relative < 1e-6,
        "{name}: |J - J_fd| / |J_fd| = {relative:e}"
    );

    let sigma = <Dim<N> as FixedSvd<N>>::singular_values(&j_fd);
    let (sigma_min, sigma_max) = (sigma.min(), sigma.max());
    let local = local_indices(mechanism, x, mode).unwrap();
    let checks = [
        ("1/κ", local.inverse_condition, sigma_min / sigma_max),
        ("σ_min", local.sigma_min, sigma_min),
        ("σ_max", local.sigma_max, sigma_max),
        ("manipulability", local.manipulability, sigma.product()),
    ];
    for (what, value, expected) in checks {
        let error = (value / expected - 1.0).abs();
        assert!(
            error < 1e-6,
            "{name}: {what} = {value}, SVD of J_fd {expected} (relative error {error:e})"
        );
    }
}

#[test]
fn six_mechanisms_kinematics_and_local_indices_match_finite_differences() {
    let placement = Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    };
    let delta_pose = Vector3::new(0.05, -0.02, -0.5);
    let delta = RotaryDelta::new(presets::miller_delta(placement)).unwrap();
    check_kinematics("Delta", &delta, ElbowMode::Out, &delta_pose, 1.0);
    let nuwar = RotaryDelta::new(presets::nuwar(placement)).unwrap();
    check_kinematics("NUWAR", &nuwar, ElbowMode::Out, &delta_pose, 1.0);

    let ratios = LinearDeltaRatios {
        l1_over_yr: 2.0,
        ya_over_yr: 0.0,
        zr_over_yr: 0.0,
        l2_over_l1: 0.63,
    };
    let linear = LinearDelta::new(LinearDeltaDesign { ratios, yr: 0.1 }).unwrap();
    let linear_pose = Vector3::new(0.05, 0.02, -0.08);
    check_kinematics(
        "Linear Delta",
        &linear,
        LinearDeltaMode::PAPER,
        &linear_pose,
        0.1,
    );

    let tsai = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let tsai_pose = Vector3::new(0.1, -0.05, 0.5);
    check_kinematics("Tsai", &tsai, [Elbow::Out; 3], &tsai_pose, 1.0);

    let upu = ThreeUpu::new(presets::park_3upu()).unwrap();
    check_kinematics("3-UPU", &upu, (), &Vector3::new(1.0, -2.0, 50.0), 50.0);

    let stewart = StewartGough::new(presets::wolf_shoham_stewart_s4_1()).unwrap();
    let stewart_pose = Vector6::new(1.0, -2.0, 40.0, 0.05, -0.03, 0.1);
    check_kinematics("Stewart–Gough", &stewart, (), &stewart_pose, 40.0);
}

#[test]
fn six_mechanisms_tsai_volume_through_the_generic_path_matches_the_column_integral() {
    let tsai = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let hemisphere = Region::Hemisphere {
        center: Vector3::zeros(),
        radius: tsai.reach(),
    };
    let points = PointSet::new(
        Domain::new(hemisphere).unwrap(),
        Sampler::Sobol { seed: 3 },
        4096,
        8,
    )
    .unwrap();
    let estimate = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[])
        .unwrap()
        .volume(&points, &Silent)
        .unwrap();
    let columns = tsai.column_volume(1000).unwrap();
    let deviation = (estimate.volume - columns).abs();
    assert!(
        estimate.volume_se > 0.0
            && estimate.volume_se < 0.01 * columns
            && deviation < 4.0 * estimate.volume_se,
        "W = {} ± {} against the column integral {columns}",
        estimate.volume,
        estimate.volume_se
    );
}
