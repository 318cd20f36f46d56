//! The skeletons are the assembled robots: every actuated and passive link has the design's
//! length (arm, forearm, parallelogram, or the leg length of the inverse kinematics) to 1e-12,
//! and the open chains close on the platform.
#![allow(clippy::unwrap_used)]

use nalgebra::{Isometry3, Vector3};
use pkm_mechanisms::{
    Elbow, ElbowMode, LegBranch, LinearDelta, LinearDeltaDesign, LinearDeltaMode,
    LinearDeltaRatios, LinkKind, Placement, PointKind, RotaryDelta, Skeleton, StewartDesign,
    StewartGough, ThreeUpu, ThreeUpuDesign, Tsai3Dof, TsaiDesign, platform_pose, presets,
};
use pkm_traits::InverseKinematics;

const TOL: f64 = 1e-12;

fn lengths(s: &Skeleton, kind: LinkKind) -> Vec<f64> {
    s.links_of(kind)
        .map(|l| (s.points[l.to].position - s.points[l.from].position).norm())
        .collect()
}

fn assert_close(found: &[f64], expected: &[f64]) {
    assert_eq!(found.len(), expected.len(), "{found:?} vs {expected:?}");
    for (f, e) in found.iter().zip(expected) {
        assert!(
            (f - e).abs() <= TOL * (1.0 + e.abs()),
            "{found:?} vs {expected:?}"
        );
    }
}

fn position(s: &Skeleton, label: &str) -> Vector3<f64> {
    s.points.iter().find(|p| p.label == label).unwrap().position
}

#[test]
fn rotary_delta_arms_and_forearms_have_the_design_lengths() {
    let designs = [
        RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap(),
        RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
        RotaryDelta::new(presets::nuwar(Placement::canonical()))
            .unwrap()
            .with_turned_plate_offsets(),
    ];
    let poses = [
        Vector3::new(0.0, -0.2, -0.9),
        Vector3::new(0.1, 0.05, -0.8),
        Vector3::new(-0.15, 0.1, -0.7),
    ];
    for robot in &designs {
        for p in &poses {
            for mode in [ElbowMode::Out, ElbowMode::In] {
                let s = Skeleton::rotary_delta(robot, p, mode).unwrap();
                assert_close(&lengths(&s, LinkKind::Actuated), &[robot.arm(); 3]);
                assert_close(&lengths(&s, LinkKind::Passive), &[robot.forearm(); 3]);
                let side = 3f64.sqrt();
                assert_close(
                    &lengths(&s, LinkKind::Base),
                    &[robot.base_radius() * side; 3],
                );
                assert_close(
                    &lengths(&s, LinkKind::Platform),
                    &[robot.plate_offset().abs() * side; 3],
                );
                assert_eq!(position(&s, "p"), *p);
                assert_eq!(s.links.len(), 12);
            }
        }
    }
}

#[test]
fn linear_delta_carriages_travel_the_joint_values() {
    let ratios = LinearDeltaRatios {
        l1_over_yr: 2.0,
        ya_over_yr: 0.3,
        zr_over_yr: 0.4,
        l2_over_l1: 1.2,
    };
    let robot = LinearDelta::new(LinearDeltaDesign { ratios, yr: 0.5 }).unwrap();
    for p in [Vector3::new(0.0, 0.0, -0.8), Vector3::new(0.3, 0.1, -0.7)] {
        let q = robot
            .inverse_kinematics(&p, LinearDeltaMode::PAPER)
            .unwrap();
        let s = Skeleton::linear_delta(&robot, &p, LinearDeltaMode::PAPER).unwrap();
        assert_close(
            &lengths(&s, LinkKind::Actuated),
            &[q[0].abs(), q[1].abs(), q[2].abs()],
        );
        assert_close(&lengths(&s, LinkKind::Passive), &robot.arm_lengths());
        for (i, [y, z]) in robot.rails().into_iter().enumerate() {
            let carriage = position(&s, &format!("A{}", i + 1));
            assert_eq!(carriage, Vector3::new(q[i], y, z));
        }
    }
}

#[test]
fn tsai_legs_close_on_the_platform_with_the_design_lengths() {
    for robot in [
        Tsai3Dof::new(TsaiDesign::from_deg(0.44, 0.56, 0.1, -0.05, 120.0, 240.0)).unwrap(),
        Tsai3Dof::new(TsaiDesign::from_deg(0.3, 0.7, 0.0, 0.2, 100.0, 250.0)).unwrap(),
    ] {
        for p in [Vector3::new(0.05, -0.1, 0.5), Vector3::new(-0.1, 0.1, 0.6)] {
            for branch in [
                LegBranch::PRINCIPAL_OUT,
                LegBranch {
                    principal_theta3: false,
                    elbow: Elbow::In,
                },
            ] {
                let s = Skeleton::tsai(&robot, &p, branch).unwrap();
                assert_close(&lengths(&s, LinkKind::Actuated), &[robot.a(); 3]);
                let half = robot.d_plus_e() / 2.0;
                assert_close(
                    &lengths(&s, LinkKind::Passive),
                    &[half, robot.b(), half].repeat(3),
                );
                // The chain from the angles of the inverse kinematics reaches the rigid platform
                // E_i = p + c u_i, with the drawing's c = r + (c - r).
                let r = robot.a().max(-robot.c_minus_r());
                let c = r + robot.c_minus_r();
                for (i, phi) in robot.phi().into_iter().enumerate() {
                    let e = position(&s, &format!("E{}", i + 1));
                    let rigid = p + Vector3::new(phi.cos(), phi.sin(), 0.0) * c;
                    assert!((e - rigid).amax() <= TOL, "{e} vs {rigid}");
                }
            }
        }
    }
}

#[test]
fn stewart_gough_legs_are_the_inverse_kinematics_lengths() {
    let robot = StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 30.0, 8.0)).unwrap();
    for (p, axis, alpha) in [
        (Vector3::new(0.0, 0.0, 40.0), Vector3::z(), 0.0),
        (
            Vector3::new(2.0, -1.0, 35.0),
            Vector3::new(1.0, 2.0, 3.0),
            0.4,
        ),
    ] {
        let pose = platform_pose(p, axis, alpha).unwrap();
        let s = Skeleton::stewart_gough(&robot, &pose).unwrap();
        let ik = robot.leg_lengths(&pose);
        assert_close(&lengths(&s, LinkKind::Actuated), ik.as_slice());
        assert_eq!(s.links_of(LinkKind::Base).count(), 6);
        assert_eq!(s.links_of(LinkKind::Platform).count(), 6);
        assert_eq!(
            s.points
                .iter()
                .filter(|p| p.kind == PointKind::Platform)
                .count(),
            6
        );
    }
    let nan = Isometry3::translation(f64::NAN, 0.0, 1.0);
    assert!(Skeleton::stewart_gough(&robot, &nan).is_err());
}

#[test]
fn three_upu_legs_are_the_closed_form_and_inverse_kinematics_lengths() {
    let park = presets::park_3upu();
    let other = ThreeUpuDesign {
        base_radius: 15.0,
        platform_radius: 6.0,
        azimuths: [0.1, 2.0, 4.0],
        ..park
    };
    for design in [park, other] {
        let robot = ThreeUpu::new(design).unwrap();
        let pose = platform_pose(Vector3::new(1.0, 2.0, 50.0), Vector3::x(), 0.3).unwrap();
        let s = Skeleton::three_upu(&robot, &pose).unwrap();
        // Leg i from b_i = a e(θ_i) to p + R b e(θ_i): its length in closed form.
        let (a, b) = (design.base_radius, design.platform_radius);
        let e = design.azimuths.map(|t| Vector3::new(t.cos(), t.sin(), 0.0));
        let expected =
            e.map(|e| (pose.translation.vector + pose.rotation * (e * b) - e * a).norm());
        assert_close(&lengths(&s, LinkKind::Actuated), &expected);
        let side = |r: f64, i: usize, j: usize| (e[i] - e[j]).norm() * r;
        assert_close(
            &lengths(&s, LinkKind::Base),
            &[side(a, 0, 1), side(a, 1, 2), side(a, 2, 0)],
        );
        assert_close(
            &lengths(&s, LinkKind::Platform),
            &[side(b, 0, 1), side(b, 1, 2), side(b, 2, 0)],
        );
        // At R = I the legs are the translational model's inverse kinematics.
        let p = Vector3::new(-3.0, 1.5, 40.0);
        let s = Skeleton::three_upu(&robot, &Isometry3::translation(p.x, p.y, p.z)).unwrap();
        let q = robot.inverse_kinematics(&p, ()).unwrap();
        assert_close(&lengths(&s, LinkKind::Actuated), q.as_slice());
        let nan = Isometry3::translation(0.0, f64::NAN, 50.0);
        assert!(Skeleton::three_upu(&robot, &nan).is_err());
    }
}

#[test]
fn unreachable_and_non_finite_poses_are_typed_errors() {
    let nuwar = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
    assert!(
        Skeleton::rotary_delta(&nuwar, &Vector3::new(f64::NAN, 0.0, -0.9), ElbowMode::Out).is_err()
    );
    assert!(Skeleton::rotary_delta(&nuwar, &Vector3::new(0.0, 0.0, -5.0), ElbowMode::Out).is_err());
    let tsai = Tsai3Dof::new(TsaiDesign::from_deg(0.44, 0.56, 0.0, 0.0, 120.0, 240.0)).unwrap();
    assert!(
        Skeleton::tsai(
            &tsai,
            &Vector3::new(0.0, 0.0, 3.0),
            LegBranch::PRINCIPAL_OUT
        )
        .is_err()
    );
    assert!(
        Skeleton::tsai(
            &tsai,
            &Vector3::new(0.0, f64::INFINITY, 0.5),
            LegBranch::PRINCIPAL_OUT
        )
        .is_err()
    );
    let ratios = LinearDeltaRatios::from_slice(&[2.0, 0.0, 0.0, 0.63]);
    let linear = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
    assert!(
        Skeleton::linear_delta(
            &linear,
            &Vector3::new(0.0, 0.0, 1.0),
            LinearDeltaMode::PAPER
        )
        .is_err()
    );
    let empty = Skeleton::default();
    assert_eq!(empty.link_length(0), None);
}
