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
/// largest effort where the actuation is not redundant; `actuator_efforts` gives the
/// efforts to the bit.
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
        let [x, v, a] = wobble(&model, t);
        assert_eq!(
            model.actuator_efforts(&x, &v, &a, mode).unwrap(),
            now.efforts,
            "{file}: the efforts alone differ from inverse_dynamics'"
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

/// Issue 31's bad input: masses and tensors a body cannot have, mass fields where they mean
/// nothing, and task motions the dynamics cannot take are typed errors with their key or
/// reason, never a panic or a NaN effort.
#[test]
fn bad_masses_and_motions_are_typed_errors() {
    use pkm_robot_file::{DynamicsError, RobotModel};
    let text = common::robot_text("stewart_gough.toml");
    let refused_at =
        |edited: String, key: &str, words: &str| common::refused_at(&edited, key, words);
    let platform =
        "mass = 1.0\ninertia = [[0.0016, 0.0, 0.0], [0.0, 0.0016, 0.0], [0.0, 0.0, 0.0032]]";
    assert!(text.contains(platform));
    let with_platform = |edited: &str| text.replacen(platform, edited, 1);
    for (mass, words) in [("-1.0", "at least 0"), ("nan", "finite"), ("1e300", "1e9")] {
        refused_at(
            with_platform(&platform.replace("mass = 1.0", &format!("mass = {mass}"))),
            "platform.mass",
            words,
        );
    }
    for (inertia, words) in [
        (
            "[[0.0016, 0.001, 0.0], [0.0, 0.0016, 0.0], [0.0, 0.0, 0.0032]]",
            "symmetric",
        ),
        (
            "[[0.0016, 0.0, 0.0], [0.0, -0.0016, 0.0], [0.0, 0.0, 0.0032]]",
            "semidefinite",
        ),
        (
            "[[0.0016, 0.0, 0.0], [0.0, 0.0016, 0.0], [0.0, 0.0, 0.004]]",
            "triangle",
        ),
        (
            "[[inf, 0.0, 0.0], [0.0, 0.0016, 0.0], [0.0, 0.0, 0.0032]]",
            "finite",
        ),
    ] {
        refused_at(
            with_platform(&format!("mass = 1.0\ninertia = {inertia}")),
            "platform.inertia",
            words,
        );
    }
    // Arrays with an extra element are refused by the parser, never truncated.
    for extra in [
        "mass = 1.0\ncenter_of_mass = [0.0, 0.0, 0.3, 7.0]",
        "mass = 1.0\ninertia = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]",
        "mass = 1.0\ninertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]",
    ] {
        let r = RobotModel::from_toml(&with_platform(extra));
        assert!(
            matches!(r, Err(pkm_robot_file::RobotFileError::Parse { line, .. }) if line > 0),
            "{r:?}"
        );
    }
    refused_at(
        with_platform("mass = 1.0\ncenter_of_mass = [1e300, 0.0, 0.0]"),
        "platform.center_of_mass",
        "±1e6",
    );
    let first_link = text.find("  { mass = 0.2274").unwrap();
    let end = first_link + text[first_link..].find('\n').unwrap() + 1;
    refused_at(
        format!("{}{}", &text[..first_link], &text[end..]),
        "legs[0].links",
        "one link between each two joints",
    );
    let p_joint = "actuated = true, offset = 0.30323713175962613 }";
    refused_at(
        text.replacen(
            p_joint,
            "actuated = true, offset = 0.30323713175962613, mass = 0.1 }",
            1,
        ),
        "legs[0].joints[1].mass",
        "P joint has none",
    );
    refused_at(
        text.replacen(
            p_joint,
            "actuated = true, offset = 0.30323713175962613, gear_ratio = 0.0 }",
            1,
        ),
        "legs[0].joints[1].gear_ratio",
        "positive",
    );
    refused_at(
        text.replacen(
            "{ type = \"S\", point = [0.07980512402078593, -0.005580517899530024, 0.3] }",
            "{ type = \"S\", point = [0.07980512402078593, -0.005580517899530024, 0.3], rotor_inertia = 1e-4 }",
            1,
        ),
        "legs[0].joints[2].rotor_inertia",
        "actuated joint",
    );
    // Motions: wrong lengths, NaN, absurd, out of reach, and no gravity.
    let model = common::robot("stewart_gough.toml");
    let (x, zero) = (model.home_task(), vec![0.0; 6]);
    let mode = model.home_mode();
    for (v, a) in [
        (vec![0.0; 5], zero.clone()),
        (vec![f64::NAN; 6], zero.clone()),
        (zero.clone(), vec![1e300; 6]),
    ] {
        let r = model.inverse_dynamics(&x, &v, &a, mode);
        assert!(matches!(r, Err(DynamicsError::Motion { .. })), "{r:?}");
    }
    let far = [5.0, 0.0, 0.3, 0.0, 0.0, 0.0];
    let r = model.inverse_dynamics(&far, &zero, &zero, mode);
    assert!(matches!(r, Err(DynamicsError::Kinematics(_))), "{r:?}");
    let weightless =
        RobotModel::from_toml(&text.replacen("gravity = [0.0, 0.0, -9.81]\n", "", 1)).unwrap();
    let r = weightless.inverse_dynamics(&x, &zero, &zero, mode);
    assert!(matches!(r, Err(DynamicsError::Missing("gravity"))), "{r:?}");
    // At rest at home the efforts hold the weight: finite, and equal in both formulations.
    let rest = model.inverse_dynamics(&x, &zero, &zero, mode).unwrap();
    assert!(rest.efforts.iter().all(|e| e.is_finite()) && rest.kinetic_energy == 0.0);
}

/// A five-bar whose end point sits on motor 0's axis (the motor's angle is free there, a
/// type I singularity): the dynamics says so with the margins instead of unbounded efforts.
#[test]
fn a_singular_configuration_is_reported_with_its_margins() {
    let text = common::robot_text("five_bar.toml")
        .replace("[-0.2, 0.16, 0.0]", "[-0.18, 0.17320508075688773, 0.0]")
        .replace("[0.2, 0.16, 0.0]", "[0.18, 0.17320508075688773, 0.0]")
        .replace("[0.0, 0.37, 0.0]", "[0.0, 0.2603830596277012, 0.0]");
    let model = pkm_robot_file::RobotModel::from_toml(&text).unwrap();
    let r = model.inverse_dynamics(&[-0.08, 0.0], &[0.1, 0.0], &[0.0, 0.0], model.home_mode());
    assert!(
        matches!(r, Err(pkm_robot_file::DynamicsError::Singular { inverse, .. }) if inverse < 1e-9),
        "{r:?}"
    );
}

/// Eq. D4 against eq. D3 on every file: the efforts of the inverse dynamics give back the
/// task accelerations (to 1e-8 of their size), and the task-space mass matrix is the kinetic
/// energy's, $\tfrac12\dot x^\top M_x\dot x = T$ to 1e-10 relative.
#[test]
fn forward_dynamics_inverts_the_inverse_dynamics_on_every_file() {
    for file in common::all_files() {
        let model = common::robot(&file);
        let mode = model.home_mode();
        let [x, v, a] = wobble(&model, 0.3);
        let inverse = model.inverse_dynamics(&x, &v, &a, mode).unwrap();
        let forward = model
            .forward_dynamics(&x, &v, inverse.efforts.as_slice(), mode)
            .unwrap();
        let a = nalgebra::DVector::from_vec(a);
        assert!(
            (&forward.acceleration - &a).amax() < 1e-8 * a.amax(),
            "{file}: {} vs {a}",
            forward.acceleration
        );
        let v = nalgebra::DVector::from_vec(v);
        let kinetic = 0.5 * v.dot(&(&forward.mass_matrix * &v));
        assert!(
            (kinetic - inverse.kinetic_energy).abs() < 1e-10 * inverse.kinetic_energy,
            "{file}: {kinetic} vs {}",
            inverse.kinetic_energy
        );
    }
}

/// Conservation: with gravity off and no actuation, the energy of the free motion integrated by
/// Dormand–Prince 5(4) (rtol 1e-10) from home with a push stays within 1e-7 of its start over
/// 0.2 s, on the Delta file, the Stewart–Gough and the 3-PRS (dependent coordinates).
#[test]
fn free_motion_conserves_energy() {
    use pkm_integrators::{AdaptiveSettings, DormandPrince54, OutputTimes, integrate};
    use pkm_robot_file::{RobotModel, TaskDynamics};
    fn run<const M: usize>(model: &RobotModel) -> Vec<f64> {
        let n = M / 2;
        let field = TaskDynamics::new(model, model.home_mode(), |_| {
            nalgebra::DVector::zeros(model.actuator_count())
        });
        let mut z0 = nalgebra::SVector::<f64, M>::zeros();
        let home = model.home_task();
        for k in 0..n {
            z0[k] = home[k];
            z0[n + k] = 0.05 * (1.0 + k as f64) * if k % 2 == 0 { 1.0 } else { -1.0 };
        }
        let settings = AdaptiveSettings::default()
            .with_rtol(1e-10)
            .unwrap()
            .with_atol(1e-12)
            .unwrap();
        let solution = integrate(
            &field,
            &mut DormandPrince54::new(settings),
            (0.0, 0.2),
            &z0,
            &OutputTimes::Uniform(0.05),
            &pkm_traits::Silent,
        )
        .unwrap();
        solution
            .states
            .iter()
            .map(|z| {
                let d = model
                    .forward_dynamics(
                        &z.as_slice()[..n],
                        &z.as_slice()[n..],
                        &vec![0.0; model.actuator_count()],
                        model.home_mode(),
                    )
                    .unwrap();
                d.kinetic_energy + d.potential_energy
            })
            .collect()
    }
    for file in ["rotary_delta.toml", "stewart_gough.toml", "three_prs.toml"] {
        let text = common::robot_text(file).replacen(
            "gravity = [0.0, 0.0, -9.81]",
            "gravity = [0.0, 0.0, 0.0]",
            1,
        );
        let model = RobotModel::from_toml(&text).unwrap();
        let energies = match model.dof() {
            3 => run::<6>(&model),
            6 => run::<12>(&model),
            n => panic!("{n}"),
        };
        let start = energies[0];
        assert!(start > 0.0);
        for e in &energies {
            assert!((e - start).abs() < 1e-7 * start, "{file}: {energies:?}");
        }
    }
}

/// Eq. D5 against brute force: the largest |effort| over the 2ⁿ corners of the acceleration
/// box (an affine function's largest |value| on a box is at a corner), by the inverse
/// dynamics at each, on the Stewart–Gough (64 corners) and the 3-PRS; to 1e-9 relative.
#[test]
fn peak_efforts_at_rest_are_the_largest_over_the_acceleration_box() {
    for (file, bounds) in [
        ("stewart_gough.toml", vec![2.0, 2.0, 5.0, 10.0, 10.0, 20.0]),
        ("three_prs.toml", vec![3.0, 8.0, 8.0]),
    ] {
        let model = common::robot(file);
        let mode = model.home_mode();
        let mut x = model.home_task();
        x[0] += 0.01;
        let peak = model.peak_efforts_at_rest(&x, &bounds, mode).unwrap();
        let n = bounds.len();
        let zero = vec![0.0; n];
        let mut brute = nalgebra::DVector::zeros(model.actuator_count());
        for corner in 0..(1_u32 << n) {
            let a: Vec<f64> = (0..n)
                .map(|k| {
                    if corner & (1 << k) != 0 {
                        bounds[k]
                    } else {
                        -bounds[k]
                    }
                })
                .collect();
            let tau = model.inverse_dynamics(&x, &zero, &a, mode).unwrap().efforts;
            brute = brute.zip_map(&tau, |b: f64, t: f64| b.max(t.abs()));
        }
        assert!(
            (&peak - &brute).amax() < 1e-9 * brute.amax(),
            "{file}: {peak} vs {brute}"
        );
        let at_rest = model
            .inverse_dynamics(&x, &zero, &zero, mode)
            .unwrap()
            .efforts
            .abs();
        assert!(peak.iter().zip(at_rest.iter()).all(|(p, r)| p >= r));
    }
}

/// Every sample of a short parabolic move of the Orthoglide is computed: at one of them
/// (t = 47 ms) the configuration closes only to its solver's tolerance and left the unit-rate
/// system inconsistent by 6e-8 of its right-hand side, which a 1e-8 check refused as singular.
#[test]
fn a_configuration_closed_to_the_solvers_tolerance_is_not_singular() {
    let model = common::robot("orthoglide.toml");
    let d = [0.0025, -0.005, 0.00125];
    for k in 0..=100 {
        let tau = f64::from(k) / 100.0;
        let (s, ds, dds) = if tau < 0.5 {
            (2.0 * tau * tau, 4.0 * tau, 4.0)
        } else {
            let r = 1.0 - tau;
            (1.0 - 2.0 * r * r, 4.0 * r, -4.0)
        };
        let x: Vec<f64> = d.iter().map(|v| v * s).collect();
        let v: Vec<f64> = d.iter().map(|v| v * ds / 0.1).collect();
        let a: Vec<f64> = d.iter().map(|v| v * dds / 0.01).collect();
        let r = model.inverse_dynamics(&x, &v, &a, model.home_mode());
        assert!(r.is_ok(), "sample {k}: {r:?}");
    }
}

/// The whole float range into the dynamics' public functions, on every example file: NaN,
/// ±infinity, ±1e300, subnormals and absurd lengths give a typed error or a finite result,
/// never a panic or a NaN; and a robot of subnormal masses is `Massless` or finite.
#[test]
fn the_dynamics_take_the_whole_float_range() {
    use pkm_robot_file::RobotModel;
    let specials = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e300,
        -1e300,
        5e-324,
        -5e-324,
    ];
    let finite = |v: &[f64]| v.iter().all(|e| e.is_finite());
    for file in common::all_files() {
        let model = common::robot(&file);
        let mode = model.home_mode();
        let (n, m) = (model.dof(), model.actuator_count());
        let home = model.home_task();
        for &s in &specials {
            let mut x = home.clone();
            x[0] = s;
            let spread = vec![s; n];
            let cases: [(&[f64], &[f64], &[f64]); 3] = [
                (&x, &vec![0.0; n], &vec![0.0; n]),
                (&home, &spread, &vec![0.0; n]),
                (&home, &vec![0.0; n], &spread),
            ];
            for (x, v, a) in cases {
                if let Ok(d) = model.inverse_dynamics(x, v, a, mode) {
                    assert!(finite(d.efforts.as_slice()), "{file}: {s}");
                }
                if let Ok(e) = model.actuator_efforts(x, v, a, mode) {
                    assert!(finite(e.as_slice()), "{file}: {s}");
                }
                if let Ok(d) = model.forward_dynamics(x, v, &vec![0.0; m], mode) {
                    assert!(finite(d.acceleration.as_slice()), "{file}: {s}");
                }
                if let Ok(p) = model.peak_efforts_at_rest(x, a, mode) {
                    assert!(finite(p.as_slice()), "{file}: {s}");
                }
            }
            let r = model.forward_dynamics(&home, &vec![0.0; n], &vec![s; m], mode);
            assert!(
                r.as_ref()
                    .map_or(true, |d| finite(d.acceleration.as_slice())),
                "{file}: {s}"
            );
        }
        for bad in [0, n + 1, 1000] {
            assert!(
                model
                    .inverse_dynamics(&home, &vec![0.0; bad], &vec![0.0; n], mode)
                    .is_err()
            );
            let efforts = if bad == n + 1 { m + 1 } else { bad };
            assert!(
                model
                    .forward_dynamics(&home, &vec![0.0; n], &vec![0.0; efforts], mode)
                    .is_err()
            );
            assert!(
                model
                    .peak_efforts_at_rest(&home, &vec![1.0; bad], mode)
                    .is_err()
            );
        }
    }
    // Subnormal masses everywhere: the task-space mass matrix is as good as zero.
    let text = common::robot_text("stewart_gough.toml");
    let tiny = regex_free_scale(&text);
    let model = RobotModel::from_toml(&tiny).unwrap();
    let (n, m) = (model.dof(), model.actuator_count());
    let r = model.forward_dynamics(
        &model.home_task(),
        &vec![0.0; n],
        &vec![1.0; m],
        model.home_mode(),
    );
    assert!(
        r.as_ref()
            .map_or(true, |d| d.acceleration.iter().all(|a| a.is_finite())),
        "{r:?}"
    );
}

/// `text` with every `mass = …` and inertia entry set to a subnormal value.
fn regex_free_scale(text: &str) -> String {
    text.lines()
        .map(|line| {
            if line.starts_with("mass = ") {
                "mass = 5e-324".to_string()
            } else if line.starts_with("inertia = ") {
                "inertia = [[5e-324, 0.0, 0.0], [0.0, 5e-324, 0.0], [0.0, 0.0, 5e-324]]".to_string()
            } else if line.trim_start().starts_with("{ mass = ") {
                let rest = line.split_once(", center_of_mass").map_or("", |(_, r)| r);
                let com = rest.split_once(", inertia").map_or("", |(c, _)| c);
                format!("  {{ mass = 5e-324, center_of_mass{com} }},")
            } else {
                line.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}
