//! `miller2004.dynamics.trajectory`, `.nuwar`, `.delta`: the pick-and-place cycle, the motor
//! torques along it (Fig. 8) by Hamilton and Lagrange, and the Delta/NUWAR ratio.

use super::{CYCLE_TIME, DT, Robot, canonical_trajectory, lines, model, placement_at};
use crate::papers::{
    Context, Experiment, ExperimentError, Figure, FigureKind, Outcome, Paper, Source, Table,
};
use nalgebra::Vector3;
use pkm_dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm_dynamics_hamilton::trajectory::{CycleReading, Trajectory};
use pkm_mechanisms::Placement;

pub(super) const TRAJECTORY: Experiment = Experiment {
    id: "miller2004.dynamics.trajectory",
    paper: Paper::Miller2004,
    title: "maximum plate acceleration of the elliptical pick-and-place cycle (§3.5)",
    run: run_trajectory,
};

pub(super) const NUWAR: Experiment = Experiment {
    id: "miller2004.dynamics.nuwar",
    paper: Paper::Miller2004,
    title: "NUWAR motor torques along the cycle, Hamilton vs Lagrange (§3.5, Fig. 8)",
    run: run_nuwar,
};

pub(super) const DELTA: Experiment = Experiment {
    id: "miller2004.dynamics.delta",
    paper: Paper::Miller2004,
    title: "Delta motor torques along the cycle and the Delta/NUWAR ratio (§3.5)",
    run: run_delta,
};

const PAPER_MAX_TORQUE_NUWAR: f64 = 33.14;
const PAPER_MAX_TORQUE_DELTA: f64 = 36.30;

fn max_acceleration(trajectory: &Trajectory) -> f64 {
    let n = (trajectory.duration() / 1e-4).round() as usize;
    (0..=n)
        .map(|k| trajectory.sample(k as f64 * 1e-4).a.norm())
        .fold(0.0, f64::max)
}

fn run_trajectory(_: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let source = Source::new(TRAJECTORY.id, Paper::Miller2004, "§3.5, trajectory");
    let canonical = max_acceleration(&canonical_trajectory()?);
    let each_leg = max_acceleration(&Trajectory::pick_and_place(
        CYCLE_TIME,
        CycleReading::EachLeg,
    )?);
    // |p̈| scales as 1/T²: the leg time at which the canonical law reaches the printed value.
    let leg_time = CYCLE_TIME / 2.0 * (canonical / 294.82).sqrt();
    Ok(Outcome {
        comparisons: vec![
            source
                .check("max_acceleration", "m/s^2", 294.82, canonical, 0.5)
                .erratum("miller2004-max-acceleration")
                .with_note("3-4-5 on the eccentric angle, 0.25 s per leg (round trip 0.5 s)"),
            source.info("max_acceleration_each_leg_0_5_s", "m/s^2", each_leg),
            source.info("leg_time_for_paper_acceleration", "s", leg_time),
        ],
        ..Outcome::default()
    })
}

/// Torques along the canonical cycle: Hamilton (central), Lagrange differenced (central) and
/// Lagrange with exact accelerations.
struct Torques {
    times: Vec<f64>,
    hamilton: Vec<Vector3<f64>>,
    lagrange_differenced: Vec<Vector3<f64>>,
    lagrange_exact: Vec<Vector3<f64>>,
}

fn torques(robot: Robot, placement: Placement) -> Result<Torques, ExperimentError> {
    let m = model(robot, placement)?;
    let samples = inverse::sample(&m, &canonical_trajectory()?, DT)?;
    let c = Differencing::Central;
    Ok(Torques {
        times: samples.iter().map(|(t, _)| *t).collect(),
        hamilton: inverse::hamilton(&m, &samples, DT, c)?,
        lagrange_differenced: inverse::lagrange(&m, &samples, DT, Accelerations::Differenced(c))?,
        lagrange_exact: inverse::lagrange(&m, &samples, DT, Accelerations::Exact)?,
    })
}

fn peak(tau: &[Vector3<f64>]) -> f64 {
    tau.iter().map(Vector3::amax).fold(0.0, f64::max)
}

fn max_diff(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).amax())
        .fold(0.0, f64::max)
}

fn figure(name: &str, robot: &str, t: &Torques) -> Figure {
    let series = (0..3)
        .map(|i| {
            let points = t
                .times
                .iter()
                .zip(&t.hamilton)
                .map(|(s, v)| (*s, v[i]))
                .collect();
            (format!("tau_{}", i + 1), points)
        })
        .collect();
    Figure {
        name: name.to_owned(),
        title: format!("{robot} motor torques along the pick-and-place cycle (Hamilton, Fig. 8)"),
        kind: FigureKind::Lines(lines("t (s)", "torque (N m)", series)),
    }
}

/// Max torque (NUWAR, Delta) over motor-plane heights and both motor-1 azimuths.
fn sensitivity_table() -> Result<Table, ExperimentError> {
    let mut rows = Vec::new();
    for azimuth in [300.0, 90.0] {
        for z0 in [-0.27, -0.28, -0.29, -0.2928, -0.30, -0.31] {
            let placement = Placement {
                motor_plane_z: z0,
                ..placement_at(azimuth)
            };
            let n = peak(&torques(Robot::Nuwar, placement)?.lagrange_exact);
            let d = peak(&torques(Robot::Delta, placement)?.lagrange_exact);
            rows.push(vec![azimuth, z0, n, d]);
        }
    }
    Ok(Table {
        name: "miller2004_max_torque_vs_placement".to_owned(),
        columns: [
            "azimuth_motor_1_deg",
            "motor_plane_z_m",
            "nuwar_nm",
            "delta_nm",
        ]
        .map(str::to_owned)
        .to_vec(),
        rows,
    })
}

fn robot_outcome(
    experiment: &Experiment,
    robot: Robot,
    paper_max: f64,
) -> Result<(Outcome, Source), ExperimentError> {
    let source = Source::new(experiment.id, Paper::Miller2004, "§3.5, Fig. 8");
    let t = torques(robot, Placement::canonical())?;
    let turned = torques(robot, placement_at(90.0))?;
    let label = match robot {
        Robot::Nuwar => "NUWAR",
        Robot::Delta => "Delta",
    };
    let comparisons = vec![
        source
            .check("max_torque", "N m", paper_max, peak(&t.lagrange_exact), 0.5)
            .erratum("miller2004-max-torque")
            .with_note("canonical convention, exact accelerations"),
        source.info("max_torque_hamilton", "N m", peak(&t.hamilton)),
        source.info(
            "max_torque_motor_1_at_90_deg",
            "N m",
            peak(&turned.lagrange_exact),
        ),
        source
            .check(
                "hamilton_vs_lagrange_max_diff",
                "N m",
                0.0,
                max_diff(&t.hamilton, &t.lagrange_differenced),
                0.01,
            )
            .with_note("both central differences at 1 ms (paper: within 0.01)"),
        source
            .info(
                "hamilton_vs_exact_lagrange_max_diff",
                "N m",
                max_diff(&t.hamilton, &t.lagrange_exact),
            )
            .with_note("Lagrange with analytic accelerations"),
    ];
    let name = format!("miller2004_fig8_{}", label.to_lowercase());
    Ok((
        Outcome {
            comparisons,
            tables: Vec::new(),
            figures: vec![figure(&name, label, &t)],
        },
        source,
    ))
}

fn run_nuwar(_: &Context<'_>) -> Result<Outcome, ExperimentError> {
    Ok(robot_outcome(&NUWAR, Robot::Nuwar, PAPER_MAX_TORQUE_NUWAR)?.0)
}

fn run_delta(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let (mut outcome, source) = robot_outcome(&DELTA, Robot::Delta, PAPER_MAX_TORQUE_DELTA)?;
    let paper_ratio = PAPER_MAX_TORQUE_DELTA / PAPER_MAX_TORQUE_NUWAR;
    for (azimuth, note) in [
        (300.0, "motor 1 at 300° (canonical)"),
        (90.0, "motor 1 at 90°"),
    ] {
        let placement = placement_at(azimuth);
        let delta = peak(&torques(Robot::Delta, placement)?.lagrange_exact);
        let nuwar = peak(&torques(Robot::Nuwar, placement)?.lagrange_exact);
        let quantity = format!("delta_nuwar_torque_ratio_motor_1_at_{azimuth}_deg");
        outcome.comparisons.push(
            source
                .check(&quantity, "1", paper_ratio, delta / nuwar, 0.02)
                .erratum("miller2004-max-torque")
                .with_note(note),
        );
    }
    context.progress.check()?;
    outcome.tables.push(sensitivity_table()?);
    Ok(outcome)
}
