//! The testkit conformance checks of pkm-traits on robots from files: closure, J_x and J_q
//! against central differences, `velocity_jacobian_at` against its default, IK → FK round
//! trips in every working mode.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::print_stdout
)]

use crate::common;

use nalgebra::SVector;
use pkm_robot_file::Robot;
use pkm_traits::testkit::{
    check_closure, check_ik_fk_round_trip, check_jacobians_against_central_differences,
    check_traits, check_velocity_jacobian_at,
};

/// Poses on a grid of `steps` per axis around `centre` with half-widths `half`.
fn grid<const N: usize>(centre: [f64; N], half: [f64; N], steps: usize) -> Vec<SVector<f64, N>> {
    let mut out = Vec::new();
    let total = steps.pow(N as u32);
    for index in 0..total {
        let mut k = index;
        let x = SVector::<f64, N>::from_fn(|i, _| {
            let s = k % steps;
            k /= steps;
            centre[i] + half[i] * (2.0 * s as f64 / (steps - 1) as f64 - 1.0)
        });
        out.push(x);
    }
    out
}

fn conform<const N: usize>(robot: &Robot<N>, poses: &[SVector<f64, N>]) {
    for mode in robot.model().working_modes() {
        let closure = check_closure(robot, mode, poses, 1e-10).unwrap();
        let fd =
            check_jacobians_against_central_differences(robot, mode, poses, 1e-6, 1e-6).unwrap();
        let vj = check_velocity_jacobian_at(robot, mode, poses, 1e-9).unwrap();
        let rt = check_ik_fk_round_trip(robot, mode, poses, 1e-3, 1e-9).unwrap();
        println!(
            "{} mode {:#b}: closure {:.1e} ({} poses), FD {:.1e}, J {:.1e}, round trip {:.1e} ({} skipped)",
            robot.model().name(),
            mode.0,
            closure.max_error,
            closure.checked,
            fd.max_error,
            vj.max_error,
            rt.max_error,
            rt.skipped
        );
    }
}

#[test]
fn traits_are_shareable() {
    check_traits::<Robot<3>>();
}

#[test]
fn five_bar_in_all_four_working_modes() {
    let robot = Robot::<2>::new(common::robot("five_bar.toml")).unwrap();
    conform(&robot, &grid([0.0, 0.33], [0.06, 0.05], 4));
}

#[test]
fn rotary_delta_in_all_eight_working_modes() {
    let robot = Robot::<3>::new(common::robot("rotary_delta.toml")).unwrap();
    conform(&robot, &grid([0.0, 0.0, -0.7], [0.08, 0.08, 0.1], 3));
}

#[test]
fn three_prs_with_parasitic_motion() {
    let robot = Robot::<3>::new(common::robot("three_prs.toml")).unwrap();
    conform(&robot, &grid([0.5, 0.0, 0.0], [0.03, 0.15, 0.15], 3));
}

#[test]
fn stewart_gough() {
    let robot = Robot::<6>::new(common::robot("stewart_gough.toml")).unwrap();
    conform(
        &robot,
        &grid(
            [0.0, 0.0, 0.3, 0.0, 0.0, 0.0],
            [0.02, 0.02, 0.02, 0.08, 0.08, 0.08],
            2,
        ),
    );
}
