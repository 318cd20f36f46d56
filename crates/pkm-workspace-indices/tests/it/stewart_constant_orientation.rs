//! The constant-orientation workspace of a Stewart–Gough platform ([`ConstantOrientation`],
//! six legs, three task coordinates) through the generic [`Workspace`], against a membership
//! test and a Jacobian written here directly from the leg vectors $p + R r_i - b_i$, and
//! against the closed-form volume of a spherical shell.
#![allow(clippy::unwrap_used)]

use nalgebra::{SMatrix, Vector3};
use pkm_mechanisms::{ConstantOrientation, StewartDesign, StewartGough, pose_from_task};
use pkm_traits::{Silent, Task, WorkspaceConstraint};
use pkm_workspace_indices::{
    Domain, PointSet, Region, Sampler, Workspace, inverse_condition_number_tall,
};
use std::f64::consts::PI;

const Q_MIN: f64 = 0.45;
const Q_MAX: f64 = 0.65;

fn view(design: StewartDesign, w: Vector3<f64>) -> ConstantOrientation {
    ConstantOrientation::new(StewartGough::new(design).unwrap(), w).unwrap()
}

/// The leg vectors $p + R r_i - b_i$ from the platform's own joints and pose.
fn legs(v: &ConstantOrientation, p: &Vector3<f64>) -> [Vector3<f64>; 6] {
    let w = v.rotation_vector();
    let pose = pose_from_task(&Task::<6>::new(p.x, p.y, p.z, w.x, w.y, w.z)).unwrap();
    v.platform().leg_vectors(&pose)
}

#[test]
fn workspace_membership_and_condition_match_a_direct_computation() {
    let v = view(
        StewartDesign::from_deg(0.3, 0.2, 20.0, 35.0),
        Vector3::new(0.0, 0.1, 0.2),
    );
    let above = WorkspaceConstraint::half_space(-Vector3::z(), -0.3).unwrap();
    let lengths = WorkspaceConstraint::joint_range(Q_MIN, Q_MAX).unwrap();
    let ws = Workspace::new(&v, &[()], &[above, lengths]).unwrap();
    let domain = Domain::new(Region::Box {
        lower: Vector3::new(-0.4, -0.4, 0.0),
        upper: Vector3::new(0.4, 0.4, 0.8),
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 3 }, 4096, 2).unwrap();
    let e = ws.volume_and_eta(&points, &Silent).unwrap();

    let mut inside = 0_u64;
    let mut eta_sum = 0.0;
    for p in points.points() {
        let l = legs(&v, p);
        let member = p.z >= 0.3 && l.iter().all(|v| (Q_MIN..=Q_MAX).contains(&v.norm()));
        assert_eq!(ws.contains(p), member, "{p}");
        let Some(r) = ws.inverse_condition(p) else {
            assert!(!member);
            continue;
        };
        inside += 1;
        // 1/κ = σ3/σ1 of the 6×3 J with rows s_i, from the eigenvalues of JᵀJ.
        let j = SMatrix::<f64, 6, 3>::from_fn(|i, k| l[i][k] / l[i].norm());
        let eig = (j.transpose() * j).symmetric_eigenvalues();
        let expected = (eig.min() / eig.max()).sqrt();
        assert!((r - expected).abs() < 1e-9, "{r} vs {expected}");
        assert!((inverse_condition_number_tall(&j) - r).abs() < 1e-15);
        eta_sum += r;
    }
    assert_eq!(e.n_inside, inside);
    assert!(inside > 200, "the test box cuts the workspace: {inside}");
    let box_volume = 0.8 * 0.8 * 0.8;
    let n = points.points().len() as f64;
    assert!((e.volume - box_volume * inside as f64 / n).abs() < 1e-12);
    assert!((e.eta.unwrap() - box_volume * eta_sum / n).abs() < 1e-9);
}

#[test]
fn concentric_legs_give_a_spherical_shell() {
    // Equal radii and separations at R = I: every c_i = b_i - r_i is the origin, so the
    // workspace above z = 0 is the half shell Q_MIN ≤ |p| ≤ Q_MAX, volume 2π/3 (Q_MAX³ − Q_MIN³).
    let v = view(
        StewartDesign::from_deg(0.25, 0.25, 30.0, 30.0),
        Vector3::zeros(),
    );
    assert!(v.shell_centres().iter().all(|c| c.amax() < 1e-15));
    let above = WorkspaceConstraint::half_space(-Vector3::z(), 0.0).unwrap();
    let lengths = WorkspaceConstraint::joint_range(Q_MIN, Q_MAX).unwrap();
    let ws = Workspace::new(&v, &[()], &[above, lengths]).unwrap();
    let domain = Domain::new(Region::Hemisphere {
        center: Vector3::zeros(),
        radius: 0.7,
    })
    .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 11 }, 1 << 14, 4).unwrap();
    let e = ws.volume_and_eta(&points, &Silent).unwrap();
    let exact = 2.0 * PI / 3.0 * (Q_MAX.powi(3) - Q_MIN.powi(3));
    assert!(
        (e.volume - exact).abs() < 4.0 * e.volume_se + 1e-4,
        "{} ± {} vs {exact}",
        e.volume,
        e.volume_se
    );
    // All six legs point along p: J has rank 1, so 1/κ = 0 everywhere.
    assert!(e.eta.unwrap().abs() < 1e-12);
}
