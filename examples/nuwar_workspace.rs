//! The workspace of your own rotary Delta with your own joint limits, compared with NUWAR's
//! motor-axis orientation (Miller 2004 §2.1), on common random points.
//! Run: `cargo run --release --example nuwar_workspace`.
#![allow(clippy::print_stdout)]

use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, RotaryDeltaDesign};
use pkm_traits::{Silent, WorkspaceConstraint};
use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, Workspace, ratio_standard_error};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Your robot: motor points 0.15 m from the axis, plate joints 0.04 m, arm 0.2 m, forearm
    // 0.45 m, motor plane at z = 0, motor 1 on the x axis.
    let placement = Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    };
    let design = RotaryDeltaDesign {
        base_radius: 0.15,
        plate_offset: 0.04,
        arm: 0.2,
        forearm: 0.45,
        alpha: 0.0,
        beta: 0.0,
        placement,
    };
    let delta = RotaryDelta::new(design)?;
    let nuwar_like = RotaryDelta::new(RotaryDeltaDesign {
        alpha: (1.0 / 2f64.sqrt()).atan(), // orthogonal motor axes
        beta: 60f64.to_radians(),
        ..design
    })?;

    // Its limits: plate below the motors, arms between 40° up and 90° down (elbow out), ball
    // joints bent by at most 35°, links of neighbouring legs at least 30 mm apart.
    let limits = [
        WorkspaceConstraint::below(0.0)?,
        WorkspaceConstraint::joint_range((-40f64).to_radians(), 90f64.to_radians())?,
        WorkspaceConstraint::passive_cone(35f64.to_radians())?,
        WorkspaceConstraint::leg_clearance(0.03)?,
    ];

    // One 120° sector of a cylinder that holds every reachable position of both designs; the
    // same 4 × 2^15 randomly shifted Sobol points serve both.
    let (radius, depth) = delta.reach_cylinder();
    let region = Region::axial_cylinder(radius, -depth, 0.0);
    let points = PointSet::new(
        Domain::new(region)?.with_sector(3, 0.0)?,
        Sampler::Sobol { seed: 42 },
        1 << 15,
        4,
    )?;

    let mut volumes = Vec::new();
    for (name, robot) in [("Delta", &delta), ("orthogonal axes", &nuwar_like)] {
        let workspace = Workspace::new(robot, &[ElbowMode::Out], &limits)?;
        let e = workspace.volume_and_eta(&points, &Silent)?;
        println!(
            "{name:>16}: W = {:.5} ± {:.5} m³, GCI = {:.4}",
            e.volume,
            e.volume_se,
            e.gci().unwrap_or(0.0)
        );
        volumes.push(e);
    }
    let ratio = volumes[1].volume / volumes[0].volume;
    let se = ratio_standard_error(&volumes[1], &volumes[0]).unwrap_or(f64::NAN);
    println!("volume ratio = {ratio:.4} ± {se:.4}");
    Ok(())
}
