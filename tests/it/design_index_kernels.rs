//! The lane-parallel design-index kernels against the scalar ones, end to end (Jacobian and
//! $1/\kappa$), and the rotary Delta kernel against the NumPy peer.

use nalgebra::Vector3;
use pkm_mechanisms::{Elbow, ElbowMode, JacobianLanes, Placement, RotaryDelta, Tsai3Dof, presets};
use pkm_traits::{ClosedChain, InverseKinematics, Silent};
use pkm_workspace_indices::{
    Accumulator, LANES, Sampler, chunked_reduce, inverse_condition_at,
    inverse_condition_number_3x3, inverse_condition_number_3x3_lanes,
};

/// The paper's Delta in the frame of `shared/peers/numpy_delta_gci.py`: motors in the plane
/// $z = 0$, motor 1 at azimuth 0. The peer's radial $e_i$, motor axis $u_i$ and arm angle
/// ($B_i = Re_i + L_a(\cos\theta\,e_i - \sin\theta\,z)$) are pkm's $u_i$, $e_i$ and $\theta$
/// ($w_i = z$ for $\alpha = \beta = 0$), and its root $\operatorname{atan2}(B, A) +
/// \arccos(C/\rho)$ is pkm's [`ElbowMode::Out`] modulo $2\pi$.
fn peer_delta() -> RotaryDelta {
    RotaryDelta::new(presets::miller_delta(Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    }))
    .unwrap()
}

fn delta_scalar(m: &RotaryDelta, p: &Vector3<f64>) -> Option<f64> {
    let q = m.inverse_kinematics(p, ElbowMode::Out).ok()?;
    Some(inverse_condition_number_3x3(&m.jacobian(p, &q).ok()?))
}

fn masked<const N: usize>(j: &JacobianLanes<N>) -> [Option<f64>; N] {
    let r = inverse_condition_number_3x3_lanes(&j.jacobian);
    std::array::from_fn(|l| j.reachable[l].then_some(r[l]))
}

fn delta_lanes<const N: usize>(m: &RotaryDelta, p: &[Vector3<f64>; N]) -> [Option<f64>; N] {
    masked(&m.jacobian_lanes(p, ElbowMode::Out))
}

fn tsai_scalar(m: &Tsai3Dof, p: &Vector3<f64>) -> Option<f64> {
    inverse_condition_at(m, p, [Elbow::Out; 3]).ok()
}

/// The peer's box, seeded points, every 97th replaced by a non-finite or huge one.
fn box_points(n: u64) -> Vec<Vector3<f64>> {
    let (lo, hi) = (
        Vector3::new(-0.2, -0.2, -0.65),
        Vector3::new(0.2, 0.2, -0.25),
    );
    let bad = [f64::NAN, f64::INFINITY, -1e300, 1e155];
    (0..n)
        .map(|i| {
            let p = Sampler::MonteCarlo { seed: 3 }.in_box(i, &lo, &hi);
            if i % 97 == 5 {
                Vector3::new(p.x, bad[(i / 97) as usize % 4], p.z)
            } else {
                p
            }
        })
        .collect()
}

/// Compares batch with scalar per point: reachability must be identical and $1/\kappa$ within
/// $2\cdot10^{-11}$ absolute. Returns (reachable points, points whose relative difference
/// exceeds $10^{-12}$).
///
/// Both kernels round the Jacobian differently (by about $10^{-14}$ relative), and the
/// closed-form eigenvalues amplify that where two eigenvalues of $J^\top J$ nearly coincide
/// ($r \approx \pm1$, see `condition_3x3_lanes`), so a few points in a thousand differ by more
/// than $10^{-12}$ relative (worst seen $1.5\cdot10^{-9}$ relative, $7\cdot10^{-12}$ absolute).
fn compare(
    points: &[Vector3<f64>],
    scalar: impl Fn(&Vector3<f64>) -> Option<f64>,
    batch: impl Fn(&[Vector3<f64>; LANES]) -> [Option<f64>; LANES],
) -> (usize, usize) {
    let (mut reachable, mut loose) = (0, 0);
    for group in points.chunks_exact(LANES) {
        let lanes: [Vector3<f64>; LANES] = std::array::from_fn(|l| group[l]);
        for (p, got) in group.iter().zip(batch(&lanes)) {
            match (got, scalar(p)) {
                (Some(g), Some(w)) => {
                    reachable += 1;
                    assert!((0.0..=1.0).contains(&g), "{p}: {g}");
                    assert!((g - w).abs() <= 2e-11, "{p}: {g} vs {w}");
                    if (g - w).abs() > 1e-12 * w {
                        loose += 1;
                    }
                }
                (None, None) => {}
                (got, want) => panic!("{p}: reachability differs, batch {got:?} scalar {want:?}"),
            }
        }
    }
    (reachable, loose)
}

#[test]
fn delta_batch_kernel_equals_the_scalar_kernel_per_point() {
    let m = peer_delta();
    let points = box_points(40_000);
    let (reachable, loose) = compare(&points, |p| delta_scalar(&m, p), |p| delta_lanes(&m, p));
    assert!(reachable > 20_000, "vacuous: {reachable} reachable");
    assert!(
        loose * 200 <= reachable,
        "{loose} of {reachable} beyond 1e-12 relative"
    );
}

#[test]
fn tsai_batch_kernel_equals_the_scalar_kernel_per_point() {
    let m = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    let points: Vec<Vector3<f64>> = Sampler::MonteCarlo { seed: 4 }
        .unit_hemisphere_points(40_000)
        .unwrap()
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            if i % 101 == 7 {
                p * 1e300
            } else {
                p * m.reach()
            }
        })
        .collect();
    let (reachable, loose) = compare(
        &points,
        |p| tsai_scalar(&m, p),
        |p| masked(&m.velocity_jacobian_elbow_out_lanes(p)),
    );
    assert!(reachable > 10_000, "vacuous: {reachable} reachable");
    assert!(
        loose * 200 <= reachable,
        "{loose} of {reachable} beyond 1e-12 relative"
    );
}

/// $1/\kappa$ of the peer (`jacobian_stack` + `index_svd` of `numpy_delta_gci.py`, NumPy 2.4)
/// at six points of its box, against pkm's batch kernel at the same points.
#[test]
fn delta_batch_kernel_matches_the_numpy_peer() {
    let peer = [
        ([0.0, 0.0, -0.4], 0.9947245885512813),
        ([0.05, -0.02, -0.5], 0.734198523773309),
        ([-0.15, 0.1, -0.3], 0.6006360343607399),
        ([0.12, 0.18, -0.6], 0.31137679486691205),
        ([0.0, 0.0, -0.64], 0.4677321181094082),
        ([0.19, -0.19, -0.26], 0.46982661455713354),
    ];
    let m = peer_delta();
    for pair in peer.chunks_exact(2) {
        let pts = [0, 1, 0, 1].map(|k| Vector3::from(pair[k].0));
        let got = delta_lanes(&m, &pts);
        for (g, (p, want)) in got.iter().zip(pair.iter().cycle()) {
            let g = g.unwrap();
            assert!((g - want).abs() <= 1e-10, "{p:?}: pkm {g} peer {want}");
        }
    }
}

#[test]
fn lane_position_and_count_do_not_change_the_bits() {
    let m = peer_delta();
    let points = box_points(64);
    let bits = |r: Option<f64>| r.map(f64::to_bits);
    for (k, group) in points.chunks_exact(8).enumerate() {
        let eight: [Vector3<f64>; 8] = std::array::from_fn(|l| group[(l + k) % 8]);
        let wide = delta_lanes(&m, &eight);
        for (l, p) in eight.iter().enumerate() {
            let one = delta_lanes(&m, &[*p]);
            let four = delta_lanes(&m, &[eight[(l + 1) % 8], eight[(l + 2) % 8], *p, *p]);
            assert_eq!(bits(one[0]), bits(wide[l]));
            assert_eq!(bits(four[2]), bits(wide[l]));
        }
    }
}

#[derive(Default)]
struct Sums(u64, f64);

impl Accumulator for Sums {
    fn merge(&mut self, later: Self) {
        self.0 += later.0;
        self.1 += later.1;
    }
}

#[test]
fn batch_sums_are_bit_identical_for_1_2_8_threads() {
    let m = peer_delta();
    let points = box_points(50_000);
    let groups = (points.len() / LANES) as u64;
    let run = || {
        let s = chunked_reduce(groups, &Silent, |acc: &mut Sums, g| {
            let lanes: [Vector3<f64>; LANES] =
                std::array::from_fn(|l| points[g as usize * LANES + l]);
            for f in delta_lanes(&m, &lanes).into_iter().flatten() {
                acc.0 += 1;
                acc.1 += f;
            }
        })
        .unwrap();
        (s.0, s.1.to_bits())
    };
    let runs: Vec<(u64, u64)> = [1, 2, 8]
        .into_iter()
        .map(|k| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(k)
                .build()
                .unwrap();
            pool.install(run)
        })
        .collect();
    assert!(runs[0].0 > 0, "vacuous");
    assert_eq!(runs[0], runs[1]);
    assert_eq!(runs[0], runs[2]);
}
