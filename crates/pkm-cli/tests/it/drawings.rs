//! Every study command draws the robot it studied: `robot.svg` is a well-formed SVG with one
//! polyline per link in every view, `robot.csv` holds the skeleton the library computes at the
//! drawn pose, both are listed in `results.json`, and both are the same bytes for any number of
//! threads.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{example, pkm, run_study, study};
use nalgebra::Vector3;
use pkm_mechanisms::{
    ElbowMode, LegBranch, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios,
    LinkKind, Placement, RotaryDelta, RotaryDeltaDesign, Skeleton, Tsai3Dof, TsaiDesign,
};
use pkm_traits::WorkspaceConstraint;
use pkm_workspace_indices::Workspace;
use std::path::Path;

/// The stroke colours of the four link kinds, as plotters writes them (pkm-draw's palette).
const LINK_STROKES: [&str; 4] = [
    "stroke=\"#5A5A5A\"",
    "stroke=\"#C82828\"",
    "stroke=\"#285AC8\"",
    "stroke=\"#148C3C\"",
];

/// The drawing's data, by element.
#[derive(Debug, Default)]
struct Drawing {
    svg: String,
    /// `point` rows: label and position.
    points: Vec<(String, Vector3<f64>)>,
    /// `link` rows (two per link).
    link_ends: usize,
    /// `axis` rows (two per axis).
    axis_rows: usize,
    /// `path` rows: kind and position.
    path: Vec<(String, Vector3<f64>)>,
}

fn read_drawing(dir: &Path, results: &serde_json::Value) -> Drawing {
    let files: Vec<&str> = results["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(
        files.contains(&"robot.svg") && files.contains(&"robot.csv"),
        "{files:?}"
    );
    let text = std::fs::read_to_string(dir.join("robot.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("element,index,label,kind,x,y,z"));
    let mut drawing = Drawing {
        svg: std::fs::read_to_string(dir.join("robot.svg")).unwrap(),
        ..Drawing::default()
    };
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let n = cells.len();
        let p = Vector3::new(
            cells[n - 3].parse().unwrap(),
            cells[n - 2].parse().unwrap(),
            cells[n - 1].parse().unwrap(),
        );
        match cells[0] {
            "point" => drawing.points.push((cells[2].to_owned(), p)),
            "link" => drawing.link_ends += 1,
            "axis" => drawing.axis_rows += 1,
            "path" => drawing.path.push((cells[n - 4].to_owned(), p)),
            other => panic!("unexpected element {other}"),
        }
    }
    drawing
}

/// The tags of `svg` nest: every opened element is closed, in order.
fn assert_well_formed(svg: &str) {
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let mut open: Vec<String> = Vec::new();
    let mut rest = svg;
    while let Some(start) = rest.find('<') {
        let end = start + rest[start..].find('>').expect("every tag ends");
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') || tag.starts_with('!') || tag.ends_with('/') {
            continue;
        }
        match tag.strip_prefix('/') {
            Some(closing) => assert_eq!(open.pop().as_deref(), Some(closing.trim()), "{tag}"),
            None => open.push(tag.split_whitespace().next().unwrap().to_owned()),
        }
    }
    assert!(open.is_empty(), "unclosed: {open:?}");
}

/// `drawing` is a well-formed picture of `skeleton` in four views: one polyline per link per
/// view plus one legend entry per kind of link, and the CSV's points are the skeleton's, bit
/// for bit.
fn assert_draws(drawing: &Drawing, skeleton: &Skeleton) {
    assert_well_formed(&drawing.svg);
    let polylines = drawing
        .svg
        .lines()
        .filter(|l| l.contains("<polyline") && LINK_STROKES.iter().any(|s| l.contains(s)))
        .count();
    let kinds = [
        LinkKind::Base,
        LinkKind::Actuated,
        LinkKind::Passive,
        LinkKind::Platform,
    ]
    .into_iter()
    .filter(|k| skeleton.links_of(*k).next().is_some())
    .count();
    assert_eq!(polylines, 4 * skeleton.links.len() + kinds);
    assert_eq!(drawing.link_ends, 2 * skeleton.links.len());
    assert_eq!(drawing.points.len(), skeleton.points.len());
    for ((label, p), expected) in drawing.points.iter().zip(&skeleton.points) {
        assert_eq!(label, &expected.label);
        assert_eq!(p, &expected.position, "{label}");
    }
}

/// The drawn pose: the platform centre, the skeleton's first point.
fn pose(drawing: &Drawing) -> Vector3<f64> {
    assert_eq!(drawing.points[0].0, "p");
    drawing.points[0].1
}

fn number(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
}

#[test]
fn the_workspace_drawing_is_the_design_at_the_member_nearest_the_centre() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "workspace",
        &study("nuwar_workspace_quick.toml"),
        out.path(),
        &[],
    );
    let drawing = read_drawing(out.path(), &results);
    // The design and constraints of the study, through the library.
    let delta = RotaryDelta::new(RotaryDeltaDesign {
        base_radius: 0.15,
        plate_offset: 0.04,
        arm: 0.2,
        forearm: 0.45,
        alpha: 35.264389682754654f64.to_radians(),
        beta: 60f64.to_radians(),
        placement: Placement {
            motor_plane_z: 0.0,
            azimuth_motor_1: 0.0,
        },
    })
    .unwrap();
    let limits = [
        WorkspaceConstraint::below(0.0).unwrap(),
        WorkspaceConstraint::joint_range((-40f64).to_radians(), 90f64.to_radians()).unwrap(),
        WorkspaceConstraint::passive_cone(35f64.to_radians()).unwrap(),
        WorkspaceConstraint::leg_clearance(0.03).unwrap(),
    ];
    let workspace = Workspace::new(&delta, &[ElbowMode::Out], &limits).unwrap();
    let p = pose(&drawing);
    assert_draws(
        &drawing,
        &Skeleton::rotary_delta(&delta, &p, ElbowMode::Out).unwrap(),
    );
    // The section y = 0 of the box around the cylinder r = 0.76 m, z in [-0.65, 0]: every
    // drawn point is a member on the plane, and none is nearer the box's centre than the pose.
    let centre = Vector3::new(0.0, 0.0, -0.325);
    assert!(!drawing.path.is_empty() && drawing.path.len() <= 48 * 48);
    for (kind, q) in &drawing.path {
        assert_eq!(kind, "workspace_points");
        assert!(q.y.abs() < 1e-15 && workspace.contains(q), "{q:?}");
        assert!((q - centre).norm() >= (p - centre).norm());
    }
    assert!(drawing.path.iter().any(|(_, q)| *q == p));
    assert!(workspace.contains(&p));
}

#[test]
fn the_sweep_draws_its_optimum_and_merge_draws_the_same() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study("sweep", &study("tsai_quick.toml"), out.path(), &[]);
    let drawing = read_drawing(out.path(), &results);
    let design = &results["result"]["optimum"]["design"];
    let (a, b) = (number(&design["a"]), number(&design["b"]));
    let tsai = Tsai3Dof::new(TsaiDesign::from_deg(a, b, 0.0, 0.0, 120.0, 240.0)).unwrap();
    let p = pose(&drawing);
    assert_draws(
        &drawing,
        &Skeleton::tsai(&tsai, &p, LegBranch::PRINCIPAL_OUT).unwrap(),
    );
    // Merged shards end in the same code: the same drawing.
    let shards: Vec<tempfile::TempDir> = (1..=2)
        .map(|i| {
            let dir = tempfile::tempdir().unwrap();
            let shard = format!("{i}/2");
            run_study(
                "sweep",
                &study("tsai_quick.toml"),
                dir.path(),
                &["--shard", &shard],
            );
            assert!(!dir.path().join("robot.svg").exists());
            dir
        })
        .collect();
    let merged = tempfile::tempdir().unwrap();
    let run = pkm(&[
        "merge",
        shards[0].path().to_str().unwrap(),
        shards[1].path().to_str().unwrap(),
        "--out",
        merged.path().to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    for name in ["robot.svg", "robot.csv"] {
        assert_eq!(
            std::fs::read(out.path().join(name)).unwrap(),
            std::fs::read(merged.path().join(name)).unwrap()
        );
    }
}

#[test]
fn the_pareto_study_draws_its_first_weighted_optimum() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "pareto",
        &study("linear_delta_pareto_quick.toml"),
        out.path(),
        &[],
    );
    let drawing = read_drawing(out.path(), &results);
    let node = &results["result"]["weighted_optima"][0]["node"];
    let front = results["result"]["front"].as_array().unwrap();
    let design = &front.iter().find(|f| &f["node"] == node).unwrap()["design"];
    let value = |key: &str, nominal: f64| design.get(key).map_or(nominal, number);
    let robot = LinearDelta::new(LinearDeltaDesign {
        ratios: LinearDeltaRatios {
            l1_over_yr: value("l1_over_yr", 2.0),
            ya_over_yr: value("ya_over_yr", 0.0),
            zr_over_yr: value("zr_over_yr", 0.0),
            l2_over_l1: value("l2_over_l1", 0.63),
        },
        yr: 1.0,
    })
    .unwrap();
    let p = pose(&drawing);
    // The Linear Delta's section is the plane x = 0, across its rails.
    assert!(p.x.abs() < 1e-15);
    let skeleton = Skeleton::linear_delta(&robot, &p, LinearDeltaMode::PAPER).unwrap();
    assert_draws(&drawing, &skeleton);
}

#[test]
fn optimize_draws_the_optimal_tsai_design() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "optimize",
        &example("tsai_volume_optimize.toml"),
        out.path(),
        &[],
    );
    let drawing = read_drawing(out.path(), &results);
    let d = &results["result"]["design"];
    let tsai = Tsai3Dof::new(TsaiDesign::from_deg(
        number(&d["a"]),
        number(&d["b"]),
        number(&d["d_plus_e"]),
        number(&d["c_minus_r"]),
        number(&d["phi2_deg"]),
        number(&d["phi3_deg"]),
    ))
    .unwrap();
    let p = pose(&drawing);
    assert_draws(
        &drawing,
        &Skeleton::tsai(&tsai, &p, LegBranch::PRINCIPAL_OUT).unwrap(),
    );
    // Inside the reach hemisphere, as every member of the drawn section.
    assert!(p.z >= 0.0 && p.norm() <= tsai.reach());
}

#[test]
fn the_task_drawing_is_the_optimal_pose_with_the_twist_axis() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "task",
        &example("stewart_task_synthesis.toml"),
        out.path(),
        &[],
    );
    let drawing = read_drawing(out.path(), &results);
    assert_well_formed(&drawing.svg);
    let r = &results["result"];
    let position: Vec<f64> = r["pose"]["position"]
        .as_array()
        .unwrap()
        .iter()
        .map(number)
        .collect();
    assert_eq!(pose(&drawing), Vector3::from_column_slice(&position));
    // Base joints B1…B6 then platform joints P1…P6 alternate after p; each leg is as long as
    // the inverse kinematics' leg length in results.json.
    let legs: Vec<f64> = r["leg_lengths"]
        .as_array()
        .unwrap()
        .iter()
        .map(number)
        .collect();
    for (i, expected) in legs.iter().enumerate() {
        let (b, q) = (&drawing.points[1 + 2 * i], &drawing.points[2 + 2 * i]);
        assert_eq!(
            (b.0.as_str(), q.0.as_str()),
            (&*format!("B{}", i + 1), &*format!("P{}", i + 1))
        );
        assert!(((q.1 - b.1).norm() - expected).abs() < 1e-12 * expected);
    }
    // One task twist: one axis (its point and point plus unit direction).
    assert_eq!(drawing.axis_rows, 2);
    assert!(drawing.svg.contains("task twist 1"));
}

#[test]
fn the_dynamics_drawing_is_the_robot_at_the_start_of_its_trajectory() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "dynamics",
        &example("nuwar_dynamics_csv.toml"),
        out.path(),
        &[],
    );
    let drawing = read_drawing(out.path(), &results);
    let delta = RotaryDelta::new(RotaryDeltaDesign {
        base_radius: 0.194,
        plate_offset: 0.03,
        arm: 0.26,
        forearm: 0.48,
        alpha: 35.26f64.to_radians(),
        beta: 60f64.to_radians(),
        placement: Placement {
            motor_plane_z: -0.2928,
            azimuth_motor_1: 300f64.to_radians(),
        },
    })
    .unwrap();
    let p = pose(&drawing);
    assert_draws(
        &drawing,
        &Skeleton::rotary_delta(&delta, &p, ElbowMode::Out).unwrap(),
    );
    let samples = results["result"]["samples"].as_u64().unwrap() as usize;
    assert_eq!(drawing.path.len(), samples);
    assert!(drawing.path.iter().all(|(kind, _)| kind == "trajectory"));
    assert_eq!(drawing.path[0].1, p);
}

#[test]
fn drawings_do_not_depend_on_the_thread_count() {
    for (command, file) in [
        ("workspace", study("nuwar_workspace_quick.toml")),
        ("workspace", study("linear_delta_workspace_quick.toml")),
        ("sweep", study("tsai_quick.toml")),
        ("task", example("three_upu_singularity.toml")),
    ] {
        let runs: Vec<Vec<Vec<u8>>> = ["1", "2"]
            .into_iter()
            .map(|threads| {
                let out = tempfile::tempdir().unwrap();
                let results = run_study(command, &file, out.path(), &["--threads", threads]);
                assert_well_formed(&read_drawing(out.path(), &results).svg);
                ["robot.svg", "robot.csv"]
                    .map(|name| std::fs::read(out.path().join(name)).unwrap())
                    .to_vec()
            })
            .collect();
        assert_eq!(runs[0], runs[1], "{command} {}", file.display());
    }
}

#[test]
fn a_design_without_a_drawable_pose_is_a_warning_not_a_failure() {
    // Positions at or below z = -10 m: the workspace, and so its cross-section, is empty.
    let text = std::fs::read_to_string(study("nuwar_workspace_quick.toml"))
        .unwrap()
        .replace("below_z = 0.0", "below_z = -10.0");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("empty.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("out");
    let run = pkm(&[
        "workspace",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    assert!(
        run.stdout
            .contains("warning: no drawing of the robot: no point of the cross-section y = 0 m"),
        "{}",
        run.stdout
    );
    assert!(!out.join("robot.svg").exists() && !out.join("robot.csv").exists());
    let results: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert!(
        !results["files"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| f.as_str().unwrap().starts_with("robot"))
    );
}
