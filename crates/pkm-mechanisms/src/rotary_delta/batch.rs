//! The design-index kernel of the rotary Delta on `N` points at once: inverse kinematics and
//! $J = -J_q^{-1}J_x$ without trigonometric functions, in [`Lanes`] so that the compiler
//! vectorises it (no calls, no branches; an unreachable lane is a mask bit).
//!
//! Per leg, with $D = C_i - A_i$, $a = D\cdot u_i$, $b = -D\cdot w_i$, $\rho^2 = a^2 + b^2$ and
//! $K = (|D|^2 + L_a^2 - L_b^2)/(2L_a)$ (see [`RotaryDelta`]'s inverse kinematics), the arm angle
//! is $\theta = \psi \mp \gamma$ with $(\cos\psi, \sin\psi) = (a, b)/\rho$ and
//! $(\cos\gamma, \sin\gamma) = (K, S)/\rho$, $S = \sqrt{\rho^2 - K^2}$. Expanding the
//! difference of angles,
//! $$ \cos\theta = \frac{aK \pm bS}{\rho^2}, \qquad \sin\theta = \frac{bK \mp aS}{\rho^2} $$
//! (upper sign: [`ElbowMode::Out`]). The forearm is $v_i = D - L_a(\cos\theta\,u_i -
//! \sin\theta\,w_i)$, and since $d_i \cdot d_i' = 0$,
//! $v_i\cdot d_i' = D\cdot d_i' = b\cos\theta - a\sin\theta = \pm S$. So row $i$ of
//! $J = -J_q^{-1}J_x$ (with $J_x$ row $2v_i^\top$, $J_q$ diagonal $-2L_a v_i\cdot d_i'$) is
//! $$ J_i = \frac{v_i^\top}{\pm L_a S}. $$
//! A leg is reachable when $S^2 = \rho^2 - K^2 > 0$ (the scalar test $|K/\rho| \le 1$ without
//! its boundary, where $J_q$ is singular); a non-finite point fails that test in every leg.
//!
//! The kernel writes each row of $J$ in place (no lane row is copied) and is `#[inline(always)]`,
//! so that a caller compiled for a wider vector unit (`pkm_workspace_indices::evaluate`, which
//! picks AVX2 at run time where the processor has it) compiles the whole kernel for that unit;
//! it uses no fused multiply-add, so every unit gives the same bits.

use super::{ElbowMode, Leg, RotaryDelta};
use crate::JacobianLanes;
use nalgebra::Vector3;
use pkm_traits::Lanes;

impl RotaryDelta {
    /// $J = -J_q^{-1}J_x$ at each of the `N` points in `mode`, computed lane-parallel without
    /// trigonometric functions (module documentation). Equal to
    /// [`pkm_traits::InverseKinematics::inverse_kinematics`] followed by
    /// [`pkm_traits::ClosedChain::jacobian`] per point, to rounding; a lane is unreachable
    /// exactly where that pair fails, except within rounding of the workspace boundary. Lanes
    /// are independent: a non-finite or huge point is an unreachable lane and leaves the
    /// others untouched.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
    /// use pkm_traits::{ClosedChain, InverseKinematics};
    /// let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    /// let p = Vector3::new(0.05, -0.02, -0.7);
    /// let lanes = delta.jacobian_lanes(&[p, Vector3::new(f64::NAN, 0.0, 0.0)], ElbowMode::Out);
    /// let q = delta.inverse_kinematics(&p, ElbowMode::Out).unwrap();
    /// let scalar = delta.jacobian(&p, &q).unwrap();
    /// assert!((lanes.matrix(0).unwrap() - scalar).norm() < 1e-12 * scalar.norm());
    /// assert_eq!(lanes.reachable, [true, false]);
    /// ```
    #[inline(always)]
    pub fn jacobian_lanes<const N: usize>(
        &self,
        points: &[Vector3<f64>; N],
        mode: ElbowMode,
    ) -> JacobianLanes<N> {
        let sign = match mode {
            ElbowMode::Out => 1.0,
            ElbowMode::In => -1.0,
        };
        let p = Lanes::coordinates(points);
        let mut out = JacobianLanes {
            jacobian: [[0.0; N]; 9],
            reachable: [true; N],
        };
        for (i, leg) in self.legs.iter().enumerate() {
            self.write_jacobian_row(leg, &p, sign, i, &mut out);
        }
        out
    }

    /// Writes row `i` of $J$ for `leg` at the points `p` (coordinates in lanes) into `out`
    /// and clears the reachability of the lanes that leg does not reach (module
    /// documentation); `sign` is $+1$ for [`ElbowMode::Out`], $-1$ for [`ElbowMode::In`].
    /// In place and without array maps, so that no lane row is copied.
    #[inline(always)]
    fn write_jacobian_row<const N: usize>(
        &self,
        leg: &Leg,
        p: &[Lanes<N>; 3],
        sign: f64,
        i: usize,
        out: &mut JacobianLanes<N>,
    ) {
        let (la, lb) = (self.design.arm, self.design.forearm);
        let offset = leg.plate_offset - leg.motor;
        let d = [p[0] + offset.x, p[1] + offset.y, p[2] + offset.z];
        let dot = |v: &Vector3<f64>| d[0] * v.x + d[1] * v.y + d[2] * v.z;
        let (a, b) = (dot(&leg.u), -dot(&leg.w));
        let rho2 = a * a + b * b;
        let k = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + (la * la - lb * lb)) * (0.5 / la);
        let s2 = rho2 - k * k;
        let s = s2.max(0.0).sqrt() * sign;
        let inv_rho2 = rho2.recip();
        let (cos_t, sin_t) = ((a * k + b * s) * inv_rho2, (b * k - a * s) * inv_rho2);
        let inv = (la * s).recip();
        for (c, entry) in out.jacobian[3 * i..3 * i + 3].iter_mut().enumerate() {
            *entry = ((d[c] - (cos_t * leg.u[c] - sin_t * leg.w[c]) * la) * inv).0;
        }
        for (all, s2) in out.reachable.iter_mut().zip(s2.0) {
            *all &= s2 > 0.0;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;
    use crate::presets;
    use crate::rotary_delta::Placement;
    use nalgebra::Matrix3;
    use pkm_traits::{ClosedChain, InverseKinematics};
    use proptest::prelude::*;

    fn designs() -> [RotaryDelta; 2] {
        let p = Placement::canonical();
        [
            RotaryDelta::new(presets::miller_delta(p)).unwrap(),
            RotaryDelta::new(presets::nuwar(p)).unwrap(),
        ]
    }

    /// The scalar reference: IK, then $J = -J_q^{-1}J_x$; `None` where either fails.
    fn scalar(m: &RotaryDelta, p: &Vector3<f64>, mode: ElbowMode) -> Option<Matrix3<f64>> {
        let q = m.inverse_kinematics(p, mode).ok()?;
        m.jacobian(p, &q).ok()
    }

    /// $1 - |K/\rho|$ of the leg nearest its boundary: how far `p` is from unreachability.
    fn margin(m: &RotaryDelta, p: &Vector3<f64>) -> f64 {
        m.legs()
            .iter()
            .map(|l| {
                let d = p + l.plate_offset - l.motor;
                let k =
                    (d.norm_squared() + m.arm().powi(2) - m.forearm().powi(2)) / (2.0 * m.arm());
                1.0 - (k / d.dot(&l.u).hypot(d.dot(&l.w))).abs()
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn check_lanes(points: &[Vector3<f64>; 4]) -> Result<(), TestCaseError> {
        for m in designs() {
            for mode in [ElbowMode::Out, ElbowMode::In] {
                let lanes = m.jacobian_lanes(points, mode);
                for (lane, p) in points.iter().enumerate() {
                    let want = scalar(&m, p, mode);
                    let got = lanes.matrix(lane);
                    let boundary = !(margin(&m, p).abs() > 1e-12);
                    match (got, want) {
                        (Some(g), Some(w)) => {
                            // Relative to the row norms: J_q is ill conditioned near the boundary.
                            let m = margin(&m, p);
                            let tol = 1e-13 / m.max(1e-300) + 1e-13;
                            for i in 0..3 {
                                let (gr, wr) = (g.row(i), w.row(i));
                                prop_assert!(
                                    (gr - wr).norm() <= tol * wr.norm(),
                                    "{p} lane {lane}: {g} vs {w}"
                                );
                            }
                        }
                        (None, None) => {}
                        _ => prop_assert!(boundary, "{p}: batch {got:?} scalar {want:?}"),
                    }
                }
            }
        }
        Ok(())
    }

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            20 => -0.4..0.4_f64,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(f64::NEG_INFINITY),
            1 => Just(1e300),
            1 => Just(-1e160),
            1 => Just(0.0),
        ]
    }

    fn height() -> impl Strategy<Value = f64> {
        prop_oneof![
            20 => -1.1..-0.3_f64,
            1 => Just(f64::NAN),
            1 => Just(-1e200),
            1 => Just(f64::MAX),
        ]
    }

    fn point() -> impl Strategy<Value = Vector3<f64>> {
        (coordinate(), coordinate(), height()).prop_map(|(x, y, z)| Vector3::new(x, y, z))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        #[test]
        fn each_lane_equals_the_scalar_kernel(points in [point(), point(), point(), point()]) {
            check_lanes(&points)?;
        }
    }

    #[test]
    fn interior_workspace_is_mostly_reachable_and_matches() {
        // A deterministic grid: the agreement is not vacuous (most lanes are reachable).
        let mut reachable = 0;
        let mut total = 0;
        for ix in -4..=4 {
            for iy in -4..=4 {
                let pts: [Vector3<f64>; 4] = std::array::from_fn(|k| {
                    Vector3::new(0.05 * ix as f64, 0.05 * iy as f64, -0.5 - 0.1 * k as f64)
                });
                check_lanes(&pts).unwrap();
                let lanes = designs()[0].jacobian_lanes(&pts, ElbowMode::Out);
                reachable += lanes.reachable.iter().filter(|r| **r).count();
                total += 4;
            }
        }
        assert!(reachable * 2 > total, "{reachable}/{total}");
    }

    #[test]
    fn lane_count_does_not_change_the_values() {
        let m = &designs()[1];
        let pts: [Vector3<f64>; 8] =
            std::array::from_fn(|k| Vector3::new(0.01 * k as f64, -0.03, -0.6 - 0.02 * k as f64));
        let wide = m.jacobian_lanes(&pts, ElbowMode::Out);
        for (k, p) in pts.iter().enumerate() {
            let one = m.jacobian_lanes(&[*p], ElbowMode::Out);
            assert_eq!(one.matrix(0), wide.matrix(k));
        }
    }
}
