//! The dynamics study of a robot file (issue 31): the actuator efforts along a trajectory in
//! the robot's task coordinates, by [`RobotModel::inverse_dynamics`] (virtual work, checked
//! against the extended space with multipliers at every sample), their peaks, RMS and power,
//! and the energy balance along the trajectory.
//!
//! The trajectory is a built-in one (`pick_and_place`, `segments`) when the task is the
//! position `["x", "y", "z"]`, rest-to-rest straight lines in the task coordinates
//! (`task_segments`) for any task, or sampled rows `[t, x_1, …, x_n]` (`positions`, `csv`),
//! whose velocities and accelerations are their differences (`dynamics.differencing`,
//! applied once and twice). The built-in forms give exact velocities and accelerations.

use super::plan::{builtin_trajectory, timed_rows};
use super::schema::{DifferencingSpec, EffortMapSpec, LagrangeSpec, LawSpec, TaskSegmentSpec};
use super::{DEFAULT_DT, DynamicsResult, DynamicsStudy};
use crate::outcome::{Artifact, Cell, Outcome, Table};
use crate::schema::robot_file::RobotFileSpec;
use crate::{StudyError, short};
use nalgebra::DVector;
use pkm_draw::chart::{Chart, Colour, Series, SeriesStyle};
use pkm_dynamics_hamilton::inverse::Differencing;
use pkm_dynamics_hamilton::trajectory::MotionLaw;
use pkm_robot_file::{InverseDynamics, RobotModel, WorkingMode};
use pkm_traits::Progress;
use serde::{Deserialize, Serialize};

/// One actuator's efforts along the trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ActuatorEfforts {
    /// The actuator's name, the key path of its joint (`legs[0].joints[1]`).
    pub name: String,
    /// `"N"` (prismatic) or `"N m"` (revolute).
    pub unit: String,
    /// Largest |effort|.
    pub peak: f64,
    /// Root mean square over the samples.
    pub rms: f64,
    /// Largest |power| τ q̇ (W).
    pub peak_power: f64,
}

/// The efforts of a robot file along its trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffortSummary {
    /// Per actuator, in the order of the robot's actuators.
    pub actuators: Vec<ActuatorEfforts>,
    /// Largest total power Σ τ q̇ (W, positive when the actuators drive the robot).
    pub peak_power: f64,
    /// Largest |τ_virtual work − τ_multipliers| over samples and actuators, relative to the
    /// largest effort (0 to rounding; redundantly actuated robots: not compared, 0).
    pub formulation_difference: f64,
    /// Largest |E(t) − E(0) − W(t)| (J), with W the actuators' work by the trapezoidal rule:
    /// the energy balance, exact up to the quadrature and the trajectory's differencing.
    pub energy_balance: f64,
}

/// The forward retrace of a robot file: its forward dynamics (eq. D4, minimal coordinates)
/// integrated by Dormand–Prince 5(4) from the first sample's state, fed with the inverse
/// dynamics' efforts (Catmull–Rom between samples).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskRetraceSummary {
    /// Largest |x(t) − x_commanded(t)| over the samples and task coordinates (m or rad).
    pub max_task_error: f64,
    /// Largest |E(t) − E(0) − W(t)| (J), W the efforts' work along the integrated motion by
    /// the trapezoidal rule at the samples.
    pub max_energy_balance: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Right-hand-side evaluations.
    pub evaluations: usize,
}

/// A task motion sample: time, position, velocity and acceleration in task coordinates.
struct Sample {
    t: f64,
    x: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

/// Runs the dynamics study of a robot file.
///
/// # Errors
/// [`StudyError::Invalid`] for a setting that cannot be used (checked before computing);
/// [`StudyError::RobotDynamics`] naming the sample and its time where the dynamics fails
/// (out of reach, singular); [`StudyError::Cancelled`].
pub(super) fn dynamics(
    study: &DynamicsStudy,
    robot: &RobotFileSpec,
    progress: &dyn Progress,
) -> Result<Outcome<DynamicsResult>, StudyError> {
    refuse_delta_settings(study)?;
    let model = robot.model()?;
    let mode = single_mode(robot, &model)?;
    let samples = samples_of(study, &model)?;
    let maps = study
        .effort_maps
        .iter()
        .enumerate()
        .map(|(k, spec)| map_plan(&model, spec, k))
        .collect::<Result<Vec<_>, _>>()?;
    let settings = study
        .dynamics
        .forward
        .as_ref()
        .map(super::plan::adaptive_settings)
        .transpose()?;
    progress.start("inverse dynamics", samples.len() as u64);
    let mut computed = Vec::with_capacity(samples.len());
    for (k, s) in samples.iter().enumerate() {
        progress.check()?;
        let d = model
            .inverse_dynamics(&s.x, &s.v, &s.a, mode)
            .map_err(|source| StudyError::RobotDynamics {
                sample: k,
                time: s.t,
                source,
            })?;
        computed.push(d);
        progress.advance(1);
    }
    progress.finish();
    let summary = summarise_efforts(&model, &samples, &computed);
    let retrace = settings
        .map(|s| retrace(&model, mode, &samples, &computed, s, progress))
        .transpose()?;
    let (t0, t1) = (samples[0].t, samples[1].t);
    let mut outcome = Outcome::new(DynamicsResult {
        title: study.title.clone(),
        samples: samples.len(),
        dt: t1 - t0,
        duration: samples[samples.len() - 1].t - t0,
        hamilton: None,
        lagrange: None,
        max_difference: None,
        forward: None,
        efforts: Some(summary),
        retrace: retrace.as_ref().map(|(r, _)| r.clone()),
        effort_maps: Vec::new(),
    });
    for (k, plan) in maps.iter().enumerate() {
        progress.start(&format!("effort map {}", k + 1), plan.cells as u64);
        let result = effort_map(&model, mode, plan, k + 1, &mut outcome.artifacts, progress);
        progress.finish();
        let result = result?;
        outcome.summary.push(format!(
            "effort map {} over ({}, {}): peak effort {} to {} (N or N m), {:.0} % of the \
             cells reached",
            k + 1,
            result.axes[0],
            result.axes[1],
            result.min_peak.map_or("-".into(), short),
            result.max_peak.map_or("-".into(), short),
            100.0 * result.inside_fraction
        ));
        outcome.result.effort_maps.push(result);
    }
    artifacts(&mut outcome.artifacts, &model, &samples, &computed);
    if let Some((_, errors)) = &retrace {
        retrace_artifacts(&mut outcome.artifacts, &model, &samples, errors);
    }
    outcome.robot(
        "the robot at t = 0 on its trajectory",
        drawing(&model, mode, &samples, &computed),
    );
    let r = &outcome.result;
    if let Some(e) = &r.efforts {
        let peaks: Vec<String> = e
            .actuators
            .iter()
            .map(|a| format!("{} {} {}", a.name, short(a.peak), a.unit))
            .collect();
        outcome.summary.push(format!(
            "{} samples every {} s: peak efforts {}; peak power {} W; formulations agree to \
             {:.1e}; energy balance {:.3e} J",
            r.samples,
            short(r.dt),
            peaks.join(", "),
            short(e.peak_power),
            e.formulation_difference,
            e.energy_balance
        ));
    }
    if let Some(f) = &r.retrace {
        outcome.summary.push(format!(
            "forward retrace in the task coordinates: max error {:.3e} (m, rad), energy \
             balance {:.3e} J, {} steps",
            f.max_task_error, f.max_energy_balance, f.steps
        ));
    }
    Ok(outcome)
}

/// The rotary Delta's settings have no meaning for a robot file: refused, not ignored.
fn refuse_delta_settings(study: &DynamicsStudy) -> Result<(), StudyError> {
    if study.masses.is_some() {
        return Err(StudyError::invalid(
            "masses",
            "a robot file carries its own masses (docs/robots.md, \"Body table\"): remove \
             [masses]",
        ));
    }
    if let Some(forward) = &study.dynamics.forward
        && forward.kappa.0 != super::schema::ForwardSpec::DEFAULT_KAPPA
    {
        return Err(StudyError::invalid(
            "dynamics.forward.kappa",
            "a robot file's forward dynamics runs in its task coordinates, with the closure \
             solved at every state: there is no constraint drift to stabilise, remove kappa",
        ));
    }
    if study.dynamics.lagrange_accelerations != LagrangeSpec::Trajectory {
        return Err(StudyError::invalid(
            "dynamics.lagrange_accelerations",
            "a robot file's accelerations are the trajectory's (sampled positions differenced \
             twice with `differencing`): remove the key",
        ));
    }
    Ok(())
}

/// The one working mode the dynamics follows.
fn single_mode(robot: &RobotFileSpec, model: &RobotModel) -> Result<WorkingMode, StudyError> {
    match robot.working_modes(model)?.as_slice() {
        [one] => Ok(*one),
        modes => Err(StudyError::invalid(
            "mechanism.robot_file.modes",
            format!(
                "{} working modes: the dynamics follows one (\"home\" or one label)",
                modes.len()
            ),
        )),
    }
}

/// The samples of the study's trajectory in the robot's task coordinates.
fn samples_of(study: &DynamicsStudy, model: &RobotModel) -> Result<Vec<Sample>, StudyError> {
    let spec = &study.trajectory;
    let forms = usize::from(spec.pick_and_place.is_some())
        + usize::from(!spec.segments.is_empty())
        + usize::from(!spec.task_segments.is_empty())
        + usize::from(spec.csv.is_some() || spec.positions.is_some());
    if forms != 1 {
        return Err(StudyError::invalid(
            "trajectory",
            "expected exactly one of pick_and_place, [[trajectory.segments]], \
             [[trajectory.task_segments]], csv (or positions)",
        ));
    }
    let names = model.task_names();
    let n = names.len();
    if let Some(rows) = &spec.positions {
        if spec.dt.is_some() {
            return Err(StudyError::invalid(
                "trajectory.dt",
                "sampled positions have the step of their own times; remove dt",
            ));
        }
        let header = format!("t, {}", names.join(", "));
        let rows = timed_rows(rows, n, &header)?;
        return differenced(&rows, study.dynamics.differencing);
    }
    if spec.csv.is_some() {
        return Err(StudyError::invalid(
            "trajectory.csv",
            "the study layer reads no files: read the CSV and give its rows as \
             trajectory.positions (the pkm command does this relative to the study file)",
        ));
    }
    let dt = spec.dt.unwrap_or(DEFAULT_DT);
    if !spec.task_segments.is_empty() {
        let segments = task_segments(&spec.task_segments, n)?;
        let duration: f64 = segments.iter().map(|s| s.duration).sum();
        return sampled(duration, dt, |t| sample_segments(&segments, t));
    }
    if names != ["x", "y", "z"] {
        return Err(StudyError::invalid(
            "trajectory",
            format!(
                "pick_and_place and segments move the position (x, y, z); this robot's task is \
                 {names:?}: use [[trajectory.task_segments]] or positions"
            ),
        ));
    }
    let trajectory = builtin_trajectory(spec)?;
    sampled(trajectory.duration(), dt, |t| {
        let m = trajectory.sample(t);
        (
            m.p.as_slice().to_vec(),
            m.v.as_slice().to_vec(),
            m.a.as_slice().to_vec(),
        )
    })
}

/// A task segment checked.
struct TaskSegment {
    start: DVector<f64>,
    end: DVector<f64>,
    law: MotionLaw,
    duration: f64,
}

fn task_segments(specs: &[TaskSegmentSpec], n: usize) -> Result<Vec<TaskSegment>, StudyError> {
    specs
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let at = |key: &str| format!("trajectory.task_segments[{k}].{key}");
            let point = |key: &str, v: &[crate::schema::units::Real]| {
                if v.len() == n && v.iter().all(|e| e.0.is_finite() && e.0.abs() <= 1e6) {
                    Ok(DVector::from_iterator(n, v.iter().map(|e| e.0)))
                } else {
                    Err(StudyError::invalid(
                        at(key).as_str(),
                        format!("expected {n} finite numbers within ±1e6, one per task coordinate"),
                    ))
                }
            };
            let duration = s.duration.0;
            if !(duration.is_finite() && duration > 0.0 && duration <= 1e6) {
                return Err(StudyError::invalid(
                    at("duration").as_str(),
                    "expected a duration > 0 and at most 1e6 s",
                ));
            }
            Ok(TaskSegment {
                start: point("start", &s.start)?,
                end: point("end", &s.end)?,
                law: match s.law {
                    LawSpec::Parabolic => MotionLaw::Parabolic,
                    LawSpec::Cycloidal => MotionLaw::Cycloidal,
                    LawSpec::Polynomial345 => MotionLaw::Polynomial345,
                },
                duration,
            })
        })
        .collect()
}

/// $x = x_0 + s(\tau)(x_1 - x_0)$, $\dot x = s'(\tau)(x_1 - x_0)/T$, $\ddot x =
/// s''(\tau)(x_1 - x_0)/T^2$ on the segment that holds `t` (the last one after the end).
fn sample_segments(segments: &[TaskSegment], t: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut start = 0.0;
    for (k, s) in segments.iter().enumerate() {
        if t <= start + s.duration || k + 1 == segments.len() {
            let (p, dp, ddp) = s.law.eval((t - start) / s.duration);
            let delta = &s.end - &s.start;
            let x = &s.start + &delta * p;
            let v = &delta * (dp / s.duration);
            let a = &delta * (ddp / (s.duration * s.duration));
            return (
                x.as_slice().to_vec(),
                v.as_slice().to_vec(),
                a.as_slice().to_vec(),
            );
        }
        start += s.duration;
    }
    (Vec::new(), Vec::new(), Vec::new())
}

/// `motion` sampled every `dt` over `duration`, after checking the count.
fn sampled(
    duration: f64,
    dt: f64,
    motion: impl Fn(f64) -> (Vec<f64>, Vec<f64>, Vec<f64>),
) -> Result<Vec<Sample>, StudyError> {
    let count = super::plan::sample_count(duration, dt)?;
    Ok((0..count)
        .map(|k| {
            let t = k as f64 * dt;
            let (x, v, a) = motion(t);
            Sample { t, x, v, a }
        })
        .collect())
}

/// Velocities and accelerations of sampled rows by `differencing`, applied once and twice.
fn differenced(
    rows: &[(f64, Vec<f64>)],
    differencing: DifferencingSpec,
) -> Result<Vec<Sample>, StudyError> {
    let scheme = match differencing {
        DifferencingSpec::Central => Differencing::Central,
        DifferencingSpec::Backward => Differencing::Backward,
    };
    let dt = rows[1].0 - rows[0].0;
    let x: Vec<DVector<f64>> = rows
        .iter()
        .map(|(_, p)| DVector::from_vec(p.clone()))
        .collect();
    let invalid =
        |e: pkm_traits::InvalidInput| StudyError::invalid("trajectory.positions", e.to_string());
    let v = scheme.apply(&x, dt).map_err(invalid)?;
    let a = scheme.apply(&v, dt).map_err(invalid)?;
    Ok(rows
        .iter()
        .zip(v.iter().zip(&a))
        .map(|((t, p), (v, a))| Sample {
            t: *t,
            x: p.clone(),
            v: v.as_slice().to_vec(),
            a: a.as_slice().to_vec(),
        })
        .collect())
}

/// The peaks, RMS, power, formulation difference and energy balance of the efforts.
fn summarise_efforts(
    model: &RobotModel,
    samples: &[Sample],
    computed: &[InverseDynamics],
) -> EffortSummary {
    let units = effort_units(model);
    let names = model.actuator_names();
    let count = computed.len().max(1) as f64;
    let actuators = (0..model.actuator_count())
        .map(|i| {
            let efforts = computed.iter().map(|d| d.efforts[i]);
            let powers = computed.iter().map(|d| d.efforts[i] * d.actuator_rates[i]);
            ActuatorEfforts {
                name: names[i].to_string(),
                unit: units[i].to_string(),
                peak: efforts.clone().map(f64::abs).fold(0.0, f64::max),
                rms: (efforts.map(|e| e * e).sum::<f64>() / count).sqrt(),
                peak_power: powers.map(f64::abs).fold(0.0, f64::max),
            }
        })
        .collect();
    let power = |d: &InverseDynamics| d.efforts.dot(&d.actuator_rates);
    let peak_power = computed.iter().map(power).fold(f64::NEG_INFINITY, f64::max);
    let largest = computed
        .iter()
        .map(|d| d.efforts.amax())
        .fold(0.0, f64::max);
    let formulation_difference = if model.actuator_count() == model.dof() {
        computed
            .iter()
            .map(|d| (&d.efforts - &d.efforts_multipliers).amax())
            .fold(0.0, f64::max)
            / largest.max(1e-300)
    } else {
        0.0
    };
    let energy = |d: &InverseDynamics| d.kinetic_energy + d.potential_energy;
    let mut work = 0.0;
    let mut energy_balance = 0.0_f64;
    for k in 1..computed.len() {
        let dt = samples[k].t - samples[k - 1].t;
        work += 0.5 * dt * (power(&computed[k]) + power(&computed[k - 1]));
        let gained = energy(&computed[k]) - energy(&computed[0]);
        energy_balance = energy_balance.max((gained - work).abs());
    }
    EffortSummary {
        actuators,
        peak_power,
        formulation_difference,
        energy_balance,
    }
}

/// `"N m"` for a revolute actuator, `"N"` for a prismatic one.
fn effort_units(model: &RobotModel) -> Vec<&'static str> {
    model
        .legs()
        .iter()
        .flat_map(|leg| {
            leg.actuators.iter().map(|a| match leg.joints[a.joint] {
                pkm_robot_file::Joint::Revolute { .. } => "N m",
                _ => "N",
            })
        })
        .collect()
}

/// `efforts.csv` (time, task coordinates, efforts and powers per actuator, total power,
/// energies) and `efforts.svg`.
fn artifacts(
    artifacts: &mut Vec<Artifact>,
    model: &RobotModel,
    samples: &[Sample],
    computed: &[InverseDynamics],
) {
    let names = model.actuator_names();
    let mut columns: Vec<String> = vec!["t".into()];
    columns.extend(model.task_names().iter().map(|s| (*s).to_string()));
    columns.extend(names.iter().map(|n| format!("effort {n}")));
    columns.extend(names.iter().map(|n| format!("power {n}")));
    columns.extend([
        "power".into(),
        "kinetic_energy".into(),
        "potential_energy".into(),
    ]);
    let mut table = Table::new(columns);
    table.rows = samples
        .iter()
        .zip(computed)
        .map(|(s, d)| {
            let mut row: Vec<Cell> = vec![s.t.into()];
            row.extend(s.x.iter().map(|v| Cell::from(*v)));
            row.extend(d.efforts.iter().map(|v| Cell::from(*v)));
            row.extend(
                d.efforts
                    .iter()
                    .zip(&d.actuator_rates)
                    .map(|(e, r)| Cell::from(e * r)),
            );
            row.push(d.efforts.dot(&d.actuator_rates).into());
            row.push(d.kinetic_energy.into());
            row.push(d.potential_energy.into());
            row
        })
        .collect();
    artifacts.push(Artifact::Table {
        name: "efforts.csv".into(),
        table,
    });
    let units = effort_units(model);
    let series = (0..model.actuator_count())
        .map(|i| {
            let points = samples
                .iter()
                .zip(computed)
                .map(|(s, d)| (s.t, d.efforts[i]))
                .collect();
            Series::styled(
                format!("{} ({})", names[i], units[i]),
                SeriesStyle::Line,
                points,
            )
            .with_colour(Colour::Palette(i))
        })
        .collect();
    let chart = Chart::series("actuator efforts", "t (s)", "effort (N or N m)", series);
    artifacts.push(Artifact::Chart {
        name: "efforts.svg".into(),
        chart: Box::new(chart),
    });
}

/// The robot at the first sample with the path of its platform origin.
fn drawing(
    model: &RobotModel,
    mode: WorkingMode,
    samples: &[Sample],
    computed: &[InverseDynamics],
) -> Result<pkm_draw::Scene, String> {
    let config = model
        .inverse_kinematics_configuration(&samples[0].x, mode)
        .map_err(|e| format!("the robot at t = 0: {e}"))?;
    let path: Vec<nalgebra::Vector3<f64>> = computed
        .iter()
        .map(|d| nalgebra::Vector3::new(d.pose[0], d.pose[1], d.pose[2]))
        .collect();
    Ok(crate::scene::with_trajectory(
        pkm_draw::Scene::new(crate::schema::robot_file::robot_skeleton(model, &config)),
        &path,
    ))
}

/// Per sample of the retrace: the integrated task coordinates minus the commanded ones.
type TaskErrors = Vec<Vec<f64>>;

/// Integrates the forward dynamics fed with the efforts from the first sample's state.
fn retrace(
    model: &RobotModel,
    mode: WorkingMode,
    samples: &[Sample],
    computed: &[InverseDynamics],
    settings: pkm_integrators::AdaptiveSettings,
    progress: &dyn Progress,
) -> Result<(TaskRetraceSummary, TaskErrors), StudyError> {
    let dt = samples[1].t - samples[0].t;
    let efforts = pkm_dynamics_hamilton::forward::SampledTorques::new(
        dt,
        computed.iter().map(|d| d.efforts.clone()).collect(),
    )?;
    // Steps no longer than the samples' spacing: the efforts are known at its resolution,
    // and a first step guessed from a state at rest could leave the workspace.
    let settings = settings
        .with_h_max(dt)
        .map_err(|e| StudyError::invalid("dynamics.forward", e.to_string()))?;
    progress.start("forward retrace", samples.len() as u64);
    let run = match model.dof() {
        1 => integrate::<2>(model, mode, samples, &efforts, settings, progress),
        2 => integrate::<4>(model, mode, samples, &efforts, settings, progress),
        3 => integrate::<6>(model, mode, samples, &efforts, settings, progress),
        4 => integrate::<8>(model, mode, samples, &efforts, settings, progress),
        5 => integrate::<10>(model, mode, samples, &efforts, settings, progress),
        _ => integrate::<12>(model, mode, samples, &efforts, settings, progress),
    };
    progress.finish();
    if progress.is_cancelled() {
        return Err(StudyError::Cancelled);
    }
    let (states, steps, evaluations) = run?;
    let n = model.dof();
    let mut errors = Vec::with_capacity(states.len());
    let (mut work, mut previous_power, mut start_energy) = (0.0, 0.0, 0.0);
    let mut max_energy_balance = 0.0_f64;
    for (k, (sample, state)) in samples.iter().zip(&states).enumerate() {
        let (x, v) = (&state[..n], &state[n..]);
        errors.push(
            x.iter()
                .zip(&sample.x)
                .map(|(a, b)| a - b)
                .collect::<Vec<f64>>(),
        );
        let tau = efforts.at(sample.t);
        let d = model
            .forward_dynamics(x, v, tau.as_slice(), mode)
            .map_err(|source| StudyError::RobotDynamics {
                sample: k,
                time: sample.t,
                source,
            })?;
        let (energy, power) = (
            d.kinetic_energy + d.potential_energy,
            tau.dot(&d.actuator_rates),
        );
        if k == 0 {
            start_energy = energy;
        } else {
            work += 0.5 * dt * (power + previous_power);
        }
        previous_power = power;
        max_energy_balance = max_energy_balance.max((energy - start_energy - work).abs());
    }
    let max_task_error = errors.iter().flatten().map(|e| e.abs()).fold(0.0, f64::max);
    let summary = TaskRetraceSummary {
        max_task_error,
        max_energy_balance,
        steps,
        evaluations,
    };
    Ok((summary, errors))
}

/// Dormand–Prince 5(4) on the state $[x; \dot x]$ of `M = 2n` entries, sampled at the sample
/// times: the states, accepted steps and evaluations.
fn integrate<const M: usize>(
    model: &RobotModel,
    mode: WorkingMode,
    samples: &[Sample],
    efforts: &pkm_dynamics_hamilton::forward::SampledTorques<DVector<f64>>,
    settings: pkm_integrators::AdaptiveSettings,
    progress: &dyn Progress,
) -> Result<(Vec<Vec<f64>>, usize, usize), StudyError> {
    use pkm_integrators::{DormandPrince54, OutputTimes};
    let n = M / 2;
    let first = &samples[0];
    let mut z0 = nalgebra::SVector::<f64, M>::zeros();
    z0.as_mut_slice()[..n].copy_from_slice(&first.x);
    z0.as_mut_slice()[n..].copy_from_slice(&first.v);
    let field = pkm_robot_file::TaskDynamics::new(model, mode, |t| efforts.at(t));
    let times: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let end = times[times.len() - 1];
    let solution = pkm_integrators::integrate(
        &field,
        &mut DormandPrince54::new(settings),
        (first.t, end),
        &z0,
        &OutputTimes::Times(times),
        progress,
    )?;
    let states = solution
        .states
        .iter()
        .map(|z| z.as_slice().to_vec())
        .collect();
    Ok((states, solution.stats.steps, solution.stats.evaluations))
}

/// `retrace.csv` (time and the error of each task coordinate) and `retrace.svg`.
fn retrace_artifacts(
    artifacts: &mut Vec<Artifact>,
    model: &RobotModel,
    samples: &[Sample],
    errors: &TaskErrors,
) {
    let names = model.task_names();
    let mut columns = vec!["t".to_string()];
    columns.extend(names.iter().map(|n| format!("error {n}")));
    let mut table = Table::new(columns);
    table.rows = samples
        .iter()
        .zip(errors)
        .map(|(s, e)| {
            std::iter::once(Cell::from(s.t))
                .chain(e.iter().map(|v| Cell::from(*v)))
                .collect()
        })
        .collect();
    artifacts.push(Artifact::Table {
        name: "retrace.csv".into(),
        table,
    });
    let series = names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let points = samples
                .iter()
                .zip(errors)
                .map(|(s, e)| (s.t, e[k]))
                .collect();
            Series::line(format!("{name} - {name}_commanded"), points)
        })
        .collect();
    let chart = Chart::series(
        "forward retrace with the inverse dynamics' efforts minus the commanded motion",
        "t (s)",
        "difference (m or rad)",
        series,
    );
    artifacts.push(Artifact::Chart {
        name: "retrace.svg".into(),
        chart: Box::new(chart),
    });
}

/// Most cells per side of an effort map.
const MAX_EFFORT_CELLS: usize = 256;

/// An effort map in the result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffortMapResult {
    /// The plane's task coordinates.
    pub axes: [String; 2],
    /// The other task coordinates' values (m, rad).
    pub at: std::collections::BTreeMap<String, f64>,
    /// The acceleration bound of each task coordinate (m/s², rad/s²).
    pub acceleration: std::collections::BTreeMap<String, f64>,
    /// Cells per side.
    pub cells: usize,
    /// Fraction of the cells the robot reaches away from singularities.
    pub inside_fraction: f64,
    /// The largest peak effort on the map (N or N m).
    pub max_peak: Option<f64>,
    /// The smallest peak effort on the map.
    pub min_peak: Option<f64>,
    /// The table's artifact name.
    pub csv: String,
    /// The heat map's artifact name.
    pub svg: String,
}

/// A checked effort map: the axes' indices and ranges, the point the plane passes through,
/// the acceleration bounds.
struct EffortMapPlan {
    axes: [usize; 2],
    ranges: [[f64; 2]; 2],
    through: Vec<f64>,
    bounds: Vec<f64>,
    cells: usize,
}

/// Checks `effort_maps[k]` against the robot's task coordinates.
fn map_plan(
    model: &RobotModel,
    spec: &EffortMapSpec,
    k: usize,
) -> Result<EffortMapPlan, StudyError> {
    let key = |field: &str| format!("effort_maps[{k}].{field}");
    let names = model.task_names();
    let index = |field: &str, name: &str| {
        names.iter().position(|n| *n == name).ok_or_else(|| {
            StudyError::invalid(
                key(field).as_str(),
                format!("{name:?} is not a task coordinate of this robot ({names:?})"),
            )
        })
    };
    let axes = [index("axes", &spec.axes[0])?, index("axes", &spec.axes[1])?];
    if axes[0] == axes[1] {
        return Err(StudyError::invalid(
            key("axes").as_str(),
            "two different task coordinates",
        ));
    }
    let mut ranges = [[0.0; 2]; 2];
    for (slot, name) in ranges.iter_mut().zip(&spec.axes) {
        let range = spec.range.get(name).copied().ok_or_else(|| {
            StudyError::invalid(key("range").as_str(), format!("give the range of {name:?}"))
        })?;
        if !(range.iter().all(|v| v.is_finite() && v.abs() <= 1e6) && range[0] < range[1]) {
            return Err(StudyError::invalid(
                key("range").as_str(),
                format!("{name}: expected [min, max], finite, min < max"),
            ));
        }
        *slot = range;
    }
    if let Some(name) = spec.range.keys().find(|n| !spec.axes.contains(n)) {
        return Err(StudyError::invalid(
            key("range").as_str(),
            format!("{name:?} is not an axis of the map"),
        ));
    }
    let mut through = model.home_task();
    for (name, &value) in &spec.at {
        let i = index("at", name)?;
        if axes.contains(&i) || !(value.is_finite() && value.abs() <= 1e6) {
            return Err(StudyError::invalid(
                key("at").as_str(),
                format!("{name}: a finite value of a task coordinate that is not an axis"),
            ));
        }
        through[i] = value;
    }
    let mut bounds = vec![0.0; names.len()];
    for (name, &value) in &spec.acceleration {
        let i = index("acceleration", name)?;
        if !(value.is_finite() && (0.0..=1e9).contains(&value)) {
            return Err(StudyError::invalid(
                key("acceleration").as_str(),
                format!("{name}: expected a bound from 0 to 1e9"),
            ));
        }
        bounds[i] = value;
    }
    if !(2..=MAX_EFFORT_CELLS).contains(&spec.cells) {
        return Err(StudyError::invalid(
            key("cells").as_str(),
            format!(
                "{}: expected 2 to {MAX_EFFORT_CELLS} cells per side",
                spec.cells
            ),
        ));
    }
    Ok(EffortMapPlan {
        axes,
        ranges,
        through,
        bounds,
        cells: spec.cells,
    })
}

/// Computes effort map `number` (from 1): the largest peak effort over the actuators at each
/// cell centre (blank where the robot does not reach or is singular), rows in parallel and
/// kept in order (the same bits for any thread count); its table and heat map. `progress`
/// advances by one per row and stops the map between cells when it is cancelled.
///
/// # Errors
/// [`StudyError::Cancelled`].
fn effort_map(
    model: &RobotModel,
    mode: WorkingMode,
    plan: &EffortMapPlan,
    number: usize,
    artifacts: &mut Vec<Artifact>,
    progress: &dyn Progress,
) -> Result<EffortMapResult, StudyError> {
    use rayon::prelude::*;
    let n = plan.cells;
    let centres = |[lo, hi]: [f64; 2]| -> Vec<f64> {
        (0..n)
            .map(|c| lo + (hi - lo) * (c as f64 + 0.5) / n as f64)
            .collect()
    };
    let (u, v) = (centres(plan.ranges[0]), centres(plan.ranges[1]));
    let [a, b] = plan.axes;
    let values: Vec<Option<f64>> = v
        .par_iter()
        .flat_map_iter(|&y| {
            let mut point = plan.through.clone();
            point[b] = y;
            let row = u
                .iter()
                .map(|&x| {
                    point[a] = x;
                    if progress.is_cancelled() {
                        return None;
                    }
                    model
                        .peak_efforts_at_rest(&point, &plan.bounds, mode)
                        .ok()
                        .map(|peaks| peaks.amax())
                })
                .collect::<Vec<_>>();
            progress.advance(1);
            row
        })
        .collect();
    progress.check()?;
    let names = model.task_names();
    let stem = format!("effort-map-{number}");
    let (csv, svg) = (format!("{stem}.csv"), format!("{stem}.svg"));
    let table = crate::task_space::grid_table(
        [names[a], names[b], "inside", "peak_effort"],
        &u,
        &v,
        &values,
    );
    let unit = |i: usize| if model.task_is_angle(i) { "rad" } else { "m" };
    let field = pkm_draw::chart::Heatmap {
        colour_axis: "peak effort (N or N m)".into(),
        x: u,
        y: v,
        values: values.clone(),
    };
    artifacts.push(Artifact::Table {
        name: csv.clone(),
        table,
    });
    artifacts.push(Artifact::Chart {
        name: svg.clone(),
        chart: Box::new(Chart::heatmap(
            "largest actuator effort at rest over the acceleration box",
            format!("{} ({})", names[a], unit(a)),
            format!("{} ({})", names[b], unit(b)),
            field,
        )),
    });
    let name = |i: usize| names[i].to_string();
    Ok(EffortMapResult {
        axes: [name(a), name(b)],
        at: (0..names.len())
            .filter(|i| !plan.axes.contains(i))
            .map(|i| (name(i), plan.through[i]))
            .collect(),
        acceleration: (0..names.len())
            .map(|i| (name(i), plan.bounds[i]))
            .collect(),
        cells: n,
        inside_fraction: values.iter().flatten().count() as f64 / values.len() as f64,
        max_peak: values.iter().flatten().copied().reduce(f64::max),
        min_peak: values.iter().flatten().copied().reduce(f64::min),
        csv,
        svg,
    })
}
