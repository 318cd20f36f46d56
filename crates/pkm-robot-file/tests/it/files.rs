//! Every example robot file loads, passes its mobility check, and its inverse kinematics at
//! home returns the home actuator coordinates in the home working mode.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::print_stdout
)]

use crate::common;

#[test]
fn every_example_file_loads_and_reproduces_home() {
    let files = common::all_files();
    assert!(files.len() >= 3, "vacuous: {files:?}");
    for name in files {
        let robot = common::robot(&name);
        let q = robot
            .inverse_kinematics(&robot.home_task(), robot.home_mode())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let home = robot.home_actuators();
        let err = q
            .iter()
            .zip(&home)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!(
            "{name}: solvers {:?}, modes {}, home error {err:.2e}",
            robot.leg_solvers(),
            robot.working_modes().len()
        );
        assert!(err < 1e-9, "{name}: {q:?} vs {home:?}");
    }
}
