//! Property tests of the Stewart–Gough platform and the 3-UPU (Wolf & Shoham).
#![allow(clippy::unwrap_used)]

use nalgebra::{Isometry3, Vector3};
use pkm_mechanisms::{
    StewartDesign, StewartDesignVariable, StewartGough, StewartTaskProblem, ThreeUpu,
    ThreeUpuDesign, UJointAxes, WrenchSystem, platform_pose, pose_from_task, presets,
};
use pkm_screw_theory::{PluckerLine, Twist, reciprocal_product_vectors};
use pkm_traits::testkit::{
    check_closure, check_ik_fk_round_trip, check_jacobians_against_central_differences,
    check_traits, check_velocity_jacobian_at,
};
use pkm_traits::{Bounds, InverseKinematics, Objective, Residuals, Task};
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
    let sg = StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 30.0, 8.0)).unwrap();
    check_closure(&sg, (), &poses(), 1e-12).unwrap();
    check_jacobians_against_central_differences(&sg, (), &poses(), 1e-6, 1e-6).unwrap();
    check_ik_fk_round_trip(&sg, (), &poses(), 1e-2, 1e-9).unwrap();
}

#[test]
fn bad_designs_and_poses_are_typed_errors() {
    assert!(StewartGough::new(StewartDesign::from_deg(-1.0, 8.0, 30.0, 8.0)).is_err());
    assert!(StewartGough::new(StewartDesign::from_deg(12.0, f64::NAN, 30.0, 8.0)).is_err());
    assert!(StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 200.0, 8.0)).is_err());
    assert!(platform_pose(Vector3::zeros(), Vector3::zeros(), 0.1).is_err());
    // Radii equal, pose at z = 0: every leg has zero length.
    let sg = StewartGough::new(StewartDesign::from_deg(8.0, 8.0, 10.0, 10.0)).unwrap();
    assert!(sg.wrench_rows(&Isometry3::identity()).is_err());
    let parallel = UJointAxes {
        u1: Vector3::x(),
        u2: Vector3::x(),
    };
    let park = presets::park_3upu();
    assert!(
        ThreeUpu::new(ThreeUpuDesign {
            upper: [parallel; 3],
            ..park
        })
        .is_err()
    );
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
        let sg = StewartGough::new(StewartDesign::from_deg(x1, x2, x3, x4)).unwrap();
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

    /// The analytic residual Jacobian of the task problem matches central differences, for the
    /// §4.1 pose problem (p in the paper's box, u in the cube) and for a problem with a free
    /// design variable and a fixed rotation; its residuals are those of `residuals` and, to
    /// rounding, the mechanism's leg rates at `evaluate`'s pose.
    #[test]
    fn task_problem_jacobian_matches_central_differences(
        pxy in prop::array::uniform2(-10.0..10.0f64), pz in 20.0..50.0f64,
        u in prop::array::uniform3(-1.0..1.0f64), x4 in 0.5..29.5f64,
        omega in prop::array::uniform3(-1.0..1.0f64), v in prop::array::uniform3(-5.0..5.0f64),
    ) {
        let twist = Twist::new(Vector3::from(omega), Vector3::from(v));
        prop_assume!(twist.as_vector().norm() > 1e-3);
        let xy = Bounds::new(-10.0, 10.0).unwrap();
        let new = |w: Vector3<f64>| StewartTaskProblem::new(
            presets::wolf_shoham_stewart_s4_1(), Vector3::new(0.0, 0.0, 35.0), w, twist,
        ).unwrap();
        let pose = new(Vector3::zeros())
            .free_position(0, xy).unwrap()
            .free_position(1, xy).unwrap()
            .free_position(2, Bounds::new(20.0, 50.0).unwrap()).unwrap()
            .free_rotation(30f64.to_radians()).unwrap();
        let design = new(Vector3::new(u[0], u[1], u[2]) * 0.4)
            .free_position(0, xy).unwrap()
            .free_design(StewartDesignVariable::PlatformSeparationDeg, Bounds::new(0.0, 30.0).unwrap())
            .free_position(2, Bounds::new(20.0, 50.0).unwrap()).unwrap();
        let cases: [(&StewartTaskProblem, Vec<f64>); 2] = [
            (&pose, vec![pxy[0], pxy[1], pz, u[0], u[1], u[2]]),
            (&design, vec![pxy[0], x4, pz]),
        ];
        for (problem, at) in cases {
            let n = problem.dimension();
            let (mut r, mut jac) = ([0.0; 6], vec![0.0; 6 * n]);
            prop_assert!(problem.residual_jacobian(&at, &mut r, &mut jac).unwrap());
            let mut plain = [0.0; 6];
            problem.residuals(&at, &mut plain).unwrap();
            prop_assert_eq!(r.map(f64::to_bits), plain.map(f64::to_bits));
            let (mechanism, pose) = problem.evaluate(&at).unwrap();
            let rates = mechanism.leg_rates(&pose, &twist).unwrap();
            for (a, b) in r.iter().zip(rates.iter()) {
                prop_assert!((a - b).abs() <= 1e-12 * (1.0 + rates.amax()), "{a} vs {b}");
            }
            let scale = 1.0 + jac.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for j in 0..n {
                let h = 1e-5 * problem.bounds()[j].width();
                let at_shift = |s: f64| {
                    let mut q = at.clone();
                    q[j] += s * h;
                    let mut out = [0.0; 6];
                    problem.residuals(&q, &mut out).unwrap();
                    out
                };
                let (rp, rm) = (at_shift(1.0), at_shift(-1.0));
                for i in 0..6 {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    prop_assert!(
                        (jac[i * n + j] - fd).abs() <= 1e-6 * scale,
                        "n = {n}, d r_{i} / d v_{j}: analytic {} vs fd {fd}", jac[i * n + j]
                    );
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// For random semi-regular designs and random well-conditioned poses around a random home
    /// height: the loop closes at the IK solution, $J_x$ and $J_q$ match central differences,
    /// and Newton's forward kinematics started 0.01 off recovers the pose (the testkit's
    /// conformance checks, each on three poses).
    ///
    /// Poses whose leg lines are nearly dependent are skipped: with $x_3 \approx x_4$ the
    /// same-pattern layout is close to the architecture singularity of §4.2 (every leg in a
    /// plane through the normal), where forward kinematics is ill-posed.
    #[test]
    fn stewart_gough_conformance_for_random_designs(
        x1 in 6.0..20.0f64, x2 in 3.0..12.0f64, x3 in 5.0..50.0f64, x4 in 5.0..50.0f64,
        height in 15.0..50.0f64,
        offsets in prop::array::uniform3(prop::array::uniform6(-1.0..1.0f64)),
    ) {
        let sg = StewartGough::new(StewartDesign::from_deg(x1, x2, x3, x4)).unwrap();
        let poses: Vec<Task<6>> = offsets
            .iter()
            .map(|o| Task::<6>::new(
                2.0 * o[0], 2.0 * o[1], height + 3.0 * o[2], 0.2 * o[3], 0.2 * o[4], 0.3 * o[5],
            ))
            .collect();
        for x in &poses {
            let rows = sg.wrench_rows(&pose_from_task(x).unwrap()).unwrap();
            let sigma = rows.singular_values();
            prop_assume!(sigma.min() > 2e-4 * sigma.max());
        }
        prop_assert!(check_closure(&sg, (), &poses, 1e-10).is_ok());
        prop_assert!(
            check_jacobians_against_central_differences(&sg, (), &poses, 1e-5, 1e-5).is_ok()
        );
        prop_assert!(check_ik_fk_round_trip(&sg, (), &poses, 1e-2, 1e-8).is_ok());
    }

    /// 3-UPU (eq. 17–18): the three leg rows are unit lines through the base and platform
    /// joints, the three couples are pure moments normal to both upper U-joint axes, and
    /// swapping $u_1$ and $u_2$ of every joint (which only flips each normal) leaves $F$ for
    /// any twist unchanged (spec §3.6).
    #[test]
    fn three_upu_rows_and_swap_invariance(
        height in 20.0..80.0f64, tilt in prop::array::uniform3(-0.5..0.5f64),
        chi in prop::array::uniform6(-1.0..1.0f64),
    ) {
        let axes = |swap: bool| presets::park_3upu().azimuths.map(|t| {
            let park = UJointAxes::park(t);
            let k = tilt[0] * t.cos() + tilt[1];
            let u1 = park.u1 + Vector3::z() * k;
            let u2 = park.u2 + Vector3::z() * tilt[2];
            if swap { UJointAxes { u1: u2, u2: u1 } } else { UJointAxes { u1, u2 } }
        });
        let pose = Isometry3::translation(0.0, 0.0, height);
        let twist = Twist::from_vector(nalgebra::Vector6::from(chi));
        let design = |swap: bool| ThreeUpuDesign { upper: axes(swap), ..presets::park_3upu() };
        let upu = ThreeUpu::new(design(false)).unwrap();
        let swapped = ThreeUpu::new(design(true)).unwrap();
        let rows = upu.wrench_rows(&pose).unwrap();
        for (i, row) in rows.row_iter().enumerate() {
            let d = Vector3::new(row[0], row[1], row[2]);
            let m = Vector3::new(row[3], row[4], row[5]);
            if i < 3 {
                prop_assert!((d.norm() - 1.0).abs() < 1e-12);
                prop_assert!(d.dot(&m).abs() < 1e-9 * (1.0 + m.norm()));
            } else {
                prop_assert!(d.norm() <= 0.0);
                let UJointAxes { u1, u2 } = axes(false)[i - 3];
                prop_assert!(m.dot(&u1).abs() < 1e-12 * u1.norm());
                prop_assert!(m.dot(&u2).abs() < 1e-12 * u2.norm());
                prop_assert!((m.norm() - 1.0).abs() < 1e-12);
            }
        }
        let (f, f_swapped) = (
            upu.task_objective(&pose, &twist).unwrap(),
            swapped.task_objective(&pose, &twist).unwrap(),
        );
        prop_assert!((f - f_swapped).abs() <= 1e-12 * (1.0 + f));
    }
}

/// §4.4: with Park's axes and the legs' apex on the horizontal line $A_2$ (printed
/// `[0.35, 0.94, 0, −93.9, 34.6, 0]`, made an exact line through its point nearest the origin),
/// $F = 0$ exactly, as for $A_1$ (spec §1.5: both lines pass through the apex).
#[test]
fn park_design_is_singular_for_a2_too() {
    let d = Vector3::new(0.35, 0.94, 0.0);
    let m = Vector3::new(-93.9, 34.6, 0.0);
    let point = d.cross(&m) / d.norm_squared();
    let line = PluckerLine::from_direction_and_point(&d, &point).unwrap();
    let a2 = Twist::new(line.direction(), line.moment());
    let design = presets::park_3upu();
    let (a, b) = (design.base_radius, design.platform_radius);
    let park = ThreeUpu::new(design).unwrap();
    let home = Isometry3::translation(0.0, 0.0, point.z * (a - b) / a);
    assert!(park.task_objective(&home, &a2).unwrap() < 1e-20);
    // Off the apex height the legs miss A2 and F is positive.
    let off = Isometry3::translation(0.0, 0.0, 0.9 * point.z * (a - b) / a);
    assert!(park.task_objective(&off, &a2).unwrap() > 1e-3);
}

fn park_upu() -> ThreeUpu {
    ThreeUpu::new(presets::park_3upu()).unwrap()
}

/// Platform positions above the base, around Park's home $p = (0, 0, 50)$.
fn upu_positions() -> Vec<Task<3>> {
    (0..12)
        .map(|k| {
            let t = f64::from(k);
            Task::<3>::new(
                6.0 * (0.7 * t).sin(),
                -5.0 * (1.3 * t).cos(),
                50.0 + 15.0 * (0.4 * t).sin(),
            )
        })
        .collect()
}

#[test]
fn three_upu_passes_the_conformance_kit() {
    check_traits::<ThreeUpu>();
    let upu = park_upu();
    let poses = upu_positions();
    let closure = check_closure(&upu, (), &poses, 1e-12).unwrap();
    let jacobians =
        check_jacobians_against_central_differences(&upu, (), &poses, 1e-6, 1e-7).unwrap();
    let round_trip = check_ik_fk_round_trip(&upu, (), &poses, 1e-3, 1e-9).unwrap();
    let velocity = check_velocity_jacobian_at(&upu, (), &poses, 1e-15).unwrap();
    for report in [closure, jacobians, round_trip, velocity] {
        assert_eq!(report.checked, poses.len());
    }
}

/// The kinematic model is the screw view at $R = I$: the rows of $J = -J_q^{-1}J_x$ are the
/// directions of the leg-force rows of eq. 18, and $\dot q = J\dot p$ are the leg rates
/// $L_i \wedge \chi$ of the pure translation $\chi = [0 ; \dot p]$.
#[test]
fn three_upu_velocity_jacobian_is_the_leg_rows_of_eq_18() {
    let upu = park_upu();
    let velocity = Vector3::new(0.3, -1.2, 0.7);
    for p in upu_positions() {
        let j = upu.velocity_jacobian_at(&p, ()).unwrap();
        let rows = upu
            .wrench_rows(&Isometry3::translation(p.x, p.y, p.z))
            .unwrap();
        for i in 0..3 {
            let direction = Vector3::new(rows[(i, 0)], rows[(i, 1)], rows[(i, 2)]);
            assert!((j.row(i).transpose() - direction).amax() < 1e-15);
        }
        let twist = Twist::new(Vector3::zeros(), velocity);
        let rates = pkm_screw_theory::task_residuals(&rows, &twist);
        let q_dot = j * velocity;
        for i in 0..3 {
            assert!((q_dot[i] - rates[i]).abs() < 1e-12, "{q_dot} vs {rates}");
        }
    }
}

#[test]
fn three_upu_kinematics_reject_degenerate_poses() {
    use pkm_traits::KinematicsError;
    let upu = park_upu();
    // Platform joint 0 on base joint 0: r_0 - b_0 = (0, 10, 0) at azimuth -90°.
    let on_joint = Task::<3>::new(0.0, -10.0, 0.0);
    assert!(matches!(
        upu.inverse_kinematics(&on_joint, ()),
        Err(KinematicsError::Unreachable { leg: 0, .. })
    ));
    assert!(matches!(
        upu.inverse_kinematics(&Task::<3>::new(f64::NAN, 0.0, 1.0), ()),
        Err(KinematicsError::NonFinite { .. })
    ));
    assert!(upu.velocity_jacobian_at(&on_joint, ()).is_err());
}

/// Both mechanisms answer through the one trait, with the objective the sum of squared row
/// powers (for the Stewart–Gough platform, the squared leg rates).
#[test]
fn wrench_systems_share_the_task_objective() {
    let sg = StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 8.0, 8.0)).unwrap();
    let upu = park_upu();
    let pose = platform_pose(
        Vector3::new(1.0, -2.0, 40.0),
        Vector3::new(0.2, 0.1, 1.0),
        0.2,
    )
    .unwrap();
    let twist = Twist::new(Vector3::new(0.1, -0.3, 0.2), Vector3::new(0.5, 0.4, -1.0));
    let systems: [&dyn WrenchSystem; 2] = [&sg, &upu];
    for m in systems {
        let rows = m.wrench_rows(&pose).unwrap();
        let by_hand: f64 = rows
            .row_iter()
            .map(|r| reciprocal_product_vectors(&r.transpose(), twist.as_vector()).powi(2))
            .sum();
        let f = m.task_objective(&pose, &twist).unwrap();
        assert!((f - by_hand).abs() <= 1e-12 * by_hand, "{f} vs {by_hand}");
        assert!(f > 0.0);
    }
    let rates = sg.leg_rates(&pose, &twist).unwrap();
    assert_eq!(
        rates.norm_squared().to_bits(),
        sg.task_objective(&pose, &twist).unwrap().to_bits()
    );
}

#[test]
fn tilted_park_axes_stay_orthonormal_and_turn_about_the_named_axes() {
    use pkm_mechanisms::UJointAxes;
    let theta = 0.7_f64;
    let park = UJointAxes::park(theta);
    let untilted = UJointAxes::park_tilted(theta, 0.0, 0.0);
    assert!((untilted.u1 - park.u1).norm() < 1e-15 && (untilted.u2 - park.u2).norm() < 1e-15);
    let (beta, gamma) = (0.3_f64, -0.5_f64);
    let t = UJointAxes::park_tilted(theta, beta, gamma);
    assert!((t.u1.norm() - 1.0).abs() < 1e-14 && (t.u2.norm() - 1.0).abs() < 1e-14);
    assert!(t.u1.dot(&t.u2).abs() < 1e-14);
    // γ alone turns u2 about u1 by γ (u1 fixed); β alone turns u1 about u2 (u2 fixed).
    let g = UJointAxes::park_tilted(theta, 0.0, gamma);
    assert!((g.u1 - park.u1).norm() < 1e-15);
    assert!((g.u2.dot(&park.u2) - gamma.cos()).abs() < 1e-14);
    let b = UJointAxes::park_tilted(theta, beta, 0.0);
    assert!((b.u2 - park.u2).norm() < 1e-15);
    assert!((b.u1.dot(&park.u1) - beta.cos()).abs() < 1e-14);
}
