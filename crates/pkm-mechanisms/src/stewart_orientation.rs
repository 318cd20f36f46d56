//! The constant-orientation workspace of a Stewart–Gough platform: the positions $p$ the
//! platform reaches at one fixed rotation $R$ with every leg length in its range (the standard
//! workspace of a 6-DOF platform; Merlet, *Parallel Robots*, §6.2).
//!
//! [`ConstantOrientation`] is a view of a [`StewartGough`] with the task coordinates the
//! position $x = p$ alone and the six leg lengths $q$ as actuated coordinates. With
//! $v_i(p) = p + R r_i - b_i$ (eq. 10 of Wolf & Shoham, $a_i = p + R r_i$), leg $i$ closes when
//! $$ \Phi_i(p, q) = |v_i|^2 - q_i^2 = 0, \qquad J_x = 2 [v_1 \cdots v_6]^\top, \qquad
//!    J_q = -2\,\mathrm{diag}(q), $$
//! so the velocity Jacobian $J = -J_q^{-1} J_x$ has the unit leg directions $s_i = v_i / q_i$ as
//! rows: the translational columns of the platform's $J_x$ ([`ClosedChain`] for
//! [`StewartGough`]). $J$ is $6 \times 3$, and its $1/\kappa$ is $\sigma_3 / \sigma_1$ of its
//! singular values (`pkm_workspace_indices::TranslationalCondition`).
//!
//! Leg $i$ alone reaches the spherical shell $q_{min} \le |p - c_i| \le q_{max}$ about
//! $c_i = b_i - R r_i$ ([`ConstantOrientation::shell_centres`]); the workspace is the intersection
//! of the six shells with the half-spaces.

use crate::{StewartGough, pose_from_task};
use nalgebra::{Rotation3, SMatrix, Vector3};
use pkm_traits::{
    ClosedChain, ConstrainedWorkspace, DesignError, InverseKinematics, Joints, KinematicsError,
    Task,
};

/// A Stewart–Gough platform held at one orientation: a translational mechanism with six legs.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_mechanisms::{ConstantOrientation, StewartDesign, StewartGough};
/// use pkm_traits::InverseKinematics;
/// let sg = StewartGough::new(StewartDesign::from_deg(0.3, 0.2, 20.0, 20.0))?;
/// let view = ConstantOrientation::new(sg, Vector3::new(0.0, 0.0, 10f64.to_radians()))?;
/// let q = view.inverse_kinematics(&Vector3::new(0.0, 0.0, 0.5), ())?;
/// assert!(q.iter().all(|l| *l > 0.5));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ConstantOrientation {
    platform: StewartGough,
    rotation_vector: Vector3<f64>,
    rotation: Rotation3<f64>,
    /// $c_i = b_i - R r_i$: leg $i$ has length $|p - c_i|$.
    centres: [Vector3<f64>; 6],
}

impl ConstantOrientation {
    /// The platform held at the rotation $R = \exp(\[w\]_\times)$ of the rotation vector `w`
    /// (radians, $w = \alpha n$, as [`pose_from_task`]).
    ///
    /// # Errors
    /// [`DesignError`] for a non-finite component of `w` or a rotation angle $|w|$ that
    /// overflows.
    pub fn new(platform: StewartGough, w: Vector3<f64>) -> Result<Self, DesignError> {
        for v in w.iter() {
            DesignError::require_finite("rotation vector", *v)?;
        }
        let pose = pose_from_task(&Task::<6>::new(0.0, 0.0, 0.0, w.x, w.y, w.z)).map_err(|_| {
            DesignError {
                parameter: "rotation angle |w|",
                value: w.amax(),
                requirement: "must be finite",
            }
        })?;
        let rotation = pose.rotation.to_rotation_matrix();
        let base = platform.base_joints();
        let joints = platform.platform_joints();
        let centres = std::array::from_fn(|i| base[i] - rotation * joints[i]);
        Ok(Self {
            platform,
            rotation_vector: w,
            rotation,
            centres,
        })
    }

    /// The platform.
    pub fn platform(&self) -> &StewartGough {
        &self.platform
    }

    /// The rotation vector $w$ (radians) the view was built with.
    pub fn rotation_vector(&self) -> Vector3<f64> {
        self.rotation_vector
    }

    /// The fixed rotation $R$.
    pub fn rotation(&self) -> &Rotation3<f64> {
        &self.rotation
    }

    /// The centres $c_i = b_i - R r_i$ of the legs' spherical shells: leg $i$ has length
    /// $|p - c_i|$.
    pub fn shell_centres(&self) -> &[Vector3<f64>; 6] {
        &self.centres
    }

    /// Leg vectors $v_i = p + R r_i - b_i = p - c_i$.
    fn leg_vectors(&self, p: &Task<3>) -> [Vector3<f64>; 6] {
        self.centres.map(|c| p - c)
    }
}

impl ClosedChain<3, 6> for ConstantOrientation {
    /// $\Phi_i = |p + R r_i - b_i|^2 - q_i^2$.
    fn closure(&self, x: &Task<3>, q: &Joints<6>) -> Joints<6> {
        let legs = self.leg_vectors(x);
        Joints::<6>::from_fn(|i, _| legs[i].norm_squared() - q[i] * q[i])
    }

    /// Row $i$: $2 v_i^\top$.
    fn jacobian_x(&self, x: &Task<3>, _q: &Joints<6>) -> SMatrix<f64, 6, 3> {
        let legs = self.leg_vectors(x);
        SMatrix::<f64, 6, 3>::from_fn(|i, k| 2.0 * legs[i][k])
    }

    /// $J_q = -2\,\mathrm{diag}(q)$.
    fn jacobian_q(&self, _x: &Task<3>, q: &Joints<6>) -> SMatrix<f64, 6, 6> {
        SMatrix::<f64, 6, 6>::from_diagonal(&(q * -2.0))
    }
}

impl InverseKinematics<3, 6> for ConstantOrientation {
    /// Prismatic legs have a single working mode.
    type WorkingMode = ();

    /// $q_i = |p + R r_i - b_i|$.
    ///
    /// # Errors
    /// [`KinematicsError::NonFinite`] for a non-finite `x`; [`KinematicsError::Unreachable`]
    /// for a leg of (numerically) zero length, where its direction is undefined, or one whose
    /// length overflows.
    fn inverse_kinematics(&self, x: &Task<3>, _mode: ()) -> Result<Joints<6>, KinematicsError> {
        if let Some(value) = x.iter().copied().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "x", value });
        }
        let mut q = Joints::<6>::zeros();
        for (leg, v) in self.leg_vectors(x).iter().enumerate() {
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

/// Half-spaces and leg-length ranges; reachability is the inverse kinematics.
impl ConstrainedWorkspace<3, 6> for ConstantOrientation {
    fn name(&self) -> &'static str {
        "StewartGough at constant orientation"
    }
}
