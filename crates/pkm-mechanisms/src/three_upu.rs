//! The 3-UPU of Wolf & Shoham §4.4 (eq. 16–18): three actuated legs and three constraint couples.
//!
//! Base joints $b_i = a(\cos\theta_i, \sin\theta_i, 0)$ and platform joints
//! $r_i = b(\cos\theta_i, \sin\theta_i, 0)$ at azimuths $\theta_i$ (Park's: $-90°, 30°, 150°$); the
//! platform pose is ${}^wR_p$ (eq. 8). The $6 \times 6$ matrix of eq. 18 stacks the three leg
//! forces $[s_i ; a_i \times s_i]$ and the three constraint couples $[0 ; u_i]$ normal to the
//! upper universal joint, $u_i = R\,(u_{1,i} \times u_{2,i}) / |u_{1,i} \times u_{2,i}|$
//! ([`WrenchSystem`]).
//!
//! # Kinematics: a translational model
//!
//! For [`ClosedChain`], [`InverseKinematics`] and [`ForwardKinematics`] the task coordinates are
//! the platform position $x = p$ at the **fixed** home orientation $R = I$, and the actuated
//! coordinates are the leg lengths $q_i$: leg $i$ closes when
//! $$ \Phi_i(x, q) = |x + r_i - b_i| - q_i = 0, \qquad J_x = [s_1\ s_2\ s_3]^\top,
//!    \qquad J_q = -I, $$
//! with $s_i$ the unit leg direction, so the velocity Jacobian is $J = J_x$ (the leg-force rows of
//! eq. 18 without their moments). This is exact for a translational 3-UPU, whose constraint
//! couples keep $R = I$ (Tsai's, with the two U joints of each leg parallel). It is only the
//! fixed-orientation slice of a 3-UPU whose couples do not span the rotations, such as Park's
//! (all three couples vertical at home, so the platform can tilt about horizontal axes, the A1
//! and A2 twists of §4.4): there the model says which leg lengths hold the platform at $p$
//! without tilting, not that it stays untilted; the six-row screw view is the full statement.
//! One working mode (`()`): $q_i \ge 0$ is the distance itself; the mirror assembly
//! $z \mapsto -z$ (base and platform joints lie in their planes) is reached by forward
//! kinematics from a guess below the base.

use crate::WrenchSystem;
use crate::stewart_gough::leg_line;
use nalgebra::{Isometry3, Matrix3, Matrix6, Point3, Vector3, Vector6};
use pkm_traits::{
    ClosedChain, DesignError, ForwardKinematics, InverseKinematics, Joints, KinematicsError, Task,
};
use serde::{Deserialize, Serialize};

/// The two axes of an upper universal joint, in the platform frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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

    /// Park's axes at the azimuth `theta` tilted by $\beta$ about the radial $u_2$, then by
    /// $\gamma$ about the tangent $u_1$ (radians), as in Wolf & Shoham §4.4:
    /// $u_j' = R_{u_2}(\beta)\,R_{u_1}(\gamma)\,u_j$.
    pub fn park_tilted(theta: f64, beta: f64, gamma: f64) -> Self {
        let Self { u1, u2 } = Self::park(theta);
        let tilt = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(u2), beta)
            * nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(u1), gamma);
        Self {
            u1: tilt * u1,
            u2: tilt * u2,
        }
    }
}

/// The design of a 3-UPU: radii in one length unit (the pose and twist use the same one), joint
/// azimuths in radians, and the upper U-joint axes. Park's design is
/// [`crate::presets::park_3upu`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThreeUpuDesign {
    /// Base radius $a$ of the base joints $b_i$ (length); positive.
    pub base_radius: f64,
    /// Platform radius $b$ of the platform joints $r_i$ (length); positive.
    pub platform_radius: f64,
    /// Azimuths $\theta_i$ of leg $i$'s base and platform joints (rad); finite.
    pub azimuths: [f64; 3],
    /// Upper U-joint axes of each leg (platform frame); finite, not parallel.
    pub upper: [UJointAxes; 3],
}

/// A 3-UPU with its upper universal-joint axes as design parameters.
///
/// # Example
/// ```
/// use pkm_mechanisms::{ThreeUpu, WrenchSystem, presets};
/// use nalgebra::Isometry3;
/// let upu = ThreeUpu::new(presets::park_3upu()).unwrap();
/// let rows = upu.wrench_rows(&Isometry3::translation(0.0, 0.0, 50.0)).unwrap();
/// // Park's couples are vertical: no moment about a horizontal rotation axis.
/// assert!(rows[(3, 5)].abs() > 0.99);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ThreeUpu {
    design: ThreeUpuDesign,
    base: [Vector3<f64>; 3],
    platform: [Vector3<f64>; 3],
    normals: [Vector3<f64>; 3],
}

impl ThreeUpu {
    /// Builds the 3-UPU of `design`.
    ///
    /// # Errors
    /// [`DesignError`] for a radius that is not finite and positive, an azimuth that is not
    /// finite, or a U joint whose axes are not finite or (numerically) parallel.
    pub fn new(design: ThreeUpuDesign) -> Result<Self, DesignError> {
        let a = DesignError::require_positive("a", design.base_radius)?;
        let b = DesignError::require_positive("b", design.platform_radius)?;
        for theta in design.azimuths {
            DesignError::require_finite("azimuth", theta)?;
        }
        let mut normals = [Vector3::zeros(); 3];
        for (n, axes) in normals.iter_mut().zip(&design.upper) {
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
        let at = |r: f64, t: f64| Vector3::new(r * t.cos(), r * t.sin(), 0.0);
        Ok(Self {
            design,
            base: design.azimuths.map(|t| at(a, t)),
            platform: design.azimuths.map(|t| at(b, t)),
            normals,
        })
    }

    /// The design the 3-UPU was built from.
    pub fn design(&self) -> ThreeUpuDesign {
        self.design
    }

    /// Leg vectors $x + r_i - b_i$ at the platform position `x` (orientation $R = I$).
    fn leg_vectors(&self, x: &Task<3>) -> [Vector3<f64>; 3] {
        std::array::from_fn(|i| x + self.platform[i] - self.base[i])
    }
}

/// The matrix of eq. 18: rows 0–2 the leg lines, rows 3–5 the constraint couples.
impl WrenchSystem for ThreeUpu {
    fn wrench_rows(&self, pose: &Isometry3<f64>) -> Result<Matrix6<f64>, KinematicsError> {
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
}

/// The translational model of the module doc: $x = p$ at $R = I$, $q$ the leg lengths.
impl ClosedChain<3, 3> for ThreeUpu {
    /// $\Phi_i = |x + r_i - b_i| - q_i$.
    fn closure(&self, x: &Task<3>, q: &Joints<3>) -> Joints<3> {
        let legs = self.leg_vectors(x);
        Joints::from_fn(|i, _| legs[i].norm() - q[i])
    }

    /// Row $i$: the unit leg direction $s_i^\top$.
    fn jacobian_x(&self, x: &Task<3>, _q: &Joints<3>) -> Matrix3<f64> {
        let legs = self.leg_vectors(x);
        Matrix3::from_fn(|i, k| legs[i][k] / legs[i].norm())
    }

    /// $J_q = -I$.
    fn jacobian_q(&self, _x: &Task<3>, _q: &Joints<3>) -> Matrix3<f64> {
        -Matrix3::identity()
    }
}

impl InverseKinematics<3, 3> for ThreeUpu {
    /// Prismatic legs have a single working mode.
    type WorkingMode = ();

    /// $q_i = |x + r_i - b_i|$.
    ///
    /// # Errors
    /// [`KinematicsError::NonFinite`] for a non-finite `x`; [`KinematicsError::Unreachable`]
    /// for a leg of (numerically) zero length, where its direction is undefined, or one whose
    /// length overflows.
    fn inverse_kinematics(&self, x: &Task<3>, _mode: ()) -> Result<Joints<3>, KinematicsError> {
        if let Some(value) = x.iter().copied().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "x", value });
        }
        let legs = self.leg_vectors(x);
        let mut q = Joints::zeros();
        for (leg, v) in legs.iter().enumerate() {
            let length = v.norm();
            if !(length > 1e-12 && length.is_finite()) {
                return Err(KinematicsError::Unreachable {
                    leg,
                    discriminant: length,
                });
            }
            q[leg] = length;
        }
        Ok(q)
    }
}

/// Newton from the guess (the default); the assembly mode ($z$ above or below the base) is the
/// guess's.
impl ForwardKinematics<3> for ThreeUpu {}
