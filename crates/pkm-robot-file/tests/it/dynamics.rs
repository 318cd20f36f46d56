//! Issue 31: the inverse dynamics of a robot file against the hand-written extended-space
//! model, between its two formulations, and against the energy balance.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use nalgebra::Vector3;
use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm_mechanisms::{Placement, RotaryDelta, presets};

/// The rotary Delta and NUWAR files with Miller's masses (`rotary_delta.toml`,
/// `nuwar.toml`) give the hand-written model's Lagrange torques (exact accelerations, rod
/// forearms) along the §3 pick-and-place cycle, to 1e-9 N·m at 101 samples, by both
/// formulations (measured: 2.6e-11 N·m on the Delta).
#[test]
fn delta_and_nuwar_files_reproduce_the_hand_written_torques() {
    for (name, design) in [
        (
            "rotary_delta.toml",
            presets::miller_delta(Placement::canonical()),
        ),
        ("nuwar.toml", presets::nuwar(Placement::canonical())),
    ] {
        let file = common::robot(name);
        let hand = ExtendedModel::new(
            RotaryDelta::new(design).unwrap(),
            &MassParameters::miller2004(),
        )
        .unwrap();
        along_the_cycle(&file, &hand);
    }
}

fn along_the_cycle(file: &pkm_robot_file::RobotModel, hand: &ExtendedModel) {
    let cycle = miller_pick_and_place(0.5).unwrap();
    let mut largest = 0.0_f64;
    for k in 0..=100 {
        let t = 0.5 * f64::from(k) / 100.0;
        let m = cycle.sample(t);
        let state = hand.joint_motion(&m.p, &m.v, &m.a).unwrap();
        let expected = hand
            .at(&state.q)
            .lagrange_torques(&state.qd, &state.qdd)
            .unwrap();
        let got = file
            .inverse_dynamics(
                m.p.as_slice(),
                m.v.as_slice(),
                m.a.as_slice(),
                file.home_mode(),
            )
            .unwrap();
        let q = file
            .inverse_kinematics(m.p.as_slice(), file.home_mode())
            .unwrap();
        let angles = Vector3::new(state.q[3], state.q[4], state.q[5]);
        assert!(
            (Vector3::from_column_slice(q.as_slice()) - angles).amax() < 1e-9,
            "t = {t}: angles {q} vs {angles}"
        );
        for (name, efforts) in [
            ("virtual work", &got.efforts),
            ("multipliers", &got.efforts_multipliers),
        ] {
            let e = Vector3::from_column_slice(efforts.as_slice());
            assert!(
                (e - expected).amax() < 1e-9,
                "t = {t}, {name}: {e} vs {expected}"
            );
        }
        largest = largest.max(expected.amax());
    }
    assert!(largest > 5.0, "the cycle's torques reach {largest} N·m");
}

/// A smooth task motion about home: $x_k(t) = x_{0k} + a_k\sin(w_k t + \varphi_k)$ with
/// amplitudes of 2 % of the robot's characteristic length or 0.04 rad.
fn wobble(model: &pkm_robot_file::RobotModel, t: f64) -> [Vec<f64>; 3] {
    let home = model.home_task();
    let names = model.task_names();
    let mut out = [home.clone(), vec![0.0; home.len()], vec![0.0; home.len()]];
    for (k, name) in names.iter().enumerate() {
        let angle = !matches!(*name, "x" | "y" | "z");
        let a = if angle {
            0.04
        } else {
            0.02 * model.characteristic_length()
        };
        let (w, phase) = (2.0 + 0.7 * k as f64, 0.3 + 1.1 * k as f64);
        let s = w * t + phase;
        out[0][k] += a * s.sin();
        out[1][k] = a * w * s.cos();
        out[2][k] = -a * w * w * s.sin();
    }
    out
}

/// The energy balance $\dot E = \tau\cdot\dot q$ (the efforts' power) along a smooth motion
/// of every robot file with masses, $\dot E$ by the fourth-order central difference of
/// $T + V$ ($h$ = 1e-4 s), to 1e-6 of the largest actuator power; and the two formulations equal to 1e-9 of the
/// largest effort where the actuation is not redundant.
#[test]
fn energy_balance_and_both_formulations_on_every_file() {
    let mut checked = 0;
    for file in common::all_files() {
        let model = common::robot(&file);
        let mode = model.home_mode();
        let at = |t: f64| {
            let [x, v, a] = wobble(&model, t);
            model.inverse_dynamics(&x, &v, &a, mode)
        };
        let t = 0.3;
        let now = at(t).unwrap_or_else(|e| panic!("{file}: {e}"));
        let energy = |dt: f64| {
            let d = at(t + dt).unwrap();
            d.kinetic_energy + d.potential_energy
        };
        let h = 1e-4;
        let rate =
            (8.0 * (energy(h) - energy(-h)) - (energy(2.0 * h) - energy(-2.0 * h))) / (12.0 * h);
        let powers = now.efforts.component_mul(&now.actuator_rates);
        let scale = powers.amax().max(1e-9);
        assert!(
            (rate - powers.sum()).abs() < 1e-6 * scale,
            "{file}: dE/dt {rate} vs power {}",
            powers.sum()
        );
        if model.actuator_count() == model.dof() {
            let gap = (&now.efforts - &now.efforts_multipliers).amax();
            assert!(
                gap < 1e-9 * now.efforts.amax(),
                "{file}: {} vs {}",
                now.efforts,
                now.efforts_multipliers
            );
        }
        checked += 1;
    }
    assert_eq!(checked, common::all_files().len());
}
