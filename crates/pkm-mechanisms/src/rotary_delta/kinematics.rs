//! Loop closure, its Jacobians and the closed-form inverse kinematics of the rotary Delta.

use super::RotaryDelta;
use nalgebra::{Matrix3, Vector3};
use pkm_traits::{
    ClosedChain, ForwardKinematics, InverseKinematics, Joints, KinematicsError, Task,
};

/// Branch of the arm-angle solution, the same for every leg.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ElbowMode {
    /// $\theta = \psi - \arccos(K/\rho)$: the elbow points away from the centreline (canonical).
    Out,
    /// $\theta = \psi + \arccos(K/\rho)$.
    In,
}

impl ClosedChain<3, 3> for RotaryDelta {
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        let f2 = self.design.forearm * self.design.forearm;
        Vector3::from_fn(|i, _| self.forearm_vector(i, x, q[i]).norm_squared() - f2)
    }

    /// Row $i$: $2 v_i^\top$.
    fn jacobian_x(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        Matrix3::from_fn(|i, j| 2.0 * self.forearm_vector(i, x, q[i])[j])
    }

    /// Diagonal: $-2 L_a\, v_i \cdot d_i'(\theta_i)$.
    fn jacobian_q(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        Matrix3::from_diagonal(&Vector3::from_fn(|i, _| {
            let d1 = self.legs[i].arm_direction_derivative(q[i]);
            -2.0 * self.design.arm * self.forearm_vector(i, x, q[i]).dot(&d1)
        }))
    }
}

impl InverseKinematics<3, 3> for RotaryDelta {
    type WorkingMode = ElbowMode;

    /// With $D = C_i - A_i$, $K = (|D|^2 + L_a^2 - L_b^2)/(2L_a)$, $a = D\cdot u_i$,
    /// $b = -D\cdot w_i$: $\theta_i = \operatorname{atan2}(b, a) \mp \arccos(K/\sqrt{a^2+b^2})$.
    ///
    /// The reported angles are this expression, not wrapped: $\theta_i \in (-2\pi, \pi]$ with
    /// [`ElbowMode::Out`] and $(-\pi, 2\pi]$ with [`ElbowMode::In`] (the form the papers' kernels
    /// and Miller's figures use; the same angle modulo $2\pi$ as a robot file's, which wraps to
    /// $(-\pi, \pi]$). Joint ranges test them modulo a turn
    /// ([`WorkspaceConstraint::angle_range`](pkm_traits::WorkspaceConstraint::angle_range)).
    fn inverse_kinematics(
        &self,
        x: &Task<3>,
        mode: ElbowMode,
    ) -> Result<Joints<3>, KinematicsError> {
        if let Some(value) = x.iter().copied().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "x", value });
        }
        let mut theta = Vector3::zeros();
        for (i, leg) in self.legs.iter().enumerate() {
            let d = x + leg.plate_offset - leg.motor;
            let k = (d.norm_squared() + self.design.arm * self.design.arm
                - self.design.forearm * self.design.forearm)
                / (2.0 * self.design.arm);
            let (a, b) = (d.dot(&leg.u), -d.dot(&leg.w));
            let ratio = k / a.hypot(b);
            if !(ratio.abs() <= 1.0) {
                return Err(KinematicsError::Unreachable {
                    leg: i,
                    discriminant: 1.0 - ratio.abs(),
                });
            }
            let psi = b.atan2(a);
            theta[i] = match mode {
                ElbowMode::Out => psi - ratio.acos(),
                ElbowMode::In => psi + ratio.acos(),
            };
        }
        Ok(theta)
    }
}

impl ForwardKinematics<3> for RotaryDelta {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets;
    use crate::rotary_delta::Placement;
    use pkm_traits::testkit::{
        check_closure, check_ik_fk_round_trip, check_jacobians_against_central_differences,
        check_traits,
    };

    /// The documented intervals of the reported angles hold over a grid of the reach
    /// cylinder (NUWAR's out-mode angles reach below −π: they are not wrapped).
    #[test]
    fn reported_angles_lie_in_the_documented_intervals() {
        use std::f64::consts::PI;
        for delta in designs() {
            let (radius, half_height) = delta.reach_cylinder();
            let z0 = delta.motor_plane_z();
            let mut solved = 0;
            for i in 0..21 {
                for j in 0..21 {
                    for k in 0..21 {
                        let t = |n: i32| f64::from(n) / 10.0 - 1.0;
                        let p = Vector3::new(radius * t(i), radius * t(j), z0 + half_height * t(k));
                        for (mode, lo, hi) in [
                            (ElbowMode::Out, -2.0 * PI, PI),
                            (ElbowMode::In, -PI, 2.0 * PI),
                        ] {
                            if let Ok(q) = delta.inverse_kinematics(&p, mode) {
                                solved += 1;
                                assert!(q.iter().all(|a| *a > lo && *a <= hi), "{mode:?} {q:?}");
                            }
                        }
                    }
                }
            }
            assert!(solved > 1000, "vacuous: {solved}");
        }
    }

    fn poses() -> Vec<Vector3<f64>> {
        let mut out = Vec::new();
        for x in [-0.1, 0.0, 0.1] {
            for y in [-0.2, 0.0, 0.15] {
                for z in [-0.85, -0.7, -0.55] {
                    out.push(Vector3::new(x, y, z));
                }
            }
        }
        out
    }

    fn designs() -> [RotaryDelta; 2] {
        let p = Placement::canonical();
        [
            RotaryDelta::new(presets::nuwar(p)).unwrap(),
            RotaryDelta::new(presets::miller_delta(p)).unwrap(),
        ]
    }

    #[test]
    fn conformance() {
        check_traits::<RotaryDelta>();
        for m in designs() {
            let ps = poses();
            check_closure(&m, ElbowMode::Out, &ps, 1e-12).unwrap();
            check_jacobians_against_central_differences(&m, ElbowMode::Out, &ps, 1e-6, 1e-6)
                .unwrap();
            check_ik_fk_round_trip(&m, ElbowMode::Out, &ps, 1e-3, 1e-9).unwrap();
        }
    }

    #[test]
    fn nuwar_axes_are_nearly_orthogonal_and_delta_axes_at_120_degrees() {
        let [nuwar, delta] = designs();
        let e = |m: &RotaryDelta, i: usize, j: usize| m.legs()[i].e.dot(&m.legs()[j].e);
        assert!(e(&nuwar, 0, 1).abs() < 2e-4, "{}", e(&nuwar, 0, 1));
        assert!((e(&delta, 1, 2) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn unreachable_pose_names_the_leg() {
        let [nuwar, _] = designs();
        let err = nuwar.inverse_kinematics(&Vector3::new(0.0, 0.0, -2.0), ElbowMode::Out);
        assert!(matches!(err, Err(KinematicsError::Unreachable { .. })));
    }
}
