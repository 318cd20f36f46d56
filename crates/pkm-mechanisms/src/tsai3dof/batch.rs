//! The closed-form elbow-out velocity Jacobian of
//! [`pkm_traits::InverseKinematics::velocity_jacobian_at`] (eq. 7) on `N` points at once, in [`Lanes`] so that the compiler
//! vectorises it: the same trigonometry-free formulas, with every early return replaced by a
//! mask bit and $\rho = \sqrt{p_u^2 + p_w^2}$ instead of `hypot` (a library call, which would
//! not vectorise). Lanes are independent: NaN or infinity in one lane stays in that lane.
//!
//! The kernel writes each row of $J$ in place (no lane row is copied) and is `#[inline(always)]`,
//! so that a caller compiled for a wider vector unit (`pkm_workspace_indices::evaluate`, which
//! picks AVX2 at run time where the processor has it) compiles the whole kernel for that unit;
//! it uses no fused multiply-add, so every unit gives the same bits.

use super::Tsai3Dof;
use crate::JacobianLanes;
use nalgebra::Vector3;
use pkm_traits::Lanes;

impl Tsai3Dof {
    /// Eq. 7 at each of the `N` points on the principal, elbow-out branch, lane-parallel: the
    /// formulas of `velocity_jacobian_at(p, [Elbow::Out; 3])` (see
    /// [`pkm_traits::InverseKinematics::velocity_jacobian_at`]). A lane is reachable exactly
    /// where that scalar kernel does not report the point unreachable (up to rounding at the
    /// workspace boundary), with the same matrix to rounding; where the scalar kernel reports
    /// a singular Jacobian ($\sin\theta_3 = 0$ or $\sin(\theta_1 - \theta_2) = 0$) the lane is
    /// reachable and holds infinite entries.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
    /// use pkm_traits::InverseKinematics;
    /// let design = Tsai3Dof::new(presets::stamper_max_gci()).unwrap();
    /// let p = Vector3::new(0.1, -0.2, 0.5);
    /// let lanes = design.velocity_jacobian_elbow_out_lanes(&[p, Vector3::new(0.0, 0.0, 5.0)]);
    /// let scalar = design.velocity_jacobian_at(&p, [Elbow::Out; 3]).unwrap();
    /// assert!((lanes.matrix(0).unwrap() - scalar).norm() < 1e-13 * scalar.norm());
    /// assert_eq!(lanes.reachable, [true, false]);
    /// ```
    #[inline(always)]
    pub fn velocity_jacobian_elbow_out_lanes<const N: usize>(
        &self,
        points: &[Vector3<f64>; N],
    ) -> JacobianLanes<N> {
        let p = Lanes::coordinates(points);
        let mut out = JacobianLanes {
            jacobian: [[0.0; N]; 9],
            reachable: [true; N],
        };
        for leg in 0..3 {
            self.write_elbow_out_row(leg, &p, &mut out);
        }
        out
    }

    /// Writes row `leg` of eq. 7 at the points `p` (coordinates in lanes) into `out` and clears
    /// the reachability of the lanes that leg does not reach: the scalar elbow-out kernel's
    /// formulas with divisions by $b$, $\rho$, $2a$ and $L$ turned into products with
    /// reciprocals computed once (a lane division is slow). In place, so that no lane row is
    /// copied.
    #[inline(always)]
    fn write_elbow_out_row<const N: usize>(
        &self,
        leg: usize,
        p: &[Lanes<N>; 3],
        out: &mut JacobianLanes<N>,
    ) {
        let (cp, sp) = self.trig[leg];
        let a = self.a;
        let (pu, pv, pw) = (p[0] * cp + p[1] * sp + self.h, p[1] * cp - p[0] * sp, p[2]);
        let c3 = pv * self.b.recip();
        let s3_sq = 1.0 - c3 * c3;
        let s3 = s3_sq.max(0.0).sqrt();
        let l = self.s + self.b * s3;
        let rho2 = pu * pu + pw * pw;
        let inv_rho = rho2.sqrt().recip();
        let k = (rho2 + a * a - l * l) * inv_rho * (0.5 / a);
        let sb = (1.0 - k * k).max(0.0).sqrt();
        let (ca, sa) = (pu * inv_rho, pw * inv_rho);
        let c1 = ca * k + sa.abs() * sb;
        let s1 = sa * k - sa.signum() * ca * sb;
        let inv_l = l.recip();
        let c2 = (pu - a * c1) * inv_l;
        let s2 = (pw - a * s1) * inv_l;
        let a_sin12 = a * (s1 * c2 - c1 * s2);
        let inv_den = (a_sin12 * s3).recip();
        let row = &mut out.jacobian[3 * leg..3 * leg + 3];
        row[0] = ((c3 * sp - c2 * cp * s3) * inv_den).0;
        row[1] = ((-(c3 * cp) - c2 * sp * s3) * inv_den).0;
        row[2] = (-s2 / a_sin12).0;
        for (l, all) in out.reachable.iter_mut().enumerate() {
            *all &= s3_sq.0[l] >= 0.0 && k.0[l].abs() <= 1.0;
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;
    use crate::{Elbow, TsaiDesign, presets};
    use nalgebra::Matrix3;
    use pkm_traits::{InverseKinematics, KinematicsError};
    use proptest::prelude::*;

    /// The scalar kernel as reachability and matrix: `Some(None)` where `p` is reachable but
    /// eq. 7 is not finite there.
    fn scalar(m: &Tsai3Dof, p: &Vector3<f64>) -> Option<Option<Matrix3<f64>>> {
        match m.velocity_jacobian_at(p, [Elbow::Out; 3]) {
            Ok(j) => Some(Some(j)),
            Err(KinematicsError::Singular { .. }) => Some(None),
            Err(_) => None,
        }
    }

    fn designs() -> [Tsai3Dof; 2] {
        [
            Tsai3Dof::new(presets::stamper_max_gci()).unwrap(),
            Tsai3Dof::new(TsaiDesign::from_deg(0.3, 0.5, 0.1, -0.05, 100.0, 230.0)).unwrap(),
        ]
    }

    /// How far `p` is from the boundary of the workspace: the smallest of $1 - |c_3|$ and
    /// $1 - |k|$ over the legs (as computed by the scalar formulas).
    fn margin(m: &Tsai3Dof, p: &Vector3<f64>) -> f64 {
        (0..3)
            .map(|i| {
                let (pu, pv, pw) = m.leg_coordinates(i, p);
                let c3 = pv / m.b;
                let l = m.s + m.b * (1.0 - c3 * c3).max(0.0).sqrt();
                let rho = pu.hypot(pw);
                let k = (rho * rho + m.a * m.a - l * l) / (2.0 * m.a * rho);
                (1.0 - c3.abs()).min(1.0 - k.abs())
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn check_lanes(points: &[Vector3<f64>; 4]) -> Result<(), TestCaseError> {
        for m in designs() {
            let lanes = m.velocity_jacobian_elbow_out_lanes(points);
            for (lane, p) in points.iter().enumerate() {
                let want = scalar(&m, p);
                let got = lanes.matrix(lane);
                let margin = margin(&m, p);
                match (got, want) {
                    (Some(g), Some(Some(w))) => {
                        // sqrt(1 - k²) and sqrt(1 - c3²) amplify rounding near the boundary.
                        let tol = 1e-14 / margin.max(1e-300) + 1e-13;
                        for i in 0..3 {
                            let (gr, wr) = (g.row(i), w.row(i));
                            prop_assert!(
                                (gr - wr).norm() <= tol * wr.norm(),
                                "{p} lane {lane}: {g} vs {w}"
                            );
                        }
                    }
                    (Some(_), Some(None)) | (None, None) => {}
                    _ => prop_assert!(
                        !(margin.abs() > 1e-12),
                        "{p}: batch {got:?} scalar {want:?}"
                    ),
                }
            }
        }
        Ok(())
    }

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            20 => -1.0..1.0_f64,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(-1e300),
            1 => Just(1e160),
            1 => Just(0.0),
        ]
    }

    fn point() -> impl Strategy<Value = Vector3<f64>> {
        (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| Vector3::new(x, y, z))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        #[test]
        fn each_lane_equals_the_scalar_kernel(points in [point(), point(), point(), point()]) {
            check_lanes(&points)?;
        }
    }

    #[test]
    fn a_grid_is_mostly_reachable_and_matches() {
        let mut reachable = 0;
        let mut total = 0;
        for ix in -5..=5 {
            for iy in -5..=5 {
                let pts: [Vector3<f64>; 4] = std::array::from_fn(|k| {
                    Vector3::new(0.1 * ix as f64, 0.1 * iy as f64, 0.1 + 0.2 * k as f64)
                });
                check_lanes(&pts).unwrap();
                let lanes = designs()[0].velocity_jacobian_elbow_out_lanes(&pts);
                reachable += lanes.reachable.iter().filter(|r| **r).count();
                total += 4;
            }
        }
        assert!(reachable * 3 > total, "{reachable}/{total}");
    }
}
