//! Pose coordinates of the platform: position and a gimbal-free orientation.
//!
//! Two orientation parametrisations, neither with a singularity at home:
//! - `rotation_vector`: $R = \exp(\[r\]_\times)$, $r = (r_x, r_y, r_z)$, singular only at
//!   $|r| = 2\pi$; for a planar robot $R = R_z(r_z)$;
//! - `tilt_torsion`: $R = \exp([(t_x, t_y, 0)]_\times)\,R_z(\sigma)$, the tilt-and-torsion
//!   angles of Bonev (tilt $\theta = |t|$ about the horizontal axis $t/|t|$, torsion $\sigma$),
//!   written with the tilt vector so that zero tilt is regular (Briot & Bonev 2008).

use nalgebra::{Isometry3, Matrix3, Matrix6, Rotation3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// What a pose coordinate is in a robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoordinateRole {
    /// An independent task coordinate.
    Task,
    /// Solved from the task coordinates through the legs' constraints.
    Dependent,
    /// Left free by the legs and held at home (the spin of a point platform).
    Idle,
    /// Held at its home value by the legs' constraints.
    Constant,
}

/// The orientation coordinates of a robot file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OrientationKind {
    /// Rotation vector $r$, $R = \exp(\[r\]_\times)$; coordinates `rx`, `ry`, `rz`.
    #[default]
    RotationVector,
    /// Tilt vector and torsion, $R = \exp([(t_x, t_y, 0)]_\times) R_z(\sigma)$; coordinates
    /// `tilt_x`, `tilt_y`, `torsion`.
    TiltTorsion,
}

/// Six pose coordinates: position (m) then three orientation coordinates (rad).
pub type PoseCoordinates = [f64; 6];

impl OrientationKind {
    /// Names of the six pose coordinates, position first.
    pub fn coordinate_names(self) -> [&'static str; 6] {
        match self {
            Self::RotationVector => ["x", "y", "z", "rx", "ry", "rz"],
            Self::TiltTorsion => ["x", "y", "z", "tilt_x", "tilt_y", "torsion"],
        }
    }

    /// The rotation of the orientation coordinates `o`.
    pub fn rotation(self, o: &Vector3<f64>) -> Rotation3<f64> {
        match self {
            Self::RotationVector => Rotation3::new(*o),
            Self::TiltTorsion => {
                Rotation3::new(Vector3::new(o.x, o.y, 0.0))
                    * Rotation3::from_axis_angle(&Vector3::z_axis(), o.z)
            }
        }
    }

    /// The coordinates of the rotation `r` within one turn: $|r| \le \pi$, or tilt $\le \pi$
    /// and torsion in $(-\pi, \pi]$.
    pub fn coordinates_of(self, r: &Rotation3<f64>) -> Vector3<f64> {
        match self {
            Self::RotationVector => rotation_vector(r),
            Self::TiltTorsion => {
                let k = r * Vector3::z();
                let axis = Vector3::z().cross(&k);
                let tilt = if axis.norm() > 1e-300 {
                    axis.normalize() * k.z.clamp(-1.0, 1.0).acos()
                } else if k.z > 0.0 {
                    Vector3::zeros()
                } else {
                    Vector3::x() * std::f64::consts::PI
                };
                let torsion = Rotation3::new(tilt).inverse() * r;
                let m = torsion.matrix();
                Vector3::new(tilt.x, tilt.y, m[(1, 0)].atan2(m[(0, 0)]))
            }
        }
    }

    /// The largest of the angles the coordinates `o` describe: $|r|$, or the tilt $|t|$ and
    /// the torsion $|\sigma|$.
    pub fn rotation_angle(self, o: &Vector3<f64>) -> f64 {
        match self {
            Self::RotationVector => o.norm(),
            Self::TiltTorsion => o.x.hypot(o.y).max(o.z.abs()),
        }
    }

    /// Column $k$: the angular velocity $\omega$ (space frame) per unit rate of orientation
    /// coordinate $k$.
    fn angular_rates(self, o: &Vector3<f64>) -> Matrix3<f64> {
        match self {
            Self::RotationVector => so3_left_jacobian(o),
            Self::TiltTorsion => {
                let tilt = Vector3::new(o.x, o.y, 0.0);
                let mut m = so3_left_jacobian(&tilt);
                m.set_column(2, &(Rotation3::new(tilt) * Vector3::z()));
                m
            }
        }
    }
}

/// The platform pose (world from platform) of the pose coordinates `c`.
pub fn platform_pose(kind: OrientationKind, c: &PoseCoordinates) -> Isometry3<f64> {
    let rotation = kind.rotation(&Vector3::new(c[3], c[4], c[5]));
    Isometry3::from_parts(Translation3::new(c[0], c[1], c[2]), rotation.into())
}

/// Column $k$: the rates $[\omega; \dot p]$ of the platform (angular velocity, velocity of its
/// origin) per unit rate of pose coordinate $k$.
pub(crate) fn hybrid_rates(kind: OrientationKind, c: &PoseCoordinates) -> Matrix6<f64> {
    let mut h = Matrix6::zeros();
    h.fixed_view_mut::<3, 3>(3, 0).fill_with_identity();
    h.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&kind.angular_rates(&Vector3::new(c[3], c[4], c[5])));
    h
}

/// The left Jacobian of SO(3): $\omega = J_l(r)\,\dot r$ for $R = \exp(\[r\]_\times)$.
pub(crate) fn so3_left_jacobian(r: &Vector3<f64>) -> Matrix3<f64> {
    let theta = r.norm();
    let k = r.cross_matrix();
    let (a, b) = if theta < 1e-6 {
        let t2 = theta * theta;
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        let t2 = theta * theta;
        (
            (1.0 - theta.cos()) / t2,
            (theta - theta.sin()) / (t2 * theta),
        )
    };
    Matrix3::identity() + k * a + k * k * b
}

/// The rotation vector of `r` with $|r| \le \pi$, through the unit quaternion
/// $(w, v)$, $w \ge 0$: $r = 2\operatorname{atan2}(|v|, w)\,v/|v|$, accurate up to and at
/// $\pi$ (the arc cosine of the trace loses half the digits there).
fn rotation_vector(r: &Rotation3<f64>) -> Vector3<f64> {
    let q = UnitQuaternion::from_rotation_matrix(r);
    let (w, v) = if q.w < 0.0 {
        (-q.w, -q.imag())
    } else {
        (q.w, q.imag())
    };
    let n = v.norm();
    if n > 0.0 {
        v * (2.0 * n.atan2(w) / n)
    } else {
        v * 2.0
    }
}

/// `c` with its orientation coordinates brought within one turn (the same pose).
pub(crate) fn canonical(kind: OrientationKind, c: &PoseCoordinates) -> PoseCoordinates {
    let o = kind.coordinates_of(&kind.rotation(&Vector3::new(c[3], c[4], c[5])));
    [c[0], c[1], c[2], o.x, o.y, o.z]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_of_inverts_rotation_within_one_turn() {
        for kind in [
            OrientationKind::RotationVector,
            OrientationKind::TiltTorsion,
        ] {
            for o in [
                [0.3, -0.2, 0.5],
                [2.0, 1.0, -3.0],
                [0.0, 0.0, 0.0],
                [4.0, 0.0, 1.0],
                [std::f64::consts::PI, 0.0, 0.0],
                [1.343, 2.3261, 1.6295],
            ] {
                let r = kind.rotation(&Vector3::from(o));
                let back = kind.coordinates_of(&r);
                assert!(kind.rotation_angle(&back) <= std::f64::consts::PI + 1e-12);
                assert!(
                    (kind.rotation(&back).matrix() - r.matrix()).amax() < 1e-12,
                    "{kind:?} {o:?}"
                );
            }
        }
    }

    /// The rates against central differences of the pose, for both parametrisations.
    #[test]
    fn hybrid_rates_match_central_differences() {
        let c = [0.1, -0.2, 0.3, 0.4, -0.3, 0.7];
        for kind in [
            OrientationKind::RotationVector,
            OrientationKind::TiltTorsion,
        ] {
            let h = hybrid_rates(kind, &c);
            for k in 0..6 {
                let step = 1e-6;
                let (mut cp, mut cm) = (c, c);
                cp[k] += step;
                cm[k] -= step;
                let (gp, gm) = (platform_pose(kind, &cp), platform_pose(kind, &cm));
                let dp = (gp.translation.vector - gm.translation.vector) / (2.0 * step);
                let dr = (gp.rotation * gm.rotation.inverse()).scaled_axis() / (2.0 * step);
                let col = h.column(k);
                assert!((dr - col.fixed_rows::<3>(0)).amax() < 1e-8, "{kind:?} {k}");
                assert!((dp - col.fixed_rows::<3>(3)).amax() < 1e-8, "{kind:?} {k}");
            }
        }
    }
}
