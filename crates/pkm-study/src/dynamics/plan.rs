//! Every setting of a dynamics study checked and turned into library values before any
//! computation: the model, the trajectory or the sampled positions with their step, the
//! differencing, and the retrace's integrator settings. Each refusal names its key path.

use super::DynamicsStudy;
use super::schema::{
    DEFAULT_DT, DifferencingSpec, ForwardSpec, LagrangeSpec, LawSpec, MassesSpec, PathSpec,
    ReadingSpec, SegmentSpec, TrajectorySpec,
};
use crate::StudyError;
use crate::registry::StudyMechanism;
use crate::schema::mechanism::MechanismSpec;
use crate::schema::units::{Metres, Real};
use nalgebra::Vector3;
use pkm_dynamics_hamilton::forward::HamiltonForm;
use pkm_dynamics_hamilton::inverse::{Accelerations, Differencing, SPACING_TOLERANCE};
use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
use pkm_dynamics_hamilton::trajectory::{MotionLaw, Path, Segment, Trajectory};
use pkm_dynamics_hamilton::{DynamicsError, ExtendedModel, ForearmModel, MassParameters};
use pkm_integrators::AdaptiveSettings;
use pkm_mechanisms::ElbowMode;
use pkm_traits::DesignError;

/// Most samples of one study: each costs about 1 kB along the inverse dynamics and the
/// retrace, so 10⁶ samples (1000 s at 1 ms) stay near 1 GB; more are refused before allocating.
pub const MAX_SAMPLES: usize = 1_000_000;

/// Where the samples come from.
#[derive(Debug, Clone)]
pub(super) enum Source {
    /// A built-in trajectory sampled every `dt` (s).
    Builtin {
        /// The trajectory.
        trajectory: Trajectory,
        /// The step (s).
        dt: f64,
    },
    /// Given positions `(t, p)` (s, m), equally spaced in time.
    Positions(Vec<(f64, Vector3<f64>)>),
}

/// The forward retrace's checked settings.
#[derive(Debug, Clone, Copy)]
pub(super) struct Forward {
    /// Baumgarte gain κ (1/s).
    pub kappa: f64,
    /// Dormand–Prince settings.
    pub settings: AdaptiveSettings,
}

/// A dynamics study with every setting checked.
#[derive(Debug, Clone)]
pub(super) struct Plan {
    pub model: ExtendedModel,
    pub source: Source,
    pub differencing: Differencing,
    pub accelerations: Accelerations,
    pub forward: Option<Forward>,
}

impl Plan {
    /// Checks every setting of `study`.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at the first setting that cannot be used.
    pub(super) fn of(study: &DynamicsStudy) -> Result<Self, StudyError> {
        let masses = study.masses.as_ref().ok_or_else(|| {
            StudyError::invalid(
                "masses",
                "the rotary Delta's dynamics needs its [masses] (plate, arm_inertia, arm_mass, \
                 arm_centre_of_mass, elbow, forearm)",
            )
        })?;
        if !study.effort_maps.is_empty() {
            return Err(StudyError::invalid(
                "effort_maps",
                "effort maps are drawn for a robot file's dynamics ([mechanism.robot_file])",
            ));
        }
        let model = model_of(&study.mechanism, masses)?;
        let source = source_of(&study.trajectory)?;
        let d = &study.dynamics;
        let differencing = match d.differencing {
            DifferencingSpec::Central => Differencing::Central,
            DifferencingSpec::Backward => Differencing::Backward,
        };
        let accelerations = match d.lagrange_accelerations {
            LagrangeSpec::Trajectory => Accelerations::Exact,
            LagrangeSpec::Differenced => Accelerations::Differenced(differencing),
        };
        let forward = d
            .forward
            .as_ref()
            .map(|f| forward_of(&model, f))
            .transpose()?;
        Ok(Self {
            model,
            source,
            differencing,
            accelerations,
            forward,
        })
    }
}

/// The rotary Delta with its masses; the inverse dynamics follow the elbow-out branch.
fn model_of(mechanism: &MechanismSpec, masses: &MassesSpec) -> Result<ExtendedModel, StudyError> {
    let MechanismSpec::RotaryDelta(spec) = mechanism else {
        return Err(StudyError::invalid(
            "mechanism",
            "pkm dynamics models the rotary Delta family: expected [mechanism.rotary_delta]",
        ));
    };
    if spec.elbow != [ElbowMode::Out] {
        return Err(StudyError::invalid(
            "mechanism.rotary_delta.elbow",
            "the dynamics follow the elbow-out branch; expected elbow = [\"out\"]",
        ));
    }
    let delta = spec.build()?;
    ExtendedModel::new(delta, &mass_parameters(masses)).map_err(mass_error)
}

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
            super::schema::ForearmSpec::Rod => ForearmModel::Rod,
            super::schema::ForearmSpec::Lumped => ForearmModel::Lumped,
        },
    }
}

/// The library's refusal of a mass, at its `[masses]` key.
fn mass_error(e: DesignError) -> StudyError {
    let key = match e.parameter {
        "m_p" => "plate",
        "I_A" => "arm_inertia",
        "m_A" => "arm_mass",
        "l_G" => "arm_centre_of_mass",
        "m_e" => "elbow",
        "m_f" => "forearm",
        "g" => "gravity",
        _ => return StudyError::invalid("masses", e.to_string()),
    };
    StudyError::invalid(format!("masses.{key}").as_str(), e.to_string())
}

/// The samples' source: exactly one form, each checked.
fn source_of(spec: &TrajectorySpec) -> Result<Source, StudyError> {
    if !spec.task_segments.is_empty() {
        return Err(StudyError::invalid(
            "trajectory.task_segments",
            "task segments move a robot file's task coordinates; the rotary Delta takes \
             [[trajectory.segments]] (or pick_and_place, csv, positions)",
        ));
    }
    let forms = usize::from(spec.pick_and_place.is_some())
        + usize::from(!spec.segments.is_empty())
        + usize::from(spec.csv.is_some() || spec.positions.is_some());
    if forms != 1 {
        return Err(StudyError::invalid(
            "trajectory",
            "expected exactly one of pick_and_place, [[trajectory.segments]], csv (or positions)",
        ));
    }
    if let Some(rows) = &spec.positions {
        if spec.dt.is_some() {
            return Err(StudyError::invalid(
                "trajectory.dt",
                "sampled positions have the step of their own times; remove dt",
            ));
        }
        return positions_of(rows).map(Source::Positions);
    }
    if spec.csv.is_some() {
        return Err(StudyError::invalid(
            "trajectory.csv",
            "the study layer reads no files: read the CSV and give its rows as \
             trajectory.positions (the pkm command does this relative to the study file)",
        ));
    }
    let trajectory = builtin_trajectory(spec)?;
    let dt = spec.dt.unwrap_or(DEFAULT_DT);
    sample_count(trajectory.duration(), dt)?;
    Ok(Source::Builtin { trajectory, dt })
}

/// The number of samples $t_k = k\,\Delta t$ over `duration`, checked: 3 to [`MAX_SAMPLES`].
///
/// # Errors
/// [`StudyError::Invalid`] at `trajectory.dt` for a step that is not finite and positive or
/// leaves another count.
pub(super) fn sample_count(duration: f64, dt: f64) -> Result<usize, StudyError> {
    let steps = (duration / dt).round();
    if !(dt.is_finite() && dt > 0.0 && (2.0..MAX_SAMPLES as f64).contains(&steps)) {
        return Err(StudyError::invalid(
            "trajectory.dt",
            format!(
                "{dt} s: expected a step > 0 that leaves 3 to {MAX_SAMPLES} samples over the \
                 {duration} s trajectory"
            ),
        ));
    }
    // `steps` is an integer in [2, MAX_SAMPLES), so the cast is exact.
    Ok(steps as usize + 1)
}

/// Checks sampled positions: at least 3 and at most [`MAX_SAMPLES`], finite, times increasing
/// in equal steps (every interval equals the first to the library's relative
/// [`SPACING_TOLERANCE`], beyond the rounding of the times themselves).
fn positions_of(rows: &[Vec<Real>]) -> Result<Vec<(f64, Vector3<f64>)>, StudyError> {
    Ok(timed_rows(rows, 3, "t, x, y, z (s, m)")?
        .into_iter()
        .map(|(t, p)| (t, Vector3::new(p[0], p[1], p[2])))
        .collect())
}

/// Checks sampled rows `[t, x_1, …, x_width]`: at least 3 and at most [`MAX_SAMPLES`], each of
/// `1 + width` finite numbers (`names` says which), times increasing in equal steps (every
/// interval equals the first to the library's relative [`SPACING_TOLERANCE`], beyond the
/// rounding of the times themselves).
///
/// # Errors
/// [`StudyError::Invalid`] at `trajectory.positions` or the offending row.
pub(super) fn timed_rows(
    rows: &[Vec<Real>],
    width: usize,
    names: &str,
) -> Result<Vec<(f64, Vec<f64>)>, StudyError> {
    let n = rows.len();
    if !(3..=MAX_SAMPLES).contains(&n) {
        return Err(StudyError::invalid(
            "trajectory.positions",
            format!("{n} samples: differencing needs at least 3 (and at most {MAX_SAMPLES})"),
        ));
    }
    let at = |k: usize| format!("trajectory.positions[{k}]");
    let mut out: Vec<(f64, Vec<f64>)> = Vec::with_capacity(n);
    for (k, row) in rows.iter().enumerate() {
        if row.len() != width + 1 {
            let message = format!("{} values; expected {}: {names}", row.len(), width + 1);
            return Err(StudyError::invalid(at(k).as_str(), message));
        }
        if !row.iter().all(|v| v.0.is_finite()) {
            return Err(StudyError::invalid(
                at(k).as_str(),
                "expected finite numbers",
            ));
        }
        let t = row[0].0;
        if let Some(&(previous, _)) = out.last() {
            let step = if k >= 2 {
                rows[1][0].0 - rows[0][0].0
            } else {
                t - previous
            };
            let rounding = 4.0 * f64::EPSILON * t.abs().max(f64::abs(previous));
            if !(step > 0.0 && (t - previous - step).abs() <= SPACING_TOLERANCE * step + rounding) {
                let message = format!(
                    "t = {t} s: times must increase in equal steps (the first step is {step} s)"
                );
                return Err(StudyError::invalid(at(k).as_str(), message));
            }
        }
        out.push((t, row[1..].iter().map(|v| v.0).collect()));
    }
    Ok(out)
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

/// The library segment of `[[trajectory.segments]]` entry `k`, checked on its own.
fn segment_of(k: usize, s: &SegmentSpec) -> Result<Segment, StudyError> {
    let at = |key: &str, e: DynamicsError| {
        StudyError::invalid(
            format!("trajectory.segments[{k}].{key}").as_str(),
            e.to_string(),
        )
    };
    let segment = Segment {
        path: path_of(&s.path).map_err(|e| at("path", e))?,
        law: match s.law {
            LawSpec::Parabolic => MotionLaw::Parabolic,
            LawSpec::Cycloidal => MotionLaw::Cycloidal,
            LawSpec::Polynomial345 => MotionLaw::Polynomial345,
        },
        duration: s.duration.0,
        reverse: s.reverse,
    };
    Trajectory::new(vec![segment]).map_err(|e| at("duration", e))?;
    Ok(segment)
}

/// The library trajectory of the built-in forms.
pub(super) fn builtin_trajectory(spec: &TrajectorySpec) -> Result<Trajectory, StudyError> {
    if let Some(p) = &spec.pick_and_place {
        let period = match p.reading {
            ReadingSpec::RoundTrip => p.cycle_time.0,
            ReadingSpec::EachLeg => 2.0 * p.cycle_time.0,
        };
        return miller_pick_and_place(period).map_err(|e| {
            StudyError::invalid("trajectory.pick_and_place.cycle_time", e.to_string())
        });
    }
    let segments = (spec.segments.iter().enumerate())
        .map(|(k, s)| segment_of(k, s))
        .collect::<Result<Vec<_>, _>>()?;
    Trajectory::new(segments).map_err(|e| StudyError::invalid("trajectory.segments", e.to_string()))
}

/// The retrace's settings, each at its key: the gain through the library's own check (a
/// Hamilton form built once without torques) and the integrator settings.
fn forward_of(model: &ExtendedModel, spec: &ForwardSpec) -> Result<Forward, StudyError> {
    let at = |key: &str, e: &dyn std::fmt::Display| {
        StudyError::invalid(format!("dynamics.forward.{key}").as_str(), e.to_string())
    };
    HamiltonForm::new(model, |_| Vector3::zeros(), spec.kappa.0).map_err(|e| at("kappa", &e))?;
    Ok(Forward {
        kappa: spec.kappa.0,
        settings: adaptive_settings(spec)?,
    })
}

/// The integrator settings of `[dynamics.forward]`, each at its key.
///
/// # Errors
/// [`StudyError::Invalid`] at `dynamics.forward.rtol`, `atol` or `max_steps`.
pub(super) fn adaptive_settings(spec: &ForwardSpec) -> Result<AdaptiveSettings, StudyError> {
    let at = |key: &str, e: &dyn std::fmt::Display| {
        StudyError::invalid(format!("dynamics.forward.{key}").as_str(), e.to_string())
    };
    AdaptiveSettings::default()
        .with_rtol(spec.rtol.0)
        .map_err(|e| at("rtol", &e))?
        .with_atol(spec.atol.0)
        .map_err(|e| at("atol", &e))?
        .with_max_steps(spec.max_steps)
        .map_err(|e| at("max_steps", &e))
}
