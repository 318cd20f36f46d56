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
use crate::{DynamicsError, ExtendedModel, ExtendedState};
use nalgebra::{Vector3, Vector6};

/// Two-point differencing of a sampled signal on a uniform grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Differencing {
    /// $(f_k - f_{k-1})/\Delta t$ (forward at the first sample).
    Backward,
    /// $(f_{k+1} - f_{k-1})/(2\Delta t)$, second-order one-sided at the ends.
    Central,
}

impl Differencing {
    /// The derivative of `f` sampled every `dt` (needs at least 3 samples).
    pub fn apply(self, f: &[Vector6<f64>], dt: f64) -> Vec<Vector6<f64>> {
        let n = f.len();
        let (inv, half_inv) = (1.0 / dt, 0.5 / dt);
        (0..n)
            .map(|k| match self {
                _ if n < 3 => Vector6::zeros(),
                Self::Backward if k == 0 => (f[1] - f[0]) * inv,
                Self::Backward => (f[k] - f[k - 1]) * inv,
                Self::Central if k == 0 => (f[1] * 4.0 - f[0] * 3.0 - f[2]) * half_inv,
                Self::Central if k + 1 == n => (f[k] * 3.0 - f[k - 1] * 4.0 + f[k - 2]) * half_inv,
                Self::Central => (f[k + 1] - f[k - 1]) * half_inv,
            })
            .collect()
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
/// [`DynamicsError::InvalidSetting`] for a step that is not positive or leaves fewer than 3
/// samples; [`DynamicsError::Unreachable`] with the time and leg of the first unreachable point.
pub fn sample(
    model: &ExtendedModel,
    trajectory: &Trajectory,
    dt: f64,
) -> Result<Vec<(f64, ExtendedState)>, DynamicsError> {
    let steps = (trajectory.duration() / dt).round();
    if !(dt > 0.0 && (2.0..1e8).contains(&steps)) {
        return Err(DynamicsError::InvalidSetting {
            setting: "dt",
            value: dt,
            requirement: "must be > 0 and leave 3 to 1e8 samples",
        });
    }
    (0..=steps as usize)
        .map(|k| {
            let t = k as f64 * dt;
            let m = trajectory.sample(t);
            let s = model.joint_motion(&m.p, &m.v, &m.a).map_err(|e| at(e, t))?;
            Ok((t, s))
        })
        .collect()
}

fn at(e: DynamicsError, t: f64) -> DynamicsError {
    match e {
        DynamicsError::Unreachable { source, .. } => DynamicsError::Unreachable { t, source },
        DynamicsError::Singular { matrix, .. } => DynamicsError::Singular { matrix, t },
        DynamicsError::NonFinite { what, .. } => DynamicsError::NonFinite { what, t },
        other => other,
    }
}

/// The motor torques for a given momentum rate $\dot p$ (steps 2 and 3 of §3.3), i.e.
/// [`Configuration::hamilton_torques`](crate::Configuration::hamilton_torques) at `q`.
///
/// # Errors
/// [`DynamicsError::Singular`] when $\Phi_x$ (a direct-kinematic singularity) is singular,
/// [`DynamicsError::NonFinite`] for a non-finite torque (times are NaN; callers set them).
pub fn torques(
    model: &ExtendedModel,
    q: &Vector6<f64>,
    qd: &Vector6<f64>,
    p_rate: &Vector6<f64>,
) -> Result<Vector3<f64>, DynamicsError> {
    model.at(q).hamilton_torques(qd, p_rate)
}

/// Hamilton's inverse dynamics (§3.3): $p_k = M(q_k)\dot q_k$, $\dot p$ by `differencing`, then
/// steps 2–3. Uses only positions and velocities; each sample's [`Configuration`](crate::Configuration)
/// is formed once and serves both its momentum and its torques.
///
/// # Errors
/// As [`torques`], with the time of the failing sample.
pub fn hamilton(
    model: &ExtendedModel,
    samples: &[(f64, ExtendedState)],
    dt: f64,
    differencing: Differencing,
) -> Result<Vec<Vector3<f64>>, DynamicsError> {
    let configurations: Vec<_> = samples.iter().map(|(_, s)| model.at(&s.q)).collect();
    let momenta: Vec<_> = (configurations.iter().zip(samples))
        .map(|(c, (_, s))| c.momentum(&s.qd))
        .collect();
    let rates = differencing.apply(&momenta, dt);
    (configurations.iter().zip(samples).zip(&rates))
        .map(|((c, (t, s)), r)| c.hamilton_torques(&s.qd, r).map_err(|e| at(e, *t)))
        .collect()
}

/// Lagrange inverse dynamics: $\dot p = M\ddot q + \dot M\dot q$, then steps 2–3.
///
/// # Errors
/// As [`torques`], with the time of the failing sample.
pub fn lagrange(
    model: &ExtendedModel,
    samples: &[(f64, ExtendedState)],
    dt: f64,
    accelerations: Accelerations,
) -> Result<Vec<Vector3<f64>>, DynamicsError> {
    let qdd: Vec<_> = match accelerations {
        Accelerations::Exact => samples.iter().map(|(_, s)| s.qdd).collect(),
        Accelerations::Differenced(d) => {
            let qd: Vec<_> = samples.iter().map(|(_, s)| s.qd).collect();
            d.apply(&qd, dt)
        }
    };
    (samples.iter().zip(&qdd))
        .map(|((t, s), a)| lagrange_torques(model, &s.q, &s.qd, a).map_err(|e| at(e, *t)))
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
) -> Result<Vector3<f64>, DynamicsError> {
    model.at(q).lagrange_torques(qd, qdd)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MassParameters;
    use crate::trajectory::{MotionLaw, Path, Segment};
    use pkm_mechanisms::{Placement, RotaryDelta};
    use pkm_traits::KinematicsError;

    fn nuwar() -> ExtendedModel {
        let m = RotaryDelta::nuwar(Placement::canonical()).unwrap();
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
        assert!(matches!(reach(t), Err(DynamicsError::Unreachable { .. })));
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
        let reading = crate::trajectory::CycleReading::RoundTrip;
        let trajectory = Trajectory::pick_and_place(0.5, reading).unwrap();
        let mut samples = sample(&model, &trajectory, 1e-3).unwrap();
        samples[7].1.qd[3] = f64::NAN;
        let e = hamilton(&model, &samples, 1e-3, Differencing::Backward).unwrap_err();
        assert!(
            matches!(e, DynamicsError::NonFinite { what: "torque", t } if (t - 0.007).abs() < 1e-15),
            "{e:?}"
        );
    }
}
