//! The six mechanisms of pkm through the same traits and the same study entry points.
//!
//! Each mechanism is built from a paper's design in `pkm_mechanisms::presets` (or a named design
//! struct), then handed to two generic functions that know nothing about it: [`kinematics`]
//! (inverse kinematics, the forward-kinematics round trip and the local indices at a pose, for
//! the 3×3 and the 6×6 mechanisms alike) and [`workspace`] (volume ± SE, η = ∫ 1/κ dW and
//! GCI = η/W over a region, for the mechanisms that implement `ConstrainedWorkspace`). The two
//! with a screw view (`WrenchSystem`) also print the task objective F = Σ (Lᵢ ∧ χ)².
//! Run: `cargo run --example six_mechanisms`.
#![allow(clippy::print_stdout)]

use nalgebra::{Isometry3, Vector3, Vector6};
use pkm_mechanisms::{
    Elbow, ElbowMode, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios,
    Placement, RotaryDelta, StewartGough, ThreeUpu, Tsai3Dof, WrenchSystem, pose_from_task,
    presets,
};
use pkm_screw_theory::Twist;
use pkm_traits::{
    ConstrainedWorkspace, ForwardKinematics, InverseKinematics, NewtonSettings, Silent, Task,
    WorkspaceConstraint,
};
use pkm_workspace_indices::{
    Dim, Domain, FixedSvd, PointSet, Region, Sampler, Workspace, local_indices,
};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// Inverse kinematics at `x`, forward kinematics back from a guess 1 % of the pose away, and the
/// local indices of the velocity Jacobian at `x`: the same code for every mechanism.
fn kinematics<M, const N: usize>(
    name: &str,
    mechanism: &M,
    mode: M::WorkingMode,
    x: &Task<N>,
) -> Result<()>
where
    M: InverseKinematics<N, N> + ForwardKinematics<N>,
    Dim<N>: FixedSvd<N>,
{
    let q = mechanism.inverse_kinematics(x, mode)?;
    let guess = x + x.map(|v| 0.01 * v);
    let x_fk = mechanism.forward_kinematics(&q, &guess, &NewtonSettings::default())?;
    let local = local_indices(mechanism, x, mode)?;
    let q: Vec<String> = q.iter().map(|v| format!("{v:.4}")).collect();
    println!("{name}");
    println!("  IK  q = [{}]", q.join(", "));
    println!("  FK  |x_fk − x|∞ = {:.1e}", (x_fk - x).amax());
    println!(
        "  local  1/κ = {:.4}, σ_min = {:.4}, σ_max = {:.4}, manipulability = {:.4}",
        local.inverse_condition, local.sigma_min, local.sigma_max, local.manipulability
    );
    Ok(())
}

/// Volume, η and GCI of the workspace of `mechanism` in `modes` under `constraints`, on 8
/// replicates of 4096 shifted Sobol points in `region`.
fn workspace<M>(
    mechanism: &M,
    modes: &[M::WorkingMode],
    constraints: &[WorkspaceConstraint],
    region: Region,
) -> Result<()>
where
    M: ConstrainedWorkspace<3, 3> + Sync,
{
    let points = PointSet::new(Domain::new(region)?, Sampler::Sobol { seed: 1 }, 4096, 8)?;
    let e = Workspace::new(mechanism, modes, constraints)?.volume_and_eta(&points, &Silent)?;
    println!(
        "  workspace  W = {:.4e} ± {:.1e}, η = {:.4e} ± {:.1e}, GCI = {:.4}",
        e.volume,
        e.volume_se,
        e.eta.unwrap_or(f64::NAN),
        e.eta_se.unwrap_or(f64::NAN),
        e.gci().unwrap_or(f64::NAN)
    );
    Ok(())
}

/// The task objective F of a vertical lift and of a turn about z at `pose`.
fn screw_view(mechanism: &dyn WrenchSystem, pose: &Isometry3<f64>) -> Result<()> {
    let lift = Twist::new(Vector3::zeros(), Vector3::z());
    let turn = Twist::new(Vector3::z(), Vector3::zeros());
    println!(
        "  screw view  F(lift) = {:.4}, F(turn about z) = {:.4}",
        mechanism.task_objective(pose, &lift)?,
        mechanism.task_objective(pose, &turn)?
    );
    Ok(())
}

fn main() -> Result<()> {
    // Rotary Delta and NUWAR (Miller 2004 §3.5), motors in the plane z = 0: the plate below the
    // motors, arms between 40° up and 90° down, in one 120° sector of the reach cylinder.
    let placement = Placement {
        motor_plane_z: 0.0,
        azimuth_motor_1: 0.0,
    };
    let limits = [
        WorkspaceConstraint::below(0.0)?,
        WorkspaceConstraint::joint_range((-40f64).to_radians(), 90f64.to_radians())?,
    ];
    for (name, design) in [
        ("Delta", presets::miller_delta(placement)),
        ("NUWAR", presets::nuwar(placement)),
    ] {
        let delta = RotaryDelta::new(design)?;
        kinematics(
            name,
            &delta,
            ElbowMode::Out,
            &Vector3::new(0.05, -0.02, -0.5),
        )?;
        let (radius, depth) = delta.reach_cylinder();
        workspace(
            &delta,
            &[ElbowMode::Out],
            &limits,
            Region::axial_cylinder(radius, -depth, 0.0),
        )?;
    }

    // Linear Delta (Miller 2004, Table 2 row 4) with rails 0.1 m apart and carriages within
    // ±0.2 m.
    let ratios = LinearDeltaRatios {
        l1_over_yr: 2.0,
        ya_over_yr: 0.0,
        zr_over_yr: 0.0,
        l2_over_l1: 0.63,
    };
    let linear = LinearDelta::new(LinearDeltaDesign { ratios, yr: 0.1 })?;
    kinematics(
        "Linear Delta",
        &linear,
        LinearDeltaMode::PAPER,
        &Vector3::new(0.05, 0.02, -0.08),
    )?;
    workspace(
        &linear,
        &[LinearDeltaMode::PAPER],
        &[WorkspaceConstraint::joint_range(-0.2, 0.2)?],
        Region::Box {
            lower: Vector3::new(-0.4, -0.13, -0.13),
            upper: Vector3::new(0.4, 0.13, 0.13),
        },
    )?;

    // Tsai 3-DOF platform (Stamper, Tsai & Walsh 1997 §5) in the hemisphere of its reach.
    let tsai = Tsai3Dof::new(presets::stamper_max_gci())?;
    kinematics(
        "Tsai",
        &tsai,
        [Elbow::Out; 3],
        &Vector3::new(0.1, -0.05, 0.5),
    )?;
    let hemisphere = Region::Hemisphere {
        center: Vector3::zeros(),
        radius: tsai.reach(),
    };
    workspace(&tsai, &[[Elbow::Out; 3]], &[], hemisphere)?;

    // Park's 3-UPU (Wolf & Shoham §4.4) at fixed orientation, legs between 40 and 60.
    let upu = ThreeUpu::new(presets::park_3upu())?;
    let p = Vector3::new(1.0, -2.0, 50.0);
    kinematics("3-UPU", &upu, (), &p)?;
    workspace(
        &upu,
        &[()],
        &[WorkspaceConstraint::joint_range(40.0, 60.0)?],
        Region::axial_cylinder(30.0, 0.0, 60.0),
    )?;
    screw_view(&upu, &Isometry3::translation(p.x, p.y, p.z))?;

    // Stewart–Gough platform (Wolf & Shoham §4.1): the 6×6 traits, pose x = (p, rotation vector)
    // in cm and rad; its J mixes the two units, so its 1/κ depends on the length unit.
    let stewart = StewartGough::new(presets::wolf_shoham_stewart_s4_1())?;
    let x = Vector6::new(1.0, -2.0, 40.0, 0.05, -0.03, 0.1);
    kinematics("Stewart–Gough", &stewart, (), &x)?;
    screw_view(&stewart, &pose_from_task(&x)?)?;
    Ok(())
}
