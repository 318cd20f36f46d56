//! Issue 32: the assembly-mode study of a robot file: Dietmaier's 40 modes with the homotopy's
//! statement of completeness, a mode at a commanded pose found again, every mode closing the
//! robot at its actuators (its inverse kinematics in some working mode gives them back), the
//! multistart for a robot without a polynomial form, and the refusals at their keys.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_robot_file::RobotModel;
use pkm_study::assembly::{AssemblyQuery, AssemblyStudy, SearchSpec};
use pkm_study::schema::mechanism::MechanismSpec;
use pkm_study::{Artifact, StudyError, assembly, from_toml_str};
use pkm_traits::Silent;
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// A study of `robot` (a file of `examples/robots/`) with the `[assembly]` table `section`,
/// its robot file resolved as a front end does.
fn study(robot: &str, section: &str) -> AssemblyStudy {
    let text =
        format!("[mechanism.robot_file]\nfile = \"../robots/{robot}\"\n[assembly]\n{section}\n");
    let mut study: AssemblyStudy = from_toml_str(&text).unwrap();
    resolve(&mut study);
    study
}

fn resolve(study: &mut AssemblyStudy) {
    let MechanismSpec::RobotFile(spec) = &mut study.mechanism else {
        panic!("a robot file")
    };
    spec.resolve_file(&pkm_study::load::Directory(examples().join("studies")))
        .unwrap();
}

fn model(robot: &str) -> RobotModel {
    RobotModel::from_toml(&std::fs::read_to_string(examples().join("robots").join(robot)).unwrap())
        .unwrap()
}

/// Every mode closes the robot at the query's actuators: the inverse kinematics of its task
/// coordinates, in one of the robot's working modes, gives them back to `tolerance`.
fn assert_every_mode_closes(model: &RobotModel, query: &AssemblyQuery, tolerance: f64) {
    for (j, mode) in query.modes.iter().enumerate() {
        let nearest = model
            .working_modes()
            .into_iter()
            .filter_map(|w| model.inverse_kinematics(&mode.task, w).ok())
            .map(|q| {
                q.iter()
                    .zip(&query.actuators)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max)
            })
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < tolerance, "mode {j}: {nearest:e}");
    }
}

#[test]
fn dietmaiers_forty_modes_are_complete_and_a_commanded_pose_is_found_again() {
    let text =
        std::fs::read_to_string(examples().join("studies/dietmaier_assembly_modes.toml")).unwrap();
    let mut example: AssemblyStudy = from_toml_str(&text).unwrap();
    resolve(&mut example);
    let outcome = assembly(&example, &Silent).unwrap();
    let result = &outcome.result;
    assert_eq!(result.form.as_deref(), Some("spatial (Study parameters)"));
    let [forty, above] = result.queries.as_slice() else {
        panic!("two queries")
    };
    let report = forty.homotopy.as_ref().unwrap();
    assert!(forty.complete && !forty.multistart);
    assert_eq!(
        (report.generic_solutions, report.real, forty.modes.len()),
        (40, 40, 40)
    );
    let robot = model("dietmaier_40.toml");
    assert_every_mode_closes(&robot, forty, 1e-9);
    // The pose asked for is among the modes at its actuators (a round trip IK → FK).
    let asked = [0.0, 0.0, 1.02, 0.0, 0.0, 0.0];
    assert!(above.complete);
    assert!(
        above
            .modes
            .iter()
            .any(|m| { m.task.iter().zip(asked).all(|(a, b)| (a - b).abs() < 1e-9) })
    );
    assert_every_mode_closes(&robot, above, 1e-9);
    // Labels were not asked for; the table has a row per mode.
    assert!(forty.modes.iter().all(|m| m.home_label.is_none()));
    let rows = outcome.artifacts.iter().find_map(|a| match a {
        Artifact::Table { name, table } if name == "modes.csv" => Some(table.rows.len()),
        _ => None,
    });
    assert_eq!(rows, Some(42));
    assert!(
        outcome.summary[0].contains("complete: 40 paths, 40 real"),
        "{:?}",
        outcome.summary
    );
}

#[test]
fn home_is_the_first_mode_labelled_zero_and_the_multistart_alone_says_nothing_more() {
    let outcome = assembly(&study("three_rpr.toml", ""), &Silent).unwrap();
    let [home] = outcome.result.queries.as_slice() else {
        panic!("the home query")
    };
    let robot = model("three_rpr.toml");
    assert_eq!(home.actuators, robot.home_actuators());
    assert_eq!(home.modes[0].home_label, Some(0));
    let home_pose = robot.home();
    assert!(
        home.modes[0]
            .pose
            .iter()
            .zip(home_pose)
            .all(|(a, b)| (a - b).abs() < 1e-9),
        "{:?}",
        home.modes[0].pose
    );
    assert_every_mode_closes(&robot, home, 1e-9);
    let multistart = study("three_rpr.toml", "search = \"multistart\"\nstarts = 50");
    let alone = assembly(&multistart, &Silent).unwrap();
    let q = &alone.result.queries[0];
    assert!(q.multistart && q.homotopy.is_none() && !q.complete);
    assert_eq!(
        multistart.assembly.search,
        SearchSpec::Multistart,
        "the setting was read"
    );
}

#[test]
fn a_robot_without_a_polynomial_form_runs_the_multistart_and_says_why() {
    let outcome = assembly(&study("three_ppsr.toml", "starts = 40"), &Silent).unwrap();
    let result = &outcome.result;
    assert_eq!(result.form, None);
    assert_eq!(
        result.unsupported.as_deref(),
        Some("a leg with several actuators")
    );
    let q = &result.queries[0];
    assert!(q.multistart && !q.complete && q.homotopy.is_none());
    // Its legs are solved numerically from home: the inverse kinematics from the task
    // coordinates finds the legs near home, so only the mode nearest home is checked by it.
    let home_mode = AssemblyQuery {
        modes: q.modes[..1].to_vec(),
        ..q.clone()
    };
    assert_every_mode_closes(&model("three_ppsr.toml"), &home_mode, 1e-9);
    assert!(outcome.summary[0].contains("no statement of completeness"));
}

#[test]
fn bad_queries_are_refused_at_their_keys() {
    let refused = |robot: &str, section: &str| match assembly(&study(robot, section), &Silent) {
        Err(StudyError::Invalid { path, message }) => format!("{path}: {message}"),
        other => panic!("{section}: {other:?}"),
    };
    let short = refused("three_rpr.toml", "actuators = [[0.3, 0.3]]");
    assert!(
        short.starts_with("assembly.actuators[0]: 2 values for 3"),
        "{short}"
    );
    let pose = refused("three_rpr.toml", "poses = [[0.0, 0.0]]");
    assert!(
        pose.starts_with("assembly.poses[0]: 2 values for 3"),
        "{pose}"
    );
    let far = refused("three_rpr.toml", "poses = [[0.0, 0.0, 4.0]]");
    assert!(far.starts_with("assembly.poses[0]:"), "{far}");
    let negative = refused("stewart_gough.toml", "actuators = [[-1.0, 1, 1, 1, 1, 1]]");
    assert!(negative.starts_with("assembly.actuators[0]:"), "{negative}");
    let starts = refused("three_rpr.toml", "starts = 100001");
    assert!(
        starts.starts_with("assembly.starts: at most 100000"),
        "{starts}"
    );
    let many = format!("actuators = [{}]", vec!["[0.3, 0.3, 0.3]"; 1001].join(", "));
    assert!(refused("three_rpr.toml", &many).starts_with("assembly: 1001 queries"));
    let not_a_file: AssemblyStudy =
        from_toml_str("[mechanism]\ntsai = { a = 0.2, b = 0.3 }\n[assembly]\n")
            .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(
        assembly(&not_a_file, &Silent),
        Err(StudyError::Invalid { ref path, .. }) if path.to_string() == "mechanism"
    ));
    let nan: Result<AssemblyStudy, _> =
        from_toml_str("[mechanism.robot_file]\nfile = \"x\"\n[assembly]\nactuators = [[nan]]\n");
    assert!(nan.is_err());
}

#[test]
fn a_cancelled_study_stops() {
    struct Stop;
    impl pkm_traits::Progress for Stop {
        fn is_cancelled(&self) -> bool {
            true
        }
    }
    assert!(matches!(
        assembly(&study("three_rpr.toml", ""), &Stop),
        Err(StudyError::Cancelled)
    ));
}

#[test]
fn extreme_actuators_give_a_typed_error_or_finite_modes() {
    for value in ["1e300", "-1e300", "1e-300", "0.0", "1e9"] {
        let section = format!("actuators = [[{value}, 0.3, 0.3]]\nlabel = false\nstarts = 20");
        match assembly(&study("three_rpr.toml", &section), &Silent) {
            Ok(outcome) => {
                for mode in &outcome.result.queries[0].modes {
                    assert!(mode.pose.iter().all(|v| v.is_finite()), "{value}: {mode:?}");
                    assert!(mode.direct_margin.is_finite() && mode.inverse_margin.is_finite());
                }
            }
            Err(StudyError::Invalid { path, .. }) => {
                assert_eq!(path.to_string(), "assembly.actuators[0]", "{value}");
            }
            Err(other) => panic!("{value}: {other:?}"),
        }
    }
}
