//! The acceptance set of issue 18, items 3, 4, 7 and 8 (with Dietmaier's 40 real postures):
//! assembly modes by multistart, working modes, and actuation wrenches (sources and tolerances
//! in `docs/conventions.md`).

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::print_stdout
)]

use crate::common;

use nalgebra::{Rotation2, Vector2, Vector3};
use pkm_robot_file::{AssemblyMode, EnumerationSettings, Robot, RobotModel};
use pkm_traits::InverseKinematics;

/// Every assembly mode closes: the IK of its pose, on the branches nearest `q`, gives back `q`.
fn assert_genuine(model: &RobotModel, q: &[f64], modes: &[AssemblyMode]) {
    for m in modes {
        let c = model.configuration_near(&m.task, q).unwrap();
        let back = model.actuators_of(&c);
        let error = back
            .iter()
            .zip(q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(error < 1e-9, "spurious mode {:?}: {back} vs {q:?}", m.task);
    }
}

/// Real solutions of the 3-RPR forward kinematics counted independently of the library: for
/// each platform angle φ, legs 1 and 2 place the platform by a circle–circle intersection (two
/// branches), and leg 3's length error changes sign at each solution.
fn independent_rpr_count(a: &[Vector2<f64>; 3], b: &[Vector2<f64>; 3], rho: &[f64; 3]) -> usize {
    let n = 40_000;
    let residual = |phi: f64, branch: f64| -> Option<f64> {
        let r = Rotation2::new(phi);
        let (c1, c2) = (a[0], a[1] - r * (b[1] - b[0]));
        let d = (c2 - c1).norm();
        if !(d < rho[0] + rho[1] && d > (rho[0] - rho[1]).abs()) {
            return None;
        }
        let along = (rho[0] * rho[0] - rho[1] * rho[1] + d * d) / (2.0 * d);
        let h = (rho[0] * rho[0] - along * along).max(0.0).sqrt();
        let u = (c2 - c1) / d;
        let p1 = c1 + u * along + Vector2::new(-u.y, u.x) * h * branch;
        Some((p1 + r * (b[2] - b[0]) - a[2]).norm() - rho[2])
    };
    let mut count = 0;
    for branch in [1.0, -1.0] {
        let values: Vec<Option<f64>> = (0..=n)
            .map(|k| {
                residual(
                    -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / n as f64,
                    branch,
                )
            })
            .collect();
        count += values
            .windows(2)
            .filter(|w| matches!((w[0], w[1]), (Some(u), Some(v)) if u * v < 0.0))
            .count();
    }
    count
}

/// Acceptance 3: a planar 3-RPR design with six real forward solutions; all six found by the
/// multistart, none spurious, and six counted independently.
#[test]
fn three_rpr_six_assembly_modes() {
    let model = common::robot("three_rpr.toml");
    let q = [0.375, 0.669, 0.393];
    let a = [
        Vector2::new(0.44, -0.74),
        Vector2::new(-0.46, -0.7),
        Vector2::new(0.22, -0.41),
    ];
    let b = [
        Vector2::new(0.37, -0.23),
        Vector2::new(0.14, 0.14),
        Vector2::new(0.44, 0.22),
    ];
    assert_eq!(independent_rpr_count(&a, &b, &q), 6);
    let modes = model
        .assembly_modes(&q, &EnumerationSettings::default())
        .unwrap();
    assert_eq!(
        modes.len(),
        6,
        "{:?}",
        modes.iter().map(|m| &m.task).collect::<Vec<_>>()
    );
    assert_genuine(&model, &q, &modes);
}

/// Acceptance 4: the Agile Eye has eight inverse working modes (eight distinct actuator
/// solutions at a generic orientation) and four assembly modes.
#[test]
fn agile_eye_working_and_assembly_modes() {
    let robot = Robot::<3>::new(common::robot("agile_eye.toml")).unwrap();
    let x = Vector3::new(0.2, -0.1, 0.15);
    let modes = robot.model().working_modes();
    assert_eq!(modes.len(), 8);
    let solutions: Vec<_> = modes
        .iter()
        .map(|&m| robot.inverse_kinematics(&x, m).unwrap())
        .collect();
    for (i, a) in solutions.iter().enumerate() {
        for b in &solutions[..i] {
            assert!((a - b).amax() > 1e-6, "two modes give one solution");
        }
    }
    let q = solutions[0];
    let found = robot
        .model()
        .assembly_modes(q.as_slice(), &EnumerationSettings::default())
        .unwrap();
    let regular: Vec<_> = found
        .iter()
        .filter(|m| !m.is_singular(1e-6))
        .cloned()
        .collect();
    println!(
        "Agile Eye: {} solutions, {} regular: {:?}",
        found.len(),
        regular.len(),
        regular.iter().map(|m| &m.task).collect::<Vec<_>>()
    );
    assert_genuine(robot.model(), q.as_slice(), &regular);
    assert_eq!(regular.len(), 4);
    // The singular solutions are self-motions: a platform axis on an actuated axis, so the
    // leg closes for every actuator value.
    assert!(
        found
            .iter()
            .filter(|m| m.is_singular(1e-6))
            .all(|m| m.margins.inverse < 1e-6)
    );
}

/// Issue 29: the Agile Eye written as its published geometry gives it, every joint point at
/// the centre, is recognised as three spherical revolute arms (it fell to the numerical solver
/// with one working mode) and has the eight working modes and the same IK as the file with
/// points at unit distance along the axes.
#[test]
fn agile_eye_with_every_joint_at_the_centre_has_eight_working_modes() {
    let text = common::robot_text("agile_eye.toml");
    let centred: String = text
        .lines()
        .map(|line| {
            let Some(at) = line.find("point = [") else {
                return format!("{line}\n");
            };
            let end = at + line[at..].find(']').unwrap() + 1;
            format!("{}point = [0.0, 0.0, 0.0]{}\n", &line[..at], &line[end..])
        })
        .collect();
    assert_ne!(centred, text);
    let (published, unit) = (
        RobotModel::from_toml(&centred).unwrap(),
        common::robot("agile_eye.toml"),
    );
    assert_eq!(published.leg_solvers(), vec!["revolute arm"; 3]);
    assert_eq!(published.working_modes().len(), 8);
    let x = [0.2, -0.1, 0.15];
    for mode in unit.working_modes() {
        let want = unit.inverse_kinematics(&x, mode).unwrap();
        let got = published.inverse_kinematics(&x, mode).unwrap();
        assert!((&want - &got).amax() < 1e-12, "{mode:?}: {got} vs {want}");
    }
}

/// Acceptance 7: the Hexa with the TUBS Hexa2 dimensions reaches a test pose, and each leg's
/// actuation wrench is the force along its rod (elbow U centre to platform S centre).
#[test]
fn hexa_actuation_wrenches_lie_along_the_rods() {
    let model = common::robot("hexa.toml");
    let mut x = model.home_task();
    for (k, dx) in [
        0.02,
        -0.01,
        0.03,
        10f64.to_radians(),
        -10f64.to_radians(),
        5f64.to_radians(),
    ]
    .iter()
    .enumerate()
    {
        x[k] += dx;
    }
    let c = model
        .inverse_kinematics_configuration(&x, model.home_mode())
        .unwrap();
    let jac = model.screw_jacobians(&c).unwrap();
    let pose = pkm_robot_file::platform_pose(model.orientation(), &c.pose());
    for (i, leg) in model.legs().iter().enumerate() {
        let (
            pkm_robot_file::Joint::Revolute { axis, point },
            pkm_robot_file::Joint::Spherical { center },
        ) = (leg.joints[0], leg.joints[3])
        else {
            panic!("leg {i} is not R-U-S");
        };
        // Elbow: the home elbow turned by the actuator about its axis; S centre: with the platform.
        let q = model.actuators_of(&c)[i];
        let elbow_home = match leg.joints[1] {
            pkm_robot_file::Joint::Revolute { point, .. } => point,
            _ => unreachable!(),
        };
        let turn = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), q);
        let elbow = point + turn * (elbow_home - point);
        let home_pose = pkm_robot_file::platform_pose(model.orientation(), &model.home());
        let s_centre = pose * (home_pose.inverse() * nalgebra::Point3::from(center));
        let s = (s_centre.coords - elbow).normalize();
        let moment = elbow.cross(&s);
        let w = jac.j_a.row(i);
        let sign = w[0] * s.x + w[1] * s.y + w[2] * s.z;
        let expected = [s.x, s.y, s.z, moment.x, moment.y, moment.z].map(|v| v * sign.signum());
        for k in 0..6 {
            assert!(
                (w[k] - expected[k]).abs() < 1e-9,
                "leg {i}: {w} vs {expected:?}"
            );
        }
    }
}

/// Acceptance 8: the Stewart–Gough forward kinematics never reports more than 40 distinct
/// assembly modes, and every mode it reports closes.
#[test]
fn stewart_gough_at_most_forty_assembly_modes() {
    let model = common::robot("stewart_gough.toml");
    let q = model.home_actuators();
    let settings = EnumerationSettings {
        starts: 300,
        ..Default::default()
    };
    let modes = model.assembly_modes(&q, &settings).unwrap();
    println!("Stewart–Gough: {} assembly modes", modes.len());
    assert!((1..=40).contains(&modes.len()), "{}", modes.len());
    assert_genuine(&model, &q, &modes);
    assert_eq!(modes[0].home_label, Some(0));
}

#[test]
fn dietmaier_stewart_gough_has_forty_real_assembly_modes() {
    // Dietmaier 1998, "The Stewart-Gough platform of general geometry can have 40 real
    // postures": base and platform points and leg lengths as transcribed in
    // martyushev/fkSGP, python/test1_fkSGP.py (commit a7baed0).
    let model = common::robot("dietmaier_40.toml");
    let q = [1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071];
    let settings = EnumerationSettings {
        starts: 1500,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let modes = model.assembly_modes(&q, &settings).unwrap();
    println!(
        "Dietmaier: {} assembly modes in {:.1} s",
        modes.len(),
        start.elapsed().as_secs_f64()
    );
    assert_genuine(&model, &q, &modes);
    assert_eq!(modes.len(), 40);
}

/// A planar 3-RPR file: base joints at `a`, platform joints at `b` (platform frame), the platform
/// frame at `home` (unrotated) in the home pose, each P axis along its leg at home.
fn three_rpr_file(a: &[Vector2<f64>; 3], b: &[Vector2<f64>; 3], home: Vector2<f64>) -> String {
    let mut text = format!(
        "name = \"3-RPR\"\ntask = [\"x\", \"y\", \"rz\"]\n[home]\nposition = [{}, {}, 0.0]\n",
        home.x, home.y
    );
    for (a, b) in a.iter().zip(b) {
        let c = home + b;
        let d = c - a;
        text += &format!(
            "[[legs]]\njoints = [\n  {{ type = \"R\", axis = [0.0, 0.0, 1.0], point = [{}, {}, 0.0] }},\n  \
             {{ type = \"P\", axis = [{}, {}, 0.0], actuated = true, offset = {} }},\n  \
             {{ type = \"R\", axis = [0.0, 0.0, 1.0], point = [{}, {}, 0.0] }},\n]\n",
            a.x,
            a.y,
            d.x,
            d.y,
            d.norm(),
            c.x,
            c.y
        );
    }
    text
}

/// Every assembly mode of `model` at `q` has its full configuration, actuators back to `q` to
/// 1e-9 relative, and finite singularity margins; returns the number of modes.
fn assert_every_mode_solved(model: &RobotModel, q: &[f64], starts: usize) -> usize {
    let settings = EnumerationSettings {
        starts,
        ..EnumerationSettings::default()
    };
    let modes = model.assembly_modes(q, &settings).unwrap();
    let scale = q.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
    for m in &modes {
        let c = model
            .inverse_kinematics_configuration(&m.task, model.home_mode())
            .unwrap_or_else(|e| panic!("mode at {:?}: {e}", m.task));
        let back = model.actuators_of(&c);
        for (got, want) in back.iter().zip(q) {
            assert!((got - want).abs() < 1e-9 * scale, "{back} vs {q:?}");
        }
        let margins = model.singularity_margins(&c).unwrap();
        assert!(margins.inverse.is_finite() && margins.direct.is_finite());
    }
    modes.len()
}

/// Issue 29: a 3-RPR in the proportions of the planar examples of the literature (lengths of
/// 10 to 20 units, the home pose away from the origin) has six real assembly modes, and every
/// one has its configuration, J and margins. Before the two-stage leg solve, the passive joints
/// of one mode (the platform a half turn of leg 3 from home) did not converge from any start.
#[test]
fn three_rpr_every_assembly_mode_has_its_configuration() {
    let a = [
        Vector2::new(0.0, 0.0),
        Vector2::new(15.91, 0.0),
        Vector2::new(0.0, 10.0),
    ];
    let (l3, theta) = (20.84, 0.882_f64);
    let b = [
        Vector2::new(0.0, 0.0),
        Vector2::new(17.04, 0.0),
        Vector2::new(l3 * theta.cos(), l3 * theta.sin()),
    ];
    let q = [14.98, 15.38, 12.0];
    let model = RobotModel::from_toml(&three_rpr_file(&a, &b, Vector2::new(5.0, 8.0))).unwrap();
    assert_eq!(independent_rpr_count(&a, &b, &q), 6);
    assert_eq!(assert_every_mode_solved(&model, &q, 2_000), 6);
}

/// Issue 29, as a class: 3-RPR designs drawn at random at two scales (1 and 20 units), every
/// assembly mode found has its configuration. Before the two-stage leg solve, 11 of the 168
/// modes of 100 such designs failed.
#[test]
fn random_three_rpr_designs_reach_every_assembly_mode() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut point = |s: f64| {
        Vector2::new(
            s * rng.random_range(-1.0..1.0),
            s * rng.random_range(-1.0..1.0),
        )
    };
    let mut modes = 0;
    for k in 0..24 {
        let scale = if k % 2 == 0 { 1.0 } else { 20.0 };
        let home = point(scale);
        let a = [point(scale), point(scale), point(scale)];
        let b = [point(0.5 * scale), point(0.5 * scale), point(0.5 * scale)];
        let model = RobotModel::from_toml(&three_rpr_file(&a, &b, home)).unwrap();
        let q: Vec<f64> = (0..3)
            .map(|i| {
                (home + b[i] - a[i]).norm()
                    * (0.6 + 0.8 * (k as f64 * 0.37 + i as f64 * 0.23).fract())
            })
            .collect();
        modes += assert_every_mode_solved(&model, &q, 200);
    }
    assert!(modes >= 24, "{modes} modes in 24 designs");
}

/// Issue 29: a 3-RPR whose platform triangle is its base triangle, with three equal leg
/// lengths, translates on a circle of diameter 1 m (the legs stay parallel: a self-motion).
/// Its assembly modes at those lengths report the circle once, with the number of solutions
/// found on it and their extent (over half a metre, in characteristic lengths), instead of one
/// "mode" per solution (616 modes before, 614 of them on the circle); every other solution is
/// regular.
#[test]
fn a_self_motion_is_reported_once() {
    let a = [
        Vector2::new(-0.4, 0.0),
        Vector2::new(0.4, 0.0),
        Vector2::new(0.1, 0.5),
    ];
    let model = RobotModel::from_toml(&three_rpr_file(&a, &a, Vector2::new(0.0, 0.5))).unwrap();
    let settings = EnumerationSettings {
        starts: 1_000,
        ..EnumerationSettings::default()
    };
    let modes = model.assembly_modes(&[0.5, 0.5, 0.5], &settings).unwrap();
    let continua: Vec<_> = modes
        .iter()
        .filter_map(|m| m.self_motion.as_ref())
        .collect();
    let singular = modes.iter().filter(|m| m.is_singular(1e-6)).count();
    println!(
        "{} modes, {singular} singular, continua {continua:?}",
        modes.len()
    );
    assert_eq!(continua.len(), 1, "{continua:?}");
    assert_eq!(singular, 1, "{} modes", modes.len());
    let size = model.characteristic_length();
    assert!(continua[0].samples >= 50 && continua[0].extent > 0.5 / size);
    // The reported point lies on the circle: legs parallel, the platform unrotated.
    let task = &modes.iter().find(|m| m.self_motion.is_some()).unwrap().task;
    assert!(
        (task[0].hypot(task[1]) - 0.5).abs() < 1e-9 && task[2].abs() < 1e-9,
        "{task:?}"
    );
}
