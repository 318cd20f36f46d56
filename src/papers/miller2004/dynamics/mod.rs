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

use crate::papers::{Experiment, ExperimentError, LinePlot, LineSeries, SeriesStyle};
pub use cycle::{CycleReading, pick_and_place};
use pkm_dynamics_hamilton::trajectory::Trajectory;
use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm_mechanisms::{Placement, RotaryDelta, presets};

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

fn model(robot: Robot, placement: Placement) -> Result<ExtendedModel, ExperimentError> {
    let mechanism = match robot {
        Robot::Nuwar => RotaryDelta::new(presets::nuwar(placement))?,
        Robot::Delta => RotaryDelta::new(presets::miller_delta(placement))?,
    };
    Ok(ExtendedModel::new(
        mechanism,
        &MassParameters::miller2004(),
    )?)
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

fn lines(x_label: &str, y_label: &str, series: Vec<(String, Vec<(f64, f64)>)>) -> LinePlot {
    LinePlot {
        x_label: x_label.to_owned(),
        y_label: y_label.to_owned(),
        series: series
            .into_iter()
            .map(|(label, points)| LineSeries {
                label,
                style: SeriesStyle::Line,
                points,
            })
            .collect(),
    }
}
