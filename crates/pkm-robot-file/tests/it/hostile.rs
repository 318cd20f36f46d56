//! Every public entry point fed hostile input: typed errors, never a panic or a hang.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::print_stdout
)]

use crate::common;

use pkm_robot_file::{EnumerationSettings, Robot, RobotFileError, RobotModel, WorkingMode};
use pkm_traits::{
    ClosedChain, ForwardKinematics, InverseKinematics, KinematicsError, NewtonSettings,
};

/// The five-bar file with `from` replaced by `to`.
fn edited(from: &str, to: &str) -> Result<RobotModel, RobotFileError> {
    let text = common::robot_text("five_bar.toml");
    assert!(text.contains(from), "{from}");
    RobotModel::from_toml(&text.replacen(from, to, 1))
}

#[test]
fn malformed_files_are_typed_errors() {
    let parse = |r: Result<RobotModel, RobotFileError>| matches!(r, Err(RobotFileError::Parse { line, .. }) if line > 0);
    assert!(parse(RobotModel::from_toml("name = ")));
    assert!(parse(edited(
        "task = [\"x\", \"y\"]",
        "task = [\"x\", \"y\"]\ncolour = 3"
    )));
    assert!(parse(edited("type = \"R\"", "type = \"Q\"")));
    assert!(matches!(
        RobotModel::from_toml(""),
        Err(RobotFileError::Parse { .. })
    ));
    let invalid =
        |r: Result<RobotModel, RobotFileError>| matches!(r, Err(RobotFileError::Invalid { .. }));
    for (from, to) in [
        ("point = [-0.08, 0.0, 0.0]", "point = [nan, 0.0, 0.0]"),
        ("point = [-0.08, 0.0, 0.0]", "point = [inf, 0.0, 0.0]"),
        ("point = [-0.08, 0.0, 0.0]", "point = [1e300, 0.0, 0.0]"),
        (
            "axis = [0.0, 0.0, 1.0], point = [-0.08",
            "axis = [0.0, 0.0, 0.0], point = [-0.08",
        ),
        ("actuated = true }", "actuated = true, offset = nan }"),
        (
            "actuated = true }",
            "actuated = true, limits = [1.0, -1.0] }",
        ),
        ("actuated = true }", "actuated = false }"),
        (
            "type = \"R\", axis = [0.0, 0.0, 1.0], point = [-0.2",
            "type = \"S\", axis = [0.0, 0.0, 1.0], point = [-0.2",
        ),
        ("task = [\"x\", \"y\"]", "task = [\"x\", \"w\"]"),
        ("task = [\"x\", \"y\"]", "task = [\"x\", \"x\"]"),
        ("task = [\"x\", \"y\"]", "task = []"),
        (
            "characteristic_length = 0.2",
            "characteristic_length = -1.0",
        ),
        ("position = [0.0, 0.37, 0.0]", "position = [0.0, nan, 0.0]"),
    ] {
        let r = edited(from, to);
        assert!(invalid(r.clone()), "{to}: {r:?}");
    }
    let name = edited("name = \"2-RRR\"", "name = \"3-RRR\"");
    assert!(
        matches!(name, Err(RobotFileError::NameMismatch { ref found, .. }) if found == "2-RRR"),
        "{name:?}"
    );
    assert!(edited("name = \"2-RRR\"", "name = \"2-R\u{332}RR\"").is_ok());
    assert!(matches!(
        edited("name = \"2-RRR\"", "name = \"2-RR\u{332}R\""),
        Err(RobotFileError::NameMismatch { .. })
    ));
}

#[test]
fn empty_and_oversized_robots_are_refused() {
    let text = common::robot_text("three_prs.toml");
    for (from, to) in [("count = 3", "count = 0"), ("count = 3", "count = 1000000")] {
        let r = RobotModel::from_toml(&text.replacen(from, to, 1));
        assert!(
            matches!(r, Err(RobotFileError::Invalid { .. })),
            "{to}: {r:?}"
        );
    }
    let no_legs = "name = \"1-R\"\ntask = [\"x\"]\nlegs = []\n[home]\nposition = [0.0, 0.0, 0.0]\n";
    assert!(matches!(
        RobotModel::from_toml(no_legs),
        Err(RobotFileError::Invalid { .. })
    ));
    let empty_leg = "name = \"1-R\"\ntask = [\"x\"]\n[home]\nposition = [0.0, 0.0, 0.0]\n[[legs]]\njoints = []\n";
    assert!(matches!(
        RobotModel::from_toml(empty_leg),
        Err(RobotFileError::Invalid { .. })
    ));
}

/// Park's 3-UPU (all upper U-joint normals vertical) lets the platform tilt: declaring it
/// translational is refused with the twist system found (dimension 5).
#[test]
fn a_wrong_mobility_is_refused_with_the_twist_system() {
    let text = common::robot_text("three_upu.toml");
    // Turn each leg's platform-side U into a spherical joint: the legs are then 6-DOF UPS…
    let mut edited = String::new();
    for line in text.lines() {
        if line.contains("type = \"U\"") && line.contains("0.3]") {
            let point = &line[line.find("point").unwrap()..];
            edited.push_str(&format!("  {{ type = \"S\", {point}\n"));
        } else {
            edited.push_str(line);
            edited.push('\n');
        }
    }
    let edited = edited.replace("name = \"3-UPU\"", "name = \"3-UPS\"");
    match RobotModel::from_toml(&edited) {
        Err(RobotFileError::Mobility {
            found,
            twist_system,
            reason,
        }) => {
            assert_eq!(found, 6);
            assert_eq!(twist_system.len(), 6);
            // Issue 29: the error names the keys and each leg's constraints.
            for part in ["`task`", "legs[0]: 0", "legs[2]: 0"] {
                assert!(reason.contains(part), "{part} in {reason}");
            }
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn hostile_poses_and_joints_are_typed_errors() {
    let robot = Robot::<3>::new(common::robot("three_prs.toml")).unwrap();
    let mode = robot.model().home_mode();
    for x in [
        [f64::NAN, 0.0, 0.0],
        [0.5, f64::INFINITY, 0.0],
        [1e300, 0.0, 0.0],
        [0.5, 1e6, -1e6],
    ] {
        let x = x.into();
        let ik = robot.inverse_kinematics(&x, mode);
        assert!(ik.is_err(), "{x}: {ik:?}");
        assert!(robot.velocity_jacobian_at(&x, mode).is_err());
        let phi = robot.closure(&x, &[0.35; 3].into());
        assert!(phi.iter().all(|v| v.is_nan()), "{x}: {phi:?}");
    }
    let settings = NewtonSettings::default();
    let home = [0.5, 0.0, 0.0].into();
    for q in [
        [f64::NAN, 0.35, 0.35],
        [1e300, 0.35, 0.35],
        [5.0, -5.0, 0.35],
    ] {
        let fk = robot.forward_kinematics(&q.into(), &home, &settings);
        assert!(fk.is_err(), "{q:?}: {fk:?}");
    }
    let bad = NewtonSettings {
        tolerance: f64::NAN,
        ..settings
    };
    assert!(matches!(
        robot.forward_kinematics(&[0.35; 3].into(), &home, &bad),
        Err(KinematicsError::InvalidInput(_))
    ));
    let model = robot.model();
    assert!(matches!(
        model.inverse_kinematics(&[0.5], mode),
        Err(KinematicsError::InvalidInput(_))
    ));
    assert!(
        model
            .inverse_kinematics(&[], WorkingMode(u64::MAX))
            .is_err()
    );
    let too_many = EnumerationSettings {
        starts: usize::MAX,
        ..Default::default()
    };
    assert!(matches!(
        model.assembly_modes(&[0.35; 3], &too_many),
        Err(KinematicsError::InvalidInput(_))
    ));
    let nan_distinct = EnumerationSettings {
        distinct: f64::NAN,
        ..Default::default()
    };
    assert!(model.assembly_modes(&[0.35; 3], &nan_distinct).is_err());
    assert!(
        model
            .assembly_modes(&[0.35, f64::NAN, 0.35], &EnumerationSettings::default())
            .is_err()
    );
    // Actuator limits: the sliders of the file stay in [0, 1] m (the closure has no limits).
    assert!(matches!(
        model.inverse_kinematics(&[50.0, 0.0, 0.0], mode),
        Err(KinematicsError::Unreachable { .. })
    ));
    assert!(matches!(
        Robot::<2>::new(model.clone()),
        Err(RobotFileError::Dimension {
            expected: 2,
            found: 3
        })
    ));
}

/// Issue 29: a subnormal `characteristic_length` loaded and then made `singularity_margins`
/// and `assembly_modes` loop forever (an infinity in the margins' SVD). Scales are bounded at
/// load, with the key, and every decomposition runs with an iteration bound: at both ends of
/// the admissible range the margins are finite and come back.
#[test]
fn extreme_scales_are_refused_or_give_finite_margins() {
    for bad in ["5e-324", "1e-310", "1e-300", "1e-7", "1e7", "inf"] {
        let r = edited(
            "characteristic_length = 0.2",
            &format!("characteristic_length = {bad}"),
        );
        match r {
            Err(RobotFileError::Invalid { ref key, .. }) => {
                assert_eq!(key, "characteristic_length", "{bad}")
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
    for good in ["1e-6", "1e6"] {
        let model = edited(
            "characteristic_length = 0.2",
            &format!("characteristic_length = {good}"),
        )
        .unwrap();
        let home = model
            .inverse_kinematics_configuration(&model.home_task(), model.home_mode())
            .unwrap();
        let m = model.singularity_margins(&home).unwrap();
        let values = [m.inverse, m.direct, m.constraint.unwrap_or(0.0)];
        assert!(
            values.iter().all(|v| v.is_finite() && *v >= 0.0),
            "{good}: {m:?}"
        );
    }
}

/// Issue 29: fixed-length arrays with extra entries (`axis = [0, 0, 1, 7, "junk"]`) loaded
/// with the extra entries dropped. Every fixed-length array refuses them, naming the length
/// it got, never quoting a huge array.
#[test]
fn fixed_length_arrays_refuse_extra_and_missing_entries() {
    for (from, to) in [
        (
            "position = [0.0, 0.37, 0.0]",
            "position = [0.0, 0.37, 0.0, 5.0]",
        ),
        ("position = [0.0, 0.37, 0.0]", "position = [0.0, 0.37]"),
        (
            "axis = [0.0, 0.0, 1.0]",
            "axis = [0.0, 0.0, 1.0, 7.0, \"junk\"]",
        ),
        ("axis = [0.0, 0.0, 1.0]", "axis = [0.0, 0.0]"),
    ] {
        let e = edited(from, to).expect_err(to);
        let text = e.to_string();
        assert!(text.contains("exactly"), "{to}: {text}");
    }
    let huge = format!("axis = [0.0, 0.0, 1.0{}]", ", 0.0".repeat(100_000));
    let e = edited("axis = [0.0, 0.0, 1.0]", &huge)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("100003") && e.len() < 400,
        "{}",
        &e[..e.len().min(400)]
    );
}

/// Issue 29: with `dependent = ["rz"]` the Orthoglide solved its dependent coordinate once per
/// working mode of every point (83 s for a 4,096-point study over all eight modes). It is now
/// solved once per point and thread and kept: the kept solution is exactly what the solver
/// computes, for points in and out of reach, whatever the order of models and modes.
#[test]
fn the_kept_dependent_solution_is_exactly_the_computed_one() {
    let text = common::robot_text("orthoglide.toml").replacen(
        "task = [\"x\", \"y\", \"z\"]",
        "task = [\"x\", \"y\", \"z\"]\ndependent = [\"rz\"]",
        1,
    );
    let a = RobotModel::from_toml(&text).unwrap();
    let b = RobotModel::from_toml(&text).unwrap();
    let modes = a.working_modes();
    let points = [[0.05, -0.02, 0.1], [0.9, 0.9, 0.9], [-0.1, 0.0, 0.02]];
    for x in points {
        // First call per model and point, then every mode alternating between the models.
        let fresh_a = a.inverse_kinematics_configuration(&x, modes[0]);
        for &mode in &modes {
            let ra = a.inverse_kinematics_configuration(&x, mode);
            let rb = b.inverse_kinematics_configuration(&x, mode);
            assert_eq!(format!("{ra:?}"), format!("{rb:?}"), "{x:?} {mode:?}");
        }
        let again = a.inverse_kinematics_configuration(&x, modes[0]);
        assert_eq!(format!("{fresh_a:?}"), format!("{again:?}"));
    }
}

/// Issue 29: a 50 MB file was refused for its leg count only after it was parsed (8.7–29 s).
/// A file above `MAX_FILE_BYTES` is refused by its size before anything is parsed.
#[test]
fn an_oversized_file_is_refused_by_its_size_first() {
    let text = common::robot_text("five_bar.toml");
    let huge = format!("{text}\n{}", "#".repeat(pkm_robot_file::MAX_FILE_BYTES));
    match RobotModel::from_toml(&huge) {
        Err(RobotFileError::Invalid { key, .. }) => assert_eq!(key, "file"),
        other => panic!("{other:?}"),
    }
    assert!(RobotModel::from_toml(&text).is_ok());
}

/// Issue 29: a dropped `[symmetry]` header put its keys into `[home]` and the error said only
/// "unknown field"; it now names the table the key was read in.
#[test]
fn an_unknown_key_names_the_table_it_was_read_in() {
    let text = common::robot_text("three_prs.toml");
    assert!(text.contains("[symmetry]\n"));
    let e = RobotModel::from_toml(&text.replacen("[symmetry]\n", "", 1)).unwrap_err();
    let message = e.to_string();
    assert!(
        message.contains("[home]") && message.contains("header"),
        "{message}"
    );
}

/// A five-bar whose distal links are as long as its proximal ones reaches its base joint: with
/// the end point on motor 0's axis (a type I singularity, that motor's angle free) the
/// inverse kinematics gives an angle in every working mode instead of "discriminant NaN < 0".
#[test]
fn a_leg_folded_onto_its_base_joint_has_a_free_angle() {
    let text = common::robot_text("five_bar.toml")
        .replace("[-0.2, 0.16, 0.0]", "[-0.18, 0.17320508075688773, 0.0]")
        .replace("[0.2, 0.16, 0.0]", "[0.18, 0.17320508075688773, 0.0]")
        .replace("[0.0, 0.37, 0.0]", "[0.0, 0.2603830596277012, 0.0]");
    let model = RobotModel::from_toml(&text).unwrap();
    for mode in model.working_modes() {
        let q = model.inverse_kinematics(&[-0.08, 0.0], mode).unwrap();
        assert!(q.iter().all(|v| v.is_finite()), "{q:?}");
        // Leg 1 still has its two closed-form branches: |P − A2| = 0.16 < 0.4.
        let config = model.inverse_kinematics_configuration(&[-0.08, 0.0], mode);
        assert!(config.is_ok(), "{mode:?}: {config:?}");
    }
    // Beyond the folded pose by a little, motor 0's angle is determined again.
    let near = model.inverse_kinematics(&[-0.08, 0.01], model.home_mode());
    assert!(near.is_ok(), "{near:?}");
}

/// Issue 33: the refusals around passive legs name the key and the reason.
#[test]
fn passive_leg_mistakes_are_refused_with_their_key() {
    // The legs' links go with their joints: dropped, as the edits below change the joints.
    let text = common::without_links(&common::robot_text("tricept.toml"));
    let passive = text.find("[[legs]]   # the passive leg").unwrap();
    let refused = common::refused_at;
    // The passive leg first: the actuators would be numbered past it.
    let first = text.find("[[legs]]").unwrap();
    let (head, actuated, rest) = (&text[..first], &text[first..passive], &text[passive..]);
    refused(
        &format!("{head}{rest}\n{actuated}"),
        "legs[1]",
        "passive leg legs[0]",
    );
    // A passive leg that constrains nothing (a UPS: six freedoms).
    let free = text.replace(
        "  { type = \"P\", axis = [0.0, 0.0, 1.0] },\n]",
        "  { type = \"P\", axis = [0.0, 0.0, 1.0] },\n  { type = \"S\", point = [0.0, 0.0, 0.6] },\n]",
    );
    refused(
        &free.replace("3-UPS+UP", "3-UPS+UPS"),
        "legs[3]",
        "must constrain",
    );
    // An actuated S joint.
    let ball = text.replacen(
        "{ type = \"S\", point",
        "{ type = \"S\", actuated = true, point",
        1,
    );
    refused(&ball, "legs[0].joints[2].type", "only an R or a P");
    // A second actuator in series with the first along its line (the Tricept's slider on the
    // passive leg's line, made an actuated leg of its own with two coaxial P joints).
    let coaxial = text.replace(
        "  { type = \"P\", axis = [0.0, 0.0, 1.0] },\n]",
        "  { type = \"P\", axis = [0.0, 0.0, 1.0], actuated = true, offset = 0.6 },\n  \
         { type = \"P\", axis = [0.0, 0.0, 1.0], actuated = true, offset = 0.0 },\n]",
    );
    refused(
        &coaxial.replace("3-UPS+UP", "3-UPS+UPP"),
        "legs[3].joints[1]",
        "cannot be driven independently",
    );
    // Four actuators for three task coordinates: a redundantly actuated robot, accepted.
    let four = text.replace(
        "{ type = \"P\", axis = [0.0, 0.0, 1.0] }",
        "{ type = \"P\", axis = [0.0, 0.0, 1.0], actuated = true, offset = 0.6 }",
    );
    assert_eq!(RobotModel::from_toml(&four).unwrap().actuator_count(), 4);
    // Two actuators for three task coordinates: refused.
    let exechon = common::robot_text("exechon.toml");
    let short = exechon.replace(
        "axis = [0.0, -0.3, 0.8], actuated = true, offset = 0.8544003745317531, limits = [0.5, 1.2] }",
        "axis = [0.0, -0.3, 0.8] }",
    );
    refused(&short, "task", "2 actuators");
}

/// A configuration of another robot, and non-finite or absurd inputs to the functions added
/// for redundant actuation: typed errors, never a panic or a silent NaN.
#[test]
fn foreign_configurations_and_hostile_redundancy_inputs_are_typed_errors() {
    let (four, tsai) = (common::robot("four_rrr.toml"), common::robot("tsai.toml"));
    let foreign = tsai
        .inverse_kinematics_configuration(&tsai.home_task(), tsai.home_mode())
        .unwrap();
    assert!(four.screw_jacobians(&foreign).is_err());
    assert!(four.singularity_margins(&foreign).is_err());
    assert!(four.force_distribution(&foreign, &[1.0; 6], None).is_err());
    assert!(
        four.forward_kinematics_from(&four.home_actuators(), &foreign)
            .is_err()
    );
    assert!(four.actuators_of(&foreign)[3].is_nan());
    assert!(four.leg_clearance(&foreign).is_none());
    assert!(four.passive_bends(&foreign).is_none());
    let home = four
        .inverse_kinematics_configuration(&four.home_task(), four.home_mode())
        .unwrap();
    let q = four.home_actuators();
    for bad in [f64::NAN, f64::INFINITY, -f64::INFINITY] {
        assert!(
            four.force_distribution(&home, &[bad, 0.0, 0.0, 0.0, 0.0, 0.0], None)
                .is_err()
        );
        let mut q_bad = q.clone();
        q_bad[1] = bad;
        assert!(
            four.forward_kinematics_least_squares(&q_bad, &[0.0; 3])
                .is_err(),
            "{bad}"
        );
        assert!(
            four.forward_kinematics_least_squares(&q, &[0.0, bad, 0.0])
                .is_err(),
            "{bad}"
        );
    }
    for limits in [
        vec![[0.0, 1.0]; 3],
        vec![[1.0, 0.0]; 4],
        vec![[f64::NAN, 1.0]; 4],
    ] {
        assert!(
            four.force_distribution(&home, &[1.0; 6], Some(&limits))
                .is_err()
        );
    }
    let wide = vec![[-f64::INFINITY, f64::INFINITY]; 4];
    let d = four.force_distribution(
        &home,
        &[1e300, -1e300, 0.0, 5e-324, 0.0, 1e300],
        Some(&wide),
    );
    assert!(
        d.as_ref()
            .is_ok_and(|d| d.efforts.iter().all(|t| t.is_finite()))
            || d.is_err(),
        "{d:?}"
    );
    assert!(
        four.forward_kinematics_least_squares(&[1e300; 4], &[0.0; 3])
            .is_err()
    );
}
