//! Inverse kinematics of one leg (eqs. 1–2, with the sign of $b^2\sin^2\theta_3$ corrected,
//! erratum E1): four branches, two signs of $\theta_3$ times two roots of $\theta_1$, and
//! $\theta_2$ from the loop closure.

use super::Tsai3Dof;
use nalgebra::Vector3;
use pkm_traits::KinematicsError;
use std::f64::consts::{PI, TAU};

/// Which root of the half-angle quadratic (eq. 2) gives $\theta_1$.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Elbow {
    /// The root with the larger $\cos\theta_1$: the elbow $B_i$ lies radially outward.
    Out,
    /// The other root.
    In,
}

/// One of the four inverse-kinematic solutions of a leg.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LegBranch {
    /// `true` for the principal $\theta_3 = +\arccos(p_v / b)$ (MATLAB's `acos`), `false`
    /// for $\theta_3 = -\arccos(p_v / b)$.
    pub principal_theta3: bool,
    /// The root of eq. 2.
    pub elbow: Elbow,
}

impl LegBranch {
    /// Principal $\theta_3$, elbow out: the branch of the workspace and GCI studies.
    pub const PRINCIPAL_OUT: Self = Self {
        principal_theta3: true,
        elbow: Elbow::Out,
    };

    /// All four branches.
    pub const ALL: [Self; 4] = [
        Self::PRINCIPAL_OUT,
        Self {
            principal_theta3: true,
            elbow: Elbow::In,
        },
        Self {
            principal_theta3: false,
            elbow: Elbow::Out,
        },
        Self {
            principal_theta3: false,
            elbow: Elbow::In,
        },
    ];
}

/// `angle` $\in (-2\pi, 2\pi]$ (twice an `atan2`) as its principal value in $(-\pi, \pi]$, the
/// range of every other angle pkm reports, so that a joint range means the same on this model
/// as on the same robot from a file.
fn principal_angle(angle: f64) -> f64 {
    if angle > PI {
        angle - TAU
    } else if angle <= -PI {
        angle + TAU
    } else {
        angle
    }
}

/// Joint angles $(\theta_1, \theta_2, \theta_3)$ of one leg, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegAngles {
    /// Actuated angle of the lower arm, from $u_i$ towards $w_i$, in $(-\pi, \pi]$.
    pub theta1: f64,
    /// Absolute angle of the offsets' direction $n_i$, from $u_i$ towards $w_i$.
    pub theta2: f64,
    /// Angle from $v_i$ to $C_iD_i$.
    pub theta3: f64,
}

impl Tsai3Dof {
    /// Coordinates $(p_u, p_v, p_w)$ of $A_i \to E_i$ in the frame of leg `leg`:
    /// $p_u = p_x\cos\phi_i + p_y\sin\phi_i + c - r$, $p_v = -p_x\sin\phi_i + p_y\cos\phi_i$,
    /// $p_w = p_z$.
    pub(crate) fn leg_coordinates(&self, leg: usize, p: &Vector3<f64>) -> (f64, f64, f64) {
        let (c, s) = self.trig[leg];
        (p.x * c + p.y * s + self.h, -p.x * s + p.y * c, p.z)
    }

    /// Inverse kinematics of leg `leg` (0, 1 or 2) at platform position `p` in `branch`.
    ///
    /// # Errors
    /// [`KinematicsError::Unreachable`] when $|p_v| > b$ or the discriminant of eq. 2 is
    /// negative; [`KinematicsError::NonFinite`] for a non-finite `p`.
    pub fn leg_inverse_kinematics(
        &self,
        leg: usize,
        p: &Vector3<f64>,
        branch: LegBranch,
    ) -> Result<LegAngles, KinematicsError> {
        if let Some(value) = p.iter().copied().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "p", value });
        }
        let (pu, pv, pw) = self.leg_coordinates(leg % 3, p);
        let cos3 = pv / self.b;
        if cos3.abs() > 1.0 {
            return Err(KinematicsError::Unreachable {
                leg,
                discriminant: 1.0 - cos3.abs(),
            });
        }
        let theta3 = if branch.principal_theta3 {
            cos3.acos()
        } else {
            -cos3.acos()
        };
        let l = self.s + self.b * theta3.sin();
        let a = self.a;
        let l2 = (pu + a).powi(2) + pw * pw - l * l;
        let l1 = -4.0 * a * pw;
        let l0 = (pu - a).powi(2) + pw * pw - l * l;
        let disc = l1 * l1 - 4.0 * l0 * l2;
        // `!(disc >= 0)`: a NaN discriminant (∞ − ∞ when the squares of a far point overflow)
        // is unreachable too, never NaN angles.
        if !(disc >= 0.0) {
            return Err(KinematicsError::Unreachable {
                leg,
                discriminant: disc,
            });
        }
        let root = disc.sqrt();
        let t_plus = 2.0 * (-l1 + root).atan2(2.0 * l2);
        let t_minus = 2.0 * (-l1 - root).atan2(2.0 * l2);
        let (t_plus, t_minus) = (principal_angle(t_plus), principal_angle(t_minus));
        let (out, inward) = if t_minus.cos() >= t_plus.cos() {
            (t_minus, t_plus)
        } else {
            (t_plus, t_minus)
        };
        let theta1 = match branch.elbow {
            Elbow::Out => out,
            Elbow::In => inward,
        };
        let (sin2, cos2) = ((pw - a * theta1.sin()) / l, (pu - a * theta1.cos()) / l);
        let theta2 = if sin2.is_finite() && cos2.is_finite() {
            sin2.atan2(cos2)
        } else {
            // L = 0 (d + e = 0 and |p_v| = b): the offsets have no length, so the loop closes
            // for every θ₂; take the direction of the remaining vector, 0 when it vanishes too.
            (l.signum() * (pw - a * theta1.sin())).atan2(l.signum() * (pu - a * theta1.cos()))
        };
        Ok(LegAngles {
            theta1,
            theta2,
            theta3,
        })
    }

    /// The point $E_i - A_i$ in leg coordinates reached by the open chain with `angles`:
    /// $a(\cos\theta_1, 0, \sin\theta_1) + (d + e) n + b(\sin\theta_3\, n + \cos\theta_3\, v)$,
    /// $n = (\cos\theta_2, 0, \sin\theta_2)$. Equal to the leg's target coordinates when the
    /// loop closes.
    pub fn leg_chain_end(&self, angles: &LegAngles) -> Vector3<f64> {
        let l = self.s + self.b * angles.theta3.sin();
        Vector3::new(
            self.a * angles.theta1.cos() + l * angles.theta2.cos(),
            self.b * angles.theta3.cos(),
            self.a * angles.theta1.sin() + l * angles.theta2.sin(),
        )
    }

    /// Leg coordinates of `p` as a vector (see [`Self::leg_chain_end`]).
    pub fn leg_target(&self, leg: usize, p: &Vector3<f64>) -> Vector3<f64> {
        let (pu, pv, pw) = self.leg_coordinates(leg % 3, p);
        Vector3::new(pu, pv, pw)
    }
}
