//! The task study through the library function: the example studies against the same
//! multistart written directly on the library, checks that do not share the study's code path
//! (the library's own objectives at the reported optimum, closed forms), and every setting
//! refused at its key path before the first start.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Isometry3, Rotation3, Unit, Vector3, Vector6};
use pkm_mechanisms::{
    StewartDesign, StewartGough, StewartTaskProblem, ThreeUpu, ThreeUpuDesign, UJointAxes,
    WrenchSystem, pose_from_task, presets,
};
use pkm_optimizers::{LmSettings, Multistart, Sense, multistart_levenberg_marquardt};
use pkm_screw_theory::Twist;
use pkm_study::schema::robot_file::RobotFileSpec;
use pkm_study::schema::units::{Degrees, Metres};
use pkm_study::task::PoseSpec;
use pkm_study::{Artifact, StudyError, TaskResult, TaskStudy, from_toml_str, task};
use pkm_traits::{Bounds, Objective, ObjectiveError, Progress, Residuals, Silent, Task};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

fn example(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

/// The result of the task study `text`, with the artifacts' names checked.
fn run_text(text: &str) -> TaskResult {
    let study: TaskStudy = from_toml_str(text).unwrap();
    let outcome = task(&study, &Silent).unwrap();
    let names: Vec<&str> = outcome
        .artifacts
        .iter()
        .map(|a| match a {
            Artifact::Table { name, .. } | Artifact::Chart { name, .. } => name.as_str(),
            Artifact::Robot { .. } => "robot",
        })
        .collect();
    assert_eq!(names, ["starts.csv", "starts.svg", "robot"]);
    assert_eq!(outcome.summary.len(), 4, "{:?}", outcome.summary);
    outcome.result
}

fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

fn section_4_1_twist() -> Twist {
    Twist::from_screw(
        &Vector3::new(2.0, 2.0, 1.0),
        &Vector3::new(0.02, 0.03, 0.06),
        0.01,
        1.0,
    )
    .unwrap()
}

fn stewart_problem(twist: Twist) -> StewartTaskProblem {
    StewartTaskProblem::new(
        StewartDesign::from_deg(0.12, 0.08, 30.0, 8.0),
        Vector3::new(0.0, 0.0, 0.35),
        Vector3::zeros(),
        twist,
    )
    .unwrap()
    .free_position(0, Bounds::new(-0.1, 0.1).unwrap())
    .unwrap()
    .free_position(1, Bounds::new(-0.1, 0.1).unwrap())
    .unwrap()
    .free_position(2, Bounds::new(0.2, 0.5).unwrap())
    .unwrap()
    .free_rotation(30f64.to_radians())
    .unwrap()
}

fn pose_of(r: &TaskResult) -> Isometry3<f64> {
    let [x, y, z] = r.pose.position;
    let [a, b, c] = r.pose.rotation_deg.map(f64::to_radians);
    pose_from_task(&Task::<6>::new(x, y, z, a, b, c)).unwrap()
}

#[test]
fn stewart_task_synthesis_matches_the_library_multistart() {
    let r = run_text(&example("stewart_task_synthesis.toml"));
    let problem = stewart_problem(section_4_1_twist());
    let best = multistart_levenberg_marquardt(
        &problem,
        Sense::Maximise,
        &Multistart::new(20, 2006),
        &LmSettings::default(),
        &Silent,
    )
    .unwrap()
    .best;
    assert!(
        close(r.objective, best.value, 1e-12),
        "{} vs {}",
        r.objective,
        best.value
    );
    let names = ["x", "y", "z", "u_x", "u_y", "u_z"];
    for (name, v) in names.iter().zip(&best.design) {
        assert!((r.optimum[*name] - v).abs() < 1e-12, "{name}");
    }
    // Independent of the problem's own evaluation: F of the library's platform at the
    // reported pose, and the leg lengths there.
    let sg = StewartGough::new(StewartDesign::from_deg(0.12, 0.08, 30.0, 8.0)).unwrap();
    let pose = pose_of(&r);
    let f = sg.task_objective(&pose, &section_4_1_twist()).unwrap();
    assert!(close(f, r.objective, 1e-9), "{f} vs {}", r.objective);
    assert!(close(r.twists[0].f, r.objective, 1e-9));
    let lengths = sg.leg_lengths(&pose);
    for (l, reported) in lengths.iter().zip(r.leg_lengths.unwrap()) {
        assert!(close(*l, reported, 1e-9));
    }
    assert!(r.pose.angle_deg <= 30.0 + 1e-9);
    assert!(r.optimality.termination.starts_with("converged"));
}

#[test]
fn weighted_copies_of_one_twist_are_that_twist() {
    let text = example("stewart_task_synthesis.toml");
    let split = text.replace(
        "weight = 1.0\n",
        "weight = 0.25\n\n[[task.twists]]\naxis = [2.0, 2.0, 1.0]\npoint = [0.02, 0.03, 0.06]\n\
         pitch = 0.01\nweight = 0.75\n",
    );
    assert_ne!(split, text);
    let r = run_text(&split);
    let best = multistart_levenberg_marquardt(
        &stewart_problem(section_4_1_twist()),
        Sense::Maximise,
        &Multistart::new(20, 2006),
        &LmSettings::default(),
        &Silent,
    )
    .unwrap()
    .best;
    // 0.25 F + 0.75 F = F: the same maximum, and each part's F is the total.
    assert!(
        close(r.objective, best.value, 1e-9),
        "{} vs {}",
        r.objective,
        best.value
    );
    assert_eq!(r.twists.len(), 2);
    for t in &r.twists {
        assert!(close(t.f, r.objective, 1e-9));
    }
}

/// σ_min of the 3-UPU's eq. 18 matrix over (x, y, z, rx, ry, rz) (m, degrees), written
/// directly.
struct UpuSigmaMin([Bounds; 6]);

/// Park's 3-UPU at base radius 0.2 m and platform radius 0.1 m, joints tilted by 30°.
fn upu_design() -> ThreeUpuDesign {
    ThreeUpuDesign {
        base_radius: 0.2,
        platform_radius: 0.1,
        azimuths: presets::PARK_AZIMUTHS_DEG.map(f64::to_radians),
        upper: tilted_axes(30.0),
    }
}

fn tilted_axes(gamma_deg: f64) -> [UJointAxes; 3] {
    presets::PARK_AZIMUTHS_DEG.map(|t| {
        let UJointAxes { u1, u2 } = UJointAxes::park(t.to_radians());
        let tilt = Rotation3::from_axis_angle(&Unit::new_normalize(u2), 0.0)
            * Rotation3::from_axis_angle(&Unit::new_normalize(u1), gamma_deg.to_radians());
        UJointAxes {
            u1: tilt * u1,
            u2: tilt * u2,
        }
    })
}

impl Objective for UpuSigmaMin {
    fn dimension(&self) -> usize {
        6
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, v: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0];
        self.residuals(v, &mut r)?;
        Ok(r[0] * r[0])
    }
}

impl Residuals for UpuSigmaMin {
    fn n_residuals(&self) -> usize {
        1
    }
    fn residuals(&self, v: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        let upu = ThreeUpu::new(upu_design())?;
        let [a, b, c] = [v[3], v[4], v[5]].map(f64::to_radians);
        let pose = pose_from_task(&Task::<6>::new(v[0], v[1], v[2], a, b, c)).unwrap();
        let rows = upu.wrench_rows(&pose).map_err(ObjectiveError::from)?;
        r[0] = rows
            .singular_values()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        Ok(())
    }
}

#[test]
fn three_upu_singularity_search_matches_the_library_multistart() {
    let r = run_text(&example("three_upu_singularity.toml"));
    let b = |lo, hi| Bounds::new(lo, hi).unwrap();
    let angle = b(-20.0, 20.0);
    let problem = UpuSigmaMin([
        b(-0.05, 0.05),
        b(-0.05, 0.05),
        b(0.0, 0.3),
        angle,
        angle,
        angle,
    ]);
    let best = multistart_levenberg_marquardt(
        &problem,
        Sense::Minimise,
        &Multistart::new(16, 44),
        &LmSettings::default(),
        &Silent,
    )
    .unwrap()
    .best;
    let names = ["x", "y", "z", "rx_deg", "ry_deg", "rz_deg"];
    for (name, v) in names.iter().zip(&best.design) {
        assert!(
            (r.optimum[*name] - v).abs() < 1e-12,
            "{name}: {} vs {v}",
            r.optimum[*name]
        );
    }
    assert!((r.objective - best.value).abs() < 1e-15);
    // A singular pose: the twist most nearly reciprocal to the rows has F = σ_min² by the
    // library's task objective, the rows lose rank and the determinant vanishes.
    let w = &r.wrench_matrix;
    assert!(w.sigma_min < 1e-6, "sigma_min = {}", w.sigma_min);
    assert!((w.most_reciprocal_f - w.sigma_min * w.sigma_min).abs() < 1e-12);
    let chi = Twist::from_vector(Vector6::from(w.most_reciprocal_twist));
    let upu = ThreeUpu::new(upu_design()).unwrap();
    assert!(upu.task_objective(&pose_of(&r), &chi).unwrap() < 1e-12);
    assert!(w.rank < 6 && w.det.unwrap().abs() < 1e-6);
}

#[test]
fn the_largest_three_upu_f_for_a_unit_rotation_is_three() {
    // The constraint couples [0; u_i] contribute (u_i·ω)² ≤ 1 each and the legs of a zero-pitch
    // twist through the apex nothing, so F ≤ 3|ω|² = 3, reached with every couple along ω.
    let text = "[mechanism.three_upu]\nbase_radius = 0.2\nplatform_radius = 0.1\n\
        [task]\ngoal = \"maximise\"\npose = { position = [0.0, 0.0, 0.1] }\n\
        [task.variables]\nbeta1_deg = [-90, 90]\ngamma1_deg = [-90, 90]\nbeta2_deg = [-90, 90]\n\
        gamma2_deg = [-90, 90]\nbeta3_deg = [-90, 90]\ngamma3_deg = [-90, 90]\n\
        [[task.twists]]\naxis = [-0.94, 0.35, 0.0]\npoint = [0.0, 0.0, 0.2]\n\
        [task.starts]\ncount = 8\nseed = 18\n";
    let r = run_text(text);
    assert!((r.objective - 3.0).abs() < 1e-9, "{}", r.objective);
    assert!(r.optimality.free_gradient_max < 1e-6);
}

#[derive(Default)]
struct Events(AtomicUsize);

impl Progress for Events {
    fn phase(&self, _: &str) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
    fn start(&self, _: &str, _: u64) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }
}

/// The key path of the error of the study `text`, checking that nothing was computed.
fn refused_at(text: &str) -> String {
    let study: TaskStudy = from_toml_str(text).unwrap();
    let events = Events::default();
    let e = task(&study, &events).expect_err("the study is invalid");
    assert!(matches!(e, StudyError::Invalid { .. }), "{e}");
    assert_eq!(
        events.0.load(Ordering::Relaxed),
        0,
        "computed before refusing: {e}"
    );
    e.path().unwrap().to_string()
}

/// `text` with each `from` replaced by `to` (which must occur).
fn edited(text: &str, edits: &[(&str, &str)]) -> String {
    let mut text = text.to_owned();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    text
}

/// A study text, its edits and the key path of the error they cause.
type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a str);

#[test]
fn every_setting_is_refused_at_its_key_before_the_first_start() {
    let sg = example("stewart_task_synthesis.toml");
    let upu = example("three_upu_singularity.toml");
    let cases: [Case<'_>; 15] = [
        (
            &sg,
            &[("seed = 2006", "seed = 2006\n[task.solver]\nfd_step = -1.0")],
            "task.solver.fd_step",
        ),
        (
            &sg,
            &[("seed = 2006", "seed = 2006\n[task.solver]\ntolerance = 0.0")],
            "task.solver.tolerance",
        ),
        (
            &sg,
            &[(
                "seed = 2006",
                "seed = 2006\n[task.solver]\nmax_iterations = 0",
            )],
            "task.solver.max_iterations",
        ),
        (&sg, &[("count = 20", "count = 0")], "task.starts.count"),
        (
            &sg,
            &[("count = 20", "count = 1000000000")],
            "task.starts.count",
        ),
        (
            &sg,
            &[("z = [0.2, 0.5]", "z = [0.5, 0.2]")],
            "task.variables.z",
        ),
        (
            &sg,
            &[("z = [0.2, 0.5]", "rz_deg = [0.0, 1.0]")],
            "task.variables.rz_deg",
        ),
        (
            &sg,
            &[("max_angle_deg = 30.0", "max_angle_deg = -30.0")],
            "task.max_angle_deg",
        ),
        (
            &sg,
            &[("weight = 1.0", "weight = -1.0")],
            "task.twists[0].weight",
        ),
        (&sg, &[("point = [0.02, 0.03, 0.06]", "")], "task.twists[0]"),
        (
            &sg,
            &[("axis = [2.0, 2.0, 1.0]", "axis = [0.0, 0.0, 0.0]")],
            "task.twists[0]",
        ),
        (
            &sg,
            &[("goal = \"maximise\"", "goal = \"singularity_det\"")],
            "task.goal",
        ),
        (
            &upu,
            &[("goal = \"singularity_sigma_min\"", "goal = \"minimise\"")],
            "task.goal",
        ),
        (
            &upu,
            &[("[task.variables]", "max_angle_deg = 10.0\n[task.variables]")],
            "task.max_angle_deg",
        ),
        (
            &sg,
            &[(
                "platform_separation_deg = 8.0",
                "platform_separation_deg = 8.0\nrotation_deg = [0.0, 0.0, 5.0]",
            )],
            "mechanism.stewart_gough.rotation_deg",
        ),
    ];
    for (text, edits, path) in cases {
        assert_eq!(refused_at(&edited(text, edits)), path, "{edits:?}");
    }
    // A mechanism without a wrench system is refused at its table.
    let section = &upu[upu.find("[task]").unwrap()..];
    let delta = format!(
        "[mechanism.linear_delta]\nl1_over_yr = 2.0\nya_over_yr = 0.0\nzr_over_yr = 0.0\n\
         l2_over_l1 = 1.0\n\n{section}"
    );
    assert_eq!(refused_at(&delta), "mechanism");
}

#[test]
fn the_three_upu_table_is_one_for_every_study() {
    // The task's 3-UPU table is the workspace's: its tilts are design variables of the registry,
    // and the built mechanism carries them (rows of a tilted design differ from Park's).
    use pkm_study::schema::mechanism::ThreeUpuSpec;
    use pkm_study::{MechanismSpec, StudyMechanism};
    let study: TaskStudy = from_toml_str(&example("three_upu_singularity.toml")).unwrap();
    let MechanismSpec::ThreeUpu(spec) = &study.mechanism else {
        panic!("a 3-UPU study")
    };
    assert_eq!(spec.get("gamma1_deg"), Some(30.0));
    let park = ThreeUpuSpec {
        gamma1_deg: Degrees(0.0),
        gamma2_deg: Degrees(0.0),
        gamma3_deg: Degrees(0.0),
        ..spec.clone()
    };
    let pose = Isometry3::translation(0.0, 0.0, 0.2);
    let tilted = spec.build().unwrap().wrench_rows(&pose).unwrap();
    let parks = park.build().unwrap().wrench_rows(&pose).unwrap();
    assert!((tilted - parks).norm() > 0.1);
    let direct = ThreeUpu::new(upu_design())
        .unwrap()
        .wrench_rows(&pose)
        .unwrap();
    assert!((tilted - direct).norm() < 1e-12);
}

fn robot_table(file: &str) -> toml::Table {
    let path = format!(
        "{}/../../examples/robots/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The study `hand` (a papers' mechanism) with the robot file `robot` in its place and the
/// nominal pose left to the file's home.
fn on_robot_file(hand: &str, robot: &str) -> TaskStudy {
    let mut study: TaskStudy = from_toml_str(hand).unwrap();
    study.mechanism =
        pkm_study::MechanismSpec::RobotFile(RobotFileSpec::inline(robot_table(robot)));
    study.task.pose = PoseSpec::default();
    study
}

const TWIST_2_2_1: &str = r#"
[[task.twists]]
axis = [2.0, 2.0, 1.0]
point = [0.02, 0.03, 0.06]
pitch = 0.01
"#;

#[test]
fn a_robot_file_task_study_is_the_hand_written_one_on_the_same_robot() {
    // Wolf & Shoham §4.1's Stewart–Gough (examples/robots/stewart_gough.toml is its same-pattern
    // layout in metres) at zero rotation: the actuation wrenches of the robot file are the unit
    // leg lines of the hand-written model, so both formulations have the same optimum.
    let stewart = |goal: &str| {
        format!(
            "[mechanism.stewart_gough]\nbase_radius = 0.12\nplatform_radius = 0.08\n\
             base_separation_deg = 30.0\nplatform_separation_deg = 8.0\n\n[task]\n\
             goal = \"{goal}\"\nvariables = {{ x = [-0.1, 0.1], y = [-0.1, 0.1], z = [0.2, \
             0.5] }}\nstarts = {{ count = 8, seed = 2006 }}\n{TWIST_2_2_1}"
        )
    };
    for goal in ["maximise", "minimise"] {
        let hand = stewart(goal);
        let expected = run_text(&hand);
        let study = on_robot_file(&hand, "stewart_gough.toml");
        let outcome = task(&study, &Silent).unwrap();
        let r = &outcome.result;
        assert_eq!(r.mechanism, "robot_file");
        assert!(
            close(r.objective, expected.objective, 1e-9),
            "{goal}: {} against {}",
            r.objective,
            expected.objective
        );
        for (name, value) in &r.optimum {
            let hand_value = expected.optimum[name];
            assert!(
                (value - hand_value).abs() < 1e-6,
                "{goal} {name}: {value} against {hand_value}"
            );
        }
        let w = &r.wrench_matrix;
        assert!(close(w.sigma_min, expected.wrench_matrix.sigma_min, 1e-9));
        assert_eq!(w.rank, expected.wrench_matrix.rank);
        let sum: f64 = r.twists.iter().map(|t| t.weight * t.f).sum();
        assert!(
            close(r.objective, sum, 1e-12),
            "{} against {sum}",
            r.objective
        );
    }
}

#[test]
fn the_robot_file_3upu_rows_at_home_are_those_of_eq_18() {
    // The translational 3-UPU of examples/robots/three_upu.toml at home: its rows (three leg
    // lines, one constraint couple per leg) give the hand-written eq. 18's F for any twist
    // when the hand-written model has the file's upper U-joint axes. (Away from home they
    // differ by design: eq. 18 keeps the upper axes fixed in the platform, while a robot file
    // takes the joints' current axes, the middle one turning with the leg.)
    let text = std::fs::read_to_string(format!(
        "{}/../../examples/robots/three_upu.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let table: toml::Table = toml::from_str(&text).unwrap();
    let model = pkm_robot_file::RobotModel::from_toml(&text).unwrap();
    let config = model
        .inverse_kinematics_configuration(&model.home_task(), model.home_mode())
        .unwrap();
    let jacobians = model.screw_jacobians(&config).unwrap();
    let axes = |leg: usize| -> [Vector3<f64>; 2] {
        let upper = &table["legs"][leg]["joints"][2]["axes"];
        std::array::from_fn(|k| {
            let a = upper[k].as_array().unwrap();
            Vector3::from_fn(|i, _| a[i].as_float().unwrap())
        })
    };
    let upu = ThreeUpu::new(ThreeUpuDesign {
        base_radius: 0.2,
        platform_radius: 0.1,
        azimuths: [-90.0_f64, 30.0, 150.0].map(f64::to_radians),
        upper: std::array::from_fn(|i| {
            let [u1, u2] = axes(i);
            UJointAxes { u1, u2 }
        }),
    })
    .unwrap();
    let pose = Isometry3::translation(0.0, 0.0, 0.3);
    let twists = [
        section_4_1_twist(),
        Twist::from_vector(Vector6::new(0.3, -0.2, 0.9, 0.05, 0.01, -0.02)),
        Twist::from_vector(Vector6::new(0.0, 0.0, 0.0, 1.0, 0.0, 0.0)),
    ];
    for twist in twists {
        let chi = twist.as_vector();
        let f_file: f64 = [&jacobians.j_a, &jacobians.j_c]
            .iter()
            .flat_map(|m| m.row_iter().map(|r| r.iter().copied().collect::<Vec<_>>()))
            .map(|w| {
                (0..3)
                    .map(|j| w[j] * chi[3 + j] + w[3 + j] * chi[j])
                    .sum::<f64>()
                    .powi(2)
            })
            .sum();
        let f_hand = upu.task_objective(&pose, &twist).unwrap();
        assert!(close(f_file, f_hand, 1e-12), "{f_file} against {f_hand}");
    }
}

#[test]
fn a_robot_file_task_study_refuses_what_does_not_fit_at_its_key() {
    let base = format!(
        "[mechanism.stewart_gough]\nbase_radius = 0.12\nplatform_radius = 0.08\n\
         base_separation_deg = 30.0\nplatform_separation_deg = 8.0\n\n[task]\n\
         goal = \"maximise\"\nvariables = {{ x = [-0.1, 0.1] }}\n\
         starts = {{ count = 2, seed = 1 }}\n{TWIST_2_2_1}"
    );
    let refused = |edit: &dyn Fn(&mut TaskStudy)| {
        let mut study = on_robot_file(&base, "stewart_gough.toml");
        edit(&mut study);
        let e = task(&study, &Silent).expect_err("refused");
        e.path().unwrap().to_string()
    };
    let variables =
        |names: &[(&str, [f64; 2])]| names.iter().map(|(n, b)| ((*n).to_owned(), *b)).collect();
    assert_eq!(
        refused(&|s| s.task.variables = variables(&[("tilt_x_deg", [0.0, 1.0])])),
        "task.variables.tilt_x_deg"
    );
    assert_eq!(
        refused(&|s| s.task.variables = variables(&[("rx", [0.0, 0.1])])),
        "task.variables.rx"
    );
    assert_eq!(
        refused(&|s| s.task.at = [("rz".to_owned(), 1.0)].into()),
        "task.at.rz"
    );
    assert_eq!(
        refused(&|s| s.task.pose.position[2] = Metres(0.3)),
        "task.pose"
    );
    assert_eq!(
        refused(&|s| s.task.max_angle_deg = Some(Degrees(10.0))),
        "task.max_angle_deg"
    );
    // `at` belongs to robot files.
    let mut hand: TaskStudy = from_toml_str(&base).unwrap();
    hand.task.at = [("z".to_owned(), 0.3)].into();
    assert_eq!(
        task(&hand, &Silent)
            .unwrap_err()
            .path()
            .unwrap()
            .to_string(),
        "task.at"
    );
}
