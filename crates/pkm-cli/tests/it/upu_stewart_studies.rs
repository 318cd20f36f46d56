//! The 3-UPU and the constant-orientation Stewart–Gough workspace end to end through the `pkm`
//! binary: each study recomputed directly through the library (to 1e-12) and its workspace
//! counted again with a membership test written here from the leg lengths
//! $|p + R r_i - b_i|$; and bad files rejected at their line.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{close, csv, pkm, run_study, study};
use nalgebra::{Rotation3, Vector3};
use pkm_mechanisms::{
    ConstantOrientation, StewartDesign, StewartGough, ThreeUpu, ThreeUpuDesign, UJointAxes,
};
use pkm_traits::{Silent, WorkspaceConstraint};
use pkm_workspace_indices::Workspace;
use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, VolumeEstimate};

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
}

fn points(lower: [f64; 3], upper: [f64; 3], seed: u64) -> PointSet {
    let region = Region::Box {
        lower: Vector3::from(lower),
        upper: Vector3::from(upper),
    };
    PointSet::new(
        Domain::new(region).unwrap(),
        Sampler::Sobol { seed },
        4096,
        4,
    )
    .unwrap()
}

fn assert_same_estimate(e: &serde_json::Value, direct: &VolumeEstimate) {
    assert_eq!(e["n_inside"].as_u64(), Some(direct.n_inside));
    assert!(close(f(&e["volume"]), direct.volume, SAME));
    assert!(close(f(&e["volume_se"]), direct.volume_se, SAME));
    assert!(close(f(&e["eta"]), direct.eta.unwrap(), SAME));
    assert!(close(f(&e["gci"]), direct.gci().unwrap(), SAME));
}

/// The volume of the points `member` accepts: the box volume times the accepted fraction.
fn counted_volume(
    points: &PointSet,
    box_volume: f64,
    member: impl Fn(&Vector3<f64>) -> bool,
) -> f64 {
    let inside = points.points().iter().filter(|p| member(p)).count();
    box_volume * inside as f64 / points.points().len() as f64
}

#[test]
fn three_upu_workspace_matches_the_library_and_a_direct_count() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "workspace",
        &study("three_upu_workspace_quick.toml"),
        out.path(),
        &[],
    );
    let azimuths = [-90f64, 30.0, 150.0].map(f64::to_radians);
    let upu = ThreeUpu::new(ThreeUpuDesign {
        base_radius: 0.2,
        platform_radius: 0.1,
        azimuths,
        upper: azimuths.map(UJointAxes::park),
    })
    .unwrap();
    let limits = [
        WorkspaceConstraint::joint_range(0.3, 0.6).unwrap(),
        WorkspaceConstraint::half_space(-Vector3::z(), -0.05).unwrap(),
    ];
    let points = points([-0.7, -0.7, 0.0], [0.7, 0.7, 0.65], 5);
    let workspace = Workspace::new(&upu, &[()], &limits).unwrap();
    let direct = workspace.volume_and_eta(&points, &Silent).unwrap();
    let e = &results["result"]["estimate"];
    assert!(direct.n_inside > 200, "{}", direct.n_inside);
    assert_same_estimate(e, &direct);

    // Leg i has length |p + r_i − b_i| with b_i, r_i on circles of 0.2 m and 0.1 m.
    let member = |p: &Vector3<f64>| {
        p.z >= 0.05
            && azimuths.iter().all(|t| {
                let radial = Vector3::new(t.cos(), t.sin(), 0.0);
                (0.3..=0.6).contains(&(p + 0.1 * radial - 0.2 * radial).norm())
            })
    };
    let volume = counted_volume(&points, 1.4 * 1.4 * 0.65, member);
    assert!(
        close(f(&e["volume"]), volume, SAME),
        "{} vs {volume}",
        e["volume"]
    );

    let (header, rows) = csv(&out.path().join("slice-1-xy.csv"));
    assert_eq!(header, ["x", "y", "inside", "inverse_condition"]);
    assert_eq!(rows.len(), 24 * 24);
    let mut inside = 0;
    for row in &rows {
        let (x, y): (f64, f64) = (row[0].parse().unwrap(), row[1].parse().unwrap());
        let p = Vector3::new(x, y, 0.35);
        assert_eq!(row[2] == "1", member(&p), "{row:?}");
        if let Some(v) = workspace.inverse_condition(&p) {
            inside += 1;
            assert!(close(row[3].parse().unwrap(), v, SAME), "{row:?} vs {v}");
        }
    }
    assert!(inside > 10);
}

#[test]
fn stewart_gough_workspace_matches_the_library_and_a_direct_count() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "workspace",
        &study("stewart_gough_workspace_quick.toml"),
        out.path(),
        &[],
    );
    let sg = StewartGough::new(StewartDesign::from_deg(0.3, 0.2, 20.0, 35.0)).unwrap();
    let w = Vector3::new(0.0, 0.0, 10f64.to_radians());
    let view = ConstantOrientation::new(sg.clone(), w).unwrap();
    let limits = [
        WorkspaceConstraint::joint_range(0.45, 0.7).unwrap(),
        WorkspaceConstraint::below(0.75).unwrap(),
        WorkspaceConstraint::half_space(-Vector3::z(), 0.0).unwrap(),
    ];
    let points = points([-0.9, -0.9, 0.0], [0.9, 0.9, 0.75], 9);
    let workspace = Workspace::new(&view, &[()], &limits).unwrap();
    let direct = workspace.volume_and_eta(&points, &Silent).unwrap();
    let e = &results["result"]["estimate"];
    assert!(direct.n_inside > 200, "{}", direct.n_inside);
    assert_same_estimate(e, &direct);

    // Membership from |p + R r_i − b_i| with the platform's joints and R = exp([w]×).
    let rotation = Rotation3::new(w);
    let member = |p: &Vector3<f64>| {
        (0.0..=0.75).contains(&p.z)
            && sg
                .base_joints()
                .iter()
                .zip(sg.platform_joints())
                .all(|(b, r)| (0.45..=0.7).contains(&(p + rotation * r - b).norm()))
    };
    let volume = counted_volume(&points, 1.8 * 1.8 * 0.75, member);
    assert!(
        close(f(&e["volume"]), volume, SAME),
        "{} vs {volume}",
        e["volume"]
    );
    // The workspace lies inside every leg's outer sphere: at most the ball of 0.7 m.
    assert!(volume < 4.0 / 3.0 * std::f64::consts::PI * 0.7f64.powi(3));
    let gci = f(&e["gci"]);
    assert!(gci > 0.0 && gci < 1.0, "{gci}");

    let (_, rows) = csv(&out.path().join("slice-1-xy.csv"));
    assert_eq!(rows.len(), 24 * 24);
    for row in &rows {
        let (x, y): (f64, f64) = (row[0].parse().unwrap(), row[1].parse().unwrap());
        let p = Vector3::new(x, y, 0.55);
        assert_eq!(row[2] == "1", member(&p), "{row:?}");
        if let Some(v) = workspace.inverse_condition(&p) {
            assert!(close(row[3].parse().unwrap(), v, SAME), "{row:?} vs {v}");
        }
    }
}

const UPU_SWEEP: &str = r#"[mechanism.three_upu]
base_radius = 0.2
platform_radius = 0.1

[constraints]
joint_range = [0.3, 0.6]

[sampling]
seed = 5
points = 1024
replicates = 2
region = { box = { lower = [-0.7, -0.7, 0.0], upper = [0.7, 0.7, 0.65] } }

[[variables]]
name = "platform_radius"
from = 0.05
to = 0.15
steps = 3

[sweep]
objective = { volume = 1.0 }
"#;

#[test]
fn three_upu_sweep_matches_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("sweep.toml");
    std::fs::write(&file, UPU_SWEEP).unwrap();
    let out = dir.path().join("out");
    run_study("sweep", &file, &out, &[]);
    let (header, rows) = csv(&out.join("landscape.csv"));
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let (radius, volume) = (column("platform_radius"), column("volume"));
    assert_eq!(rows.len(), 3);
    let region = Region::Box {
        lower: Vector3::new(-0.7, -0.7, 0.0),
        upper: Vector3::new(0.7, 0.7, 0.65),
    };
    let points = PointSet::new(
        Domain::new(region).unwrap(),
        Sampler::Sobol { seed: 5 },
        1024,
        2,
    )
    .unwrap();
    let limits = [WorkspaceConstraint::joint_range(0.3, 0.6).unwrap()];
    for row in &rows {
        let b: f64 = row[radius].parse().unwrap();
        let azimuths = [-90f64, 30.0, 150.0].map(f64::to_radians);
        let upu = ThreeUpu::new(ThreeUpuDesign {
            base_radius: 0.2,
            platform_radius: b,
            azimuths,
            upper: azimuths.map(UJointAxes::park),
        })
        .unwrap();
        let direct = Workspace::new(&upu, &[()], &limits)
            .unwrap()
            .volume(&points, &Silent)
            .unwrap();
        let v: f64 = row[volume].parse().unwrap();
        assert!(direct.volume > 0.0);
        assert!(
            close(v, direct.volume, SAME),
            "{row:?} vs {}",
            direct.volume
        );
    }
}

/// Runs `pkm workspace` on `text` and expects failure at `line` with `expected` in the message.
fn rejects(text: &str, line: usize, expected: &str) {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("out");
    let run = pkm(&[
        "workspace",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!run.ok, "accepted:\n{text}");
    let position = format!("bad.toml:{line}:");
    assert!(
        run.stderr.contains(&position),
        "expected {position} in: {}",
        run.stderr
    );
    assert!(
        run.stderr.contains(expected),
        "expected `{expected}` in: {}",
        run.stderr
    );
    assert!(!out.join("results.json").exists());
}

const STEWART: &str = r#"[mechanism.stewart_gough]
rotation_deg = [0.0, 0.0, 10.0]
base_radius = 0.3
platform_radius = 0.2
base_separation_deg = 20.0
platform_separation_deg = 35.0

[constraints]
joint_range = [0.45, 0.7]

[sampling]
points = 256
region = { box = { lower = [-0.5, -0.5, 0.0], upper = [0.5, 0.5, 0.75] } }
"#;

#[test]
fn bad_three_upu_and_stewart_files_are_rejected_at_their_line() {
    let upu = UPU_SWEEP.split("[[variables]]").next().unwrap();
    rejects(
        &upu.replacen(
            "platform_radius = 0.1",
            "platform_radius = 0.1\nlegs = 3",
            1,
        ),
        4,
        "unknown field `legs`",
    );
    rejects(
        &upu.replacen("base_radius = 0.2", "base_radius = -0.2", 1),
        2,
        "metres",
    );
    rejects(
        &STEWART.replacen("rotation_deg", "orientation_deg", 1),
        2,
        "unknown field `orientation_deg`",
    );
    rejects(
        &STEWART.replacen("base_radius = 0.3", "base_radius = -0.3", 1),
        3,
        "metres",
    );
    rejects(
        &STEWART.replacen("joint_range = [0.45, 0.7]", "joint_range_deg = [0, 90]", 1),
        8,
        "leg lengths in metres",
    );
    rejects(
        &STEWART.replacen("joint_range = [0.45, 0.7]", "passive_cone_deg = 30", 1),
        8,
        "PassiveCone",
    );
}
