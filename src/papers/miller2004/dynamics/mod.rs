//! Miller 2004 §3: the start angles of NUWAR, the pick-and-place cycle, inverse dynamics by
//! Hamilton and Lagrange, forward dynamics and constraint drift.
//!
//! The canonical convention of `../shared/spec/miller-dynamics.md` is the default; the open
//! choices (motor-plane height, azimuth of motor 1, reading of the cycle time) are reported
//! beside it. Evidence for every erratum: `docs/conventions.md`, "Miller 2004 §3: dynamics".

mod cycle;
mod forward;
mod start_angle_search;
mod start_angles;
mod torques;

use crate::papers::{Experiment, ExperimentError};
pub use cycle::{CycleReading, pick_and_place};
use pkm_draw::chart::{Chart, Quantity, Series};
use pkm_draw::{Axis, PathKind, Scene};
use pkm_dynamics_hamilton::trajectory::Trajectory;
use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, Skeleton, presets};

/// The experiments of this part of the paper.
pub fn experiments() -> Vec<Experiment> {
    vec![
        start_angles::EXPERIMENT,
        torques::TRAJECTORY,
        torques::NUWAR,
        torques::DELTA,
        forward::EXPERIMENT,
    ]
}

/// The two robots of §3.5.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Robot {
    Nuwar,
    Delta,
}

/// Inverse-dynamics grid of §3.3 (1 ms).
const DT: f64 = 1e-3;

/// The paper's cycle time "0.5 s".
const CYCLE_TIME: f64 = 0.5;

fn mechanism(robot: Robot, placement: Placement) -> Result<RotaryDelta, ExperimentError> {
    Ok(match robot {
        Robot::Nuwar => RotaryDelta::new(presets::nuwar(placement))?,
        Robot::Delta => RotaryDelta::new(presets::miller_delta(placement))?,
    })
}

fn model(robot: Robot, placement: Placement) -> Result<ExtendedModel, ExperimentError> {
    Ok(ExtendedModel::new(
        mechanism(robot, placement)?,
        &MassParameters::miller2004(),
    )?)
}

/// Points of the path sampled by the drawings.
const DRAWN_PATH_POINTS: u32 = 200;

/// `robot` at `placement` at the start of `trajectory` (elbows out, the branch of the
/// dynamics), with the path of the cycle and, when `motor_axes`, the motor axes $e_i$ (0.15 m
/// long, through the motor points): the layouts of Figs. 1 and 2 and the trajectory of Fig. 7.
fn drawing(
    robot: Robot,
    placement: Placement,
    trajectory: &Trajectory,
    motor_axes: bool,
) -> Result<Scene, ExperimentError> {
    let m = mechanism(robot, placement)?;
    let start = trajectory.sample(0.0).p;
    let step = trajectory.duration() / f64::from(DRAWN_PATH_POINTS);
    let path = (0..=DRAWN_PATH_POINTS)
        .map(|k| trajectory.sample(f64::from(k) * step).p)
        .collect();
    let mut scene = Scene::new(Skeleton::rotary_delta(&m, &start, ElbowMode::Out)?).with_path(
        "pick-and-place path",
        PathKind::Trajectory,
        path,
    );
    if motor_axes {
        for leg in m.legs() {
            scene = scene.with_axis(Axis {
                label: "motor axes e_i".to_owned(),
                point: leg.motor,
                direction: leg.e,
                length: Some(0.15),
            });
        }
    }
    Ok(scene)
}

fn canonical_trajectory() -> Result<Trajectory, ExperimentError> {
    Ok(pick_and_place(CYCLE_TIME, CycleReading::RoundTrip)?)
}

/// The canonical placement with motor 1 at `azimuth_deg`.
fn placement_at(azimuth_deg: f64) -> Placement {
    Placement {
        azimuth_motor_1: azimuth_deg.to_radians(),
        ..Placement::canonical()
    }
}

/// A chart of solid lines `series` (label, points) against time in seconds.
fn lines(title: String, y_axis: Quantity, series: Vec<(String, Vec<(f64, f64)>)>) -> Chart {
    let series = series
        .into_iter()
        .map(|(label, points)| Series::line(label, points))
        .collect();
    Chart::series(title, Quantity::new("t", "s"), y_axis, series)
}
