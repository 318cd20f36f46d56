//! The rotary Delta family in the extended coordinates $q = (x, y, z, \theta_1, \theta_2, \theta_3)$
//! (Miller 2004 §3.2, eqs. 8–12): mass matrix, Lagrangian gradient, constraints and their
//! Jacobians.

use crate::ConfigurationError;
use crate::kernel::{self, Constants, Leg};
use crate::mass::{Coefficients, MassParameters};
use nalgebra::{Matrix6, SMatrix, Vector3, Vector6};
use pkm_mechanisms::{ElbowMode, RotaryDelta};
use pkm_traits::{ClosedChain, DesignError, InverseKinematics};

/// Positions, velocities and accelerations in the extended space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtendedState {
    /// $q = (p, \theta)$.
    pub q: Vector6<f64>,
    /// $\dot q$.
    pub qd: Vector6<f64>,
    /// $\ddot q$.
    pub qdd: Vector6<f64>,
}

/// A rotary Delta with its mass model.
///
/// # Example
/// ```
/// use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
/// use pkm_mechanisms::{Placement, RotaryDelta, presets};
/// use nalgebra::Vector3;
/// let model = ExtendedModel::new(RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
///     &MassParameters::miller2004()).unwrap();
/// let s = model.joint_motion(&Vector3::new(0.0, -0.2, -0.9), &Vector3::zeros(), &Vector3::zeros())
///     .unwrap();
/// assert!(model.constraints(&s.q).amax() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ExtendedModel {
    mechanism: RotaryDelta,
    c: Coefficients,
    constants: Constants,
}

/// The model at one configuration $q$: the per-leg quantities $d_i$, $d_i'$, $v_i$ and
/// $\Phi_{\theta,ii}$ evaluated once (three `sin_cos`), from which every dynamics evaluation at
/// that $q$ follows in a few hundred arithmetic operations, without forming $M$, $\Phi_q$ or a
/// saddle-point matrix. A sweep over samples forms one per sample and uses it for the momentum
/// and the torques (as Pinocchio's `Data` holds the kinematics of one configuration).
///
/// # Example
/// ```
/// use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
/// use pkm_mechanisms::{Placement, RotaryDelta, presets};
/// use nalgebra::Vector3;
/// let model = ExtendedModel::new(RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
///     &MassParameters::miller2004()).unwrap();
/// let s = model.joint_motion(&Vector3::new(0.0, -0.1, -0.8), &Vector3::new(0.0, 1.0, 0.5),
///     &Vector3::zeros()).unwrap();
/// let at = model.at(&s.q);
/// assert!((at.momentum(&s.qd) - model.mass_matrix(&s.q) * s.qd).amax() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Configuration<'a> {
    constants: &'a Constants,
    legs: [Leg<f64>; 3],
}

fn split(q: &Vector6<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (q.fixed_rows::<3>(0).into(), q.fixed_rows::<3>(3).into())
}

impl ExtendedModel {
    /// Couples a mechanism with a mass model.
    ///
    /// # Errors
    /// [`DesignError`] for an invalid mass parameter.
    pub fn new(mechanism: RotaryDelta, mass: &MassParameters) -> Result<Self, DesignError> {
        let c = mass.coefficients(mechanism.arm())?;
        let constants = Constants {
            legs: mechanism
                .legs()
                .map(|leg| [leg.u, leg.w, leg.plate_offset - leg.motor]),
            arm: mechanism.arm(),
            forearm_squared: mechanism.forearm() * mechanism.forearm(),
            m_t: c.m_t,
            j: c.j,
            k: c.k,
            g_m_g: c.gravity * c.m_g,
            g_c_g: c.gravity * c.c_g,
        };
        Ok(Self {
            mechanism,
            c,
            constants,
        })
    }

    /// The model at configuration `q` (see [`Configuration`]).
    #[inline]
    pub fn at(&self, q: &Vector6<f64>) -> Configuration<'_> {
        let p = Vector3::new(q[0], q[1], q[2]);
        let trig = [q[3].sin_cos(), q[4].sin_cos(), q[5].sin_cos()];
        Configuration {
            constants: &self.constants,
            legs: kernel::legs(&self.constants, &p, trig),
        }
    }

    /// The mechanism.
    pub fn mechanism(&self) -> &RotaryDelta {
        &self.mechanism
    }

    /// The inertia coefficients.
    pub fn coefficients(&self) -> &Coefficients {
        &self.c
    }

    /// $M(q) = \begin{pmatrix} m_t I_3 & K \\ K^\top & J I_3 \end{pmatrix}$,
    /// $K_{:,i} = k\, d_i'(\theta_i)$.
    pub fn mass_matrix(&self, q: &Vector6<f64>) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        for (i, leg) in self.mechanism.legs().iter().enumerate() {
            m[(i, i)] = self.c.m_t;
            m[(3 + i, 3 + i)] = self.c.j;
            let col = leg.arm_direction_derivative(q[3 + i]) * self.c.k;
            for r in 0..3 {
                m[(r, 3 + i)] = col[r];
                m[(3 + i, r)] = col[r];
            }
        }
        m
    }

    /// $L_q = \partial L / \partial q$ at fixed $\dot q$: $L_z = -g m_g$,
    /// $L_{\theta_i} = -k\dot\theta_i (d_i\cdot\dot p) - g c_g (d_i')_z$.
    pub fn lagrangian_gradient(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> Vector6<f64> {
        let (pd, thd) = split(qd);
        let mut l = Vector6::zeros();
        l[2] = -self.c.gravity * self.c.m_g;
        for (i, leg) in self.mechanism.legs().iter().enumerate() {
            let d = leg.arm_direction(q[3 + i]);
            let d1 = leg.arm_direction_derivative(q[3 + i]);
            l[3 + i] = -self.c.k * thd[i] * d.dot(&pd) - self.c.gravity * self.c.c_g * d1.z;
        }
        l
    }

    /// $\dot M \dot q$: task rows $-k\sum_i \dot\theta_i^2 d_i$, row $3+i$:
    /// $-k\dot\theta_i (d_i\cdot\dot p)$.
    pub fn mass_matrix_rate_times_velocity(
        &self,
        q: &Vector6<f64>,
        qd: &Vector6<f64>,
    ) -> Vector6<f64> {
        let (pd, thd) = split(qd);
        let mut out = Vector6::zeros();
        for (i, leg) in self.mechanism.legs().iter().enumerate() {
            let d = leg.arm_direction(q[3 + i]) * self.c.k;
            let task = -d * thd[i] * thd[i];
            for r in 0..3 {
                out[r] += task[r];
            }
            out[3 + i] = -thd[i] * d.dot(&pd);
        }
        out
    }

    /// The loop closure $\Phi(q)$.
    pub fn constraints(&self, q: &Vector6<f64>) -> Vector3<f64> {
        let (p, th) = split(q);
        self.mechanism.closure(&p, &th)
    }

    /// $\Phi_q = [\Phi_x \;\; \Phi_\theta]$ (3 × 6, $\Phi_\theta$ diagonal).
    pub fn constraint_jacobian(&self, q: &Vector6<f64>) -> SMatrix<f64, 3, 6> {
        let (p, th) = split(q);
        let mut out = SMatrix::<f64, 3, 6>::zeros();
        out.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&self.mechanism.jacobian_x(&p, &th));
        out.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&self.mechanism.jacobian_q(&p, &th));
        out
    }

    /// $\dot\Phi_q$: row $i$ is $[2\dot v_i^\top,\; -2L_a(\dot v_i\cdot d_i' - \dot\theta_i\, v_i\cdot d_i)]$
    /// with $v_i = C_i - B_i$, $\dot v_i = \dot p - L_a\dot\theta_i d_i'$.
    pub fn constraint_jacobian_rate(
        &self,
        q: &Vector6<f64>,
        qd: &Vector6<f64>,
    ) -> SMatrix<f64, 3, 6> {
        let (p, th) = split(q);
        let (pd, thd) = split(qd);
        let la = self.mechanism.arm();
        let mut out = SMatrix::<f64, 3, 6>::zeros();
        for (i, leg) in self.mechanism.legs().iter().enumerate() {
            let v = self.mechanism.forearm_vector(i, &p, th[i]);
            let d = leg.arm_direction(th[i]);
            let d1 = leg.arm_direction_derivative(th[i]);
            let vd = pd - d1 * (la * thd[i]);
            for r in 0..3 {
                out[(i, r)] = 2.0 * vd[r];
            }
            out[(i, 3 + i)] = -2.0 * la * (vd.dot(&d1) - thd[i] * v.dot(&d));
        }
        out
    }

    /// $\gamma = \dot\Phi_q \dot q$, so that $\ddot\Phi = \Phi_q \ddot q + \gamma$.
    pub fn gamma(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> Vector3<f64> {
        self.constraint_jacobian_rate(q, qd) * qd
    }

    /// The potential $V = g\,[m_g z + \sum_i c_g\, d_i(\theta_i)_z]$.
    pub fn potential(&self, q: &Vector6<f64>) -> f64 {
        let arms: f64 = (self.mechanism.legs().iter().enumerate())
            .map(|(i, leg)| leg.arm_direction(q[3 + i]).z)
            .sum();
        self.c.gravity * (self.c.m_g * q[2] + self.c.c_g * arms)
    }

    /// $\partial V / \partial q = -L_q$ at $\dot q = 0$.
    pub fn potential_gradient(&self, q: &Vector6<f64>) -> Vector6<f64> {
        -self.lagrangian_gradient(q, &Vector6::zeros())
    }

    /// Kinetic energy $T = \tfrac12 \dot q^\top M \dot q$. IEEE arithmetic, never a panic: finite
    /// for finite $q$ and rates below about 1e150 (the product squares them); NaN in, NaN out.
    pub fn kinetic_energy(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> f64 {
        0.5 * qd.dot(&(self.mass_matrix(q) * qd))
    }

    /// Total energy $T + V$, with the contract of [`ExtendedModel::kinetic_energy`].
    pub fn energy(&self, q: &Vector6<f64>, qd: &Vector6<f64>) -> f64 {
        self.kinetic_energy(q, qd) + self.potential(q)
    }

    /// The acceleration-level inverse kinematics alone: $\ddot q = (\ddot p, \ddot\theta)$ with
    /// $\ddot\theta = -\Phi_\theta^{-1}(\Phi_x\ddot p + \gamma)$ at given consistent $(q, \dot q)$
    /// ($\Phi_\theta$ is diagonal). This is what Lagrange's inverse dynamics needs per sample
    /// beyond the positions and velocities that Hamilton's needs as well.
    ///
    /// # Errors
    /// [`ConfigurationError::Singular`] when a diagonal entry of $\Phi_\theta$ is zero (a leg
    /// stretched or folded) or the result is not finite.
    pub fn joint_accelerations(
        &self,
        q: &Vector6<f64>,
        qd: &Vector6<f64>,
        a: &Vector3<f64>,
    ) -> Result<Vector6<f64>, ConfigurationError> {
        self.at(q).joint_accelerations(qd, a)
    }

    /// Extended positions, velocities and accelerations of a task motion $(p, \dot p, \ddot p)$:
    /// $\theta = \mathrm{IK}(p)$ (elbow out), $\dot\theta = -\Phi_\theta^{-1}\Phi_x\dot p$,
    /// $\ddot\theta = -\Phi_\theta^{-1}(\Phi_x\ddot p + \gamma)$.
    ///
    /// # Errors
    /// [`ConfigurationError::Unreachable`] (naming the leg) or [`ConfigurationError::Singular`]
    /// when a leg is stretched or folded.
    pub fn joint_motion(
        &self,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        a: &Vector3<f64>,
    ) -> Result<ExtendedState, ConfigurationError> {
        let th = self.mechanism.inverse_kinematics(p, ElbowMode::Out)?;
        let q = Vector6::new(p.x, p.y, p.z, th.x, th.y, th.z);
        let at = self.at(&q);
        let qd = at.joint_velocities(v)?;
        let qdd = at.joint_accelerations(&qd, a)?;
        Ok(ExtendedState { q, qd, qdd })
    }
}

impl Configuration<'_> {
    /// The momenta $p = M(q)\dot q$ (eq. 15).
    #[inline]
    pub fn momentum(&self, qd: &Vector6<f64>) -> Vector6<f64> {
        kernel::momentum(self.constants, &self.legs, qd)
    }

    /// The loop closure $\Phi(q)$.
    #[inline]
    pub fn constraints(&self) -> Vector3<f64> {
        kernel::constraints(self.constants, &self.legs)
    }

    /// Steps 2 and 3 of Hamilton's inverse dynamics (§3.3) for a given momentum rate
    /// $\dot p$: $\Phi_x^\top\lambda = L_{q,x} - \dot p_x$ (Cramer's rule on the forearm
    /// vectors), $\tau = \dot p_\theta - L_{q,\theta} + \Phi_\theta\lambda$ ($\Phi_\theta$
    /// diagonal).
    ///
    /// # Errors
    /// [`ConfigurationError::Singular`] (`"Phi_x^T"`) at a direct-kinematic singularity,
    /// [`ConfigurationError::NonFinite`] for a non-finite torque.
    #[inline]
    pub fn hamilton_torques(
        &self,
        qd: &Vector6<f64>,
        p_rate: &Vector6<f64>,
    ) -> Result<Vector3<f64>, ConfigurationError> {
        checked_torques(kernel::hamilton_torques(
            self.constants,
            &self.legs,
            qd,
            p_rate,
        ))
    }

    /// Lagrange's inverse dynamics from $\ddot q$: $\dot p = M\ddot q + \dot M\dot q$, then the
    /// same steps as [`Configuration::hamilton_torques`].
    ///
    /// # Errors
    /// As [`Configuration::hamilton_torques`].
    #[inline]
    pub fn lagrange_torques(
        &self,
        qd: &Vector6<f64>,
        qdd: &Vector6<f64>,
    ) -> Result<Vector3<f64>, ConfigurationError> {
        checked_torques(kernel::lagrange_torques(
            self.constants,
            &self.legs,
            qd,
            qdd,
        ))
    }

    /// The velocity-level inverse kinematics $\dot\theta_i = -2 v_i\cdot\dot x /
    /// \Phi_{\theta,ii}$, as $\dot q = (\dot x, \dot\theta)$.
    ///
    /// # Errors
    /// [`ConfigurationError::Singular`] (`"Phi_theta"`) when a diagonal entry of $\Phi_\theta$
    /// is zero (a leg stretched or folded).
    #[inline]
    pub fn joint_velocities(&self, v: &Vector3<f64>) -> Result<Vector6<f64>, ConfigurationError> {
        if self.legs.iter().any(|leg| leg.phi_theta == 0.0) {
            return Err(phi_theta_singular());
        }
        let thd = Vector3::from_fn(|i, _| {
            -(2.0 * kernel::dot(&self.legs[i].v, v)) / self.legs[i].phi_theta
        });
        Ok(Vector6::new(v.x, v.y, v.z, thd.x, thd.y, thd.z))
    }

    /// The acceleration-level inverse kinematics: see [`ExtendedModel::joint_accelerations`].
    ///
    /// # Errors
    /// As [`ExtendedModel::joint_accelerations`].
    #[inline]
    pub fn joint_accelerations(
        &self,
        qd: &Vector6<f64>,
        a: &Vector3<f64>,
    ) -> Result<Vector6<f64>, ConfigurationError> {
        let qdd = kernel::joint_accelerations(self.constants, &self.legs, qd, a);
        if qdd.iter().all(|v| v.is_finite()) {
            Ok(qdd)
        } else {
            Err(phi_theta_singular())
        }
    }

    pub(crate) fn legs(&self) -> &[Leg<f64>; 3] {
        &self.legs
    }

    pub(crate) fn model_constants(&self) -> &Constants {
        self.constants
    }
}

#[cfg(test)]
impl ExtendedModel {
    pub(crate) fn constants(&self) -> &Constants {
        &self.constants
    }
}

fn phi_theta_singular() -> ConfigurationError {
    ConfigurationError::Singular {
        matrix: "Phi_theta",
    }
}

#[inline]
fn checked_torques((tau, det): (Vector3<f64>, f64)) -> Result<Vector3<f64>, ConfigurationError> {
    if det == 0.0 {
        Err(ConfigurationError::Singular { matrix: "Phi_x^T" })
    } else if tau.iter().all(|v| v.is_finite()) {
        Ok(tau)
    } else {
        Err(ConfigurationError::NonFinite { what: "torque" })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pkm_mechanisms::{Placement, presets};

    #[test]
    fn acceleration_level_ik_agrees_with_joint_motion() {
        let model = ExtendedModel::new(
            RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
            &MassParameters::miller2004(),
        )
        .unwrap();
        let (p, v, a) = (
            Vector3::new(0.05, -0.1, -0.8),
            Vector3::new(0.3, -1.2, 2.0),
            Vector3::new(-40.0, 25.0, 180.0),
        );
        let s = model.joint_motion(&p, &v, &a).unwrap();
        let qdd = model.joint_accelerations(&s.q, &s.qd, &a).unwrap();
        assert!(
            (qdd - s.qdd).amax() < 1e-9 * s.qdd.amax(),
            "{qdd} vs {}",
            s.qdd
        );
    }
}
