//! The generic entry points over the kinematics traits: local indices at a pose against closed
//! forms and finite differences, and GCI = η/W of the workspace estimators.
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use nalgebra::{Matrix3, SMatrix, Vector2, Vector3};
use pkm_mechanisms::{ThreeUpu, presets};
use pkm_traits::{
    ClosedChain, ConstrainedWorkspace, InverseKinematics, Joints, KinematicsError, Silent, Task,
};
use pkm_workspace_indices::{
    Domain, Plane, PointSet, Region, Sampler, Workspace, inverse_condition_at, local_indices,
};

/// Actuators that track scaled task coordinates, $q = Dx$ inside the unit ball:
/// $\Phi = q - Dx$, so $J_x = -D$, $J_q = I$ and $J = D$.
#[derive(Debug, Clone)]
struct Diagonal<const N: usize> {
    scales: [f64; N],
}

impl<const N: usize> ClosedChain<N, N> for Diagonal<N> {
    fn closure(&self, x: &Task<N>, q: &Joints<N>) -> Joints<N> {
        q - self.matrix() * x
    }
    fn jacobian_x(&self, _: &Task<N>, _: &Joints<N>) -> SMatrix<f64, N, N> {
        -self.matrix()
    }
    fn jacobian_q(&self, _: &Task<N>, _: &Joints<N>) -> SMatrix<f64, N, N> {
        SMatrix::identity()
    }
}

impl<const N: usize> InverseKinematics<N, N> for Diagonal<N> {
    type WorkingMode = ();
    fn inverse_kinematics(&self, x: &Task<N>, _: ()) -> Result<Joints<N>, KinematicsError> {
        if !(x.norm() <= 1.0) {
            return Err(KinematicsError::Unreachable {
                leg: 0,
                discriminant: 1.0 - x.norm(),
            });
        }
        Ok(self.matrix() * x)
    }
}

impl ConstrainedWorkspace<3, 3> for Diagonal<3> {
    fn name(&self) -> &'static str {
        "Diagonal"
    }
}

impl<const N: usize> Diagonal<N> {
    fn matrix(&self) -> SMatrix<f64, N, N> {
        SMatrix::from_diagonal(&self.scales.into())
    }
}

/// $\Phi = x_1 q - x$: $J_q = x_1 I$ vanishes on the plane $x_1 = 0$, an inverse-kinematic
/// singularity inside the reachable set.
#[derive(Debug, Clone)]
struct SingularOnAPlane;

impl ClosedChain<3, 3> for SingularOnAPlane {
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        q * x[0] - x
    }
    fn jacobian_x(&self, _: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        let mut j = -Matrix3::identity();
        j.set_column(0, &(j.column(0) + q));
        j
    }
    fn jacobian_q(&self, x: &Task<3>, _: &Joints<3>) -> Matrix3<f64> {
        Matrix3::identity() * x[0]
    }
}

impl InverseKinematics<3, 3> for SingularOnAPlane {
    type WorkingMode = ();
    fn inverse_kinematics(&self, x: &Task<3>, _: ()) -> Result<Joints<3>, KinematicsError> {
        // q = x / x₁ off the plane; on it only x = 0 closes, for every q: take q = 0.
        Ok(if x[0] == 0.0 {
            Joints::zeros()
        } else {
            x / x[0]
        })
    }
}

#[test]
fn local_indices_of_a_diagonal_jacobian_are_its_closed_forms() {
    let m = Diagonal {
        scales: [4.0, -2.0, 0.5],
    };
    let x = Vector3::new(0.1, 0.2, -0.3);
    let local = local_indices(&m, &x, ()).unwrap();
    // σ = |d_i|: σ_min = 0.5, σ_max = 4, 1/κ = 1/8, w = |det D| = 4.
    assert!((local.sigma_min - 0.5).abs() < 1e-15);
    assert!((local.sigma_max - 4.0).abs() < 1e-14);
    assert!((local.inverse_condition - 0.125).abs() < 1e-15);
    assert!((local.manipulability - 4.0).abs() < 1e-14);
    // The fast kernel (closed-form 3×3) agrees.
    assert!((inverse_condition_at(&m, &x, ()).unwrap() - 0.125).abs() < 1e-14);
    // Two dimensions go through the SVD.
    let planar = Diagonal { scales: [3.0, 1.0] };
    let x2 = Vector2::new(0.2, 0.1);
    assert!((inverse_condition_at(&planar, &x2, ()).unwrap() - 1.0 / 3.0).abs() < 1e-15);
    assert!((local_indices(&planar, &x2, ()).unwrap().manipulability - 3.0).abs() < 1e-14);
    // Outside the unit ball: the IK's error, typed.
    let far = Vector3::new(2.0, 0.0, 0.0);
    assert!(matches!(
        local_indices(&m, &far, ()),
        Err(KinematicsError::Unreachable { .. })
    ));
    assert!(inverse_condition_at(&m, &far, ()).is_err());
}

#[test]
fn local_indices_are_scale_invariant_where_they_should_be() {
    // Scaling J by 2^k scales σ and w (w by 2^{3k}) and leaves 1/κ, also past the range where
    // the SVD is run on a rescaled matrix.
    let base = local_indices(
        &Diagonal {
            scales: [4.0, -2.0, 0.5],
        },
        &Vector3::zeros(),
        (),
    )
    .unwrap();
    for k in [-300, -120, 120, 300] {
        let s = 2f64.powi(k);
        let m = Diagonal {
            scales: [4.0 * s, -2.0 * s, 0.5 * s],
        };
        match local_indices(&m, &Vector3::zeros(), ()) {
            Ok(l) => {
                assert_eq!(l.inverse_condition, base.inverse_condition, "k = {k}");
                assert!((l.sigma_max / s - base.sigma_max).abs() < 1e-14 * base.sigma_max);
                assert!(l.manipulability.is_finite());
            }
            // w = 4 · 2^{3k} overflows for k = 300: typed.
            Err(e) => assert!(
                k == 300 && matches!(e, KinematicsError::Singular { .. }),
                "{e}"
            ),
        }
    }
}

#[test]
fn at_an_inverse_kinematic_singularity_the_condition_index_is_its_limit_zero() {
    let m = SingularOnAPlane;
    let on_plane = Vector3::new(0.0, 0.0, 0.0);
    assert_eq!(inverse_condition_at(&m, &on_plane, ()).unwrap(), 0.0);
    assert!(matches!(
        local_indices(&m, &on_plane, ()),
        Err(KinematicsError::Singular { .. })
    ));
    // Off the plane J = −J_q⁻¹J_x is finite and so are the indices.
    let off = Vector3::new(0.5, 0.1, 0.2);
    let local = local_indices(&m, &off, ()).unwrap();
    assert!(local.manipulability > 0.0 && local.inverse_condition > 0.0);
}

/// The indices of the 3-UPU from its trait Jacobian against the SVD of a central-difference
/// Jacobian of its inverse kinematics, $\partial q / \partial x$.
#[test]
fn local_indices_of_the_three_upu_match_finite_differences() {
    let upu = ThreeUpu::new(presets::park_3upu()).unwrap();
    let h = 1e-5;
    let mut checked = 0;
    for p in [
        Vector3::new(0.0, 0.0, 50.0),
        Vector3::new(3.0, -4.0, 30.0),
        Vector3::new(-8.0, 2.0, 70.0),
        Vector3::new(1.0, 1.0, 5.0),
    ] {
        let mut j_fd = Matrix3::zeros();
        for k in 0..3 {
            let (mut plus, mut minus) = (p, p);
            plus[k] += h;
            minus[k] -= h;
            let column = (upu.inverse_kinematics(&plus, ()).unwrap()
                - upu.inverse_kinematics(&minus, ()).unwrap())
                / (2.0 * h);
            j_fd.set_column(k, &column);
        }
        let sigma = j_fd.singular_values();
        let local = local_indices(&upu, &p, ()).unwrap();
        assert!((local.sigma_min - sigma.min()).abs() < 1e-8, "{p}");
        assert!((local.sigma_max - sigma.max()).abs() < 1e-8, "{p}");
        assert!(
            (local.manipulability - j_fd.determinant().abs()).abs() < 1e-8,
            "{p}"
        );
        let fast = inverse_condition_at(&upu, &p, ()).unwrap();
        assert!((fast - sigma.min() / sigma.max()).abs() < 1e-8, "{p}");
        // The closed-form 3×3 kernel loses digits where two singular values coincide (the
        // symmetric home pose): 7e-9 there, 1e-11 elsewhere.
        assert!(
            (fast - local.inverse_condition).abs() < 2e-8,
            "{p}: {fast} vs {}",
            local.inverse_condition
        );
        checked += 1;
    }
    assert_eq!(checked, 4);
}

/// GCI = η/W: for a constant Jacobian the mean of 1/κ over the workspace is 1/κ itself, and
/// η = (1/κ) W, on any domain; both estimators return exactly η/W.
#[test]
fn gci_is_eta_over_the_volume() {
    let m = Diagonal {
        scales: [4.0, -2.0, 0.5],
    };
    let ws = Workspace::new(&m, &[()], &[]).unwrap();
    let domain = Domain::new(Region::Box {
        lower: Vector3::repeat(-1.0),
        upper: Vector3::repeat(1.0),
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 2 }, 1 << 12, 4).unwrap();
    let e = ws.volume_and_eta(&points, &Silent).unwrap();
    let (eta, gci) = (e.eta.unwrap(), e.gci().unwrap());
    assert_eq!(gci, eta / e.volume);
    assert!((gci - 0.125).abs() < 1e-14, "{gci}");
    // The unit ball: W = 4π/3 within the replicates' error.
    let ball = 4.0 * std::f64::consts::PI / 3.0;
    assert!((e.volume - ball).abs() < 5.0 * e.volume_se + 1e-3, "{e:?}");
    // The hemisphere path on scaled unit points.
    let unit = Sampler::Sobol { seed: 2 }
        .unit_hemisphere_points(1 << 12)
        .unwrap();
    let h = ws.hemisphere_estimate(&unit, 0.9, &Silent).unwrap();
    assert_eq!(h.gci().unwrap(), h.eta / h.volume);
    // The whole hemisphere of radius 0.9 lies in the unit ball: W is its volume exactly.
    assert!((h.volume - 2.0 * std::f64::consts::PI * 0.9_f64.powi(3) / 3.0).abs() < 1e-12);
    assert!((h.gci().unwrap() - 0.125).abs() < 1e-14);
    // An empty workspace has no GCI.
    let none = ws
        .hemisphere_estimate(
            &unit
                .iter()
                .map(|p| p + Vector3::new(0.0, 0.0, 5.0))
                .collect::<Vec<_>>(),
            1.0,
            &Silent,
        )
        .unwrap();
    assert_eq!(none.n_inside, 0);
    assert_eq!(none.gci(), None);
}

#[test]
fn a_slice_of_a_constant_index_is_the_index_inside_the_ball_on_every_plane() {
    let m = Diagonal {
        scales: [4.0, -2.0, 0.5],
    };
    let ws = Workspace::new(&m, &[()], &[]).unwrap();
    let bounds = Region::Ball {
        center: Vector3::zeros(),
        radius: 1.0,
    }
    .bounding_box();
    for plane in [Plane::Xy, Plane::Xz, Plane::Yz] {
        let slice = ws.inverse_condition_slice(plane, 0.5, &bounds, 8).unwrap();
        let mut inside = 0;
        for (k, v) in slice.values.iter().enumerate() {
            let (u, w) = (slice.u[k % 8], slice.v[k / 8]);
            let expected = (u * u + w * w + 0.25 <= 1.0).then_some(0.125);
            match (v, expected) {
                (Some(v), Some(e)) => {
                    assert!((v - e).abs() < 1e-14);
                    inside += 1;
                }
                (None, None) => {}
                _ => panic!("{plane:?} ({u}, {w}): {v:?} vs {expected:?}"),
            }
        }
        assert!(inside > 10, "vacuous: {inside}");
    }
}
