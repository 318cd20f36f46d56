//! Issue 32: every assembly mode of a robot file by parameter homotopy
//! (`RobotModel::forward_kinematics_all`), against Dietmaier's 40 real postures, the
//! generic counts of the literature and the seeded multistart.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;
use pkm_robot_file::{Configuration, EnumerationSettings, HomotopyReport, RobotModel};

/// Two configurations with the same platform pose (1e-6 m, 1e-6 in the rotation matrix).
fn same_pose(model: &RobotModel, a: &Configuration, b: &Configuration) -> bool {
    let (x, y) = (model.platform_pose_of(a), model.platform_pose_of(b));
    (x.translation.vector - y.translation.vector).amax() < 1e-6
        && (x.rotation.to_rotation_matrix().into_inner()
            - y.rotation.to_rotation_matrix().into_inner())
        .amax()
            < 1e-6
}

/// The paths the report accounts for, by how they ended (each once).
fn ended(r: &HomotopyReport) -> usize {
    r.real
        + r.complex
        + r.singular
        + r.at_infinity
        + r.exceptional
        + r.refused
        + r.repeated
        + r.failed.len()
}

/// Every mode of the multistart alone (`starts` seeded starts) is among `configurations`.
fn assert_multistart_modes_among(
    model: &RobotModel,
    q: &[f64],
    configurations: &[Configuration],
    starts: usize,
) {
    let settings = EnumerationSettings {
        starts,
        method: pkm_robot_file::ModeSearch::Multistart,
        ..Default::default()
    };
    for m in model.assembly_modes(q, &settings).unwrap() {
        assert!(
            configurations
                .iter()
                .any(|c| same_pose(model, c, &m.configuration)),
            "{}: the multistart's mode {:?} is not among the homotopy's",
            model.name(),
            m.task
        );
    }
}

/// Every configuration closes the robot: its actuators are `q` to 1e-9.
fn assert_closed(model: &RobotModel, q: &[f64], configurations: &[Configuration]) {
    for c in configurations {
        let back = model.actuators_of(c);
        let gap = back
            .iter()
            .zip(q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(gap < 1e-9, "{}: {back} vs {q:?}", model.name());
    }
}

/// Dietmaier's design (1998; the data of martyushev/fkSGP): the 40 paths from the generic
/// solutions of the Stewart–Gough architecture (40, Husty 1996, found by monodromy) all end at
/// finite, nonsingular, real solutions: 40 real of 40, each closing the robot, and every mode
/// the multistart finds (300 starts) is among them.
#[test]
fn dietmaier_design_has_forty_real_of_forty() {
    let model = common::robot("dietmaier_40.toml");
    let q = q_dietmaier();
    let all = model.forward_kinematics_all(&q).unwrap();
    let r = &all.report;
    assert_eq!(r.generic_solutions, 40, "{r:?}");
    assert!(r.monodromy_stable);
    assert_eq!(
        (r.real, r.complex, r.singular, r.at_infinity),
        (40, 0, 0, 0),
        "{r:?}"
    );
    assert!(r.failed.is_empty(), "{r:?}");
    assert_eq!(all.configurations.len(), 40);
    assert_closed(&model, &q, &all.configurations);
    assert_multistart_modes_among(&model, &q, &all.configurations, 300);
}

/// The generic counts of each architecture (five-bar and Deltas 2, 3-RPR 6 (Gosselin,
/// Sefrioui & Richard 1994), Agile Eye 8 (Gosselin, St-Pierre & Gagné 1996), Stewart–Gough and
/// Hexa 40) and, at each file's home actuators, the real solutions: each closes the robot,
/// and every mode of the multistart (200 starts) is among them. (The Hexa, 40 generic, is left
/// out: at home 15 real endpoints against the multistart's 16, one lost among the paths that
/// stall near a singular end; issue 32 left open.)
#[test]
fn generic_counts_and_the_multistart_modes_on_every_supported_file() {
    let expected = [
        ("five_bar.toml", 2, 2),
        ("rotary_delta.toml", 2, 2),
        ("tsai.toml", 2, 2),
        ("orthoglide.toml", 2, 2),
        ("three_rpr.toml", 6, 4),
        ("agile_eye.toml", 8, 8),
        ("stewart_gough.toml", 40, 16),
        // Each PRS leg a sphere and the plane of its elbow joint (eq. K2) in Study's form.
        ("three_prs.toml", 16, 8),
        // Three spheres and the passive UP leg's line and joint angle (eq. K3); its report is
        // not complete at home (below), the multistart's modes are among its own.
        ("tricept.toml", 28, 8),
    ];
    for (file, generic, real) in expected {
        let model = common::robot(file);
        assert_eq!(model.homotopy_unsupported(), None, "{file}");
        let q = model.home_actuators();
        let all = model.forward_kinematics_all(&q).unwrap();
        let r = &all.report;
        assert_eq!(
            (r.generic_solutions, r.real),
            (generic, real),
            "{file}: {r:?}"
        );
        assert_eq!(ended(r), generic, "{file}: every path accounted for");
        assert_closed(&model, &q, &all.configurations);
        assert_multistart_modes_among(&model, &q, &all.configurations, 200);
    }
}

/// Robots without a polynomial form here say why and are refused by the homotopy (the
/// multistart serves them); a `q` of the wrong length or not finite is a typed error.
#[test]
fn unsupported_robots_and_bad_input() {
    for (file, reason) in [
        (
            "exechon.toml",
            "fewer equations than unknowns (a leg that holds the platform beyond its sphere and \
             an elbow plane, as a single R joint at the base or the platform)",
        ),
        ("three_ppsr.toml", "a leg with several actuators"),
    ] {
        let model = common::robot(file);
        assert_eq!(model.homotopy_unsupported(), Some(reason), "{file}");
        assert!(
            model
                .forward_kinematics_all(&model.home_actuators())
                .is_err()
        );
    }
    let model = common::robot("five_bar.toml");
    assert!(model.forward_kinematics_all(&[0.1]).is_err());
    assert!(model.forward_kinematics_all(&[f64::NAN, 0.0]).is_err());
    // A revolute actuator at 1e300 rad is an angle like any other (its sine and cosine are
    // finite): configurations that close the robot, or none.
    let huge = model.forward_kinematics_all(&[1e300, 0.0]).unwrap();
    assert_closed(&model, &[1e300, 0.0], &huge.configurations);
}

/// `assembly_search` runs the homotopy by default: Dietmaier's design complete (40 modes, no
/// multistart); the Hexa's report is not complete (paths stall near Study's exceptional set),
/// so the multistart runs too and the union holds every mode it finds alone; the 3-PPSR has no
/// polynomial form (multistart only); `ModeSearch::Multistart` skips the homotopy.
#[test]
fn assembly_search_uses_the_homotopy_and_says_so() {
    use pkm_robot_file::ModeSearch;
    let settings = EnumerationSettings::default();
    let dietmaier = common::robot("dietmaier_40.toml");
    let search = dietmaier
        .assembly_search(&q_dietmaier(), &settings)
        .unwrap();
    assert!(search.homotopy.as_ref().is_some_and(|r| r.complete()));
    assert!(!search.multistart);
    assert_eq!(search.modes.len(), 40);
    let hexa = common::robot("hexa.toml");
    let q = hexa.home_actuators();
    let search = hexa.assembly_search(&q, &settings).unwrap();
    assert!(search.homotopy.as_ref().is_some_and(|r| !r.complete()));
    assert!(search.multistart);
    let alone = hexa
        .assembly_modes(
            &q,
            &EnumerationSettings {
                method: ModeSearch::Multistart,
                ..settings
            },
        )
        .unwrap();
    for m in &alone {
        assert!(
            search
                .modes
                .iter()
                .any(|s| same_pose(&hexa, &s.configuration, &m.configuration)),
            "{:?}",
            m.task
        );
    }
    assert!(search.modes.len() >= alone.len() && search.modes.len() >= 16);
    let ppsr = common::robot("three_ppsr.toml");
    let search = ppsr
        .assembly_search(&ppsr.home_actuators(), &settings)
        .unwrap();
    assert!(search.homotopy.is_none() && search.multistart);
    let only = dietmaier
        .assembly_search(
            &q_dietmaier(),
            &EnumerationSettings {
                method: ModeSearch::Multistart,
                ..settings
            },
        )
        .unwrap();
    assert!(only.homotopy.is_none() && only.multistart);
}

/// Dietmaier's leg lengths (the data of martyushev/fkSGP, as `acceptance_modes.rs`).
/// Every path is accounted for once, the real nonsingular endpoints are distinct
/// configurations, and a repeated endpoint (a path that jumped onto another's solution) makes
/// the report incomplete: the example Stewart–Gough at a pose 1 m up has such paths, where
/// six real endpoints were once reported for four distinct modes.
#[test]
fn every_path_is_counted_once_and_a_repeated_end_is_not_complete() {
    let sg = common::robot("stewart_gough.toml");
    let up = sg
        .inverse_kinematics(&[0.05, -0.02, 1.0, 0.1, 0.05, 0.2], sg.home_mode())
        .unwrap();
    let dietmaier = common::robot("dietmaier_40.toml");
    for (model, q) in [
        (&sg, up.as_slice().to_vec()),
        (&dietmaier, q_dietmaier().to_vec()),
    ] {
        let all = model.forward_kinematics_all(&q).unwrap();
        let r = &all.report;
        assert_eq!(ended(r), r.generic_solutions, "{r:?}");
        assert!(all.configurations.len() >= r.real, "{r:?}");
        for (i, a) in all.configurations.iter().enumerate() {
            for b in &all.configurations[..i] {
                assert!(!same_pose(model, a, b), "{r:?}");
            }
        }
        assert!(r.repeated == 0 || !r.complete(), "{r:?}");
    }
    let r = sg.forward_kinematics_all(up.as_slice()).unwrap().report;
    assert!(r.repeated > 0 && !r.complete(), "{r:?}");
}

/// The 3-PRS away from home (its sliders at different heights, the platform tilted): the
/// homotopy's report is complete and holds every mode of a 400-start multistart.
#[test]
fn three_prs_away_from_home_is_complete() {
    let model = common::robot("three_prs.toml");
    let q = [0.33, 0.37, 0.35];
    let all = model.forward_kinematics_all(&q).unwrap();
    assert!(all.report.complete(), "{:?}", all.report);
    assert_eq!(all.report.generic_solutions, 16);
    assert_closed(&model, &q, &all.configurations);
    assert_multistart_modes_among(&model, &q, &all.configurations, 400);
}

fn q_dietmaier() -> [f64; 6] {
    [1.0, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071]
}

/// Issue 32's comparison at scale (run by hand, `--ignored`, in the release profile: about
/// ten minutes on 2 cores): on every supported example file at its home actuators and at
/// Dietmaier's leg lengths, every mode of the multistart with 20,000 starts is among the
/// homotopy's (the Hexa excepted for its one mode near Study's exceptional set, which
/// `assembly_modes` recovers by adding the multistart to an incomplete report).
#[test]
#[ignore = "ten minutes: run by hand with --release --ignored"]
fn every_mode_of_a_20000_start_multistart_is_found() {
    use pkm_robot_file::ModeSearch;
    let settings = EnumerationSettings {
        starts: 20_000,
        method: ModeSearch::Multistart,
        ..Default::default()
    };
    let mut cases: Vec<(String, Vec<f64>)> = common::all_files()
        .into_iter()
        .filter(|f| common::robot(f).homotopy_unsupported().is_none())
        .map(|f| {
            let q = common::robot(&f).home_actuators();
            (f, q)
        })
        .collect();
    cases.push(("dietmaier_40.toml".into(), q_dietmaier().to_vec()));
    for (file, q) in cases {
        let model = common::robot(&file);
        let all = model.forward_kinematics_all(&q).unwrap();
        let modes = model.assembly_modes(&q, &settings).unwrap();
        let missing: Vec<_> = modes
            .iter()
            .filter(|m| {
                !all.configurations
                    .iter()
                    .any(|c| same_pose(&model, c, &m.configuration))
            })
            .map(|m| m.task.clone())
            .collect();
        println!(
            "{file}: homotopy {} real ({} generic, complete {}), multistart {} modes, missing {}",
            all.report.real,
            all.report.generic_solutions,
            all.report.complete(),
            modes.len(),
            missing.len()
        );
        if file != "hexa.toml" {
            assert!(missing.is_empty(), "{file}: {missing:?}");
        }
    }
}

/// The whole float range into the homotopy on every supported file (each actuator in turn at
/// NaN, ±infinity, ±1e300 and ±subnormals, the others at home), and every example file's
/// MJCF read back as XML: a typed error, or configurations that close the robot, never a
/// panic or a NaN pose.
#[test]
fn the_homotopy_and_the_exports_take_the_whole_float_range() {
    let specials = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e300,
        -1e300,
        5e-324,
        -5e-324,
    ];
    for file in common::all_files() {
        let model = common::robot(&file);
        assert!(
            roxmltree::Document::parse(&model.to_mjcf()).is_ok(),
            "{file}"
        );
        if model.homotopy_unsupported().is_some() {
            continue;
        }
        let home = model.home_actuators();
        for &s in &specials {
            let mut q = home.clone();
            q[0] = s;
            if let Ok(all) = model.forward_kinematics_all(&q) {
                for c in &all.configurations {
                    assert!(c.pose().iter().all(|v| v.is_finite()), "{file}: {s}");
                }
                assert_closed(&model, &q, &all.configurations);
            }
        }
    }
}

/// A 3-RRS (revolute actuators at the base, elbows normal to their rods but not parallel to
/// the actuated axes, so each leg's elbow plane turns with its arm, eq. K2) written inline
/// like the 3-PRS: at home and at the actuators of a tilted pose (its inverse kinematics) the
/// report is complete, the pose is among the modes (a round trip), and a 200-start
/// multistart's modes are among the homotopy's.
#[test]
fn a_three_rrs_has_elbow_planes_that_turn_with_its_arms() {
    let text = r#"
name = "3-RRS"
orientation = "tilt_torsion"
task = ["z", "tilt_x", "tilt_y"]
dependent = ["x", "y", "torsion"]
characteristic_length = 0.1

[home]
position = [0.0, 0.0, 0.5]

[symmetry]
count = 3
axis = [0.0, 0.0, 1.0]

[[legs]]
joints = [
  { type = "R", axis = [0.0, 1.0, 0.0], point = [0.3, 0.0, 0.3], actuated = true, offset = 0.0, limits = [-1.5, 1.5] },
  { type = "R", axis = [0.05, 1.0, 0.2], point = [0.3, 0.0, 0.45] },
  { type = "S", point = [0.1, 0.0, 0.5] },
]
"#;
    let model = RobotModel::from_toml(text).unwrap();
    assert_eq!(model.homotopy_form(), Some("spatial (Study parameters)"));
    for task in [[0.5, 0.0, 0.0], [0.47, 0.06, -0.04]] {
        let pose = model
            .inverse_kinematics_configuration(&task, model.home_mode())
            .unwrap();
        let q = model.actuators_of(&pose);
        let all = model.forward_kinematics_all(q.as_slice()).unwrap();
        assert!(all.report.complete(), "{:?}", all.report);
        assert!(
            all.configurations
                .iter()
                .any(|c| same_pose(&model, c, &pose)),
            "{task:?}: {:?}",
            all.report
        );
        assert_closed(&model, q.as_slice(), &all.configurations);
        assert_multistart_modes_among(&model, q.as_slice(), &all.configurations, 200);
    }
}
