//! Inverse dynamics along a sampled trajectory, by Hamilton's three steps (Miller 2004 §3.3) and
//! by the acceleration-based Lagrange equations in the same coordinates.
//!
//! Both end in the same two linear solves. With $\dot p = \frac{d}{dt}\partial L/\partial\dot q$
//! the task rows give the multipliers and the joint rows the torques:
//! $$ \Phi_x^\top \lambda = L_{q,x} - \dot p_x, \qquad
//!    \tau = \dot p_\theta - L_{q,\theta} + \Phi_\theta^\top \lambda. $$
//! Hamilton obtains $\dot p$ by differencing the momenta $p = M\dot q$ (no accelerations);
//! Lagrange forms $\dot p = M\ddot q + \dot M\dot q$ from accelerations.

use crate::trajectory::Trajectory;
use crate::{ConfigurationError, DynamicsError, ExtendedModel, ExtendedState};
use nalgebra::{Vector3, Vector6};
use pkm_traits::InvalidInput;

/// Two-point differencing of a sampled signal on a uniform grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Differencing {
    /// $(f_k - f_{k-1})/\Delta t$ (forward at the first sample).
    Backward,
    /// $(f_{k+1} - f_{k-1})/(2\Delta t)$, second-order one-sided at the ends.
    Central,
}

impl Differencing {
    /// The derivative of `f` sampled every `dt`.
    ///
    /// # Errors
    /// [`InvalidInput`] for fewer than 3 samples (the one-sided second-order ends need three)
    /// or a step that is not finite and positive.
    pub fn apply<V>(self, f: &[V], dt: f64) -> Result<Vec<V>, InvalidInput>
    where
        V: Clone
            + std::ops::Add<Output = V>
            + std::ops::Sub<Output = V>
            + std::ops::Mul<f64, Output = V>,
    {
        let n = f.len();
        if n < 3 {
            return Err(InvalidInput::new("samples", n as f64, "at least 3"));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(InvalidInput::new("dt", dt, "finite and > 0"));
        }
        let (inv, half_inv) = (1.0 / dt, 0.5 / dt);
        Ok((0..n)
            .map(|k| {
                let at = |i: usize| f[i].clone();
                match self {
                    Self::Backward if k == 0 => (at(1) - at(0)) * inv,
                    Self::Backward => (at(k) - at(k - 1)) * inv,
                    Self::Central if k == 0 => (at(1) * 4.0 - at(0) * 3.0 - at(2)) * half_inv,
                    Self::Central if k + 1 == n => {
                        (at(k) * 3.0 - at(k - 1) * 4.0 + at(k - 2)) * half_inv
                    }
                    Self::Central => (at(k + 1) - at(k - 1)) * half_inv,
                }
            })
            .collect())
    }
}

/// Where the Lagrange formulation takes $\ddot q$ from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Accelerations {
    /// The analytic $\ddot q$ (acceleration-level inverse kinematics).
    Exact,
    /// $\ddot q$ by differencing the sampled $\dot q$.
    Differenced(Differencing),
}

/// The extended states of `trajectory` on the grid $t_k = k\,\Delta t$ up to its end.
///
/// # Errors
/// [`DynamicsError::Invalid`] for a step that is not positive or leaves fewer than 3
/// samples, or more than fit in [`pkm_traits::MEMORY_BUDGET_BYTES`] (checked before
/// allocating); [`DynamicsError::Unreachable`] with the time and leg of the first unreachable
/// point.
pub fn sample(
    model: &ExtendedModel,
    trajectory: &Trajectory,
    dt: f64,
) -> Result<Vec<(f64, ExtendedState)>, DynamicsError> {
    let steps = (trajectory.duration() / dt).round();
    if !(dt > 0.0 && (2.0..1e8).contains(&steps)) {
        return Err(InvalidInput::new("dt", dt, "must be > 0 and leave 3 to 1e8 samples").into());
    }
    // `steps` is an integer in [2, 1e8), so the cast is exact.
    let count = steps as usize + 1;
    InvalidInput::require_within_budget("samples", count, size_of::<(f64, ExtendedState)>())?;
    (0..count)
        .map(|k| {
            let t = k as f64 * dt;
            let m = trajectory.sample(t);
            let s = model.joint_motion(&m.p, &m.v, &m.a).map_err(|e| e.at(t))?;
            Ok((t, s))
        })
        .collect()
}

/// The motor torques for a given momentum rate $\dot p$ (steps 2 and 3 of §3.3), i.e.
/// [`Configuration::hamilton_torques`](crate::Configuration::hamilton_torques) at `q`.
///
/// # Errors
/// [`ConfigurationError::Singular`] when $\Phi_x$ (a direct-kinematic singularity) is
/// singular, [`ConfigurationError::NonFinite`] for a non-finite torque (a configuration has no
/// time: [`hamilton`] and [`lagrange`] attach the sample's).
pub fn torques(
    model: &ExtendedModel,
    q: &Vector6<f64>,
    qd: &Vector6<f64>,
    p_rate: &Vector6<f64>,
) -> Result<Vector3<f64>, ConfigurationError> {
    model.at(q).hamilton_torques(qd, p_rate)
}

/// Relative tolerance on the spacing of sample times that [`hamilton`] and [`lagrange`] accept as
/// one uniform grid.
pub const SPACING_TOLERANCE: f64 = 1e-9;

/// The grid step $\Delta t = t_1 - t_0$ of `samples`, after checking that every interval
/// $t_k - t_{k-1}$ equals it to a relative [`SPACING_TOLERANCE`] (beyond the rounding of the
/// times themselves, a few ulps of $|t_k|$). On a grid from [`sample`] ($t_k = k\,\Delta t$) it
/// is exactly the `dt` given there.
///
/// # Errors
/// [`DynamicsError::Invalid`]: name `"samples"` (value: their number) for fewer than
/// 3 samples, `"sample step"` for a step that is not finite and positive, and `"sample time"`
/// (value: $t_k$) at the first sample off the uniform grid.
pub fn sample_step<T>(samples: &[(f64, T)]) -> Result<f64, DynamicsError> {
    let n = samples.len();
    let [(first, _), (second, _), _, ..] = samples else {
        let requirement = "differencing needs at least 3 samples";
        return Err(InvalidInput::new("samples", n as f64, requirement).into());
    };
    let step = second - first;
    if !(step.is_finite() && step > 0.0) {
        let requirement = "sample times must increase and be finite";
        return Err(InvalidInput::new("sample step", step, requirement).into());
    }
    let off_grid = samples.windows(2).find(|w| {
        let (before, after) = (w[0].0, w[1].0);
        let rounding = 4.0 * f64::EPSILON * before.abs().max(after.abs());
        // Negated so that a NaN time counts as off the grid.
        !((after - before - step).abs() <= SPACING_TOLERANCE * step + rounding)
    });
    match off_grid {
        Some(w) => {
            let requirement = "samples must be equally spaced to a relative 1e-9";
            Err(InvalidInput::new("sample time", w[1].0, requirement).into())
        }
        None => Ok(step),
    }
}

/// The extended states of platform positions $p_k$ sampled at equally spaced times $t_k$
/// (measured or planned positions without derivatives): $\dot p$ by second-order central
/// differences of the positions and $\ddot p$ by the same differences of $\dot p$
/// ([`Differencing::Central`] applied once and twice, one-sided at the ends), then the joint
/// motion of each sample ([`ExtendedModel::joint_motion`]). Hamilton's torques
/// ([`hamilton`]) of these states use first differences of the data only.
///
/// # Errors
/// As [`sample_step`] for positions that are too few or not equally spaced in time;
/// [`DynamicsError::Unreachable`] or [`DynamicsError::Singular`] with the time of the first
/// sample out of reach (a non-finite position is out of reach).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_dynamics_hamilton::{ExtendedModel, MassParameters, inverse};
/// use pkm_mechanisms::{Placement, RotaryDelta, presets};
/// let robot = RotaryDelta::new(presets::nuwar(Placement::canonical()))?;
/// let model = ExtendedModel::new(robot, &MassParameters::miller2004())?;
/// // A uniform descent at 0.1 m/s, sampled every 10 ms.
/// let positions: Vec<_> = (0..20)
///     .map(|k| (k as f64 * 0.01, Vector3::new(0.0, 0.0, -0.8 - 0.001 * k as f64)))
///     .collect();
/// let states = inverse::sample_positions(&model, &positions)?;
/// assert!((states[7].1.qd[2] + 0.1).abs() < 1e-12 && states[7].1.qdd[2].abs() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sample_positions(
    model: &ExtendedModel,
    positions: &[(f64, Vector3<f64>)],
) -> Result<Vec<(f64, ExtendedState)>, DynamicsError> {
    let dt = sample_step(positions)?;
    let padded: Vec<Vector6<f64>> = positions
        .iter()
        .map(|(_, p)| Vector6::new(p.x, p.y, p.z, 0.0, 0.0, 0.0))
        .collect();
    let velocities = Differencing::Central.apply(&padded, dt)?;
    let accelerations = Differencing::Central.apply(&velocities, dt)?;
    let head = |v: &Vector6<f64>| Vector3::new(v[0], v[1], v[2]);
    (positions.iter().zip(&velocities).zip(&accelerations))
        .map(|(((t, p), v), a)| {
            let state = model.joint_motion(p, &head(v), &head(a));
            state.map(|s| (*t, s)).map_err(|e| e.at(*t))
        })
        .collect()
}

/// Hamilton's inverse dynamics (§3.3): $p_k = M(q_k)\dot q_k$, $\dot p$ by `differencing` on
/// the grid step of the samples' own times ([`sample_step`]), then steps 2–3. Uses only
/// positions and velocities; each sample's [`Configuration`](crate::Configuration) is formed
/// once and serves both its momentum and its torques.
///
/// # Errors
/// As [`sample_step`] for samples that are too few or not equally spaced; otherwise as
/// [`torques`], with the time of the failing sample.
pub fn hamilton(
    model: &ExtendedModel,
    samples: &[(f64, ExtendedState)],
    differencing: Differencing,
) -> Result<Vec<Vector3<f64>>, DynamicsError> {
    let dt = sample_step(samples)?;
    let configurations: Vec<_> = samples.iter().map(|(_, s)| model.at(&s.q)).collect();
    let momenta: Vec<_> = (configurations.iter().zip(samples))
        .map(|(c, (_, s))| c.momentum(&s.qd))
        .collect();
    let rates = differencing.apply(&momenta, dt)?;
    (configurations.iter().zip(samples).zip(&rates))
        .map(|((c, (t, s)), r)| c.hamilton_torques(&s.qd, r).map_err(|e| e.at(*t)))
        .collect()
}

/// Lagrange inverse dynamics: $\dot p = M\ddot q + \dot M\dot q$, then steps 2–3. With
/// [`Accelerations::Differenced`] the step is that of the samples' own times ([`sample_step`]);
/// with [`Accelerations::Exact`] the times may be any.
///
/// # Errors
/// As [`sample_step`] when differencing samples that are too few or not equally spaced;
/// otherwise as [`torques`], with the time of the failing sample.
pub fn lagrange(
    model: &ExtendedModel,
    samples: &[(f64, ExtendedState)],
    accelerations: Accelerations,
) -> Result<Vec<Vector3<f64>>, DynamicsError> {
    let qdd: Vec<_> = match accelerations {
        Accelerations::Exact => samples.iter().map(|(_, s)| s.qdd).collect(),
        Accelerations::Differenced(d) => {
            let dt = sample_step(samples)?;
            let qd: Vec<_> = samples.iter().map(|(_, s)| s.qd).collect();
            d.apply(&qd, dt)?
        }
    };
    (samples.iter().zip(&qdd))
        .map(|((t, s), a)| lagrange_torques(model, &s.q, &s.qd, a).map_err(|e| e.at(*t)))
        .collect()
}

/// One Lagrange evaluation from $(q, \dot q, \ddot q)$, i.e.
/// [`Configuration::lagrange_torques`](crate::Configuration::lagrange_torques) at `q`.
///
/// # Errors
/// As [`torques`].
pub fn lagrange_torques(
    model: &ExtendedModel,
    q: &Vector6<f64>,
    qd: &Vector6<f64>,
    qdd: &Vector6<f64>,
) -> Result<Vector3<f64>, ConfigurationError> {
    model.at(q).lagrange_torques(qd, qdd)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MassParameters;
    use crate::trajectory::{MotionLaw, Path, Segment};
    use pkm_mechanisms::{Placement, RotaryDelta, presets};
    use pkm_traits::KinematicsError;

    fn nuwar() -> ExtendedModel {
        let m = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
        ExtendedModel::new(m, &MassParameters::miller2004()).unwrap()
    }

    #[test]
    fn an_unreachable_point_reports_its_time_and_leg() {
        let model = nuwar();
        // From the middle of the workspace straight away from motor 1 (horizontally): leg 1
        // (index 0) is stretched first.
        let radial = model.mechanism().legs()[0].plate_offset.normalize();
        let start = Vector3::new(0.0, 0.0, -0.75);
        let path = Path::line(start, start - radial * 1.0).unwrap();
        let law = MotionLaw::Cycloidal;
        let segment = Segment {
            path,
            law,
            duration: 1.0,
            reverse: false,
        };
        let trajectory = Trajectory::new(vec![segment]).unwrap();
        let dt = 1e-3;
        let Err(DynamicsError::Unreachable { t, source }) = sample(&model, &trajectory, dt) else {
            panic!("the line leaves the workspace");
        };
        let KinematicsError::Unreachable { leg, .. } = source else {
            panic!("expected a leg that cannot reach, got {source:?}");
        };
        assert_eq!(leg, 0, "{source}");
        // `t` is the first grid time whose point is out of reach.
        let k = (t / dt).round();
        assert!((t - k * dt).abs() < 1e-15 && t > 0.0 && t < 1.0, "t = {t}");
        let reach = |t: f64| {
            let m = trajectory.sample(t);
            model.joint_motion(&m.p, &m.v, &m.a)
        };
        assert!(reach(t - dt).is_ok());
        assert!(matches!(reach(t), Err(ConfigurationError::Unreachable(_))));
        // The message names both.
        let message = DynamicsError::Unreachable { t, source }.to_string();
        assert!(
            message.contains(&format!("t = {t}")) && message.contains("leg 0"),
            "{message}"
        );
    }

    #[test]
    fn failures_of_one_sample_carry_its_time() {
        let model = nuwar();
        let trajectory = crate::trajectory::tests::ellipse_cycle(0.5);
        let mut samples = sample(&model, &trajectory, 1e-3).unwrap();
        samples[7].1.qd[3] = f64::NAN;
        let e = hamilton(&model, &samples, Differencing::Backward).unwrap_err();
        assert!(
            matches!(e, DynamicsError::NonFinite { what: "torque", t } if (t - 0.007).abs() < 1e-15),
            "{e:?}"
        );
    }

    #[test]
    fn the_step_is_read_from_the_sample_times() {
        let model = nuwar();
        let trajectory = crate::trajectory::tests::ellipse_cycle(0.5);
        // Bit for bit the step given to `sample`, also where (t_n - t_0)/n is not (0.3 s, 0.1 ms).
        for duration in [0.5, 0.3] {
            let trajectory = crate::trajectory::tests::ellipse_cycle(duration);
            for dt in [1e-3, 1e-4, 2.5e-3, 1.0 / 3000.0] {
                let samples = sample(&model, &trajectory, dt).unwrap();
                let step = sample_step(&samples).unwrap();
                assert_eq!(step.to_bits(), dt.to_bits(), "{step} vs {dt}");
            }
        }
        // The step read from the times is the one the differences use: Hamilton's torques equal
        // steps 2-3 applied to the momenta differenced by hand with the known step.
        let dt = 2e-3;
        let samples = sample(&model, &trajectory, dt).unwrap();
        let momenta: Vec<_> = (samples.iter())
            .map(|(_, s)| model.mass_matrix(&s.q) * s.qd)
            .collect();
        let rates = Differencing::Central.apply(&momenta, dt).unwrap();
        let tau = hamilton(&model, &samples, Differencing::Central).unwrap();
        for ((t, s), (r, tau)) in samples.iter().zip(rates.iter().zip(&tau)) {
            let by_hand = torques(&model, &s.q, &s.qd, r).unwrap();
            assert!(
                (by_hand - tau).amax() <= 1e-9 * by_hand.amax().max(1.0),
                "t = {t}"
            );
        }
    }

    #[test]
    fn unevenly_spaced_or_too_few_samples_are_typed_errors() {
        let model = nuwar();
        let trajectory = crate::trajectory::tests::ellipse_cycle(0.5);
        let samples = sample(&model, &trajectory, 1e-3).unwrap();
        let differenced = Accelerations::Differenced(Differencing::Central);
        let rejects = |samples: &[(f64, ExtendedState)], setting: &str, value: f64| {
            for e in [
                hamilton(&model, samples, Differencing::Backward).unwrap_err(),
                lagrange(&model, samples, differenced).unwrap_err(),
            ] {
                assert!(
                    matches!(e, DynamicsError::Invalid(InvalidInput { name: s, value: v, .. })
                        if s == setting && ((v.is_nan() && value.is_nan()) || (v - value).abs() < 1e-15)),
                    "{e:?}, expected {setting} = {value}"
                );
            }
        };
        // One time moved by a relative 1e-8 of the step.
        let mut uneven = samples.clone();
        uneven[200].0 += 1e-11;
        rejects(&uneven, "sample time", uneven[200].0);
        // ... and a NaN time, a reversed grid, too few samples.
        let mut nan = samples.clone();
        nan[5].0 = f64::NAN;
        rejects(&nan, "sample time", f64::NAN);
        let mut reversed = samples.clone();
        reversed.reverse();
        rejects(&reversed, "sample step", -1e-3);
        rejects(&samples[..2], "samples", 2.0);
        rejects(&[], "samples", 0.0);
        // Within 1e-9 of the step the grid is accepted, and the exact Lagrange form needs none.
        let mut jittered = samples.clone();
        jittered[200].0 += 1e-13;
        assert!(hamilton(&model, &jittered, Differencing::Central).is_ok());
        assert!(lagrange(&model, &uneven, Accelerations::Exact).is_ok());
        assert!(lagrange(&model, &samples[..2], Accelerations::Exact).is_ok());
    }
}
