//! Property tests of the Stewart–Gough platform and the 3-UPU (Wolf & Shoham).
#![allow(clippy::unwrap_used)]

use nalgebra::{Isometry3, Vector3};
use pkm_mechanisms::{StewartGough, ThreeUpu, UJointAxes, platform_pose, pose_from_task};
use pkm_screw_theory::{PluckerLine, Twist};
use pkm_traits::Task;
use pkm_traits::testkit::{
    check_closure, check_ik_fk_round_trip, check_jacobians_against_central_differences,
    check_traits,
};
use proptest::prelude::*;

fn poses() -> Vec<Task<6>> {
    (0..12)
        .map(|k| {
            let t = k as f64;
            Task::<6>::new(
                3.0 * (0.7 * t).sin(),
                -2.0 * (1.3 * t).cos(),
                30.0 + 5.0 * (0.4 * t).sin(),
                0.3 * (0.9 * t).sin(),
                0.2 * (1.7 * t).cos(),
                0.4 * (0.5 * t).sin(),
            )
        })
        .collect()
}

#[test]
fn stewart_gough_conforms_to_the_testkit() {
    check_traits::<StewartGough>();
    let sg = StewartGough::new(12.0, 8.0, 30.0, 8.0).unwrap();
    check_closure(&sg, (), &poses(), 1e-12).unwrap();
    check_jacobians_against_central_differences(&sg, (), &poses(), 1e-6, 1e-6).unwrap();
    check_ik_fk_round_trip(&sg, (), &poses(), 1e-2, 1e-9).unwrap();
}

#[test]
fn bad_designs_and_poses_are_typed_errors() {
    assert!(StewartGough::new(-1.0, 8.0, 30.0, 8.0).is_err());
    assert!(StewartGough::new(12.0, f64::NAN, 30.0, 8.0).is_err());
    assert!(StewartGough::new(12.0, 8.0, 200.0, 8.0).is_err());
    assert!(platform_pose(Vector3::zeros(), Vector3::zeros(), 0.1).is_err());
    // Radii equal, pose at z = 0: every leg has zero length.
    let sg = StewartGough::new(8.0, 8.0, 10.0, 10.0).unwrap();
    assert!(sg.wrench_rows(&Isometry3::identity()).is_err());
    let parallel = UJointAxes {
        u1: Vector3::x(),
        u2: Vector3::x(),
    };
    assert!(ThreeUpu::new(20.0, 10.0, [parallel; 3]).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Rows of eq. 10 are unit lines (Klein's identity) and $L_i \wedge \chi$ is the leg rate.
    #[test]
    fn rows_are_lines_and_give_leg_rates(
        x1 in 5.0..20.0f64, x2 in 3.0..15.0f64, x3 in 0.0..60.0f64, x4 in 0.0..60.0f64,
        px in -5.0..5.0f64, pz in 20.0..50.0f64, wx in -0.5..0.5f64, wz in -0.5..0.5f64,
        omega in prop::array::uniform3(-1.0..1.0f64), v in prop::array::uniform3(-1.0..1.0f64),
    ) {
        let sg = StewartGough::new(x1, x2, x3, x4).unwrap();
        let x = Task::<6>::new(px, 0.5, pz, wx, 0.1, wz);
        let pose = pose_from_task(&x).unwrap();
        let rows = sg.wrench_rows(&pose).unwrap();
        for row in rows.row_iter() {
            let d = Vector3::new(row[0], row[1], row[2]);
            let m = Vector3::new(row[3], row[4], row[5]);
            prop_assert!((d.norm() - 1.0).abs() < 1e-12);
            prop_assert!(d.dot(&m).abs() < 1e-9 * (1.0 + m.norm()));
            let p = d.cross(&m);
            let line = PluckerLine::from_direction_and_point(&d, &p).unwrap();
            prop_assert!((line.moment() - m).norm() < 1e-9 * (1.0 + m.norm()));
        }
        // Finite-difference leg rates under the rigid motion of twist (omega, v at the origin).
        let twist = Twist::new(Vector3::from(omega), Vector3::from(v));
        let rates = sg.leg_rates(&pose, &twist).unwrap();
        let h = 1e-6;
        let moved = |s: f64| {
            let step = Isometry3::new(twist.linear() * s, twist.angular() * s);
            sg.leg_lengths(&(step * pose))
        };
        let fd = (moved(h) - moved(-h)) / (2.0 * h);
        prop_assert!((fd - rates).amax() < 1e-6 * (1.0 + rates.amax()));
    }
}
