//! The 3-UPU of Wolf & Shoham §4.4 (eq. 16–18): three actuated legs and three constraint couples.
//!
//! Base joints $b_i = a(\cos\theta_i, \sin\theta_i, 0)$ and platform joints
//! $r_i = b(\cos\theta_i, \sin\theta_i, 0)$ at Park's azimuths $\theta_i = -90°, 30°, 150°$; the
//! platform pose is ${}^wR_p$ (eq. 8). The $6 \times 6$ matrix of eq. 18 stacks the three leg
//! forces $[s_i ; a_i \times s_i]$ and the three constraint couples $[0 ; u_i]$ normal to the
//! upper universal joint, $u_i = R\,(u_{1,i} \times u_{2,i}) / |u_{1,i} \times u_{2,i}|$.

use crate::stewart_gough::leg_line;
use nalgebra::{Isometry3, Matrix6, Point3, Vector3, Vector6};
use pkm_screw_theory::{Twist, task_objective};
use pkm_traits::{DesignError, KinematicsError};

/// The two axes of an upper universal joint, in the platform frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UJointAxes {
    /// First axis $\hat u_{1,i}$.
    pub u1: Vector3<f64>,
    /// Second axis $\hat u_{2,i}$.
    pub u2: Vector3<f64>,
}

impl UJointAxes {
    /// Park's axes at azimuth `theta` (radians): the tangent and the outward radial.
    pub fn park(theta: f64) -> Self {
        Self {
            u1: Vector3::new(-theta.sin(), theta.cos(), 0.0),
            u2: Vector3::new(theta.cos(), theta.sin(), 0.0),
        }
    }
}

/// A 3-UPU with its upper universal-joint axes as design parameters.
///
/// # Example
/// ```
/// use pkm_mechanisms::{ThreeUpu, UJointAxes};
/// use nalgebra::{Isometry3, Vector6};
/// let azimuths = ThreeUpu::PARK_AZIMUTHS.map(f64::to_radians);
/// let upu = ThreeUpu::new(20.0, 10.0, azimuths.map(UJointAxes::park)).unwrap();
/// let rows = upu.wrench_rows(&Isometry3::translation(0.0, 0.0, 50.0)).unwrap();
/// // Park's couples are vertical: no moment about a horizontal rotation axis.
/// assert!(rows[(3, 5)].abs() > 0.99);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ThreeUpu {
    base: [Vector3<f64>; 3],
    platform: [Vector3<f64>; 3],
    normals: [Vector3<f64>; 3],
}

impl ThreeUpu {
    /// Azimuths of the joints in Park's design, degrees.
    pub const PARK_AZIMUTHS: [f64; 3] = [-90.0, 30.0, 150.0];

    /// The 3-UPU with base radius `a`, platform radius `b` (joints at
    /// [`ThreeUpu::PARK_AZIMUTHS`]) and upper U-joint axes `upper`.
    ///
    /// # Errors
    /// [`DesignError`] for a radius that is not finite and positive, or a U joint whose axes are
    /// not finite or (numerically) parallel.
    pub fn new(a: f64, b: f64, upper: [UJointAxes; 3]) -> Result<Self, DesignError> {
        DesignError::require_positive("a", a)?;
        DesignError::require_positive("b", b)?;
        let mut normals = [Vector3::zeros(); 3];
        for (n, axes) in normals.iter_mut().zip(&upper) {
            let cross = axes.u1.normalize().cross(&axes.u2.normalize());
            let norm = cross.norm();
            if !(norm.is_finite() && norm > 1e-9) {
                return Err(DesignError {
                    parameter: "|u1 x u2|",
                    value: norm,
                    requirement: "U-joint axes must be finite and not parallel",
                });
            }
            *n = cross / norm;
        }
        let at = |r: f64, deg: f64| {
            let t = deg.to_radians();
            Vector3::new(r * t.cos(), r * t.sin(), 0.0)
        };
        Ok(Self {
            base: Self::PARK_AZIMUTHS.map(|t| at(a, t)),
            platform: Self::PARK_AZIMUTHS.map(|t| at(b, t)),
            normals,
        })
    }

    /// The matrix of eq. 18: rows 0–2 the leg lines, rows 3–5 the constraint couples.
    ///
    /// # Errors
    /// [`KinematicsError::Singular`] when a leg has (numerically) zero length.
    pub fn wrench_rows(&self, pose: &Isometry3<f64>) -> Result<Matrix6<f64>, KinematicsError> {
        let mut rows = Matrix6::zeros();
        for i in 0..3 {
            let a = (pose * Point3::from(self.platform[i])).coords;
            rows.set_row(i, &leg_line(&self.base[i], &a)?.transpose());
            let u = pose.rotation * self.normals[i];
            rows.set_row(
                3 + i,
                &Vector6::new(0.0, 0.0, 0.0, u.x, u.y, u.z).transpose(),
            );
        }
        Ok(rows)
    }

    /// $F = \sum_i (L_i \wedge \chi)^2$ over the six rows of eq. 18.
    ///
    /// # Errors
    /// As [`ThreeUpu::wrench_rows`].
    pub fn task_objective(
        &self,
        pose: &Isometry3<f64>,
        twist: &Twist,
    ) -> Result<f64, KinematicsError> {
        Ok(task_objective(&self.wrench_rows(pose)?, twist))
    }
}
