//! Every study kind end to end through the `pkm` binary, its numbers checked against the same
//! computation done directly through the library.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

use common::{close, csv, run_study, study};
use nalgebra::Vector3;
use pkm_mechanisms::{
    ElbowMode, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios, Placement,
    RotaryDelta, RotaryDeltaDesign,
};
use pkm_traits::{Silent, WorkspaceConstraint};
use pkm_workspace_indices::{
    Domain, IndexError, PointSet, Region, Sampler, SectionIndex, SectionIndices, Workspace,
};

/// Relative agreement of two evaluations of the same formula with the same inputs.
const SAME: f64 = 1e-12;

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap()
}

/// A cross-section index of the Linear Delta `[L1/YR, YA/YR, ZR/YR, L2/L1]` (YR = 1),
/// straight from the library.
fn section_index(design: &[f64; 4], index: SectionIndex) -> Result<f64, IndexError> {
    let ratios = LinearDeltaRatios::from_slice(design);
    let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 })?;
    SectionIndices::new(&delta, LinearDeltaMode::PAPER).value(index)
}

#[test]
fn nuwar_workspace_matches_the_library() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "workspace",
        &study("nuwar_workspace_quick.toml"),
        out.path(),
        &[],
    );
    assert_eq!(results["schema"], "pkm-cli/results/v1");
    assert!(
        results["study"]["text"]
            .as_str()
            .unwrap()
            .contains("rotary_delta")
    );

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

    let e = &results["result"]["estimate"];
    assert!(direct.volume > 0.0 && direct.n_inside > 100);
    assert_eq!(e["n_inside"].as_u64(), Some(direct.n_inside));
    assert!(close(f(&e["volume"]), direct.volume, SAME));
    assert!(close(f(&e["volume_se"]), direct.volume_se, SAME));
    assert!(close(f(&e["eta"]), direct.eta.unwrap(), SAME));
    assert!(close(f(&e["gci"]), direct.gci().unwrap(), SAME));

    // The horizontal slice at z = -0.36 m: every cell is 1/κ at its centre, or outside.
    let (header, rows) = csv(&out.path().join("slice-1-xy.csv"));
    assert_eq!(header, ["x", "y", "inside", "inverse_condition"]);
    assert_eq!(rows.len(), 32 * 32);
    let mut inside = 0;
    for row in &rows {
        let (x, y): (f64, f64) = (row[0].parse().unwrap(), row[1].parse().unwrap());
        let expected = workspace.inverse_condition(&Vector3::new(x, y, -0.36));
        match expected {
            Some(v) => {
                inside += 1;
                assert!(close(row[3].parse().unwrap(), v, SAME), "{row:?} vs {v}");
            }
            None => assert_eq!(row[2], "0"),
        }
    }
    assert!(inside > 10, "the slice at z = -0.36 m cuts the workspace");
    assert!(out.path().join("slice-2-yz.svg").exists());
}

#[test]
fn linear_delta_workspace_matches_the_library() {
    let out = tempfile::tempdir().unwrap();
    let results = run_study(
        "workspace",
        &study("linear_delta_workspace_quick.toml"),
        out.path(),
        &[],
    );
    let ratios = LinearDeltaRatios::from_slice(&[2.0, 0.0, 0.0, 0.63]);
    let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 0.2 }).unwrap();
    let carriages = [WorkspaceConstraint::joint_range(-0.5, 0.5).unwrap()];
    let region = Region::Box {
        lower: Vector3::new(-1.2, -0.6, -0.6),
        upper: Vector3::new(1.2, 0.6, 0.05),
    };
    let points = PointSet::new(
        Domain::new(region).unwrap(),
        Sampler::Sobol { seed: 1 },
        4096,
        4,
    )
    .unwrap();
    let workspace = Workspace::new(&delta, &[LinearDeltaMode::PAPER], &carriages).unwrap();
    let direct = workspace.volume_and_eta(&points, &Silent).unwrap();
    let e = &results["result"]["estimate"];
    assert!(direct.n_inside > 100);
    assert_eq!(e["n_inside"].as_u64(), Some(direct.n_inside));
    assert!(close(f(&e["volume"]), direct.volume, SAME));
    assert!(close(f(&e["gci"]), direct.gci().unwrap(), SAME));
    // Bounded by the cross-section area (YR² · A_W/YR²) times the carriage stroke.
    let area = section_index(&[2.0, 0.0, 0.0, 0.63], SectionIndex::Area).unwrap();
    assert!(f(&e["volume"]) < 0.2 * 0.2 * area * 1.0);
}
