//! Loop closure, the velocity Jacobian in closed form (eq. 7) and the allocation-free kernel of
//! the workspace studies.
//!
//! With $\theta_2, \theta_3$ eliminated (principal $\theta_3$), leg $i$ closes when
//! $$ \Phi_i = (p_u - a\cos\theta_1)^2 + (p_w - a\sin\theta_1)^2
//!            - \big(d + e + \sqrt{b^2 - p_v^2}\big)^2 = 0, $$
//! and $J = -J_q^{-1}J_x$ reproduces eq. 7 (with $\theta_{0i}$ read as $\phi_i$, erratum E2):
//! $$ J_{i1} = \frac{\cos\theta_3\sin\phi_i - \cos\theta_2\cos\phi_i\sin\theta_3}
//!                  {a\sin\theta_3\sin(\theta_1-\theta_2)},\;
//!    J_{i2} = \frac{-\cos\theta_3\cos\phi_i - \cos\theta_2\sin\phi_i\sin\theta_3}
//!                  {a\sin\theta_3\sin(\theta_1-\theta_2)},\;
//!    J_{i3} = \frac{-\sin\theta_2}{a\sin(\theta_1-\theta_2)}. $$

use super::{Elbow, LegBranch, Tsai3Dof};
use nalgebra::{Matrix3, Vector3};
use pkm_traits::{
    ClosedChain, ForwardKinematics, InverseKinematics, Joints, KinematicsError, Task,
};

impl ClosedChain<3, 3> for Tsai3Dof {
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        Vector3::from_fn(|i, _| {
            let (pu, pv, pw) = self.leg_coordinates(i, x);
            let l = self.s + (self.b * self.b - pv * pv).max(0.0).sqrt();
            (pu - self.a * q[i].cos()).powi(2) + (pw - self.a * q[i].sin()).powi(2) - l * l
        })
    }

    fn jacobian_x(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        let mut j = Matrix3::zeros();
        for i in 0..3 {
            let (pu, pv, pw) = self.leg_coordinates(i, x);
            let root = (self.b * self.b - pv * pv).max(0.0).sqrt();
            let l = self.s + root;
            let du = 2.0 * (pu - self.a * q[i].cos());
            let dv = 2.0 * l * pv / root;
            let dw = 2.0 * (pw - self.a * q[i].sin());
            let (c, s) = self.trig[i];
            j[(i, 0)] = du * c - dv * s;
            j[(i, 1)] = du * s + dv * c;
            j[(i, 2)] = dw;
        }
        j
    }

    fn jacobian_q(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        Matrix3::from_fn(|i, k| {
            if i != k {
                return 0.0;
            }
            let (pu, _, pw) = self.leg_coordinates(i, x);
            let (c1, s1) = (q[i].cos(), q[i].sin());
            2.0 * self.a * ((pu - self.a * c1) * s1 - (pw - self.a * s1) * c1)
        })
    }
}

impl InverseKinematics<3, 3> for Tsai3Dof {
    /// The $\theta_1$ root of each leg; $\theta_3$ is principal (the closure's branch).
    type WorkingMode = [Elbow; 3];

    fn inverse_kinematics(
        &self,
        x: &Task<3>,
        mode: [Elbow; 3],
    ) -> Result<Joints<3>, KinematicsError> {
        let mut q = Vector3::zeros();
        for (i, elbow) in mode.into_iter().enumerate() {
            let branch = LegBranch {
                principal_theta3: true,
                elbow,
            };
            q[i] = self.leg_inverse_kinematics(i, x, branch)?.theta1;
        }
        Ok(q)
    }

    /// Eq. 7 in closed form, without trigonometric functions, on the elbow-out branch of every
    /// leg (`[Elbow::Out; 3]`, the branch of the workspace and GCI studies); the default
    /// (IK, then $-J_q^{-1}J_x$) for any other mode.
    fn velocity_jacobian_at(
        &self,
        x: &Task<3>,
        mode: [Elbow; 3],
    ) -> Result<Matrix3<f64>, KinematicsError> {
        if mode == [Elbow::Out; 3] {
            self.velocity_jacobian_elbow_out(x)
        } else {
            let q = self.inverse_kinematics(x, mode)?;
            self.jacobian(x, &q)
        }
    }
}

impl ForwardKinematics<3> for Tsai3Dof {}

impl Tsai3Dof {
    /// Eq. 7 at `p` on the principal, elbow-out branch of every leg, computed without
    /// trigonometric functions: $\theta_1 = \alpha - \operatorname{sgn}(p_w)\beta$ with
    /// $\alpha = \operatorname{atan2}(p_w, p_u)$, $\cos\beta = (\rho^2 + a^2 - L^2)/(2a\rho)$.
    /// Reached through [`InverseKinematics::velocity_jacobian_at`] with `[Elbow::Out; 3]`.
    ///
    /// # Errors
    /// [`KinematicsError::NonFinite`] for a non-finite `p`; [`KinematicsError::Unreachable`]
    /// when `p` lies outside the workspace (some leg has $|p_v| > b$ or $|\cos\beta| > 1$);
    /// [`KinematicsError::Singular`] where eq. 7 is not finite ($\sin\theta_3 = 0$,
    /// $\sin(\theta_1 - \theta_2) = 0$, $\rho = 0$ or $L = 0$).
    fn velocity_jacobian_elbow_out(
        &self,
        p: &Vector3<f64>,
    ) -> Result<Matrix3<f64>, KinematicsError> {
        if let Some(value) = p.iter().copied().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "p", value });
        }
        let mut j = Matrix3::zeros();
        for i in 0..3 {
            let (pu, pv, pw) = self.leg_coordinates(i, p);
            let c3 = pv / self.b;
            let s3_sq = 1.0 - c3 * c3;
            if !(s3_sq >= 0.0) {
                return Err(KinematicsError::Unreachable {
                    leg: i,
                    discriminant: s3_sq,
                });
            }
            let s3 = s3_sq.sqrt();
            let l = self.s + self.b * s3;
            let rho = pu.hypot(pw);
            let k = (rho * rho + self.a * self.a - l * l) / (2.0 * self.a * rho);
            if !(k.abs() <= 1.0) {
                return Err(KinematicsError::Unreachable {
                    leg: i,
                    discriminant: 1.0 - k.abs(),
                });
            }
            let sb = (1.0 - k * k).sqrt();
            let (ca, sa) = (pu / rho, pw / rho);
            let c1 = ca * k + sa.abs() * sb;
            let s1 = sa * k - sa.signum() * ca * sb;
            let c2 = (pu - self.a * c1) / l;
            let s2 = (pw - self.a * s1) / l;
            let sin12 = s1 * c2 - c1 * s2;
            let den = self.a * s3 * sin12;
            let (cp, sp) = self.trig[i];
            j[(i, 0)] = (c3 * sp - c2 * cp * s3) / den;
            j[(i, 1)] = (-c3 * cp - c2 * sp * s3) / den;
            j[(i, 2)] = -s2 / (self.a * sin12);
        }
        if j.iter().all(|v| v.is_finite()) {
            Ok(j)
        } else {
            Err(KinematicsError::Singular {
                matrix: "J_q",
                sigma_min: 0.0,
            })
        }
    }

    /// Whether `p` is in the workspace: every leg has real $\theta_3$ (principal) and $\theta_1$
    /// (sec. 4, step 3).
    pub fn contains(&self, p: &Vector3<f64>) -> bool {
        (0..3).all(|i| {
            let (pu, pv, pw) = self.leg_coordinates(i, p);
            let s3_sq = self.b * self.b - pv * pv;
            if !(s3_sq >= 0.0) {
                return false;
            }
            let l = self.s + s3_sq.sqrt();
            let rho = pu.hypot(pw);
            (rho - self.a).abs() <= l.abs() && l.abs() <= rho + self.a
        })
    }
}
