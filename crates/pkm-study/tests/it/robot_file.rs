//! A robot file as a study mechanism (issue 18, the study hookup): the workspace study of the
//! Tsai platform and the Linear Delta written as robot files agrees with the same study on the
//! hand-written tables point by point; a sweep over a robot file's `[parameters]` variable
//! agrees with the hand-written sweep at the same nodes; a Pareto study runs on a robot file;
//! errors name their key path.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::print_stdout
)]

use nalgebra::Vector3;
use pkm_mechanisms::{LinkKind, PointKind, Skeleton};
use pkm_robot_file::Joint;
use pkm_study::Actuation;
use pkm_study::outcome::{Artifact, Cell, Table};
use pkm_study::registry::Built;
use pkm_study::schema::mechanism::{MechanismSpec, WorkspaceVisitor};
use pkm_study::schema::robot_file::RobotFileSpec;
use pkm_study::workspace::constraints_of;
use pkm_study::{
    GridRun, GridStudy, StudyError, StudyMechanism, WorkspaceStudy, from_json_str, from_toml_str,
    pareto, sweep, workspace,
};
use pkm_traits::{ConstrainedWorkspace, Silent};
use pkm_workspace_indices::{Dim, Region, TranslationalCondition, Workspace};

/// Relative agreement of the study numbers (W, η, GCI, 1/κ at a point).
const AGREE: f64 = 1e-9;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= AGREE * a.abs().max(b.abs()) + 1e-300
}

fn robot_table(file: &str) -> toml::Table {
    let path = format!(
        "{}/../../examples/robots/{file}",
        env!("CARGO_MANIFEST_DIR")
    );
    toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn robot_spec(table: toml::Table) -> MechanismSpec {
    MechanismSpec::RobotFile(RobotFileSpec::inline(table))
}

/// 1/κ at every sample point, `None` outside the workspace.
struct PerPoint<'a>(&'a [Vector3<f64>]);

impl WorkspaceVisitor for PerPoint<'_> {
    type Output = Vec<Option<f64>>;
    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        self.0
            .iter()
            .map(|x| workspace.inverse_condition(x))
            .collect()
    }
}

/// The hand-written study and the same study on `robot`: the same members, 1/κ at every member,
/// W, η and GCI within [`AGREE`]. Returns the number of members.
fn workspace_agrees(hand: &str, robot: toml::Table) -> usize {
    let hand: WorkspaceStudy = from_toml_str(hand).unwrap();
    let mut file = hand.clone();
    file.mechanism = robot_spec(robot);
    let points = {
        let domain = hand.sampling.domain(None).unwrap();
        hand.sampling.point_set(domain).unwrap()
    };
    let values = |study: &WorkspaceStudy| {
        let constraints = constraints_of(&study.mechanism, study.constraints.as_ref()).unwrap();
        Built::new(study.mechanism.clone())
            .unwrap()
            .with_workspace(&constraints, PerPoint(points.points()))
            .unwrap()
    };
    let (a, b) = (values(&hand), values(&file));
    let (mut members, mut worst) = (0, 0.0_f64);
    for (k, (a, b)) in a.iter().zip(&b).enumerate() {
        match (a, b) {
            (Some(a), Some(b)) => {
                assert!(close(*a, *b), "point {k}: 1/κ {a} vs {b}");
                worst = worst.max((a - b).abs() / a.abs().max(b.abs()));
                members += 1;
            }
            (None, None) => {}
            _ => panic!(
                "point {k} at {}: membership {a:?} vs {b:?}",
                points.points()[k]
            ),
        }
    }
    assert!(members >= 100, "vacuous: {members} members");
    let (a, b) = (
        workspace(&hand, &Silent).unwrap().result.estimate,
        workspace(&file, &Silent).unwrap().result.estimate,
    );
    assert_eq!(a.n_inside, b.n_inside);
    assert!(close(a.volume, b.volume), "W {} vs {}", a.volume, b.volume);
    assert!(close(a.eta, b.eta), "η {} vs {}", a.eta, b.eta);
    let (ga, gb) = (a.gci.unwrap(), b.gci.unwrap());
    assert!(close(ga, gb), "GCI {ga} vs {gb}");
    println!(
        "{members} members of {}; largest relative 1/κ difference {worst:.1e}; \
         GCI {:.1e}, W {:.1e}",
        points.points().len(),
        (ga - gb).abs() / ga,
        (a.volume - b.volume).abs() / a.volume
    );
    members
}

#[test]
fn tsai_robot_file_workspace_agrees_with_the_tsai_table_with_and_without_a_joint_range() {
    // Under the joint range, lower arms near θ1 = 0: the hand-written model reported
    // 2π − 0.11 rad where the file reports −0.11 rad, so a range across 0 kept other members.
    for (seed, points, constraints) in [
        (3, 4096, ""),
        (5, 8192, "[constraints]\njoint_range_deg = [-30.0, 60.0]\n"),
    ] {
        let hand = format!(
            "[mechanism.tsai]\na = 0.44\nb = 0.56\n{constraints}[sampling]\nseed = {seed}\n\
             points = {points}\nreplicates = 2\n\
             region = {{ hemisphere = {{ center = [0.0, 0.0, 0.0], radius = 1.0 }} }}\n"
        );
        let members = workspace_agrees(&hand, robot_table("tsai.toml"));
        assert!(members > 1000, "{constraints}: {members}");
    }
}

#[test]
fn linear_delta_robot_file_workspace_agrees_with_its_table_under_joint_ranges() {
    let hand = r#"
[mechanism.linear_delta]
l1_over_yr = 1.5
ya_over_yr = 0.0
zr_over_yr = 0.0
l2_over_l1 = 0.8333333333333334
yr = 0.2
[constraints]
joint_range = [-0.3, 0.3]
below_z = 0.0
[sampling]
seed = 5
points = 4096
replicates = 2
region = { box = { lower = [-0.3, -0.25, -0.35], upper = [0.3, 0.25, 0.0] } }
"#;
    let members = workspace_agrees(hand, robot_table("linear_delta.toml"));
    assert!(members > 300, "{members}");
}

/// A Linear Delta (YR = 0.2 m, L1 = 0.3 m, YA = 0, ZR = 0.1 m) whose centre arm lies along
/// its rail at home, so that the centre arm length L2 is one number of the file: the centre
/// carriage leads the end effector (0, 0, 0.1) by `centre_arm` along x. The outer carriages
/// trail by 0.2 m (the paper's leaning, as `examples/robots/linear_delta.toml`); each U joint's
/// first axis is $\hat x \times d$ (d the arm), its second $d \times$ the first.
const LINEAR_DELTA_BY_PARAMETERS: &str = r#"
name = "3-PUU"
task = ["x", "y", "z"]

[parameters]
centre_arm = 0.18

[home]
position = [0.0, 0.0, 0.1]

[[legs]]
joints = [
  { type = "P", axis = [1.0, 0.0, 0.0], actuated = true, offset = -0.2 },
  { type = "U", axes = [[0.0, -0.1, 0.2], [0.05, -0.04, -0.02]], point = [-0.2, -0.2, 0.0] },
  { type = "U", axes = [[0.05, -0.04, -0.02], [0.0, -0.1, 0.2]], point = [0.0, 0.0, 0.1] },
]

[[legs]]
joints = [
  { type = "P", axis = [1.0, 0.0, 0.0], actuated = true, offset = -0.2 },
  { type = "U", axes = [[0.0, -0.1, -0.2], [0.05, 0.04, -0.02]], point = [-0.2, 0.2, 0.0] },
  { type = "U", axes = [[0.05, 0.04, -0.02], [0.0, -0.1, -0.2]], point = [0.0, 0.0, 0.1] },
]

[[legs]]
joints = [
  { type = "P", axis = [1.0, 0.0, 0.0], actuated = true, offset = "centre_arm" },
  { type = "U", axes = [[0.0, 1.0, 0.0], [0.0, 0.0, -1.0]], point = ["centre_arm", 0.0, 0.1] },
  { type = "U", axes = [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0]], point = [0.0, 0.0, 0.1] },
]
"#;

/// The hand-written table of the same robot (L2/L1 = `centre_arm` / 0.3) with its grid over
/// L2/L1, and the robot file's study over `centre_arm` at the same designs.
fn linear_delta_grids() -> (GridStudy, GridStudy) {
    // z ≤ 0: the plane the hand-written model's end effector cannot pass (Miller 2004 §2.2).
    let common = r#"
[constraints]
below_z = 0.0
[sampling]
seed = 11
points = 4096
replicates = 2
region = { box = { lower = [-0.4, -0.3, -0.45], upper = [0.4, 0.3, 0.05] } }
[sweep]
objective = { gci = 1.0 }
report = ["volume", "eta"]
[pareto]
objectives = ["volume", "gci"]
"#;
    let hand = format!(
        "[mechanism.linear_delta]\nl1_over_yr = 1.5\nya_over_yr = 0.0\nzr_over_yr = 0.5\n\
         l2_over_l1 = 0.6\nyr = 0.2\n{common}\n\
         [[variables]]\nname = \"l2_over_l1\"\nfrom = 0.6\nto = 0.9\nstep = 0.1\n"
    );
    let file = format!(
        "{common}\n[[variables]]\nname = \"centre_arm\"\nfrom = 0.18\nto = 0.27\nstep = 0.03\n\
         [mechanism.robot_file]\nfile = \"unused\"\n"
    );
    let hand: GridStudy = from_toml_str(&hand).unwrap();
    let mut file: GridStudy = from_toml_str(&file).unwrap();
    file.mechanism = robot_spec(toml::from_str(LINEAR_DELTA_BY_PARAMETERS).unwrap());
    (hand, file)
}

fn landscape(artifacts: &[Artifact]) -> &Table {
    artifacts
        .iter()
        .find_map(|a| match a {
            Artifact::Table { name, table } if name.contains("landscape") => Some(table),
            _ => None,
        })
        .expect("a landscape table")
}

#[test]
fn a_sweep_over_a_robot_file_parameter_matches_the_linear_delta_sweep() {
    let (hand, file) = linear_delta_grids();
    let a = sweep(&hand, pkm_study::Shard::WHOLE, &Silent).unwrap();
    let b = sweep(&file, pkm_study::Shard::WHOLE, &Silent).unwrap();
    let (ta, tb) = (landscape(&a.artifacts), landscape(&b.artifacts));
    assert_eq!(ta.header[2..], tb.header[2..]);
    assert_eq!((ta.rows.len(), tb.rows.len()), (4, 4));
    let mut compared = 0;
    for (ra, rb) in ta.rows.iter().zip(&tb.rows) {
        // Columns: node, the variable (L2/L1 against L2), the indices, infeasible.
        assert_eq!(ra[0], rb[0]);
        let (Cell::Number(ratio), Cell::Number(l2)) = (&ra[1], &rb[1]) else {
            panic!("{ra:?} vs {rb:?}")
        };
        assert!(close(*ratio * 0.3, *l2), "L2/L1 = {ratio}, L2 = {l2}");
        for (ca, cb) in ra[2..].iter().zip(&rb[2..]) {
            match (ca, cb) {
                (Cell::Number(x), Cell::Number(y)) => {
                    assert!(close(*x, *y), "{ra:?} vs {rb:?}");
                    compared += 1;
                }
                (x, y) => assert_eq!(x, y),
            }
        }
    }
    // volume, eta, gci and the utility at four nodes.
    assert_eq!(compared, 16, "{ta:?}");
    let (GridRun::Complete(a), GridRun::Complete(b)) = (a.result, b.result) else {
        panic!("a whole grid")
    };
    assert_eq!(a.grid_optimum.0, b.grid_optimum.0);
    assert_eq!(b.mechanism, "robot_file");
}

#[test]
fn a_pareto_study_runs_on_a_robot_file() {
    let (hand, file) = linear_delta_grids();
    let run = |study| match pareto(study, pkm_study::Shard::WHOLE, &Silent)
        .unwrap()
        .result
    {
        GridRun::Complete(r) => r,
        GridRun::Part(_) => panic!("a whole grid"),
    };
    let (a, b) = (run(&hand), run(&file));
    assert!(!b.front.is_empty());
    let nodes = |r: &pkm_study::ParetoResult| r.front.iter().map(|p| p.node).collect::<Vec<_>>();
    assert_eq!(nodes(&a), nodes(&b));
    for (p, q) in a.front.iter().zip(&b.front) {
        for (x, y) in p.values.iter().zip(&q.values) {
            assert!(close(*x, *y), "{p:?} vs {q:?}");
        }
    }
}

#[test]
fn parameters_are_the_design_variables() {
    let mut table: toml::Table = toml::from_str(LINEAR_DELTA_BY_PARAMETERS).unwrap();
    let parameters = table["parameters"].as_table_mut().unwrap();
    parameters.insert("tilt_deg".into(), toml::Value::Integer(3));
    let mut spec = robot_spec(table);
    let variables = spec.variables();
    let names: Vec<_> = variables.iter().map(|v| (&*v.name, v.unit)).collect();
    assert_eq!(
        names,
        [
            ("centre_arm", pkm_study::Unit::Length),
            ("tilt_deg", pkm_study::Unit::Angle)
        ]
    );
    assert_eq!(spec.get("tilt_deg"), Some(3.0));
    spec.set("centre_arm", 0.25).unwrap();
    assert_eq!(spec.get("centre_arm"), Some(0.25));
    let unknown = spec.set("b", 0.5).unwrap_err();
    assert!(
        unknown.contains("expected one of centre_arm, tilt_deg"),
        "{unknown}"
    );
}

#[test]
fn a_workspace_study_reads_an_inline_robot_from_json() {
    let robot =
        serde_json::to_value(toml::from_str::<toml::Table>(LINEAR_DELTA_BY_PARAMETERS).unwrap());
    let study = serde_json::json!({
        "mechanism": { "robot_file": robot.unwrap() },
        "sampling": {
            "points": 1024,
            "region": { "box": { "lower": [-0.4, -0.3, -0.45], "upper": [0.4, 0.3, 0.05] } }
        }
    });
    let study: WorkspaceStudy = from_json_str(&study.to_string()).unwrap();
    let result = workspace(&study, &Silent).unwrap().result;
    assert!(result.estimate.n_inside > 0);
    assert_eq!(result.mechanism, "robot_file");
}

/// The key path of the study error of `robot` (a robot file's keys) in a workspace study.
fn error_path(robot: &str) -> (String, String) {
    let table: toml::Table = toml::from_str(robot).unwrap();
    let hand = "[mechanism.tsai]\na = 0.44\nb = 0.56\n[sampling]\npoints = 64\n";
    let mut study: WorkspaceStudy = from_toml_str(hand).unwrap();
    study.mechanism = robot_spec(table);
    match workspace(&study, &Silent) {
        Err(e @ StudyError::Invalid { .. }) => (e.path().unwrap().to_string(), e.to_string()),
        other => panic!("{other:?}"),
    }
}

#[test]
fn robot_file_errors_name_their_key_path() {
    let unknown_name =
        LINEAR_DELTA_BY_PARAMETERS.replace(r#"point = ["centre_arm""#, r#"point = ["center_arm""#);
    let (path, message) = error_path(&unknown_name);
    assert_eq!(path, "mechanism.robot_file.legs[2].joints[1].point[0]");
    assert!(message.contains("expected one of centre_arm"), "{message}");

    let parallel_axes = LINEAR_DELTA_BY_PARAMETERS.replace(
        "[[0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]",
        "[[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]",
    );
    let (path, message) = error_path(&parallel_axes);
    assert!(
        path.starts_with("mechanism.robot_file.legs[2].joints[1]"),
        "{path}: {message}"
    );

    let three_prs = std::fs::read_to_string(format!(
        "{}/../../examples/robots/three_prs.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    // A workspace study of a robot whose task is not the platform position needs its
    // [task_space] section.
    let (path, message) = error_path(&three_prs);
    assert_eq!(path, "task_space");
    assert!(message.contains("tilt_x"), "{message}");
}

#[test]
fn a_named_file_is_resolved_by_the_caller() {
    let study = r#"
[mechanism.robot_file]
file = "../robots/tsai.toml"
[sampling]
points = 256
region = { hemisphere = { center = [0.0, 0.0, 0.0], radius = 1.0 } }
"#;
    let mut study: WorkspaceStudy = from_toml_str(study).unwrap();
    let unresolved = workspace(&study, &Silent).unwrap_err();
    assert_eq!(
        unresolved.path().unwrap().to_string(),
        "mechanism.robot_file.file"
    );
    let MechanismSpec::RobotFile(spec) = &mut study.mechanism else {
        panic!("a robot file")
    };
    let studies = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies");
    let missing = spec
        .clone()
        .resolve_file(&pkm_study::load::Directory::default());
    let message = missing.unwrap_err().to_string();
    assert!(
        message.contains("cannot read ../robots/tsai.toml"),
        "{message}"
    );
    spec.resolve_file(&pkm_study::load::Directory(studies.clone()))
        .unwrap();
    assert!(workspace(&study, &Silent).unwrap().result.estimate.n_inside > 0);
}

/// The file's platform point of every leg (its last joint point), read from the model's legs.
fn platform_points(model: &pkm_robot_file::RobotModel) -> Vec<Vector3<f64>> {
    model
        .legs()
        .iter()
        .map(|leg| {
            leg.joints
                .iter()
                .rev()
                .find_map(|j| match j {
                    Joint::Revolute { point, .. } => Some(*point),
                    Joint::Spherical { center } => Some(*center),
                    Joint::Prismatic { .. } => None,
                })
                .unwrap()
        })
        .collect()
}

/// The length of every link of `kind` in `s`, in order.
fn lengths(s: &Skeleton, kind: LinkKind) -> Vec<f64> {
    (0..s.links.len())
        .filter(|&k| s.links[k].kind == kind)
        .map(|k| s.link_length(k).unwrap())
        .collect()
}

#[test]
fn a_robot_file_is_drawn_from_its_joints() {
    let cases = [
        ("tsai.toml", [[0.1, 0.2, 0.6], [-0.2, 0.1, 0.5]], 3, 3),
        (
            "linear_delta.toml",
            [[0.02, -0.01, -0.21], [-0.03, 0.0, -0.19]],
            3,
            // Every arm ends at the end effector: a point platform has no polygon.
            0,
        ),
    ];
    let mut worst = 0.0_f64;
    for (file, poses, base_links, plate_links) in cases {
        let spec = Built::new(RobotFileSpec::inline(robot_table(file))).unwrap();
        let model = spec.spec().model().unwrap();
        let home = Vector3::from_column_slice(&model.home()[..3]);
        let at_home = spec.skeleton_at(&home).unwrap();
        let anchors = platform_points(&model);
        for p in poses.map(Vector3::from) {
            let s = spec.skeleton_at(&p).unwrap();
            assert_eq!(s.links, at_home.links, "{file}: one topology");
            assert_eq!(s.links_of(LinkKind::Base).count(), base_links, "{file}");
            assert_eq!(
                s.links_of(LinkKind::Platform).count(),
                plate_links,
                "{file}"
            );
            let plate = s.points.iter().filter(|q| q.kind == PointKind::Platform);
            let plate: Vec<_> = plate.collect();
            assert_eq!(plate.len(), anchors.len(), "{file}");
            // A translational platform: the pose applied to a platform point is a shift.
            for (q, c) in plate.iter().zip(&anchors) {
                let error = (q.position - (p + c - home)).norm();
                assert!(error < 1e-12, "{file} {}: anchor off by {error:e}", q.label);
                worst = worst.max(error);
            }
            for (a, b) in lengths(&s, LinkKind::Passive)
                .iter()
                .zip(lengths(&at_home, LinkKind::Passive))
            {
                assert!(
                    (a - b).abs() < 1e-12,
                    "{file}: passive link {a} vs {b} at home"
                );
                worst = worst.max((a - b).abs());
            }
            // The actuated links: a motor arm keeps its length, a rail is the carriage travel.
            let q = model
                .inverse_kinematics(p.as_slice(), model.home_mode())
                .unwrap();
            let actuated = lengths(&s, LinkKind::Actuated);
            assert_eq!(actuated.len(), 3);
            for (i, (a, b)) in actuated
                .iter()
                .zip(lengths(&at_home, LinkKind::Actuated))
                .enumerate()
            {
                let expected = match spec.spec().actuation() {
                    Actuation::Revolute => b,
                    Actuation::Prismatic => q[i].abs(),
                };
                assert!(
                    (a - expected).abs() < 1e-12,
                    "{file}: actuated {a} vs {expected}"
                );
            }
        }
    }
    println!("anchors and link lengths within {worst:.1e} m");
}

#[test]
fn the_reach_region_of_a_robot_file_holds_its_workspace() {
    let path = format!(
        "{}/../../examples/robots/linear_delta.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let limited = std::fs::read_to_string(path)
        .unwrap()
        .replace("actuated = true,", "actuated = true, limits = [-0.6, 0.6],");
    let cases = [
        (
            robot_table("tsai.toml"),
            "{ ball = { center = [0.0, 0.0, 0.0], radius = 2.0 } }",
        ),
        (
            toml::from_str(&limited).unwrap(),
            "{ box = { lower = [-1.5, -1.5, -1.5], upper = [1.5, 1.5, 1.5] } }",
        ),
    ];
    for (robot, larger) in cases {
        let spec = robot_spec(robot);
        let built = Built::new(spec.clone()).unwrap();
        let Some(Region::Box { lower, upper }) = built.reach_region() else {
            panic!("a box")
        };
        assert!(lower.iter().chain(upper.iter()).all(|v| v.is_finite()));
        let text = format!(
            "[mechanism.tsai]\na = 0.44\nb = 0.56\n[sampling]\nseed = 2\npoints = 16384\nregion = {larger}\n"
        );
        let mut study: WorkspaceStudy = from_toml_str(&text).unwrap();
        study.mechanism = spec.clone();
        let points = {
            let domain = study.sampling.domain(None).unwrap();
            study.sampling.point_set(domain).unwrap()
        };
        let values = built
            .with_workspace(&[], PerPoint(points.points()))
            .unwrap();
        let inside: Vec<_> = points
            .points()
            .iter()
            .zip(&values)
            .filter(|(_, v)| v.is_some())
            .collect();
        let outside_the_bound = inside
            .iter()
            .filter(|(p, _)| (0..3).any(|a| p[a] < lower[a] || p[a] > upper[a]));
        assert_eq!(outside_the_bound.count(), 0);
        assert!(inside.len() > 100, "vacuous: {}", inside.len());
        // Without [sampling.region], the study samples the reach region.
        study.sampling.region = None;
        let estimate = workspace(&study, &Silent).unwrap().result.estimate;
        println!(
            "{} inside of {} in the larger region; {} in the reach box",
            inside.len(),
            values.len(),
            estimate.n_inside
        );
        assert!(estimate.n_inside > 0);
    }
    // Without limits the Linear Delta's carriages run without end: no reach region.
    assert!(
        Built::new(robot_spec(robot_table("linear_delta.toml")))
            .unwrap()
            .reach_region()
            .is_none()
    );
}

/// Membership at every point of the hand-written study `hand` and of the same study on `robot`
/// agrees; returns the members.
fn membership_agrees(hand: &str, robot: toml::Table) -> usize {
    let hand: WorkspaceStudy = from_toml_str(hand).unwrap();
    let mut file = hand.clone();
    file.mechanism = robot_spec(robot);
    let points = {
        let domain = hand.sampling.domain(None).unwrap();
        hand.sampling.point_set(domain).unwrap()
    };
    let inside = |study: &WorkspaceStudy| -> Vec<bool> {
        let constraints = constraints_of(&study.mechanism, study.constraints.as_ref()).unwrap();
        let built = Built::new(study.mechanism.clone()).unwrap();
        let values = built.with_workspace(&constraints, PerPoint(points.points()));
        values.unwrap().iter().map(Option::is_some).collect()
    };
    let (a, b) = (inside(&hand), inside(&file));
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(
        differ,
        0,
        "membership differs at {differ} of {} points",
        a.len()
    );
    let (ea, eb) = (
        workspace(&hand, &Silent).unwrap().result.estimate,
        workspace(&file, &Silent).unwrap().result.estimate,
    );
    assert_eq!(ea.n_inside, eb.n_inside);
    a.iter().filter(|m| **m).count()
}

/// `robot_table(file)` with `modes` in its table.
fn with_modes(file: &str, modes: &[&str]) -> toml::Table {
    let mut table = robot_table(file);
    let modes = modes
        .iter()
        .map(|m| toml::Value::String((*m).into()))
        .collect();
    table.insert("modes".into(), toml::Value::Array(modes));
    table
}

/// The label of the mode with every leg on the other branch than at home.
fn flipped_home(file: &str) -> String {
    let model = RobotFileSpec::inline(robot_table(file)).model().unwrap();
    let home = model.mode_label(model.home_mode());
    home.chars()
        .map(|c| if c == '+' { '-' } else { '+' })
        .collect()
}

#[test]
fn working_modes_of_a_robot_file_match_the_rotary_delta_elbows() {
    // Miller 2004's §3.5 Delta in its canonical placement (examples/robots/rotary_delta.toml);
    // the joint range makes the elbows differ (without it, both branches exist wherever one
    // does).
    let study = |elbows: &str| {
        format!(
            "[mechanism.rotary_delta]\nbase_radius = 0.194\nplate_offset = 0.03\narm = 0.26\n\
             forearm = 0.48\nmotor_plane_z = -0.2928\nazimuth_motor_1_deg = 300.0\n\
             elbow = {elbows}\n[constraints]\njoint_range_deg = [-30.0, 60.0]\n[sampling]\n\
             seed = 3\npoints = 4096\n\
             region = {{ box = {{ lower = [-0.6, -0.6, -1.1], upper = [0.6, 0.6, 0.0] }} }}\n"
        )
    };
    let file = "rotary_delta.toml";
    let other = flipped_home(file);
    // The default is the home mode alone: the elbows out.
    let out = membership_agrees(&study(r#"["out"]"#), robot_table(file));
    let inward = membership_agrees(&study(r#"["in"]"#), with_modes(file, &[&other]));
    let both = membership_agrees(
        &study(r#"["out", "in"]"#),
        with_modes(file, &["home", &other]),
    );
    println!("rotary Delta members: out {out}, in {inward}, both {both}");
    assert!(
        out < both && inward < both && out > 100 && inward > 10,
        "{out} {inward} {both}"
    );
    let spec = RobotFileSpec::inline(robot_table(file));
    let model = spec.model().unwrap();
    assert_eq!(spec.working_modes(&model).unwrap(), [model.home_mode()]);
    let both = RobotFileSpec::inline(with_modes(file, &["home", &other, "home"]));
    assert_eq!(
        both.working_modes(&model).unwrap().len(),
        2,
        "each mode once"
    );
}

#[test]
fn all_working_modes_are_the_union_of_the_modes() {
    // Every combination of the rotary Delta's elbows, leg by leg, under a joint range.
    let region = r#"{ box = { lower = [-0.6, -0.6, -1.1], upper = [0.6, 0.6, 0.0] } }"#;
    let text = format!(
        "[mechanism.tsai]\na = 0.44\nb = 0.56\n[constraints]\njoint_range_deg = [-30.0, 60.0]\n\
         [sampling]\nseed = 4\npoints = 8192\nregion = {region}\n"
    );
    let study: WorkspaceStudy = from_toml_str(&text).unwrap();
    let points = study
        .sampling
        .point_set(study.sampling.domain(None).unwrap())
        .unwrap();
    let inside = |modes: &[&str]| -> Vec<bool> {
        let spec = robot_spec(with_modes("rotary_delta.toml", modes));
        let constraints = constraints_of(&spec, study.constraints.as_ref()).unwrap();
        let built = Built::new(spec).unwrap();
        let values = built.with_workspace(&constraints, PerPoint(points.points()));
        values.unwrap().iter().map(Option::is_some).collect()
    };
    let all = inside(&["all"]);
    let mut union = vec![false; all.len()];
    for label in ["---", "--+", "-+-", "-++", "+--", "+-+", "++-", "+++"] {
        for (u, m) in union.iter_mut().zip(inside(&[label])) {
            *u |= m;
        }
    }
    assert_eq!(all, union);
    let (members, home) = (
        all.iter().filter(|m| **m).count(),
        inside(&["home"]).iter().filter(|m| **m).count(),
    );
    println!("rotary Delta: {members} members in every mode, {home} in the home mode");
    assert!(members > home && home > 100, "{members} {home}");
}

#[test]
fn a_bad_working_mode_is_reported_at_its_key() {
    let mut table = robot_table("tsai.toml");
    table.insert(
        "modes".into(),
        toml::Value::Array(vec!["home".into(), "+-".into()]),
    );
    let spec = RobotFileSpec::inline(table);
    let e = spec.check().unwrap_err();
    assert_eq!(
        e.path().unwrap().to_string(),
        "mechanism.robot_file.modes[1]"
    );
    assert!(
        e.to_string().contains("one `+` or `-` per actuated leg"),
        "{e}"
    );
    let mut table = robot_table("tsai.toml");
    table.insert("modes".into(), toml::Value::Array(vec![]));
    let e = RobotFileSpec::inline(table).check().unwrap_err();
    assert_eq!(e.path().unwrap().to_string(), "mechanism.robot_file.modes");
}

#[test]
fn passive_cones_limit_a_robot_file() {
    let study = |constraints: &str| {
        let text = format!(
            "[mechanism.tsai]\na = 0.44\nb = 0.56\n[constraints]\n{constraints}\n[sampling]\n\
             seed = 6\npoints = 4096\n\
             region = {{ hemisphere = {{ center = [0.0, 0.0, 0.0], radius = 1.0 }} }}\n"
        );
        let mut study: WorkspaceStudy = from_toml_str(&text).unwrap();
        study.mechanism = robot_spec(robot_table("tsai.toml"));
        study
    };
    let inside = |constraints: &str| {
        workspace(&study(constraints), &Silent)
            .unwrap()
            .result
            .estimate
            .n_inside
    };
    let free = inside("below_z = 2.0");
    let wide = inside("passive_cone_deg = 179.9");
    let narrow = inside("passive_cone_deg = 30.0");
    println!("members: free {free}, cone 179.9° {wide}, cone 30° {narrow}");
    assert_eq!(free, wide);
    assert!(0 < narrow && narrow < free, "{narrow} {free}");
}

#[test]
fn leg_clearance_limits_a_robot_file_as_the_rotary_delta() {
    // Miller 2004's §3.5 Delta (examples/robots/rotary_delta.toml) against its table: the same
    // members under a clearance of 0.2 m, fewer than under none.
    let study = |constraints: &str| {
        format!(
            "[mechanism.rotary_delta]\nbase_radius = 0.194\nplate_offset = 0.03\narm = 0.26\n\
             forearm = 0.48\nmotor_plane_z = -0.2928\nazimuth_motor_1_deg = 300.0\n\
             [constraints]\n{constraints}\n[sampling]\nseed = 7\npoints = 4096\n\
             region = {{ box = {{ lower = [-0.6, -0.6, -1.1], upper = [0.6, 0.6, 0.0] }} }}\n"
        )
    };
    let file = robot_table("rotary_delta.toml");
    let free = membership_agrees(&study("below_z = 0.0"), file.clone());
    let limited = membership_agrees(&study("below_z = 0.0\nleg_clearance = 0.2"), file);
    println!("rotary Delta members: {free} free, {limited} with 0.2 m clearance");
    assert!(100 < limited && limited < free, "{limited} {free}");
}

/// Issue 29: the Orthoglide with actuator limits of ±1e5 m samples a reach box of about 1e16 m³
/// where no sample lands in its 0.13 m³ workspace: the study says so, with the 95 % bound,
/// instead of reporting a bare 0; limits beyond ±1e6 are refused at their key.
#[test]
fn a_study_that_cannot_resolve_its_workspace_says_so() {
    let text = std::fs::read_to_string(format!(
        "{}/../../examples/robots/orthoglide.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let huge = text.replace("limits = [-0.6, 0.0]", "limits = [-1e5, 1e5]");
    let hand = "[mechanism.tsai]\na = 0.44\nb = 0.56\n[sampling]\npoints = 256\n";
    let mut study: WorkspaceStudy = from_toml_str(hand).unwrap();
    study.mechanism = robot_spec(toml::from_str(&huge).unwrap());
    let outcome = workspace(&study, &Silent).unwrap();
    assert_eq!(outcome.result.estimate.n_inside, 0);
    let warning = outcome
        .summary
        .iter()
        .find(|l| l.starts_with("warning: no sample"));
    assert!(
        warning.is_some_and(|w| w.contains("below about")),
        "{:?}",
        outcome.summary
    );
    let beyond = text.replace("limits = [-0.6, 0.0]", "limits = [-1e300, 1e300]");
    let (path, _) = error_path(&beyond);
    assert!(path.ends_with(".limits"), "{path}");
}

/// Issue 29: `from_json_str` read one JSON value and ignored what followed it.
#[test]
fn a_json_study_with_trailing_text_is_refused() {
    let study = r#"{"mechanism": {"tsai": {"a": 0.44, "b": 0.56}}, "sampling": {"points": 64}}"#;
    let ok: Result<WorkspaceStudy, _> = from_json_str(&format!("{study}\n  "));
    assert!(ok.is_ok(), "{ok:?}");
    for trailing in [" garbage", " {}", "]", " 1"] {
        let e = from_json_str::<WorkspaceStudy>(&format!("{study}{trailing}")).unwrap_err();
        assert!(matches!(e, StudyError::Schema { .. }), "{trailing}: {e}");
        assert!(e.to_string().contains("after the study"), "{e}");
    }
}

/// Issue 33: a redundantly actuated robot whose task is the position (the Tricept with its
/// central leg actuated too: four actuators) cannot be rated by 1/κ of a square J without
/// `[task_space]`; the study says so at `mechanism.robot_file.legs`.
#[test]
fn a_redundant_robot_without_task_space_is_refused_at_its_legs() {
    let path = format!(
        "{}/../../examples/robots/tricept.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).unwrap().replace(
        "{ type = \"P\", axis = [0.0, 0.0, 1.0] }",
        "{ type = \"P\", axis = [0.0, 0.0, 1.0], actuated = true, offset = 0.6 }",
    );
    let spec = RobotFileSpec::inline(toml::from_str(&text).unwrap());
    let e = spec.translational_robot().unwrap_err();
    assert_eq!(e.path().unwrap().to_string(), "mechanism.robot_file.legs");
    assert!(e.to_string().contains("4 actuators"), "{e}");
}
