//! The acceptance set of issue 18, items 2, 5 and 6 (sources and tolerances in
//! `docs/conventions.md`, "Robot files: acceptance set").

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::print_stdout
)]

use crate::common;

use nalgebra::{Matrix2, Rotation3, Vector2, Vector3};
use pkm_robot_file::{EnumerationSettings, Robot, WorkingMode};
use pkm_traits::InverseKinematics;

/// Acceptance 2: the five-bar has four inverse working modes (two per leg) with four distinct
/// actuator solutions, two assembly modes, and its Jacobian equals the closed form
/// $\dot\theta_i = (P - B_i)\cdot\dot p\,/\,((P - B_i)\cdot(\hat z \times (B_i - A_i)))$.
#[test]
fn five_bar_modes_and_jacobian() {
    let robot = Robot::<2>::new(common::robot("five_bar.toml")).unwrap();
    let model = robot.model();
    let x = Vector2::new(0.03, 0.33);
    let modes = model.working_modes();
    assert_eq!(modes.len(), 4);
    let mut solutions: Vec<Vector2<f64>> = Vec::new();
    for &mode in &modes {
        let q = robot.inverse_kinematics(&x, mode).unwrap();
        assert!(
            solutions.iter().all(|s| (s - q).amax() > 1e-3),
            "mode {mode:?} repeats a solution"
        );
        solutions.push(q);
        // The closed form, from the elbows of this mode: q_i turns the home arm (−0.12, 0.16)
        // or (0.12, 0.16) about z.
        let a = [Vector3::new(-0.08, 0.0, 0.0), Vector3::new(0.08, 0.0, 0.0)];
        let arm = [
            Vector3::new(-0.12, 0.16, 0.0),
            Vector3::new(0.12, 0.16, 0.0),
        ];
        let p = Vector3::new(x[0], x[1], 0.0);
        let expected = Matrix2::from_fn(|i, k| {
            let elbow = a[i] + Rotation3::from_axis_angle(&Vector3::z_axis(), q[i]) * arm[i];
            let rod = p - elbow;
            rod[k] / rod.dot(&Vector3::z().cross(&(elbow - a[i])))
        });
        let j = robot.velocity_jacobian_at(&x, mode).unwrap();
        assert!(
            (j - expected).amax() < 1e-9 * expected.amax(),
            "mode {mode:?}:\n{j}\n{expected}"
        );
    }
    // Two assembly modes at the actuators of the home working mode.
    let q = robot.inverse_kinematics(&x, model.home_mode()).unwrap();
    let found = model
        .assembly_modes(q.as_slice(), &EnumerationSettings::default())
        .unwrap();
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        found
            .iter()
            .any(|m| (m.task[0] - x[0]).abs() < 1e-9 && (m.task[1] - x[1]).abs() < 1e-9)
    );
    assert_eq!(
        found[0].home_label,
        Some(0),
        "the mode continued from home comes first"
    );
}

/// Acceptance 5: the Orthoglide is isotropic at its isotropic configuration, $J = I$, κ = 1,
/// and only there among nearby poses.
#[test]
fn orthoglide_is_isotropic_at_home() {
    let robot = Robot::<3>::new(common::robot("orthoglide.toml")).unwrap();
    let mode = robot.model().home_mode();
    let j = robot.velocity_jacobian_at(&Vector3::zeros(), mode).unwrap();
    let sv = j.singular_values();
    let kappa = sv.max() / sv.min();
    assert!((kappa - 1.0).abs() < 1e-12, "κ = {kappa}");
    assert!((j - nalgebra::Matrix3::identity()).amax() < 1e-12, "{j}");
    let off = robot
        .velocity_jacobian_at(&Vector3::new(0.05, -0.03, 0.02), mode)
        .unwrap();
    let sv = off.singular_values();
    assert!(sv.max() / sv.min() > 1.01);
}

/// Acceptance 6: the symmetric 3-PRS has zero torsion over its workspace, its parasitic x, y
/// follow $x = \tfrac r2(\cos\theta - 1)\cos 2\phi$, $y = -\tfrac r2(\cos\theta - 1)\sin 2\phi$
/// (tilt θ about the axis at azimuth φ + 90°), and its three constraint wrenches have rank 3.
#[test]
fn three_prs_zero_torsion_and_parasitic_motion() {
    let robot = Robot::<3>::new(common::robot("three_prs.toml")).unwrap();
    let model = robot.model();
    let r = 0.1;
    let mut checked = 0;
    for z in [0.45, 0.5, 0.55] {
        for k in 0..12 {
            for theta in [0.05, 0.15, 0.3] {
                let phi = f64::from(k) * std::f64::consts::PI / 6.0;
                let task = [z, -theta * phi.sin(), theta * phi.cos()];
                let c = model
                    .inverse_kinematics_configuration(&task, WorkingMode::default())
                    .unwrap();
                let pose = c.pose();
                let x = r / 2.0 * (theta.cos() - 1.0) * (2.0 * phi).cos();
                let y = -r / 2.0 * (theta.cos() - 1.0) * (2.0 * phi).sin();
                assert!(pose[5].abs() < 1e-10, "torsion {} at {task:?}", pose[5]);
                assert!(
                    (pose[0] - x).abs() < 1e-10 && (pose[1] - y).abs() < 1e-10,
                    "{pose:?} vs ({x}, {y})"
                );
                let jac = model.screw_jacobians(&c).unwrap();
                assert_eq!(jac.j_c.nrows(), 3);
                let sv = jac.j_c.singular_values();
                assert!(sv.min() > 1e-3 * sv.max(), "rank-3 J_c: {sv}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 108);
}

/// The inverse-kinematic margin of the five-bar vanishes as leg 0 stretches out
/// ($|P - A_1| \to l_1 + l_2$), while the direct one stays away from zero.
#[test]
fn five_bar_inverse_margin_vanishes_when_a_leg_stretches_out() {
    let model = common::robot("five_bar.toml");
    let a1 = Vector2::new(-0.08, 0.0);
    let direction = Vector2::new(0.3, 1.0).normalize();
    let mut previous = f64::INFINITY;
    for gap in [1e-2, 1e-4, 1e-6] {
        let p = a1 + direction * (0.49 - gap);
        let c = model
            .inverse_kinematics_configuration(p.as_slice(), model.home_mode())
            .unwrap();
        let m = model.singularity_margins(&c).unwrap();
        assert!(m.inverse < previous && m.direct > 1e-3, "gap {gap}: {m:?}");
        previous = m.inverse;
    }
    assert!(previous < 1e-2, "{previous}");
}

/// The Exechon's configuration solves at every sample of a slow move from home (z + 2.25 cm,
/// tilts + 0.0225 rad, 201 samples): its dependent coordinates are solved to rounding, not
/// just below the closure tolerance of 1e-12, so that the SPR leg's passive joints, solved at
/// that pose with the same tolerance, can close (before, sample 22 of this move failed with
/// "did not converge, best |Φ| = 1.077e-12", found by the Pinocchio peer's trajectory).
#[test]
fn exechon_configuration_solves_along_a_move() {
    let model = common::robot("exechon.toml");
    let mode = model.home_mode();
    for k in 0..=200 {
        let s = f64::from(k) / 200.0;
        let d = 0.0225
            * if s < 0.5 {
                2.0 * s * s
            } else {
                1.0 - 2.0 * (1.0 - s).powi(2)
            };
        let x = [0.8 + d, d, d];
        if let Err(e) = model.inverse_kinematics_configuration(&x, mode) {
            panic!("sample {k}: {e}");
        }
    }
}

/// Issue 33: an Exechon-type 2-UPR + SPR head (`exechon.toml`, illustrative dimensions) is
/// served by today's model, one actuator per leg. At seeded task poses (z, tilt) the solved
/// full pose satisfies the legs' constraints written independently (each UPR leg's R axis
/// $R\hat y$ normal to its rod, the SPR leg's $R\hat x$ normal to its rod), each actuator is
/// the rod length $\lvert B_i - A_i\rvert$, $J$ equals central differences of the IK to 1e-7,
/// and forward kinematics from a guess returns the pose.
#[test]
fn exechon_head_agrees_with_its_closed_form() {
    use pkm_traits::{ForwardKinematics, NewtonSettings};
    let robot = Robot::<3>::new(common::robot("exechon.toml")).unwrap();
    let model = robot.model();
    let base = [
        Vector3::new(-0.35, 0.0, 0.0),
        Vector3::new(0.35, 0.0, 0.0),
        Vector3::new(0.0, 0.45, 0.0),
    ];
    let platform = [
        Vector3::new(-0.12, 0.0, 0.0),
        Vector3::new(0.12, 0.0, 0.0),
        Vector3::new(0.0, 0.15, 0.0),
    ];
    let mode = model.home_mode();
    let mut checked = 0;
    for k in 0..40 {
        let s = |a: f64| (k as f64 * a).sin();
        let x = Vector3::new(0.8 + 0.1 * s(0.7), 0.15 * s(1.3), 0.15 * s(2.9));
        let pose = model.full_pose(x.as_slice()).unwrap();
        // R = exp([(t_x, t_y, 0)]x) R_z(σ), the tilt-and-torsion coordinates.
        let r = Rotation3::new(Vector3::new(pose[3], pose[4], 0.0))
            * Rotation3::from_axis_angle(&Vector3::z_axis(), pose[5]);
        let p = Vector3::new(pose[0], pose[1], pose[2]);
        let rods: Vec<Vector3<f64>> = (0..3).map(|i| p + r * platform[i] - base[i]).collect();
        let constraints = [
            rods[0].dot(&(r * Vector3::y())),
            rods[1].dot(&(r * Vector3::y())),
            rods[2].dot(&(r * Vector3::x())),
        ];
        assert!(
            constraints.iter().all(|c| c.abs() < 1e-12),
            "{constraints:?} at {x}"
        );
        let q = robot.inverse_kinematics(&x, mode).unwrap();
        for i in 0..3 {
            assert!((q[i] - rods[i].norm()).abs() < 1e-12, "leg {i} at {x}");
        }
        let j = robot.velocity_jacobian_at(&x, mode).unwrap();
        let h = 1e-6;
        for c in 0..3 {
            let mut e = Vector3::zeros();
            e[c] = h;
            let fd = (robot.inverse_kinematics(&(x + e), mode).unwrap()
                - robot.inverse_kinematics(&(x - e), mode).unwrap())
                / (2.0 * h);
            assert!(
                (fd - j.column(c)).amax() < 1e-7,
                "J[:, {c}] at {x}: {fd} vs {j}"
            );
        }
        let guess = x.add_scalar(0.01);
        let fk = robot
            .forward_kinematics(&q, &guess, &NewtonSettings::default())
            .unwrap();
        assert!((fk - x).amax() < 1e-9, "FK at {x}: {fk}");
        checked += 1;
    }
    assert_eq!(checked, 40);
    // Parasitic motion is there: away from home the platform origin leaves the z axis.
    let pose = model.full_pose(&[0.8, 0.1, 0.1]).unwrap();
    assert!(pose[0].abs().max(pose[1].abs()) > 1e-4, "{pose:?}");
}

/// Issue 33: a Tricept-type head (`tricept.toml`, illustrative dimensions): three actuated UPS
/// legs and a central passive UP leg, which a robot file could not describe before (`legs[3]:
/// exactly one joint per leg must be actuated`). The passive leg is a U at the base centre O
/// with axes x then y, so the platform turns by $R = R_x(\alpha) R_y(\beta)$ with
/// $R\hat z = p / \lvert p\rvert$: $\beta = \arcsin u_x$, $\alpha = \operatorname{atan2}(-u_y,
/// u_z)$. At seeded positions the solved orientation is that $R$ (the platform's constrained
/// motion), each actuator is $\lvert p + R b_i - A_i\rvert$, J equals central differences of
/// that closed form, and forward kinematics from a guess returns the position.
#[test]
fn tricept_head_agrees_with_its_closed_form() {
    use pkm_traits::{ForwardKinematics, NewtonSettings};
    let robot = Robot::<3>::new(common::robot("tricept.toml")).unwrap();
    let model = robot.model();
    assert_eq!(model.legs().len(), 4);
    assert_eq!(model.leg_solvers()[3], "passive (pointing)");
    let corner = |radius: f64, k: usize| {
        let t = std::f64::consts::TAU * k as f64 / 3.0;
        Vector3::new(radius * t.cos(), radius * t.sin(), 0.0)
    };
    let closed_form = |p: &Vector3<f64>| {
        let u = p.normalize();
        let r = Rotation3::from_axis_angle(&Vector3::x_axis(), (-u.y).atan2(u.z))
            * Rotation3::from_axis_angle(&Vector3::y_axis(), u.x.asin());
        let q = Vector3::from_fn(|i, _| (p + r * corner(0.1, i) - corner(0.3, i)).norm());
        (r, q)
    };
    let mode = model.home_mode();
    for k in 0..30 {
        let s = |a: f64| (k as f64 * a).sin();
        let x = Vector3::new(0.15 * s(0.9), 0.15 * s(2.3), 0.6 + 0.12 * s(1.7));
        let (r, q_closed) = closed_form(&x);
        let pose = model.full_pose(x.as_slice()).unwrap();
        let solved = Rotation3::new(Vector3::new(pose[3], pose[4], pose[5]));
        // The pointing leg's closed form (Paden–Kahan) against this one, to rounding.
        let error = (solved.matrix() - r.matrix()).amax();
        assert!(error < 1e-14, "R at {x}: {error:e}");
        let q = robot.inverse_kinematics(&x, mode).unwrap();
        assert!(
            (q - q_closed).amax() < 1e-12,
            "IK at {x}: {q} vs {q_closed}"
        );
        let j = robot.velocity_jacobian_at(&x, mode).unwrap();
        let h = 1e-6;
        for c in 0..3 {
            let mut e = Vector3::zeros();
            e[c] = h;
            let fd = (closed_form(&(x + e)).1 - closed_form(&(x - e)).1) / (2.0 * h);
            assert!(
                (fd - j.column(c)).amax() < 1e-7,
                "J[:, {c}] at {x}: {fd} vs {j}"
            );
        }
        let fk = robot
            .forward_kinematics(&q, &x.add_scalar(0.01), &NewtonSettings::default())
            .unwrap();
        assert!((fk - x).amax() < 1e-9, "FK at {x}: {fk}");
    }
}

/// The 4-RRR's legs: base point A, platform point b (platform frame), the motor angle of the
/// home elbow branch from the two-circle intersection with links of 0.4 m.
fn four_rrr_ik(x: &Vector3<f64>) -> nalgebra::Vector4<f64> {
    let corners = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)];
    let (c, s) = (x.z.cos(), x.z.sin());
    nalgebra::Vector4::from_fn(|i, _| {
        let (sx, sy) = corners[i];
        let a = Vector2::new(0.5 * sx, 0.5 * sy);
        let b = Vector2::new(x.x + 0.1 * (c * sx - s * sy), x.y + 0.1 * (s * sx + c * sy));
        let d = b - a;
        let along = d.norm() / 2.0; // equal links: the elbow above the midpoint
        let h = (0.16 - along * along).sqrt();
        let u = d / d.norm();
        let e = a + u * along + Vector2::new(-u.y, u.x) * h;
        (e.y - a.y).atan2(e.x - a.x)
    })
}

/// Issue 33: a redundantly actuated planar 4-RRR (`four_rrr.toml`): the IK against the
/// two-circle closed form, the 4 × 3 J and its singular values against central differences of
/// that closed form, forward kinematics from consistent actuator values (the pose, residual 0)
/// and from inconsistent ones (the least-squares pose of an independent Gauss–Newton on the
/// closed form, with its residual), and the force distribution against the least-norm
/// solution by hand, with and without effort limits.
#[test]
fn redundant_four_rrr_kinematics_and_force_distribution() {
    use nalgebra::{DMatrix, Matrix4x3, Vector4};
    let model = common::robot("four_rrr.toml");
    assert_eq!((model.dof(), model.actuator_count()), (3, 4));
    assert!(matches!(
        Robot::<3>::new(model.clone()),
        Err(pkm_robot_file::RobotFileError::Redundant { .. })
    ));
    let fd_jacobian = |x: &Vector3<f64>| {
        let h = 1e-6;
        Matrix4x3::from_fn(|i, k| {
            let mut e = Vector3::zeros();
            e[k] = h;
            (four_rrr_ik(&(x + e))[i] - four_rrr_ik(&(x - e))[i]) / (2.0 * h)
        })
    };
    let mode = model.home_mode();
    let x = Vector3::new(0.03, -0.02, 0.1);
    let q = model.inverse_kinematics(x.as_slice(), mode).unwrap();
    let closed = four_rrr_ik(&x);
    let wrapped = |d: f64| {
        (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    for i in 0..4 {
        assert!(
            wrapped(closed[i] - q[i]).abs() < 1e-12,
            "IK {q} vs {closed}"
        );
    }
    let config = model
        .inverse_kinematics_configuration(x.as_slice(), mode)
        .unwrap();
    let j = model.screw_jacobians(&config).unwrap().j;
    assert_eq!(j.shape(), (4, 3));
    let j_fd = fd_jacobian(&x);
    assert!((&j - DMatrix::from_column_slice(4, 3, j_fd.as_slice())).amax() < 1e-7);
    let (sv, sv_fd) = (j.singular_values(), j_fd.singular_values());
    for k in 0..3 {
        assert!(
            (sv[k] - sv_fd[k]).abs() < 1e-7 * sv_fd[0],
            "σ {sv} vs {sv_fd}"
        );
    }
    // Consistent actuator values: the pose back, residual zero.
    let guess = [0.0, 0.0, 0.0];
    let back = model
        .forward_kinematics_least_squares(q.as_slice(), &guess)
        .unwrap();
    assert!(
        (Vector3::from_column_slice(&back.task) - x).amax() < 1e-10,
        "{:?}",
        back.task
    );
    assert!(back.residual.amax() < 1e-12);
    // Inconsistent ones: leg 2 off by 5 mrad. An independent Gauss–Newton on the closed form.
    let mut q_bad = closed;
    q_bad[2] += 5e-3;
    let mut x_ls = x;
    for _ in 0..50 {
        let jac = fd_jacobian(&x_ls);
        let step = (jac.transpose() * jac).try_inverse().unwrap()
            * jac.transpose()
            * (q_bad - four_rrr_ik(&x_ls));
        x_ls += step;
    }
    let ls = model
        .forward_kinematics_least_squares(q_bad.as_slice(), x.as_slice())
        .unwrap();
    assert!(
        (Vector3::from_column_slice(&ls.task) - x_ls).amax() < 1e-8,
        "{:?} vs {x_ls}",
        ls.task
    );
    let r_hand = q_bad - four_rrr_ik(&x_ls);
    assert!((Vector4::from_column_slice(ls.residual.as_slice()) - r_hand).amax() < 1e-8);
    assert!(r_hand.norm() > 1e-3 && r_hand.norm() < 5e-3, "{r_hand}");
    // Force distribution: 10 N along x, -5 N along y and 2 N·m about z at the platform origin.
    let p = Vector3::new(x.x, x.y, 0.0);
    let force = Vector3::new(10.0, -5.0, 0.0);
    let moment_o = Vector3::new(0.0, 0.0, 2.0) + p.cross(&force);
    let wrench = [
        force.x, force.y, force.z, moment_o.x, moment_o.y, moment_o.z,
    ];
    // Generalised forces of (x, y, rz): the force, and the moment about the platform origin.
    let f_task = Vector3::new(10.0, -5.0, 2.0);
    let jt = j_fd.transpose();
    let by_hand = jt.pseudo_inverse(1e-12).unwrap() * f_task;
    let free = model.force_distribution(&config, &wrench, None).unwrap();
    assert!(free.held && free.imbalance < 1e-9);
    let efforts = Vector4::from_column_slice(free.efforts.as_slice());
    assert!(
        (efforts - by_hand).amax() < 1e-6 * by_hand.amax(),
        "{efforts} vs {by_hand}"
    );
    // Limits that cut the least-norm efforts: with one redundancy the efforts are
    // τ0 + z n (n spanning the null space of Jᵀ), z clamped into the interval the limits allow.
    let n = {
        let svd = j_fd.svd(true, false);
        let u = svd.u.unwrap();
        // The left singular vector outside the column space of J.
        let full = nalgebra::Matrix4::from_fn(|r, c| if c < 3 { u[(r, c)] } else { 0.0 });
        let mut v = Vector4::new(1.0, -1.0, 1.0, -1.0);
        for c in 0..3 {
            let col = full.column(c).into_owned();
            v -= col * col.dot(&v);
        }
        v.normalize()
    };
    let cap = 0.5 * by_hand[0].abs();
    let limits: Vec<[f64; 2]> = (0..4)
        .map(|i| if i == 0 { [-cap, cap] } else { [-1e3, 1e3] })
        .collect();
    let bounded = model
        .force_distribution(&config, &wrench, Some(&limits))
        .unwrap();
    assert!(bounded.held, "{bounded:?}");
    let z = (cap.copysign(by_hand[0]) - by_hand[0]) / n[0];
    let expected = by_hand + n * z;
    let got = Vector4::from_column_slice(bounded.efforts.as_slice());
    assert!(
        (got - expected).amax() < 1e-6 * expected.amax(),
        "{got} vs {expected}"
    );
    // Limits no efforts can meet: reported, not hidden.
    let tight = vec![[-1e-3, 1e-3]; 4];
    let refused = model
        .force_distribution(&config, &wrench, Some(&tight))
        .unwrap();
    assert!(!refused.held && refused.imbalance > 1.0, "{refused:?}");
}

/// The 3-PPSR's stage points $S_i = (s_x, s_y, 0)$ at pose `x` = (p, rotation vector), by
/// hand: the platform joint $C_i = p + R c_i$ with axis $u = R u_i$; $S_i$ lies on the base
/// plane, in the plane through $C_i$ normal to $u$ (the link is normal to its revolute axis)
/// and at the link length from $C_i$, on the outward branch.
fn three_ppsr_ik(x: &nalgebra::Vector6<f64>) -> nalgebra::Vector6<f64> {
    let (rb, rp, h) = (0.35, 0.15, 0.4);
    let length = (0.2_f64.powi(2) + h * h).sqrt();
    let p = Vector3::new(x[0], x[1], x[2]);
    let r = Rotation3::new(Vector3::new(x[3], x[4], x[5]));
    let mut q = nalgebra::Vector6::zeros();
    for k in 0..3 {
        let a = (90.0 + 120.0 * k as f64).to_radians();
        let (c, s) = (a.cos(), a.sin());
        let joint = p + r * Vector3::new(rp * c, rp * s, 0.0);
        let u = r * Vector3::new(-s, c, 0.0);
        // The line {S : S_z = 0, (S − C)·u = 0}: its point nearest C, and its direction.
        let horizontal = u.x * u.x + u.y * u.y;
        let foot = Vector3::new(joint.x, joint.y, 0.0)
            + Vector3::new(u.x, u.y, 0.0) * (u.z * joint.z / horizontal);
        let along = Vector3::new(-u.y, u.x, 0.0) / horizontal.sqrt();
        let t = -(length * length - (foot - joint).norm_squared()).sqrt();
        let stage = foot + along * t;
        assert!((stage.norm() - rb).abs() < 0.2, "far from home: {stage}");
        q[2 * k] = stage.x;
        q[2 * k + 1] = stage.y;
    }
    q
}

/// Issue 33: several actuators in one leg, a 3-PPSR on planar XY stages (`three_ppsr.toml`,
/// six actuators in three legs): the actuators named by their joints, the IK against the
/// closed form, the 6 × 6 J against central differences of it, the forward kinematics from
/// the actuator values back to the pose, and the singularity margins finite and positive.
#[test]
fn three_ppsr_two_actuators_per_leg() {
    use nalgebra::{DMatrix, Matrix6, Vector6};
    let model = common::robot("three_ppsr.toml");
    assert_eq!((model.dof(), model.actuator_count()), (6, 6));
    assert_eq!(
        model.actuator_names(),
        [
            "legs[0].joints[0]",
            "legs[0].joints[1]",
            "legs[1].joints[0]",
            "legs[1].joints[1]",
            "legs[2].joints[0]",
            "legs[2].joints[1]"
        ]
    );
    let mode = model.home_mode();
    let home = model.inverse_kinematics(&model.home_task(), mode).unwrap();
    let home_q = Vector6::from_column_slice(&model.home_actuators());
    assert!((&home - home_q).amax() < 1e-12, "{home} vs {home_q}");
    let x = Vector6::new(0.02, -0.03, 0.43, 0.05, -0.04, 0.1);
    let q = model.inverse_kinematics(x.as_slice(), mode).unwrap();
    let closed = three_ppsr_ik(&x);
    assert!((&q - closed).amax() < 1e-10, "IK {q} vs {closed}");
    let config = model
        .inverse_kinematics_configuration(x.as_slice(), mode)
        .unwrap();
    let j = model.screw_jacobians(&config).unwrap().j;
    let h = 1e-6;
    let j_fd = Matrix6::from_fn(|i, k| {
        let mut e = Vector6::zeros();
        e[k] = h;
        (three_ppsr_ik(&(x + e))[i] - three_ppsr_ik(&(x - e))[i]) / (2.0 * h)
    });
    assert!(
        (&j - DMatrix::from_column_slice(6, 6, j_fd.as_slice())).amax() < 1e-7,
        "J {j} vs {j_fd}"
    );
    let mut seed = model
        .inverse_kinematics_configuration(&model.home_task(), mode)
        .unwrap();
    seed = model.forward_kinematics_from(q.as_slice(), &seed).unwrap();
    let back = Vector6::from_column_slice(&seed.pose());
    assert!((back - x).amax() < 1e-10, "FK {back} vs {x}");
    let margins = model.singularity_margins(&config).unwrap();
    assert!(margins.inverse > 0.0 && margins.direct > 0.0, "{margins:?}");
}
