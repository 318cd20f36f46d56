//! The 6-6 semi-regular Stewart–Gough platform of Wolf & Shoham (Fig. 3, eq. 8–10).
//!
//! Design $x = (x_1, x_2, x_3, x_4)$ ([`StewartDesign`]): base radius, platform radius, and the
//! angular separations (radians; the paper prints degrees) of the two joints of a pair on the
//! base and on the platform. Joint $k = 0..5$ belongs to pair $m = \lfloor k/2 \rfloor$ on side
//! $\sigma = \mp 1$ (even/odd $k$):
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
use serde::{Deserialize, Serialize};

/// The largest joint separation of a pair, $120°$ (`120f64.to_radians()`, so that
/// [`StewartDesign::from_deg`] accepts 120 exactly): beyond it the pairs overlap.
const MAX_SEPARATION: f64 = 120.0 * (std::f64::consts::PI / 180.0);

/// The design $x = (x_1, x_2, x_3, x_4)$ of a semi-regular Stewart–Gough platform: radii in one
/// length unit (the pose and twist use the same one; Wolf & Shoham use cm), separations in
/// radians. The papers' designs are in [`crate::presets`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StewartDesign {
    /// Base radius $x_1$ (length); positive.
    pub base_radius: f64,
    /// Platform radius $x_2$ (length); positive.
    pub platform_radius: f64,
    /// Angular separation $x_3$ of the two joints of a base pair (rad); in $[0, 2\pi/3]$.
    pub base_separation: f64,
    /// Angular separation $x_4$ of the two joints of a platform pair (rad); in $[0, 2\pi/3]$.
    pub platform_separation: f64,
    /// Pairing, angle reading and azimuth of the first pair.
    pub layout: JointLayout,
}

impl StewartDesign {
    /// The design in the default layout with the separations $x_3$, $x_4$ in degrees, as the
    /// paper prints them.
    pub fn from_deg(
        base_radius: f64,
        platform_radius: f64,
        base_separation_deg: f64,
        platform_separation_deg: f64,
    ) -> Self {
        Self {
            base_radius,
            platform_radius,
            base_separation: base_separation_deg.to_radians(),
            platform_separation: platform_separation_deg.to_radians(),
            layout: JointLayout::default(),
        }
    }
}

/// A semi-regular 6-6 Stewart–Gough platform (Wolf & Shoham Fig. 3).
///
/// # Example
/// ```
/// use pkm_mechanisms::{StewartDesign, StewartGough, platform_pose};
/// use nalgebra::Vector3;
/// let sg = StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 8.0, 8.0)).unwrap();
/// let pose = platform_pose(Vector3::new(0.0, 0.0, 40.0), Vector3::z(), 0.0).unwrap();
/// let lengths = sg.leg_lengths(&pose);
/// assert!(lengths.iter().all(|l| *l > 40.0));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct StewartGough {
    design: StewartDesign,
    base: [Vector3<f64>; 6],
    platform: [Vector3<f64>; 6],
}

impl StewartGough {
    /// Builds the platform of `design`.
    ///
    /// # Errors
    /// [`DesignError`] when a radius is not finite and positive, a separation is not finite or
    /// outside $[0, 2\pi/3]$ rad, or the layout's offset is not finite.
    pub fn new(design: StewartDesign) -> Result<Self, DesignError> {
        DesignError::require_positive("x1", design.base_radius)?;
        DesignError::require_positive("x2", design.platform_radius)?;
        for (name, angle) in [
            ("x3", design.base_separation),
            ("x4", design.platform_separation),
        ] {
            if !(angle.is_finite() && (0.0..=MAX_SEPARATION).contains(&angle)) {
                return Err(DesignError {
                    parameter: name,
                    value: angle,
                    requirement: "must be finite and in [0, 2pi/3] rad (0 to 120 degrees)",
                });
            }
        }
        DesignError::require_finite("offset", design.layout.offset_deg)?;
        let (base, platform) = design.layout.joints(
            [design.base_radius, design.platform_radius],
            [design.base_separation, design.platform_separation],
        );
        Ok(Self {
            design,
            base,
            platform,
        })
    }

    /// The design the platform was built from.
    pub fn design(&self) -> StewartDesign {
        self.design
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

    /// Leg lengths $|a_i - b_i|$ (inverse kinematics). IEEE arithmetic, never a panic: finite
    /// for a finite pose whose translation stays below about 1e150 (beyond, the squared norms
    /// overflow to ∞); NaN in, NaN out.
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
