//! The constant-orientation view of the Stewart–Gough platform: conformance, and agreement with
//! the full 6-DOF platform at the same pose.
#![allow(clippy::unwrap_used)]

use nalgebra::Vector3;
use pkm_mechanisms::{ConstantOrientation, StewartDesign, StewartGough, pose_from_task};
use pkm_traits::testkit::{
    check_closure, check_jacobians_against_central_differences, check_traits,
};
use pkm_traits::{ClosedChain, InverseKinematics, Task};

fn view() -> ConstantOrientation {
    let sg = StewartGough::new(StewartDesign::from_deg(0.3, 0.2, 20.0, 35.0)).unwrap();
    ConstantOrientation::new(sg, Vector3::new(0.1, -0.2, 0.3)).unwrap()
}

fn positions() -> Vec<Task<3>> {
    (0..12)
        .map(|k| {
            let t = f64::from(k);
            Vector3::new(
                0.1 * (0.7 * t).sin(),
                -0.08 * (1.3 * t).cos(),
                0.5 + 0.1 * (0.4 * t).sin(),
            )
        })
        .collect()
}

#[test]
fn constant_orientation_conforms_to_the_testkit() {
    check_traits::<ConstantOrientation>();
    let v = view();
    check_closure(&v, (), &positions(), 1e-12).unwrap();
    check_jacobians_against_central_differences(&v, (), &positions(), 1e-6, 1e-7).unwrap();
}

#[test]
fn it_is_the_six_dof_platform_at_a_fixed_rotation() {
    let v = view();
    let w = v.rotation_vector();
    for p in positions() {
        let x = Task::<6>::new(p.x, p.y, p.z, w.x, w.y, w.z);
        let q6 = v.platform().inverse_kinematics(&x, ()).unwrap();
        let q = v.inverse_kinematics(&p, ()).unwrap();
        assert!((q - q6).amax() < 1e-12, "{q} vs {q6}");
        // The velocity Jacobian is the translational part of the platform's (J_q = -I there).
        let j6 = v.platform().velocity_jacobian_at(&x, ()).unwrap();
        let j = v.velocity_jacobian_at(&p, ()).unwrap();
        assert!((j - j6.fixed_columns::<3>(0)).amax() < 1e-12);
        // The shell centres: leg i has length |p - c_i|.
        let pose = pose_from_task(&x).unwrap();
        let lengths = v.platform().leg_lengths(&pose);
        for (c, l) in v.shell_centres().iter().zip(lengths.iter()) {
            assert!(((p - c).norm() - l).abs() < 1e-12);
        }
        assert!(v.closure(&p, &q).amax() < 1e-12);
    }
}

#[test]
fn bad_rotations_and_positions_are_typed_errors() {
    let sg = view().platform().clone();
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(ConstantOrientation::new(sg.clone(), Vector3::new(bad, 0.0, 0.0)).is_err());
    }
    // |w|² overflows: the scaled-norm path of pose_from_task, still a rotation.
    let huge = ConstantOrientation::new(sg.clone(), Vector3::repeat(1e300)).unwrap();
    assert!(huge.rotation().matrix().iter().all(|v| v.is_finite()));
    let v = view();
    for p in [
        Vector3::new(f64::NAN, 0.0, 0.5),
        Vector3::new(0.0, f64::INFINITY, 0.5),
        Vector3::repeat(1e300),
    ] {
        assert!(v.inverse_kinematics(&p, ()).is_err(), "{p}");
    }
    // Coincident joints: base radius = platform radius, equal separations, R = I, p = 0.
    let flat = StewartGough::new(StewartDesign::from_deg(0.2, 0.2, 20.0, 20.0)).unwrap();
    let flat = ConstantOrientation::new(flat, Vector3::zeros()).unwrap();
    assert!(flat.inverse_kinematics(&Vector3::zeros(), ()).is_err());
}
