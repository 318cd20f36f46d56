//! `pkm dynamics FILE`: inverse dynamics of a rotary Delta / NUWAR with its masses along a
//! trajectory (Miller 2004 §3): the motor torques by Hamilton's three steps (momenta
//! $p = M\dot q$ differenced, no accelerations) and by Lagrange for comparison, and optionally
//! the forward retrace (eqs. 16–19 with Baumgarte stabilisation) fed with the Hamilton torques,
//! with its position error and constraint drift.
//!
//! The trajectory is Miller's elliptical pick-and-place cycle, a chain of built-in segments
//! (line, ellipse, sheared ellipse or clothoid paths under parabolic, cycloidal or 3-4-5 motion
//! laws), or a CSV of equally spaced time-stamped positions. From a CSV the velocities are the
//! second-order central differences of the positions and the accelerations those of the
//! velocities (`Differencing::Central` applied once and twice), so Hamilton's torques use
//! first differences of the data only.

use super::{Context, Report, Run};
use crate::CliError;
use pkm_traits::Progress as _;
use crate::drawing;
use crate::output::Output;
use crate::plot;
use crate::study::mechanism::{MechanismSpec, rotary_delta};
use pkm_mechanisms::ElbowMode;
use crate::study::units::{Degrees, Metres, PositiveMetres, Real};
use crate::study::StudyFile;
use nalgebra::Vector3;
use pkm_dynamics_hamilton::forward::retrace_sampled;
use pkm_dynamics_hamilton::inverse::{self, Accelerations, Differencing, SPACING_TOLERANCE};
use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
use pkm_dynamics_hamilton::trajectory::{MotionLaw, Path, Segment, Trajectory};
use pkm_dynamics_hamilton::{
    DynamicsError, ExtendedModel, ExtendedState, ForearmModel, MassParameters,
};
use pkm_draw::chart::{Chart, Colour, Series, SeriesStyle};
use pkm_integrators::{AdaptiveSettings, DormandPrince54};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Arguments of `pkm dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

/// The study of `pkm dynamics`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsStudy {
    /// Free text.
    pub title: Option<String>,
    /// The robot: a `[mechanism.rotary_delta]` table (elbows out).
    pub mechanism: toml::Spanned<MechanismSpec>,
    /// Its masses.
    pub masses: MassesSpec,
    /// The plate's motion.
    pub trajectory: toml::Spanned<TrajectorySpec>,
    /// How the dynamics are computed.
    #[serde(default)]
    pub dynamics: DynamicsSection,
}

/// `[masses]`: Miller 2004 §3.5's mass model.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MassesSpec {
    /// Plate mass (kg).
    pub plate: Real,
    /// Arm inertia about the motor axis (kg m²).
    pub arm_inertia: Real,
    /// Arm mass (kg; enters the potential only).
    pub arm_mass: Real,
    /// Distance of the arm's centre of mass from the motor axis (m).
    pub arm_centre_of_mass: Metres,
    /// Elbow mass per chain (kg).
    pub elbow: Real,
    /// Mass of one forearm, both rods together (kg).
    pub forearm: Real,
    /// Gravity along −z (m/s²; default 9.81, 0 switches it off).
    #[serde(default = "standard_gravity")]
    pub gravity: Real,
    /// `"rod"` (default: slender rods) or `"lumped"` (half at each end).
    #[serde(default)]
    pub forearm_model: ForearmSpec,
}

fn standard_gravity() -> Real {
    Real(9.81)
}

/// [`ForearmModel`] in a study file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ForearmSpec {
    /// [`ForearmModel::Rod`].
    #[default]
    Rod,
    /// [`ForearmModel::Lumped`].
    Lumped,
}

/// `[trajectory]`: exactly one of `pick_and_place`, `segments`, `csv`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrajectorySpec {
    /// Miller's elliptical pick-and-place cycle.
    pub pick_and_place: Option<PickAndPlaceSpec>,
    /// Rest-to-rest segments run one after the other.
    #[serde(default)]
    pub segments: Vec<SegmentSpec>,
    /// A CSV file of `t, x, y, z` (s, m) with a header line, equally spaced in time; the path
    /// is relative to the study file.
    pub csv: Option<toml::Spanned<String>>,
    /// Sampling step of the built-in trajectories (s; default 0.001).
    pub dt: Option<toml::Spanned<f64>>,
}

/// The pick-and-place cycle.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PickAndPlaceSpec {
    /// Cycle time (s).
    pub cycle_time: Real,
    /// `"round_trip"` (default: there and back in the cycle time) or `"each_leg"`.
    #[serde(default)]
    pub reading: ReadingSpec,
}

/// How the cycle time of Miller's cycle is read (Miller 2004, §3.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ReadingSpec {
    /// There and back in the cycle time.
    #[default]
    RoundTrip,
    /// Each way in the cycle time (a round trip in twice it).
    EachLeg,
}

/// One `[[trajectory.segments]]` entry.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// The path.
    pub path: PathSpec,
    /// `"parabolic"`, `"cycloidal"` or `"polynomial345"`.
    pub law: LawSpec,
    /// Duration (s).
    pub duration: Real,
    /// Run the path from its end back to its start.
    #[serde(default)]
    pub reverse: bool,
}

/// [`MotionLaw`] in a study file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LawSpec {
    /// [`MotionLaw::Parabolic`].
    Parabolic,
    /// [`MotionLaw::Cycloidal`].
    Cycloidal,
    /// [`MotionLaw::Polynomial345`].
    Polynomial345,
}

/// A path shape, lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PathSpec {
    /// Straight line.
    Line {
        /// Start (m).
        start: [Metres; 3],
        /// End (m).
        end: [Metres; 3],
    },
    /// $c + \cos\varphi\,a_1 + \sin\varphi\,a_2$, $\varphi$ from `start_angle_deg` over
    /// `sweep_deg`.
    Ellipse {
        /// Centre (m).
        centre: [Metres; 3],
        /// $a_1$ (m).
        axis_1: [Metres; 3],
        /// $a_2$ (m).
        axis_2: [Metres; 3],
        /// $\varphi_0$ (degrees).
        start_angle_deg: Degrees,
        /// $\Delta\varphi$ (degrees).
        sweep_deg: Degrees,
    },
    /// The ellipse of orthogonal semi-axes sheared along the first by `shear`.
    ShearedEllipse {
        /// Centre (m).
        centre: [Metres; 3],
        /// First semi-axis (m).
        semi_axis_1: [Metres; 3],
        /// Second semi-axis, orthogonal to the first (m).
        semi_axis_2: [Metres; 3],
        /// Shear factor (dimensionless).
        shear: Real,
        /// $\varphi_0$ (degrees).
        start_angle_deg: Degrees,
        /// $\Delta\varphi$ (degrees).
        sweep_deg: Degrees,
    },
    /// Clothoid (Euler spiral).
    Clothoid {
        /// Start (m).
        start: [Metres; 3],
        /// Initial direction (any length).
        tangent: [Real; 3],
        /// Direction of positive curvature (any length).
        normal: [Real; 3],
        /// Initial curvature (1/m).
        curvature: Real,
        /// Rate of curvature along the arc (1/m²).
        sharpness: Real,
        /// Arc length (m).
        length: PositiveMetres,
    },
}

/// The `[dynamics]` section.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DynamicsSection {
    /// Differencing of Hamilton's momenta: `"central"` (default) or `"backward"`.
    #[serde(default)]
    pub differencing: DifferencingSpec,
    /// Lagrange's accelerations: `"trajectory"` (default: the trajectory's, analytic for the
    /// built-in shapes) or `"differenced"` (the joint velocities differenced).
    #[serde(default)]
    pub lagrange_accelerations: LagrangeSpec,
    /// The forward retrace, when present.
    pub forward: Option<ForwardSpec>,
}

/// [`Differencing`] in a study file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DifferencingSpec {
    /// [`Differencing::Central`].
    #[default]
    Central,
    /// [`Differencing::Backward`].
    Backward,
}

impl DifferencingSpec {
    fn to_library(self) -> Differencing {
        match self {
            Self::Central => Differencing::Central,
            Self::Backward => Differencing::Backward,
        }
    }
}

/// Where Lagrange takes $\ddot q$ from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LagrangeSpec {
    /// The trajectory's accelerations through the acceleration-level inverse kinematics.
    #[default]
    Trajectory,
    /// $\dot q$ differenced with the same scheme as Hamilton's momenta.
    Differenced,
}

/// `[dynamics.forward]`: Dormand–Prince 5(4) on the Hamilton form.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ForwardSpec {
    /// Velocity-level Baumgarte gain κ (1/s; 0 = unstabilised; default 20).
    #[serde(default = "default_kappa")]
    pub kappa: Real,
    /// Relative tolerance (default 1e-8).
    #[serde(default = "default_rtol")]
    pub rtol: Real,
    /// Absolute tolerance (default 1e-11).
    #[serde(default = "default_atol")]
    pub atol: Real,
    /// Step limit (default 1,000,000).
    #[serde(default = "default_max_steps")]
    pub max_steps: usize,
}

fn default_kappa() -> Real {
    Real(20.0)
}
fn default_rtol() -> Real {
    Real(1e-8)
}
fn default_atol() -> Real {
    Real(1e-11)
}
fn default_max_steps() -> usize {
    1_000_000
}

/// Default sampling step of the built-in trajectories (s).
pub const DEFAULT_DT: f64 = 1e-3;

/// The library's mass parameters of `[masses]`.
pub fn mass_parameters(m: &MassesSpec) -> MassParameters {
    MassParameters {
        plate: m.plate.0,
        arm_inertia: m.arm_inertia.0,
        arm_mass: m.arm_mass.0,
        arm_centre_of_mass: m.arm_centre_of_mass.0,
        elbow: m.elbow.0,
        forearm: m.forearm.0,
        gravity: m.gravity.0,
        forearm_model: match m.forearm_model {
            ForearmSpec::Rod => ForearmModel::Rod,
            ForearmSpec::Lumped => ForearmModel::Lumped,
        },
    }
}

/// The model of a study, errors at the `[mechanism]` table.
///
/// # Errors
/// [`CliError::Study`] for a mechanism other than the rotary Delta, an elbow other than `out`
/// (the inverse dynamics follow the elbow-out branch), or an invalid design or mass.
pub fn model_of(file: &StudyFile<DynamicsStudy>) -> Result<ExtendedModel, CliError> {
    let spanned = &file.study.mechanism;
    let MechanismSpec::RotaryDelta(spec) = spanned.get_ref() else {
        return Err(file.error_at(
            spanned.span(),
            "pkm dynamics models the rotary Delta family: expected [mechanism.rotary_delta]",
        ));
    };
    if spec.elbow != [ElbowMode::Out] {
        return Err(file.error_at(
            spanned.span(),
            "elbow: the dynamics follow the elbow-out branch; expected elbow = [\"out\"]",
        ));
    }
    let delta = rotary_delta(spec).map_err(|e| file.error_at(spanned.span(), e.to_string()))?;
    ExtendedModel::new(delta, &mass_parameters(&file.study.masses))
        .map_err(|e| CliError::Invalid(format!("[masses]: {e}")))
}

fn vector(v: [Metres; 3]) -> Vector3<f64> {
    Vector3::new(v[0].0, v[1].0, v[2].0)
}

fn real_vector(v: [Real; 3]) -> Vector3<f64> {
    Vector3::new(v[0].0, v[1].0, v[2].0)
}

/// The library path of a `path` entry.
///
/// # Errors
/// The library's reason for parameters that describe no path.
pub fn path_of(p: &PathSpec) -> Result<Path, DynamicsError> {
    match *p {
        PathSpec::Line { start, end } => Path::line(vector(start), vector(end)),
        PathSpec::Ellipse {
            centre,
            axis_1,
            axis_2,
            start_angle_deg,
            sweep_deg,
        } => Path::ellipse(
            vector(centre),
            vector(axis_1),
            vector(axis_2),
            start_angle_deg.radians(),
            sweep_deg.radians(),
        ),
        PathSpec::ShearedEllipse {
            centre,
            semi_axis_1,
            semi_axis_2,
            shear,
            start_angle_deg,
            sweep_deg,
        } => Path::sheared_ellipse(
            vector(centre),
            vector(semi_axis_1),
            vector(semi_axis_2),
            shear.0,
            start_angle_deg.radians(),
            sweep_deg.radians(),
        ),
        PathSpec::Clothoid {
            start,
            tangent,
            normal,
            curvature,
            sharpness,
            length,
        } => Path::clothoid(
            vector(start),
            real_vector(tangent),
            real_vector(normal),
            curvature.0,
            sharpness.0,
            length.0,
        ),
    }
}

/// The library trajectory of the built-in forms.
///
/// # Errors
/// The library's reason for an invalid cycle time, segment or path.
pub fn builtin_trajectory(spec: &TrajectorySpec) -> Result<Trajectory, DynamicsError> {
    match &spec.pick_and_place {
        Some(p) => miller_pick_and_place(match p.reading {
            ReadingSpec::RoundTrip => p.cycle_time.0,
            ReadingSpec::EachLeg => 2.0 * p.cycle_time.0,
        }),
        None => Trajectory::new(
            spec.segments
                .iter()
                .map(|s| {
                    Ok(Segment {
                        path: path_of(&s.path)?,
                        law: match s.law {
                            LawSpec::Parabolic => MotionLaw::Parabolic,
                            LawSpec::Cycloidal => MotionLaw::Cycloidal,
                            LawSpec::Polynomial345 => MotionLaw::Polynomial345,
                        },
                        duration: s.duration.0,
                        reverse: s.reverse,
                    })
                })
                .collect::<Result<Vec<_>, DynamicsError>>()?,
        ),
    }
}

/// Reads `t, x, y, z` rows (s, m) after a header line; every interval must equal the first
/// to the library's relative [`SPACING_TOLERANCE`] (plus the rounding of the times).
///
/// # Errors
/// A message naming the line for a row that is not four finite numbers, times that are not
/// equally spaced and increasing, or fewer than 3 rows.
pub fn parse_positions(text: &str) -> Result<Vec<(f64, Vector3<f64>)>, String> {
    let mut times: Vec<f64> = Vec::new();
    let mut positions = Vec::new();
    for (k, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("line {}: {e}: expected t (s), x, y, z (m)", k + 1))?;
        let &[t, x, y, z] = values.as_slice() else {
            return Err(format!(
                "line {}: {} values; expected 4: t (s), x, y, z (m)",
                k + 1,
                values.len()
            ));
        };
        if !values.iter().all(|v| v.is_finite()) {
            return Err(format!("line {}: expected finite numbers", k + 1));
        }
        if let (Some(&t1), Some(&t0)) = (times.last(), times.first()) {
            let step = if times.len() >= 2 { times[1] - t0 } else { t - t1 };
            let rounding = 4.0 * f64::EPSILON * t.abs().max(t1.abs());
            if !(step > 0.0 && (t - t1 - step).abs() <= SPACING_TOLERANCE * step + rounding) {
                return Err(format!(
                    "line {}: t = {t} s: times must increase in equal steps (the first step is \
                     {step} s)",
                    k + 1
                ));
            }
        }
        times.push(t);
        positions.push(Vector3::new(x, y, z));
    }
    if times.len() < 3 {
        return Err(format!(
            "{} rows: differencing needs at least 3 (after a header line t,x,y,z)",
            times.len()
        ));
    }
    Ok(times.into_iter().zip(positions).collect())
}

fn dynamics_error(e: DynamicsError) -> CliError {
    CliError::Invalid(e.to_string())
}

/// Extended states at their sample times.
pub type Samples = Vec<(f64, ExtendedState)>;

/// The samples and the commanded positions of the study's trajectory.
///
/// # Errors
/// [`CliError::Study`] for a trajectory table that does not give exactly one form, an
/// unreadable or invalid CSV; the library's reason for an invalid trajectory or an
/// unreachable point.
pub fn samples_of(
    file: &StudyFile<DynamicsStudy>,
    model: &ExtendedModel,
) -> Result<(Samples, Vec<Vector3<f64>>), CliError> {
    let spec = file.study.trajectory.get_ref();
    let forms = usize::from(spec.pick_and_place.is_some())
        + usize::from(!spec.segments.is_empty())
        + usize::from(spec.csv.is_some());
    if forms != 1 {
        return Err(file.error_at(
            file.study.trajectory.span(),
            "[trajectory]: expected exactly one of pick_and_place, [[trajectory.segments]], csv",
        ));
    }
    if let Some(csv) = &spec.csv {
        if let Some(dt) = &spec.dt {
            return Err(file.error_at(
                dt.span(),
                "dt: a CSV trajectory has the step of its own times; remove dt",
            ));
        }
        let base = file.path.parent().unwrap_or(std::path::Path::new(""));
        let path = base.join(csv.get_ref());
        let text = std::fs::read_to_string(&path).map_err(|e| CliError::io(&path, e))?;
        let sampled = parse_positions(&text)
            .map_err(|m| file.error_at(csv.span(), format!("{}: {m}", path.display())))?;
        let states = inverse::sample_positions(model, &sampled).map_err(dynamics_error)?;
        return Ok((states, sampled.into_iter().map(|(_, p)| p).collect()));
    }
    let dt = spec.dt.as_ref().map_or(DEFAULT_DT, |d| *d.get_ref());
    let trajectory = builtin_trajectory(spec).map_err(dynamics_error)?;
    let samples = inverse::sample(model, &trajectory, dt).map_err(|e| match (&spec.dt, e) {
        (Some(d), e @ DynamicsError::Invalid(_)) => {
            file.error_at(d.span(), format!("dt (s): {e}"))
        }
        (_, e) => dynamics_error(e),
    })?;
    let commanded = samples.iter().map(|(t, _)| trajectory.sample(*t).p).collect();
    Ok((samples, commanded))
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
    fn of(torques: &[Vector3<f64>]) -> Self {
        let mut per_motor = [0.0_f64; 3];
        let mut squares = 0.0;
        for t in torques {
            for i in 0..3 {
                per_motor[i] = per_motor[i].max(t[i].abs());
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

/// The `result` of `results.json`.
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
    /// Hamilton's torques.
    pub hamilton: TorquePeaks,
    /// Lagrange's torques.
    pub lagrange: TorquePeaks,
    /// Largest |τ_Hamilton − τ_Lagrange| over samples and motors (N m).
    pub max_difference: f64,
    /// The forward retrace, when asked for.
    pub forward: Option<RetraceSummary>,
}

/// What the inverse dynamics computed.
#[derive(Debug, Clone, PartialEq)]
pub struct Torques {
    /// The samples.
    pub samples: Vec<(f64, ExtendedState)>,
    /// The commanded plate positions at the samples (m).
    pub commanded: Vec<Vector3<f64>>,
    /// Hamilton's torques (N m).
    pub hamilton: Vec<Vector3<f64>>,
    /// Lagrange's torques (N m).
    pub lagrange: Vec<Vector3<f64>>,
}

/// Hamilton's and Lagrange's torques of the study's samples.
///
/// # Errors
/// As [`samples_of`]; the library's reason when a sample is singular.
pub fn inverse_dynamics(
    file: &StudyFile<DynamicsStudy>,
    model: &ExtendedModel,
) -> Result<Torques, CliError> {
    let (samples, commanded) = samples_of(file, model)?;
    let d = &file.study.dynamics;
    let differencing = d.differencing.to_library();
    let hamilton = inverse::hamilton(model, &samples, differencing).map_err(dynamics_error)?;
    let accelerations = match d.lagrange_accelerations {
        LagrangeSpec::Trajectory => Accelerations::Exact,
        LagrangeSpec::Differenced => Accelerations::Differenced(differencing),
    };
    let lagrange = inverse::lagrange(model, &samples, accelerations).map_err(dynamics_error)?;
    Ok(Torques {
        samples,
        commanded,
        hamilton,
        lagrange,
    })
}

/// Per-sample numbers of the forward retrace: position error (m) and drift (m).
type RetraceSamples = Vec<(f64, Vector3<f64>, f64)>;

/// The Hamilton form fed with the Hamilton torques (Catmull–Rom between samples) from the
/// first sample's state, sampled at the sample times ([`retrace_sampled`]).
///
/// # Errors
/// Invalid settings, an integration failure, [`CliError::Cancelled`].
pub fn retrace(
    model: &ExtendedModel,
    torques: &Torques,
    spec: &ForwardSpec,
    progress: &dyn pkm_traits::Progress,
) -> Result<(RetraceSummary, RetraceSamples), CliError> {
    let invalid = |e: &dyn std::fmt::Display| CliError::Invalid(format!("[dynamics.forward]: {e}"));
    let settings = AdaptiveSettings::default()
        .with_rtol(spec.rtol.0)
        .and_then(|s| s.with_atol(spec.atol.0))
        .and_then(|s| s.with_max_steps(spec.max_steps))
        .map_err(|e| invalid(&e))?;
    let (samples, hamilton) = (&torques.samples, &torques.hamilton);
    progress.start("forward retrace", 1);
    let scheme = &mut DormandPrince54::new(settings);
    let run = retrace_sampled(model, samples, hamilton, spec.kappa.0, scheme, progress);
    progress.finish();
    let run = run.map_err(|e| match e {
        _ if progress.is_cancelled() => CliError::Cancelled,
        DynamicsError::Integration(e) => invalid(&e),
        e => dynamics_error(e),
    })?;
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

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_study("dynamics", &self.file, context, compute)
    }
}

/// Runs the study in `file`, writing the torque histories (and the retrace) to `context.out`.
///
/// # Errors
/// Study errors at their line, dynamics and integration failures, I/O errors,
/// [`CliError::Cancelled`].
pub fn compute(
    file: &StudyFile<DynamicsStudy>,
    context: &Context,
) -> Result<(DynamicsResult, Report, Output), CliError> {
    let model = model_of(file)?;
    context.progress.phase("inverse dynamics");
    let torques = inverse_dynamics(file, &model)?;
    pkm_traits::Progress::check(&context.progress)?;
    let forward = match &file.study.dynamics.forward {
        Some(spec) => Some(retrace(&model, &torques, spec, &context.progress)?),
        None => None,
    };
    let samples = &torques.samples;
    let dt = samples[1].0 - samples[0].0;
    let max_difference = torques
        .hamilton
        .iter()
        .zip(&torques.lagrange)
        .map(|(h, l)| (h - l).amax())
        .fold(0.0, f64::max);
    let mut out = Output::create(&context.out)?;
    write_torques(&mut out, &torques)?;
    if let Some((_, per_sample)) = &forward {
        write_retrace(&mut out, per_sample)?;
    }
    let result = DynamicsResult {
        title: file.study.title.clone(),
        samples: samples.len(),
        dt,
        duration: samples[samples.len() - 1].0 - samples[0].0,
        hamilton: TorquePeaks::of(&torques.hamilton),
        lagrange: TorquePeaks::of(&torques.lagrange),
        max_difference,
        forward: forward.map(|(r, _)| r),
    };
    let mut report = Report::default();
    let scene = drawing::trajectory_scene(file.study.mechanism.get_ref(), &torques.commanded);
    out.write_robot(&mut report,
        "rotary Delta at t = 0 on its trajectory",
        scene,
    )?;
    report.line(format!(
        "{} samples every {:.4} s: max |tau| Hamilton {:.4} N m, Lagrange {:.4} N m, largest \
         difference {:.3e} N m",
        result.samples, dt, result.hamilton.max, result.lagrange.max, result.max_difference
    ));
    if let Some(r) = &result.forward {
        report.line(format!(
            "forward retrace: max position error {:.3e} m, max drift {:.3e} m, energy balance \
             {:.3e} J, {} steps",
            r.max_position_error, r.max_drift, r.max_energy_balance, r.steps
        ));
    }
    report.line(format!("wrote {}", out.dir().join("results.json").display()));
    Ok((result, report, out))
}

fn write_torques(out: &mut Output, torques: &Torques) -> Result<(), CliError> {
    let header = [
        "t", "x", "y", "z", "theta_1_deg", "theta_2_deg", "theta_3_deg", "tau_hamilton_1",
        "tau_hamilton_2", "tau_hamilton_3", "tau_lagrange_1", "tau_lagrange_2", "tau_lagrange_3",
    ];
    let rows = torques
        .samples
        .iter()
        .zip(&torques.hamilton)
        .zip(&torques.lagrange)
        .map(|(((t, s), h), l)| {
            let mut row = vec![format!("{t}")];
            row.extend((0..3).map(|i| format!("{}", s.q[i])));
            row.extend((3..6).map(|i| format!("{}", s.q[i].to_degrees())));
            row.extend(h.iter().chain(l.iter()).map(|v| format!("{v}")));
            row
        });
    out.write_csv("torques.csv", &header, rows)?;
    let times: Vec<f64> = torques.samples.iter().map(|(t, _)| *t).collect();
    let mut series = Vec::new();
    for (name, history, style) in [
        ("Hamilton", &torques.hamilton, SeriesStyle::Line),
        ("Lagrange", &torques.lagrange, SeriesStyle::Dashed),
    ] {
        for motor in 0..3 {
            let points = times.iter().zip(history).map(|(t, v)| (*t, v[motor])).collect();
            series.push(
                Series::styled(format!("{name}, motor {}", motor + 1), style, points)
                    .with_colour(Colour::Palette(motor)),
            );
        }
    }
    let plot = Chart::series("motor torques", "t (s)", "torque (N m)", series);
    out.write_svg("torques.svg", |path| plot::render(&plot, path))?;
    Ok(())
}

fn write_retrace(out: &mut Output, per_sample: &RetraceSamples) -> Result<(), CliError> {
    let header = ["t", "error_x", "error_y", "error_z", "drift"];
    let rows = per_sample.iter().map(|(t, e, d)| {
        vec![
            format!("{t}"),
            format!("{}", e.x),
            format!("{}", e.y),
            format!("{}", e.z),
            format!("{d}"),
        ]
    });
    out.write_csv("retrace.csv", &header, rows)?;
    let series = ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(i, axis)| {
            let points = per_sample.iter().map(|(t, e, _)| (*t, e[i] * 1e3)).collect();
            Series::line(format!("{axis} - {axis}_commanded"), points)
        })
        .collect();
    let plot = Chart::series(
        "forward retrace with the Hamilton torques minus the commanded path",
        "t (s)",
        "position difference (mm)",
        series,
    );
    out.write_svg("retrace.svg", |path| plot::render(&plot, path))?;
    Ok(())
}
