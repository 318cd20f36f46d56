//! The 6-6 semi-regular Stewart–Gough platform of Wolf & Shoham (Fig. 3, eq. 8–10).
//!
//! Design $x = (x_1, x_2, x_3, x_4)$: base radius, platform radius, and the angular
//! separations (degrees) of the two joints of a pair on the base and on the platform. Joint
//! $k = 0..5$ belongs to pair $m = \lfloor k/2 \rfloor$ on side $\sigma = \mp 1$ (even/odd $k$):
//! $$ b_k = x_1 (\cos t, \sin t, 0), \quad t = o + 120^\circ m + \sigma x_3/2, $$
//! $$ r_k = x_2 (\cos t, \sin t, 0), \quad t = o + 120^\circ m + \sigma x_4/2 $$
//! (same-pattern pairing; Fig. 3 is missing from the paper, see `docs/conventions.md`).
//!
//! A pose is the platform frame ${}^wR_p$ of eq. 8: position $p$ and rotation
//! $R = \exp(\alpha [n]_\times)$ (eq. 9, with the corrected skew matrix). The task coordinates of
//! [`ClosedChain`] are $x = (p, w)$ with the rotation vector $w = \alpha n$.
//!
//! The rows of the wrench Jacobian $J^\top$ (eq. 10) are the legs' Plücker lines
//! $L_i = [s_i ; a_i \times s_i]$ with $a_i = p + R r_i$ and $s_i$ the unit leg direction, moments
//! about the world origin.

use crate::WrenchSystem;
use crate::stewart_layout::JointLayout;
use nalgebra::{Isometry3, Matrix3, Matrix6, Rotation3, Translation3, Unit, Vector3, Vector6};
use pkm_screw_theory::{PluckerLine, Twist, task_residuals};
use pkm_traits::{
    ClosedChain, DesignError, ForwardKinematics, InverseKinematics, Joints, KinematicsError, Task,
};

/// A semi-regular 6-6 Stewart–Gough platform (Wolf & Shoham Fig. 3).
///
/// # Example
/// ```
/// use pkm_mechanisms::{StewartGough, platform_pose};
/// use nalgebra::Vector3;
/// let sg = StewartGough::new(12.0, 8.0, 8.0, 8.0).unwrap();
/// let pose = platform_pose(Vector3::new(0.0, 0.0, 40.0), Vector3::z(), 0.0).unwrap();
/// let lengths = sg.leg_lengths(&pose);
/// assert!(lengths.iter().all(|l| *l > 40.0));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct StewartGough {
    design: [f64; 4],
    layout: JointLayout,
    base: [Vector3<f64>; 6],
    platform: [Vector3<f64>; 6],
}

impl StewartGough {
    /// The platform with base radius `x1`, platform radius `x2` and joint separations `x3`
    /// (base) and `x4` (platform) in degrees, in the default layout.
    ///
    /// # Errors
    /// [`DesignError`] when a radius is not finite and positive or an angle is not finite or
    /// outside $[0°, 120°]$.
    pub fn new(x1: f64, x2: f64, x3: f64, x4: f64) -> Result<Self, DesignError> {
        Self::with_layout(x1, x2, x3, x4, JointLayout::default())
    }

    /// As [`StewartGough::new`] with an explicit joint layout.
    ///
    /// # Errors
    /// As [`StewartGough::new`].
    pub fn with_layout(
        x1: f64,
        x2: f64,
        x3: f64,
        x4: f64,
        layout: JointLayout,
    ) -> Result<Self, DesignError> {
        DesignError::require_positive("x1", x1)?;
        DesignError::require_positive("x2", x2)?;
        for (name, angle) in [("x3", x3), ("x4", x4)] {
            if !(angle.is_finite() && (0.0..=120.0).contains(&angle)) {
                return Err(DesignError {
                    parameter: name,
                    value: angle,
                    requirement: "must be finite and in [0, 120] degrees",
                });
            }
        }
        DesignError::require_finite("offset", layout.offset_deg)?;
        let (base, platform) = layout.joints(x1, x2, x3, x4);
        Ok(Self {
            design: [x1, x2, x3, x4],
            layout,
            base,
            platform,
        })
    }

    /// The design $(x_1, x_2, x_3, x_4)$.
    pub fn design(&self) -> [f64; 4] {
        self.design
    }

    /// The joint layout.
    pub fn layout(&self) -> JointLayout {
        self.layout
    }

    /// Base joints $b_i$ (world frame).
    pub fn base_joints(&self) -> &[Vector3<f64>; 6] {
        &self.base
    }

    /// Platform joints $r_i$ (platform frame).
    pub fn platform_joints(&self) -> &[Vector3<f64>; 6] {
        &self.platform
    }

    /// Platform joints in the world frame, $a_i = p + R r_i$ (eq. 10).
    pub fn platform_joints_world(&self, pose: &Isometry3<f64>) -> [Vector3<f64>; 6] {
        self.platform
            .map(|r| pose * nalgebra::Point3::from(r))
            .map(|a| a.coords)
    }

    /// Leg vectors $a_i - b_i$.
    pub fn leg_vectors(&self, pose: &Isometry3<f64>) -> [Vector3<f64>; 6] {
        let a = self.platform_joints_world(pose);
        std::array::from_fn(|i| a[i] - self.base[i])
    }

    /// Leg lengths $|a_i - b_i|$ (inverse kinematics).
    pub fn leg_lengths(&self, pose: &Isometry3<f64>) -> Vector6<f64> {
        Vector6::from_iterator(self.leg_vectors(pose).iter().map(|v| v.norm()))
    }

    /// Leg-length rates $\dot l_i = L_i \wedge \chi = s_i \cdot (\bar x + x \times a_i)$ under the twist
    /// $\chi = [x ; \bar x]$ (eq. 5, 14).
    ///
    /// # Errors
    /// As [`WrenchSystem::wrench_rows`].
    pub fn leg_rates(
        &self,
        pose: &Isometry3<f64>,
        twist: &Twist,
    ) -> Result<Vector6<f64>, KinematicsError> {
        Ok(task_residuals(&self.wrench_rows(pose)?, twist))
    }
}

/// The six leg forces of eq. 10: row $i$ is the Plücker line of leg $i$,
/// $L_i = [s_i ; a_i \times s_i]$ (unit direction; moment about the world origin), the matrix
/// $J^\top$; the task objective is then the sum of the squared leg rates.
impl WrenchSystem for StewartGough {
    fn wrench_rows(&self, pose: &Isometry3<f64>) -> Result<Matrix6<f64>, KinematicsError> {
        let a = self.platform_joints_world(pose);
        let mut rows = Matrix6::zeros();
        for (i, (b, a)) in self.base.iter().zip(&a).enumerate() {
            rows.set_row(i, &leg_line(b, a)?.transpose());
        }
        Ok(rows)
    }
}

/// The Plücker line of a leg from base joint `b` to platform joint `a` (eq. 1), scaled to a unit
/// direction: $[s ; a \times s]$, moment about the world origin.
pub(crate) fn leg_line(
    b: &Vector3<f64>,
    a: &Vector3<f64>,
) -> Result<Vector6<f64>, KinematicsError> {
    let length = (a - b).norm();
    if !(length.is_finite() && length > 1e-12) {
        return Err(KinematicsError::Singular {
            matrix: "leg direction",
            sigma_min: length,
        });
    }
    PluckerLine::from_points(b, a)
        .map(|line| line.normalized().to_vector())
        .map_err(|_| KinematicsError::Singular {
            matrix: "leg direction",
            sigma_min: length,
        })
}

/// The pose ${}^wR_p$ of eq. 8–9: position `p`, rotation by `alpha` (radians) about `axis`
/// (normalised here).
///
/// # Errors
/// [`KinematicsError::NonFinite`] for a non-finite input or an axis of zero length.
pub fn platform_pose(
    p: Vector3<f64>,
    axis: Vector3<f64>,
    alpha: f64,
) -> Result<Isometry3<f64>, KinematicsError> {
    let norm = axis.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(KinematicsError::NonFinite {
            what: "axis norm",
            value: norm,
        });
    }
    let w = axis / norm * alpha;
    pose_from_task(&Task::<6>::new(p.x, p.y, p.z, w.x, w.y, w.z))
}

/// The pose of the task coordinates $x = (p, w)$, rotation vector $w = \alpha n$.
///
/// # Errors
/// [`KinematicsError::NonFinite`] for a non-finite coordinate, or a rotation angle $|w|$ that
/// overflows.
pub fn pose_from_task(x: &Task<6>) -> Result<Isometry3<f64>, KinematicsError> {
    if let Some(value) = x.iter().copied().find(|v| !v.is_finite()) {
        return Err(KinematicsError::NonFinite { what: "x", value });
    }
    let w = Vector3::new(x[3], x[4], x[5]);
    let mut rotation = Rotation3::new(w);
    if !rotation.matrix().iter().all(|v| v.is_finite()) {
        // |w|² overflowed: the angle |w| with a scaled norm, about the axis w / |w|.
        let largest = w.amax();
        let scaled = w / largest;
        let angle = largest * scaled.norm();
        if !angle.is_finite() {
            return Err(KinematicsError::NonFinite {
                what: "rotation angle |w|",
                value: angle,
            });
        }
        rotation = Rotation3::from_axis_angle(&Unit::new_normalize(scaled), angle);
    }
    Ok(Isometry3::from_parts(
        Translation3::new(x[0], x[1], x[2]),
        rotation.into(),
    ))
}

/// The left Jacobian of SO(3), $\omega = J_l(w)\,\dot w$ for $R = \exp([w]_\times)$.
pub(crate) fn so3_left_jacobian(w: &Vector3<f64>) -> Matrix3<f64> {
    let theta = w.norm();
    let k = w.cross_matrix();
    let (a, b) = if theta < 1e-6 {
        (
            0.5 - theta * theta / 24.0,
            1.0 / 6.0 - theta * theta / 120.0,
        )
    } else {
        let t2 = theta * theta;
        (
            (1.0 - theta.cos()) / t2,
            (theta - theta.sin()) / (t2 * theta),
        )
    };
    Matrix3::identity() + k * a + k * k * b
}

impl ClosedChain<6, 6> for StewartGough {
    /// $\Phi_i = |a_i - b_i| - q_i$.
    fn closure(&self, x: &Task<6>, q: &Joints<6>) -> Joints<6> {
        match pose_from_task(x) {
            Ok(pose) => self.leg_lengths(&pose) - q,
            Err(_) => Joints::repeat(f64::NAN),
        }
    }

    /// Row $i$: $[s_i^\top, ((R r_i) \times s_i)^\top J_l(w)]$.
    fn jacobian_x(&self, x: &Task<6>, _q: &Joints<6>) -> nalgebra::SMatrix<f64, 6, 6> {
        let Ok(pose) = pose_from_task(x) else {
            return Matrix6::repeat(f64::NAN);
        };
        let jl = so3_left_jacobian(&Vector3::new(x[3], x[4], x[5]));
        let mut j = Matrix6::zeros();
        for (i, leg) in self.leg_vectors(&pose).iter().enumerate() {
            let s = leg / leg.norm();
            let arm = pose.rotation * self.platform[i];
            j.fixed_view_mut::<1, 3>(i, 0).copy_from(&s.transpose());
            j.fixed_view_mut::<1, 3>(i, 3)
                .copy_from(&(arm.cross(&s).transpose() * jl));
        }
        j
    }

    /// $J_q = -I$.
    fn jacobian_q(&self, _x: &Task<6>, _q: &Joints<6>) -> nalgebra::SMatrix<f64, 6, 6> {
        -Matrix6::identity()
    }
}

impl InverseKinematics<6, 6> for StewartGough {
    /// Prismatic legs have a single working mode.
    type WorkingMode = ();

    fn inverse_kinematics(&self, x: &Task<6>, _mode: ()) -> Result<Joints<6>, KinematicsError> {
        let pose = pose_from_task(x)?;
        let lengths = self.leg_lengths(&pose);
        for (leg, l) in lengths.iter().enumerate() {
            // A length that overflows (a pose near 1e308) is as unreachable as a zero one.
            if !(*l > 1e-12 && l.is_finite()) {
                return Err(KinematicsError::Unreachable {
                    leg,
                    discriminant: *l,
                });
            }
        }
        Ok(lengths)
    }
}

/// Newton from the guess; the assembly mode is the guess's.
impl ForwardKinematics<6> for StewartGough {}
