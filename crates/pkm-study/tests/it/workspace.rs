//! The workspace study against the same computation done directly through the library: the
//! estimate of the quick study files of `crates/pkm-cli/tests/studies/` (the files the command's
//! tests and the baseline comparison also run) and each cell of a slice.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::Vector3;
use pkm_mechanisms::{
    ElbowMode, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios, Placement,
    RotaryDelta, RotaryDeltaDesign,
};
use pkm_study::{Artifact, Cell, Outcome, WorkspaceResult, WorkspaceStudy, workspace};
use pkm_traits::{Silent, WorkspaceConstraint};
use pkm_workspace_indices::{
    Domain, PointSet, Region, Sampler, SectionIndex, SectionIndices, Workspace,
};
use std::path::Path;

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

/// `a` and `b` agree to `rel` relative (and 1e-300 absolute).
fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300
}

/// Runs the quick study `name` of `crates/pkm-cli/tests/studies/`.
fn run(name: &str) -> Outcome<WorkspaceResult> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../pkm-cli/tests/studies")
        .join(name);
    let study: WorkspaceStudy =
        pkm_study::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    workspace(&study, &Silent).unwrap()
}

fn artifact<'a>(outcome: &'a Outcome<WorkspaceResult>, name: &str) -> Option<&'a Artifact> {
    outcome.artifacts.iter().find(|a| match a {
        Artifact::Table { name: n, .. } | Artifact::Chart { name: n, .. } => n == name,
        Artifact::Robot { .. } => false,
    })
}

fn number(cell: &Cell) -> f64 {
    match cell {
        Cell::Number(v) => *v,
        c => panic!("not a number: {c:?}"),
    }
}

#[test]
fn nuwar_workspace_matches_the_library() {
    let outcome = run("nuwar_workspace_quick.toml");
    let placement = Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    };
    let delta = RotaryDelta::new(RotaryDeltaDesign {
        base_radius: 0.15,
        plate_offset: 0.04,
        arm: 0.2,
        forearm: 0.45,
        alpha: 35.264389682754654f64.to_radians(),
        beta: 60f64.to_radians(),
        placement,
    })
    .unwrap();
    let limits = [
        WorkspaceConstraint::below(0.0).unwrap(),
        WorkspaceConstraint::joint_range((-40f64).to_radians(), 90f64.to_radians()).unwrap(),
        WorkspaceConstraint::passive_cone(35f64.to_radians()).unwrap(),
        WorkspaceConstraint::leg_clearance(0.03).unwrap(),
    ];
    let domain = Domain::new(Region::axial_cylinder(0.76, -0.65, 0.0))
        .unwrap()
        .with_sector(3, 0.0)
        .unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 42 }, 4096, 4).unwrap();
    let workspace = Workspace::new(&delta, &[ElbowMode::Out], &limits).unwrap();
    let direct = workspace.volume_and_eta(&points, &Silent).unwrap();

    let e = &outcome.result.estimate;
    assert!(direct.volume > 0.0 && direct.n_inside > 100);
    assert_eq!(e.n_inside, direct.n_inside);
    assert!(close(e.volume, direct.volume, SAME));
    assert!(close(e.volume_se, direct.volume_se, SAME));
    assert!(close(e.eta, direct.eta.unwrap(), SAME));
    assert!(close(e.gci.unwrap(), direct.gci().unwrap(), SAME));

    // The horizontal slice at z = -0.36 m: every cell is 1/κ at its centre, or outside.
    let Some(Artifact::Table { table, .. }) = artifact(&outcome, "slice-1-xy.csv") else {
        panic!("no slice table");
    };
    assert_eq!(table.header, ["x", "y", "inside", "inverse_condition"]);
    assert_eq!(table.rows.len(), 32 * 32);
    let mut inside = 0;
    for row in &table.rows {
        let (x, y) = (number(&row[0]), number(&row[1]));
        match workspace.inverse_condition(&Vector3::new(x, y, -0.36)) {
            Some(v) => {
                inside += 1;
                assert!(close(number(&row[3]), v, SAME), "{row:?} vs {v}");
            }
            None => assert_eq!(row[2], Cell::Flag(false)),
        }
    }
    assert!(inside > 10, "the slice at z = -0.36 m cuts the workspace");
    assert!(artifact(&outcome, "slice-2-yz.svg").is_some());
}

#[test]
fn linear_delta_workspace_matches_the_library() {
    let outcome = run("linear_delta_workspace_quick.toml");
    let ratios = LinearDeltaRatios::from_slice(&[2.0, 0.0, 0.0, 0.63]);
    let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 0.2 }).unwrap();
    let carriages = [WorkspaceConstraint::joint_range(-0.5, 0.5).unwrap()];
    let region = Region::Box {
        lower: Vector3::new(-1.2, -0.6, -0.6),
        upper: Vector3::new(1.2, 0.6, 0.05),
    };
    let domain = Domain::new(region).unwrap();
    let points = PointSet::new(domain, Sampler::Sobol { seed: 1 }, 4096, 4).unwrap();
    let workspace = Workspace::new(&delta, &[LinearDeltaMode::PAPER], &carriages).unwrap();
    let direct = workspace.volume_and_eta(&points, &Silent).unwrap();
    let e = &outcome.result.estimate;
    assert!(direct.n_inside > 100);
    assert_eq!(e.n_inside, direct.n_inside);
    assert!(close(e.volume, direct.volume, SAME));
    assert!(close(e.gci.unwrap(), direct.gci().unwrap(), SAME));
    // Bounded by the cross-section area (YR² · A_W/YR²) times the carriage stroke.
    let unit = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
    let area = SectionIndices::new(&unit, LinearDeltaMode::PAPER)
        .value(SectionIndex::Area)
        .unwrap();
    assert!(e.volume < 0.2 * 0.2 * area * 1.0);
}

/// A refused sample count names the key that sets it (it named none).
#[test]
fn refused_sample_counts_name_their_keys() {
    let base = "[mechanism.tsai]\na = 0.44\nb = 0.56\n[sampling]\n";
    for (sampling, key) in [
        ("points = 10000000000000\n", "sampling.points"),
        ("replicates = 1000000\n", "sampling.replicates"),
        (
            "sampler = \"grid\"\nper_axis = 100000\n",
            "sampling.per_axis",
        ),
    ] {
        let study: WorkspaceStudy = pkm_study::from_toml_str(&format!("{base}{sampling}")).unwrap();
        let e = workspace(&study, &Silent).unwrap_err();
        assert_eq!(
            e.path().map(ToString::to_string).as_deref(),
            Some(key),
            "{e}"
        );
    }
}

/// Issue 29: a revolute joint's range is tested modulo 360°. NUWAR's inverse kinematics reports
/// angles in about [-355°, 175°], so `[-180, 180]` (a user's "no limit") shrank its workspace
/// from 12.1 % to 8.1 % of the box; now it changes nothing, and a range shifted by a turn
/// gives the same workspace.
#[test]
fn revolute_joint_ranges_hold_angles_modulo_a_turn() {
    let nuwar = "[mechanism.rotary_delta]\nbase_radius = 0.15\nplate_offset = 0.04\n\
                 arm = 0.2\nforearm = 0.45\nalpha_deg = 35.264389682754654\nbeta_deg = 60.0\n\
                 [sampling]\npoints = 8192\nreplicates = 2\n\
                 region = { cylinder = { radius = 0.76, z_min = -0.65, z_max = 0.0 } }\n";
    let inside = |constraints: &str| {
        let study: WorkspaceStudy =
            pkm_study::from_toml_str(&format!("{nuwar}[constraints]\n{constraints}")).unwrap();
        let outcome = workspace(&study, &Silent).unwrap();
        outcome.result.estimate.n_inside
    };
    let free = inside("");
    assert!(free > 1000);
    assert_eq!(inside("joint_range_deg = [-180.0, 180.0]\n"), free);
    let limited = inside("joint_range_deg = [-40.0, 90.0]\n");
    assert!(limited < free);
    assert_eq!(inside("joint_range_deg = [320.0, 450.0]\n"), limited);
    assert_eq!(inside("joint_range_deg = [-400.0, -270.0]\n"), limited);
}
