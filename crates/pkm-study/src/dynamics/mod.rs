//! The dynamics study: inverse dynamics of a rotary Delta / NUWAR with its masses along a
//! trajectory (Miller 2004 §3): the motor torques by Hamilton's three steps (momenta
//! $p = M\dot q$ differenced, no accelerations) and by Lagrange for comparison, and optionally
//! the forward retrace (eqs. 16–19 with Baumgarte stabilisation) fed with the Hamilton torques,
//! with its position error and constraint drift.
//!
//! The trajectory is Miller's elliptical pick-and-place cycle, a chain of built-in segments
//! (line, ellipse, sheared ellipse or clothoid paths under parabolic, cycloidal or 3-4-5 motion
//! laws), or equally spaced time-stamped positions given as data
//! ([`TrajectorySpec::positions`]). From positions the velocities are the second-order central
//! differences of the positions and the accelerations those of the velocities
//! (`Differencing::Central` applied once and twice), so Hamilton's torques use first
//! differences of the data only.
//!
//! **Files are the front end's.** A study may name a CSV file (`trajectory.csv`); the study
//! layer opens no file itself: [`dynamics_reading`] reads it through the front end's
//! [`crate::load::FileReader`] (`pkm` and `pkm.dynamics(path)` read it relative to the study
//! file). The schema stays plain serde: a JSON document or a Python dict gives its positions
//! inline.

mod artifacts;
mod csv;
mod plan;
mod robot_file;
pub mod schema;

pub use csv::{TrajectoryCsv, dynamics_reading};
pub use plan::{MAX_SAMPLES, mass_parameters, path_of};
pub use robot_file::{ActuatorEfforts, EffortMapResult, EffortSummary, TaskRetraceSummary};
pub use schema::{
    DEFAULT_DT, DifferencingSpec, DynamicsSection, EffortMapSpec, ForearmSpec, ForwardSpec,
    LagrangeSpec, LawSpec, MassesSpec, PathSpec, PickAndPlaceSpec, ReadingSpec, SegmentSpec,
    TaskSegmentSpec, TrajectorySpec,
};

use crate::outcome::Outcome;
use crate::registry::Built;
use crate::schema::mechanism::MechanismSpec;
use crate::{StudyError, scene, short};
use nalgebra::Vector3;
use pkm_dynamics_hamilton::forward::retrace_sampled;
use pkm_dynamics_hamilton::inverse;
use pkm_dynamics_hamilton::{ExtendedModel, ExtendedState};
use pkm_integrators::DormandPrince54;
use pkm_traits::Progress;
use plan::{Forward, Plan, Source};
use serde::{Deserialize, Serialize};

/// A dynamics study.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsStudy {
    /// Free text.
    pub title: Option<String>,
    /// The robot: a `[mechanism.rotary_delta]` table (elbows out), or a
    /// `[mechanism.robot_file]` whose file carries its masses and gravity.
    pub mechanism: MechanismSpec,
    /// The rotary Delta's masses (a robot file has its own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub masses: Option<MassesSpec>,
    /// The plate's motion.
    pub trajectory: TrajectorySpec,
    /// How the dynamics are computed.
    #[serde(default)]
    pub dynamics: DynamicsSection,
    /// Maps of the largest effort at rest over a box of accelerations (a robot file).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effort_maps: Vec<EffortMapSpec>,
}

/// Largest |τ| per motor, and over all motors, of a torque history (N m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TorquePeaks {
    /// Per motor.
    pub per_motor: [f64; 3],
    /// Over all motors.
    pub max: f64,
    /// Root mean square over samples and motors.
    pub rms: f64,
}

impl TorquePeaks {
    /// The peaks of `torques`: $\max_k |\tau_{k,i}|$ per motor $i$, their maximum, and
    /// $\sqrt{\sum_k |\tau_k|^2 / (3n)}$.
    pub fn of(torques: &[Vector3<f64>]) -> Self {
        let mut per_motor = [0.0_f64; 3];
        let mut squares = 0.0;
        for t in torques {
            for (peak, v) in per_motor.iter_mut().zip(t.iter()) {
                *peak = peak.max(v.abs());
            }
            squares += t.norm_squared();
        }
        Self {
            per_motor,
            max: per_motor.iter().copied().fold(0.0, f64::max),
            rms: (squares / (3.0 * torques.len().max(1) as f64)).sqrt(),
        }
    }
}

/// The forward retrace's numbers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RetraceSummary {
    /// Largest |p(t) − p_commanded(t)| at the sample times (m).
    pub max_position_error: f64,
    /// Largest constraint drift max_i |Φ_i| / (2 L_b) (m).
    pub max_drift: f64,
    /// Largest |E(t) − W(t) − (E(0) − W(0))| (J): energy balance against the motor work.
    pub max_energy_balance: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Right-hand-side evaluations.
    pub evaluations: usize,
}

/// The result of a dynamics study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DynamicsResult {
    /// The study's title.
    pub title: Option<String>,
    /// Samples.
    pub samples: usize,
    /// Their step (s).
    pub dt: f64,
    /// Duration (s).
    pub duration: f64,
    /// Hamilton's torques (the rotary Delta).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hamilton: Option<TorquePeaks>,
    /// Lagrange's torques (the rotary Delta).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lagrange: Option<TorquePeaks>,
    /// Largest |τ_Hamilton − τ_Lagrange| over samples and motors (N m; the rotary Delta).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_difference: Option<f64>,
    /// The forward retrace, when asked for.
    pub forward: Option<RetraceSummary>,
    /// A robot file's actuator efforts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub efforts: Option<EffortSummary>,
    /// A robot file's forward retrace, when asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retrace: Option<TaskRetraceSummary>,
    /// A robot file's effort maps.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effort_maps: Vec<EffortMapResult>,
}

/// What the inverse dynamics computed.
#[derive(Debug, Clone, PartialEq)]
struct Torques {
    /// The samples.
    samples: Vec<(f64, ExtendedState)>,
    /// The commanded plate positions at the samples (m).
    commanded: Vec<Vector3<f64>>,
    /// Hamilton's torques (N m).
    hamilton: Vec<Vector3<f64>>,
    /// Lagrange's torques (N m).
    lagrange: Vec<Vector3<f64>>,
}

/// Per-sample numbers of the forward retrace: time (s), position error (m) and drift (m).
type RetraceSamples = Vec<(f64, Vector3<f64>, f64)>;

/// Runs a dynamics study: the torque histories (a table and a chart), the forward retrace
/// when asked for (a table and a chart), and the drawing of the robot at the start of its
/// trajectory.
///
/// # Errors
/// [`StudyError::Invalid`] for a setting that cannot be used (every setting is checked before
/// any computation), [`StudyError::Dynamics`] when a sample is out of reach or singular,
/// [`StudyError::Integration`] when the retrace's integrator fails,
/// [`StudyError::Cancelled`] when `progress` asks to stop.
pub fn dynamics(
    study: &DynamicsStudy,
    progress: &dyn Progress,
) -> Result<Outcome<DynamicsResult>, StudyError> {
    if let MechanismSpec::RobotFile(robot) = &study.mechanism {
        return robot_file::dynamics(study, robot, progress);
    }
    let plan = Plan::of(study)?;
    progress.phase("inverse dynamics");
    let torques = inverse_dynamics(&plan)?;
    progress.check()?;
    let forward = match &plan.forward {
        Some(f) => Some(retrace(&plan.model, &torques, f, progress)?),
        None => None,
    };
    let samples = &torques.samples;
    let (t0, t1, t_end) = (samples[0].0, samples[1].0, samples[samples.len() - 1].0);
    let max_difference = (torques.hamilton.iter().zip(&torques.lagrange))
        .map(|(h, l)| (h - l).amax())
        .fold(0.0, f64::max);
    let mut outcome = Outcome::new(DynamicsResult {
        title: study.title.clone(),
        samples: samples.len(),
        dt: t1 - t0,
        duration: t_end - t0,
        hamilton: Some(TorquePeaks::of(&torques.hamilton)),
        lagrange: Some(TorquePeaks::of(&torques.lagrange)),
        max_difference: Some(max_difference),
        forward: forward.as_ref().map(|(r, _)| r.clone()),
        efforts: None,
        retrace: None,
        effort_maps: Vec::new(),
    });
    artifacts::torques(&mut outcome.artifacts, &torques);
    if let Some((_, per_sample)) = &forward {
        artifacts::retrace(&mut outcome.artifacts, per_sample);
    }
    let scene = Built::new(study.mechanism.clone())
        .map_err(|e| e.to_string())
        .and_then(|built| scene::trajectory_scene(&built, &torques.commanded));
    outcome.robot("rotary Delta at t = 0 on its trajectory", scene);
    summarise(&mut outcome);
    Ok(outcome)
}

/// The samples, commanded positions, and Hamilton's and Lagrange's torques of `plan`.
fn inverse_dynamics(plan: &Plan) -> Result<Torques, StudyError> {
    let model = &plan.model;
    let (samples, commanded) = match &plan.source {
        Source::Builtin { trajectory, dt } => {
            let samples = inverse::sample(model, trajectory, *dt)?;
            let commanded = samples
                .iter()
                .map(|(t, _)| trajectory.sample(*t).p)
                .collect();
            (samples, commanded)
        }
        Source::Positions(positions) => (
            inverse::sample_positions(model, positions)?,
            positions.iter().map(|(_, p)| *p).collect(),
        ),
    };
    let hamilton = inverse::hamilton(model, &samples, plan.differencing)?;
    let lagrange = inverse::lagrange(model, &samples, plan.accelerations)?;
    Ok(Torques {
        samples,
        commanded,
        hamilton,
        lagrange,
    })
}

/// The Hamilton form fed with the Hamilton torques (Catmull–Rom between samples) from the
/// first sample's state, sampled at the sample times ([`retrace_sampled`]).
fn retrace(
    model: &ExtendedModel,
    torques: &Torques,
    forward: &Forward,
    progress: &dyn Progress,
) -> Result<(RetraceSummary, RetraceSamples), StudyError> {
    let (samples, hamilton) = (&torques.samples, &torques.hamilton);
    progress.start("forward retrace", 1);
    let scheme = &mut DormandPrince54::new(forward.settings);
    let run = retrace_sampled(model, samples, hamilton, forward.kappa, scheme, progress);
    progress.finish();
    if progress.is_cancelled() {
        return Err(StudyError::Cancelled);
    }
    let run = run?;
    let errors = run.position_errors(&torques.commanded);
    let per_sample = (run.times.iter().zip(&errors).zip(&run.drift))
        .map(|((t, e), d)| (*t, *e, *d))
        .collect();
    let summary = RetraceSummary {
        max_position_error: run.max_position_error(&torques.commanded),
        max_drift: run.max_drift(),
        max_energy_balance: run.max_energy_balance(),
        steps: run.steps,
        evaluations: run.evaluations,
    };
    Ok((summary, per_sample))
}

/// `v` with 4 decimals, as the command has always printed it, or in [`short`] form outside
/// [1e-4, 1e9) so an extreme value stays short.
fn four_decimals(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e9).contains(&v.abs()) {
        short(v)
    } else {
        format!("{v:.4}")
    }
}

fn summarise(outcome: &mut Outcome<DynamicsResult>) {
    let r = &outcome.result;
    let (Some(hamilton), Some(lagrange), Some(max_difference)) =
        (&r.hamilton, &r.lagrange, r.max_difference)
    else {
        return;
    };
    let mut lines = vec![format!(
        "{} samples every {} s: max |tau| Hamilton {} N m, Lagrange {} N m, largest \
         difference {:.3e} N m",
        r.samples,
        four_decimals(r.dt),
        four_decimals(hamilton.max),
        four_decimals(lagrange.max),
        max_difference
    )];
    if let Some(f) = &r.forward {
        lines.push(format!(
            "forward retrace: max position error {:.3e} m, max drift {:.3e} m, energy balance \
             {:.3e} J, {} steps",
            f.max_position_error, f.max_drift, f.max_energy_balance, f.steps
        ));
    }
    outcome.summary.extend(lines);
}
