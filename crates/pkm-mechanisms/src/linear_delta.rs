//! The Linear Delta (Miller 2004, §2.2; Stock & Miller 2003): three carriages on parallel rails
//! along $x$, each carrying a parallelogram arm to a translating end effector.
//!
//! Geometry (reconstructed, `docs/conventions.md#linear-delta-geometry`), in the $y$–$z$ plane:
//! rails at $A_1 = (-Y_R, 0)$, $A_2 = (Y_R, 0)$ (arms of length $L_1$) and
//! $A_3 = (Y_A, Z_R)$ (arm of length $L_2$). Carriage $i$ sits at $x = q_i$. Leg $i$ closes
//!
//! $$ \Phi_i(x, q) = (x - q_i)^2 + (y - A_{iy})^2 + (z - A_{iz})^2 - L_i^2 = 0. $$

use crate::JacobianLanes;
use nalgebra::{Matrix3, Vector3};
use pkm_traits::{
    ClosedChain, DesignError, ForwardKinematics, InverseKinematics, Joints, KinematicsError, Lanes,
    Task,
};
use serde::{Deserialize, Serialize};

/// The four dimensionless design variables of Table 1 (Miller 2004).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearDeltaRatios {
    /// $L_1/Y_R$: outer arm length over actuator separation; at least 1.
    pub l1_over_yr: f64,
    /// $Y_A/Y_R$: horizontal eccentricity of the centre rail; $|Y_A/Y_R| < 1$.
    pub ya_over_yr: f64,
    /// $Z_R/Y_R$: vertical eccentricity of the centre rail.
    pub zr_over_yr: f64,
    /// $L_2/L_1$: centre arm length over outer arm length; positive.
    pub l2_over_l1: f64,
}

impl LinearDeltaRatios {
    /// The ratios from a design vector `[L1/YR, YA/YR, ZR/YR, L2/L1]` (the order of Table 2).
    pub fn from_slice(p: &[f64; 4]) -> Self {
        Self {
            l1_over_yr: p[0],
            ya_over_yr: p[1],
            zr_over_yr: p[2],
            l2_over_l1: p[3],
        }
    }
}

/// The design of a Linear Delta: the dimensionless ratios of Table 1 and the length scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearDeltaDesign {
    /// The shape, as ratios to $Y_R$ (Table 1).
    pub ratios: LinearDeltaRatios,
    /// The actuator separation $Y_R$ (m), the length unit of the ratios; positive.
    pub yr: f64,
}

/// Which way each arm leans along the rails: arm $i$ has $x - q_i = s_i u_i$ with $u_i \ge 0$.
///
/// The paper's design has the outer carriages trailing the end effector and the centre carriage
/// leading it, $s = (+1, +1, -1)$ ([`LinearDeltaMode::PAPER`]); Table 2 row 2 rules out the
/// other readings (`docs/conventions.md#linear-delta-geometry`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct LinearDeltaMode {
    /// $s_i$, `true` for $+1$.
    pub leans_positive: [bool; 3],
}

impl LinearDeltaMode {
    /// Outer arms $+1$, centre arm $-1$: the reading that reproduces Table 2.
    pub const PAPER: Self = Self {
        leans_positive: [true, true, false],
    };

    #[inline(always)]
    fn sign(&self, leg: usize) -> f64 {
        if self.leans_positive[leg] { 1.0 } else { -1.0 }
    }
}

/// A validated Linear Delta.
///
/// # Example
/// ```
/// use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
/// use pkm_traits::InverseKinematics;
/// let ratios = LinearDeltaRatios { l1_over_yr: 2.0, ya_over_yr: 0.0, zr_over_yr: 0.0, l2_over_l1: 0.63 };
/// let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
/// let q = delta.inverse_kinematics(&[0.0, 0.0, -1.0].into(), LinearDeltaMode::PAPER).unwrap();
/// assert!((q[0] + 2.0_f64.sqrt()).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearDelta {
    design: LinearDeltaDesign,
    rails: [[f64; 2]; 3],
    lengths: [f64; 3],
}

impl LinearDelta {
    /// Builds the mechanism of `design` (the ratios of Table 1 and the scale $Y_R$).
    ///
    /// # Errors
    /// [`DesignError`] for a non-finite value, $Y_R \le 0$, $L_1/Y_R < 1$ (the outer discs do not
    /// meet: the workspace is empty), $|Y_A/Y_R| \ge 1$ or $L_2/L_1 \le 0$, or when the fourth
    /// power of its largest length or of $Y_R$ is not a normal number (a design so large or so
    /// small that its cross-section overflows or underflows: about $10^{\pm 77}$).
    pub fn new(design: LinearDeltaDesign) -> Result<Self, DesignError> {
        let LinearDeltaDesign { ratios, yr } = design;
        let yr = DesignError::require_positive("YR", yr)?;
        let l1 = DesignError::require_finite("L1/YR", ratios.l1_over_yr)?;
        if l1 < 1.0 {
            return Err(DesignError {
                parameter: "L1/YR",
                value: l1,
                requirement: "must be >= 1, or the outer arms' discs do not meet (empty workspace)",
            });
        }
        let ya = DesignError::require_finite("YA/YR", ratios.ya_over_yr)?;
        if ya.abs() >= 1.0 {
            return Err(DesignError {
                parameter: "YA/YR",
                value: ya,
                requirement: "must satisfy |YA/YR| < 1 (centre rail between the outer rails)",
            });
        }
        let zr = DesignError::require_finite("ZR/YR", ratios.zr_over_yr)?;
        let l2 = DesignError::require_positive("L2/L1", ratios.l2_over_l1)?;
        // The cross-section squares the arms and the rail coordinates, and its area is a
        // product of two of them.
        let scale = [l1, l2 * l1, ya.abs(), zr.abs(), 1.0]
            .into_iter()
            .fold(0.0, f64::max)
            * yr;
        // Its corners solve quadratics in these squares: their squares must not overflow or
        // underflow either.
        DesignError::require_derived_normal("(largest length)^4", (4.0 * scale * scale).powi(2))?;
        DesignError::require_derived_normal("YR^4", (yr * yr).powi(2))?;
        Ok(Self {
            design,
            rails: [[-yr, 0.0], [yr, 0.0], [ya * yr, zr * yr]],
            lengths: [l1 * yr, l1 * yr, l2 * l1 * yr],
        })
    }

    /// The design the mechanism was built from.
    pub fn design(&self) -> LinearDeltaDesign {
        self.design
    }

    /// The design ratios.
    pub fn ratios(&self) -> LinearDeltaRatios {
        self.design.ratios
    }

    /// The actuator separation $Y_R$ (the length unit).
    pub fn yr(&self) -> f64 {
        self.design.yr
    }

    /// Rail positions $A_i = (y, z)$.
    pub fn rails(&self) -> [[f64; 2]; 3] {
        self.rails
    }

    /// Arm lengths $(L_1, L_1, L_2)$.
    pub fn arm_lengths(&self) -> [f64; 3] {
        self.lengths
    }

    /// $u_i = \sqrt{L_i^2 - (y - A_{iy})^2 - (z - A_{iz})^2} \ge 0$ of every arm.
    ///
    /// # Errors
    /// [`KinematicsError::Unreachable`] when $(y, z)$ lies outside arm $i$'s disc.
    pub fn arm_reaches(&self, y: f64, z: f64) -> Result<[f64; 3], KinematicsError> {
        let mut u = [0.0; 3];
        for (leg, (a, l)) in self.rails.iter().zip(self.lengths).enumerate() {
            let discriminant = l * l - (y - a[0]).powi(2) - (z - a[1]).powi(2);
            if !(discriminant >= 0.0) {
                return Err(KinematicsError::Unreachable { leg, discriminant });
            }
            u[leg] = discriminant.sqrt();
        }
        Ok(u)
    }

    /// The inverse-kinematic Jacobian $J = -J_q^{-1} J_x$ with rows
    /// $[1,\ (y - A_{iy})/(s_i u_i),\ (z - A_{iz})/(s_i u_i)]$ wherever the arms reach $(y, z)$
    /// (the three discs; the half-planes of the cross-section are not tested): it depends on
    /// $(y, z)$ only. Public through [`InverseKinematics::velocity_jacobian_at`].
    ///
    /// # Errors
    /// [`KinematicsError::Unreachable`] outside a disc, [`KinematicsError::Singular`] on a disc
    /// boundary ($u_i = 0$, a serial singularity).
    fn disc_velocity_jacobian(
        &self,
        y: f64,
        z: f64,
        mode: LinearDeltaMode,
    ) -> Result<Matrix3<f64>, KinematicsError> {
        let u = self.arm_reaches(y, z)?;
        let mut j = Matrix3::zeros();
        for leg in 0..3 {
            if !(u[leg] > 0.0) {
                return Err(KinematicsError::Singular {
                    matrix: "J_q",
                    sigma_min: 0.0,
                });
            }
            let inv_su = 1.0 / (u[leg] * mode.sign(leg));
            let a = self.rails[leg];
            j[(leg, 0)] = 1.0;
            j[(leg, 1)] = (y - a[0]) * inv_su;
            j[(leg, 2)] = (z - a[1]) * inv_su;
        }
        Ok(j)
    }

    /// The closed-form Jacobian of [`InverseKinematics::velocity_jacobian_at`] at the `N` points
    /// $(y, z_l)$ of one slice at once, in [`Lanes`] (no branch, so the compiler vectorises
    /// it), without the half-plane tests of the cross-section (callers sample inside it). Lane
    /// `l` is reachable exactly where the arms reach $(y, z_l)$ (every discriminant
    /// $L_i^2 - (y - A_{iy})^2 - (z_l - A_{iz})^2 > 0$), and there its entries are the same
    /// floating-point operations, so bit-identical.
    #[inline(always)]
    pub fn velocity_jacobian_lanes<const N: usize>(
        &self,
        y: f64,
        z: &[f64; N],
        mode: LinearDeltaMode,
    ) -> JacobianLanes<N> {
        let z = Lanes(*z);
        let mut jacobian = [[1.0; N]; 9];
        let mut reachable = [true; N];
        for (leg, (a, l)) in self.rails.iter().zip(self.lengths).enumerate() {
            let dy = y - a[0];
            let dz = z - a[1];
            let discriminant = Lanes::splat(l * l - dy * dy) - dz * dz;
            for (lane, d) in reachable.iter_mut().zip(discriminant.gt(0.0)) {
                *lane &= d;
            }
            let inv_su = (discriminant.sqrt() * mode.sign(leg)).recip();
            jacobian[3 * leg + 1] = (inv_su * dy).0;
            jacobian[3 * leg + 2] = (dz * inv_su).0;
        }
        JacobianLanes {
            jacobian,
            reachable,
        }
    }

    fn leg_vector(&self, x: &Task<3>, q: &Joints<3>, leg: usize) -> Vector3<f64> {
        let a = self.rails[leg];
        Vector3::new(x[0] - q[leg], x[1] - a[0], x[2] - a[1])
    }
}

impl ClosedChain<3, 3> for LinearDelta {
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        Joints::from_fn(|leg, _| {
            self.leg_vector(x, q, leg).norm_squared() - self.lengths[leg].powi(2)
        })
    }

    fn jacobian_x(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        Matrix3::from_fn(|leg, k| 2.0 * self.leg_vector(x, q, leg)[k])
    }

    fn jacobian_q(&self, x: &Task<3>, q: &Joints<3>) -> Matrix3<f64> {
        Matrix3::from_diagonal(&Vector3::from_fn(|leg, _| {
            -2.0 * self.leg_vector(x, q, leg)[0]
        }))
    }
}

impl InverseKinematics<3, 3> for LinearDelta {
    type WorkingMode = LinearDeltaMode;

    /// $q_i = x - s_i u_i$, for $(y, z)$ in the workspace cross-section $W$ only.
    ///
    /// # Errors
    /// [`KinematicsError::NonFinite`] for NaN or infinite input;
    /// [`KinematicsError::Unreachable`] when $(y, z) \notin W$ ([`CrossSection`](crate::CrossSection)'s membership):
    /// outside arm `leg`'s disc (negative discriminant), above the plane $z = 0$ that the end
    /// effector cannot pass (`leg` the outer leg on the side of $y$), or, when $Z_R < 0$, outside
    /// the wedge below the centre rail (`leg` the outer leg whose arm the rail blocks); the
    /// `discriminant` of a half-plane is its margin $a y + b - z < 0$.
    fn inverse_kinematics(
        &self,
        x: &Task<3>,
        mode: LinearDeltaMode,
    ) -> Result<Joints<3>, KinematicsError> {
        for (k, what) in ["x[0]", "x[1]", "x[2]"].into_iter().enumerate() {
            if !x[k].is_finite() {
                return Err(KinematicsError::NonFinite { what, value: x[k] });
            }
        }
        let u = self.arm_reaches(x[1], x[2])?;
        if let Some((leg, margin)) = outside_half_plane(&self.rails, x[1], x[2]) {
            return Err(KinematicsError::Unreachable {
                leg,
                discriminant: margin,
            });
        }
        Ok(Joints::from_fn(|leg, _| x[0] - mode.sign(leg) * u[leg]))
    }

    /// In closed form: rows $[1,\ (y - A_{iy})/(s_i u_i),\ (z - A_{iz})/(s_i u_i)]$ for
    /// $(y, z)$ in the cross-section $W$ (the same membership as the inverse kinematics); it
    /// depends on $(y, z)$ only.
    fn velocity_jacobian_at(
        &self,
        x: &Task<3>,
        mode: LinearDeltaMode,
    ) -> Result<Matrix3<f64>, KinematicsError> {
        for (k, what) in ["x[0]", "x[1]", "x[2]"].into_iter().enumerate() {
            if !x[k].is_finite() {
                return Err(KinematicsError::NonFinite { what, value: x[k] });
            }
        }
        let j = self.disc_velocity_jacobian(x[1], x[2], mode);
        if let Some((leg, margin)) = outside_half_plane(&self.rails, x[1], x[2]) {
            // Unreachable wins over a singular disc boundary, as in the inverse kinematics.
            if !matches!(j, Err(KinematicsError::Unreachable { .. })) {
                return Err(KinematicsError::Unreachable {
                    leg,
                    discriminant: margin,
                });
            }
        }
        match j {
            // An arm reach u_i so small that (y - A_iy)/u_i overflows: numerically singular.
            Ok(j) if !j.iter().all(|v| v.is_finite()) => Err(KinematicsError::Singular {
                matrix: "J_q",
                sigma_min: 0.0,
            }),
            j => j,
        }
    }
}

/// Newton's method on $\Phi$ (the default): the assembly mode follows the guess.
impl ForwardKinematics<3> for LinearDelta {}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Lane by lane, the batch Jacobian is the scalar one (bit for bit) and defined exactly
        /// where the scalar one is, including points outside the discs and non-finite ones.
        #[test]
        fn lanes_jacobian_is_the_scalar_one_lane_by_lane(
            design in (1.0..2.8f64, -0.9..0.9f64, -1.2..0.6f64, 0.01..2.0f64),
            y in -3.0..3.0f64,
            z in prop::array::uniform8(-4.0..1.0f64),
            nan_lane in 0usize..16,
            mode in prop::array::uniform3(any::<bool>()),
        ) {
            let ratios = LinearDeltaRatios::from_slice(&[design.0, design.1, design.2, design.3]);
            let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
            let mode = LinearDeltaMode { leans_positive: mode };
            let mut z = z;
            if let Some(lane) = z.get_mut(nan_lane) {
                *lane = f64::NAN;
            }
            let batch = delta.velocity_jacobian_lanes(y, &z, mode);
            for (lane, &z) in z.iter().enumerate() {
                prop_assert_eq!(batch.matrix(lane), delta.disc_velocity_jacobian(y, z, mode).ok());
            }
        }
    }
}

/// A half-plane $z \le a y + b$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Line {
    pub(crate) a: f64,
    pub(crate) b: f64,
}

/// The half-planes of $W$ besides the discs: $z \le 0$ (the plane of the outer rails) and, when
/// $Z_R < 0$, the wedge below the centre rail, $z \le Z_R (y - s)/(Y_A - s)$ through
/// $A_k = (s, 0)$ and $A_3$ for $s = \mp Y_R$ (`None` when $Z_R \ge 0$).
pub(crate) fn half_planes(rails: &[[f64; 2]; 3]) -> [Option<Line>; 3] {
    let [ya, zr] = rails[2];
    let wedge = |k: usize| {
        (zr < 0.0).then(|| {
            let s = rails[k][0];
            let a = zr / (ya - s);
            Line { a, b: -a * s }
        })
    };
    [Some(Line { a: 0.0, b: 0.0 }), wedge(0), wedge(1)]
}

/// The first half-plane of $W$ (closed, no tolerance) that $(y, z)$ lies outside, as the outer
/// leg it stands for and the margin $a y + b - z < 0$: the line $A_kA_3$ stands for outer leg $k$
/// (the centre rail blocks its arm), the plane $z = 0$ for the outer leg on the side of $y$.
/// `None` when $(y, z)$ satisfies them all.
pub(crate) fn outside_half_plane(rails: &[[f64; 2]; 3], y: f64, z: f64) -> Option<(usize, f64)> {
    half_planes(rails)
        .into_iter()
        .enumerate()
        .find_map(|(k, line)| {
            let line = line?;
            let margin = line.a * y + line.b - z;
            let leg = if k == 0 { usize::from(y > 0.0) } else { k - 1 };
            (!(margin >= 0.0)).then_some((leg, margin))
        })
}
