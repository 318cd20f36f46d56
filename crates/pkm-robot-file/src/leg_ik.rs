//! Closed-form inverse kinematics of the leg classes that have one.
//!
//! Every class reduces a leg to one scalar equation in its actuator, found from the joint
//! geometry at home (no leg names are trusted):
//! - **distance** (UPS, UPU, RPR, RPS): an actuated P joint between a point $A$ fixed to the
//!   base (all joints before it have axes through $A$) and a point $C$ fixed to the platform
//!   (all joints after it have axes through $C$): $q = \pm(|C(x) - A| - |C_0 - A|)$;
//! - **revolute arm** (RUS, RUU, planar RR, RRR, spherical RRR): an actuated first R joint, an
//!   elbow group of joints with axes through a point $E$ carried by the arm, then a wrist group
//!   through a point $C$ of the platform; $|C(x) - E(\theta)| = L$ gives
//!   $a\cos\theta + b\sin\theta = K$, so
//!   $\theta = \operatorname{atan2}(b, a) \mp \arccos(K/\sqrt{a^2+b^2})$ (branches 0 and 1);
//! - **prismatic arm** (PUS, PUU, PRS, PR): the same with an actuated first P joint,
//!   $s = d\cdot u \mp \sqrt{(d\cdot u)^2 - |d|^2 + L^2}$.
//!
//! Anything else is solved numerically (damped Newton on the leg's SE(3) closure).

use crate::chain::{Joint, LegChain};
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Unit, Vector3};

/// How a leg's actuator is found from the platform pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum LegClass {
    /// Actuated P between base point `base` and platform point `platform` (platform frame).
    Distance {
        base: Vector3<f64>,
        platform: Vector3<f64>,
        home_length: f64,
        /// +1 when the P axis points from `base` to the platform point.
        sign: f64,
    },
    /// Actuated first R joint (unit `axis` through `foot`), arm `arm` ⊥ axis from `foot` to
    /// the elbow point at home, rod of length `rod` to the platform point `wrist`.
    RevoluteArm {
        axis: Vector3<f64>,
        foot: Vector3<f64>,
        arm: Vector3<f64>,
        wrist: Vector3<f64>,
        rod: f64,
    },
    /// Actuated first P joint (unit `axis`) moving the elbow point `elbow` (at home), rod of
    /// length `rod` to the platform point `wrist`.
    PrismaticArm {
        axis: Vector3<f64>,
        elbow: Vector3<f64>,
        wrist: Vector3<f64>,
        rod: f64,
    },
    /// No closed form: damped Newton.
    Numeric,
}

/// With its actuator at a given motion, a closed-form leg holds its platform point `point`
/// (platform frame) at distance `length` from `center` (base frame): the base point of a
/// distance leg, or an arm's elbow moved by the actuator; with the derivatives of the centre
/// and the length in the motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sphere {
    pub point: Vector3<f64>,
    pub center: Vector3<f64>,
    pub length: f64,
    pub d_center: Vector3<f64>,
    pub d_length: f64,
}

/// Why a closed form has no solution: the discriminant that went negative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NoRoot(pub f64);

impl LegClass {
    /// Recognises the class of `leg` from its geometry at home.
    pub(crate) fn classify(leg: &LegChain, home: &Isometry3<f64>, size: f64) -> Self {
        let class = distance_class(leg, home, size)
            .or_else(|| arm_class(leg, home, size))
            .unwrap_or(Self::Numeric);
        // A class must reproduce the home configuration on one of its branches.
        let reproduces = (0..class.branch_count() as u8)
            .any(|b| class.solve(home, b).is_ok_and(|m| m.abs() < 1e-9 * size));
        if reproduces { class } else { Self::Numeric }
    }

    /// A short name of the class.
    pub(crate) fn label(&self) -> &'static str {
        match self {
            Self::Distance { .. } => "distance",
            Self::RevoluteArm { .. } => "revolute arm",
            Self::PrismaticArm { .. } => "prismatic arm",
            Self::Numeric => "numerical",
        }
    }

    /// The platform point (platform frame) that the closed form places, if any.
    pub(crate) fn platform_point(&self) -> Option<Vector3<f64>> {
        match *self {
            Self::Distance { platform, .. } => Some(platform),
            Self::RevoluteArm { wrist, .. } | Self::PrismaticArm { wrist, .. } => Some(wrist),
            Self::Numeric => None,
        }
    }

    /// Number of closed-form branches.
    pub(crate) fn branch_count(&self) -> usize {
        match self {
            Self::RevoluteArm { .. } | Self::PrismaticArm { .. } => 2,
            Self::Distance { .. } | Self::Numeric => 1,
        }
    }

    /// The leg's sphere with its actuator at `motion` (`None` for a numerical leg).
    pub(crate) fn sphere(&self, motion: f64) -> Option<Sphere> {
        Some(match *self {
            Self::Distance {
                base,
                platform,
                home_length,
                sign,
            } => Sphere {
                point: platform,
                center: base,
                length: home_length + sign * motion,
                d_center: Vector3::zeros(),
                d_length: sign,
            },
            Self::RevoluteArm {
                axis,
                foot,
                arm,
                wrist,
                rod,
            } => {
                let arm = Rotation3::from_axis_angle(&Unit::new_unchecked(axis), motion) * arm;
                Sphere {
                    point: wrist,
                    center: foot + arm,
                    length: rod,
                    d_center: axis.cross(&arm),
                    d_length: 0.0,
                }
            }
            Self::PrismaticArm {
                axis,
                elbow,
                wrist,
                rod,
            } => Sphere {
                point: wrist,
                center: elbow + axis * motion,
                length: rod,
                d_center: axis,
                d_length: 0.0,
            },
            Self::Numeric => return None,
        })
    }

    /// The actuator motion from home (rad or m) at platform pose `pose` on `branch`.
    ///
    /// # Errors
    /// [`NoRoot`] with the negative discriminant when the leg cannot reach the pose (and for
    /// [`LegClass::Numeric`], which has no closed form).
    pub(crate) fn solve(&self, pose: &Isometry3<f64>, branch: u8) -> Result<f64, NoRoot> {
        let at = |p: &Vector3<f64>| (pose * Point3::from(*p)).coords;
        match *self {
            Self::Distance {
                base,
                platform,
                home_length,
                sign,
            } => {
                let length = (at(&platform) - base).norm();
                if length.is_finite() && length > 1e-12 {
                    Ok(sign * (length - home_length))
                } else {
                    Err(NoRoot(length))
                }
            }
            Self::RevoluteArm {
                axis,
                foot,
                arm,
                wrist,
                rod,
            } => revolute_arm(&axis, &(at(&wrist) - foot), &arm, rod, branch),
            Self::PrismaticArm {
                axis,
                elbow,
                wrist,
                rod,
            } => {
                let d = at(&wrist) - elbow;
                let du = d.dot(&axis);
                let disc = du * du - d.norm_squared() + rod * rod;
                if !(disc >= 0.0) || !disc.is_finite() {
                    return Err(NoRoot(disc));
                }
                Ok(if branch == 0 {
                    du - disc.sqrt()
                } else {
                    du + disc.sqrt()
                })
            }
            Self::Numeric => Err(NoRoot(f64::NAN)),
        }
    }
}

/// $|d - R_e(\theta) a| = L$ with $a \perp e$: $a\cos\theta + b\sin\theta = K$.
///
/// Where the wrist point lies on the joint's axis ($a = b = 0$) and $K = 0$ (the rod as long as
/// the arm: a leg folded onto its base joint, a type I singularity), every $\theta$ solves it:
/// the arm's home angle $\theta = 0$ is returned for both branches; with $K \ne 0$ there it
/// has no root.
fn revolute_arm(
    e: &Vector3<f64>,
    d: &Vector3<f64>,
    arm: &Vector3<f64>,
    rod: f64,
    branch: u8,
) -> Result<f64, NoRoot> {
    let k = (d.norm_squared() + arm.norm_squared() - rod * rod) / 2.0;
    let (a, b) = (d.dot(arm), d.dot(&e.cross(arm)));
    let radius = a.hypot(b);
    if radius == 0.0 {
        // The rounding of K: a few ulps of its terms.
        let folded = k.abs() <= 8.0 * f64::EPSILON * (arm.norm_squared() + rod * rod);
        return if folded { Ok(0.0) } else { Err(NoRoot(-1.0)) };
    }
    let ratio = k / radius;
    if !(ratio.abs() <= 1.0) {
        return Err(NoRoot(1.0 - ratio.abs()));
    }
    let psi = b.atan2(a);
    let theta = if branch == 0 {
        psi - ratio.acos()
    } else {
        psi + ratio.acos()
    };
    Ok(wrap_angle(theta))
}

/// The angle in $(-\pi, \pi]$.
pub(crate) fn wrap_angle(t: f64) -> f64 {
    let w = t.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The common point of a group of joints (their axes meet there), if any. A single R joint
/// has no unique point: its `point`, or the foot of `hint` on its axis.
fn group_point(joints: &[Joint], hint: Option<Vector3<f64>>, size: f64) -> Option<Vector3<f64>> {
    if let [Joint::Revolute { axis, point }] = joints {
        return Some(match hint {
            Some(h) => point + axis * (h - point).dot(axis),
            None => *point,
        });
    }
    let mut a = Matrix3::zeros();
    let mut b = Vector3::zeros();
    for joint in joints {
        match joint {
            Joint::Revolute { axis, point } => {
                let proj = Matrix3::identity() - axis * axis.transpose();
                a += proj;
                b += proj * point;
            }
            Joint::Spherical { center } => {
                a += Matrix3::identity();
                b += center;
            }
            Joint::Prismatic { .. } => return None,
        }
    }
    if joints.is_empty() || a.determinant().abs() < 1e-9 {
        return None;
    }
    let c = a.try_inverse()? * b;
    let on_every_axis = joints.iter().all(|j| match j {
        Joint::Revolute { axis, point } => (c - point).cross(axis).norm() < 1e-9 * size,
        Joint::Spherical { center } => (c - center).norm() < 1e-9 * size,
        Joint::Prismatic { .. } => false,
    });
    on_every_axis.then_some(c)
}

/// The points of two groups, each single-R group taking the foot of the other group's point
/// on its axis. Two single R joints keep their own points, and must be parallel or meet (a
/// planar or spherical pair), where $|C - E|$ is the only condition between them; when both
/// are written through one point $O$ (a spherical chain with every joint at its centre), each
/// takes the point of its axis at distance `size` from $O$ instead.
pub(crate) fn group_points(
    first: &[Joint],
    second: &[Joint],
    size: f64,
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    if let (
        [
            Joint::Revolute {
                axis: a1,
                point: p1,
            },
        ],
        [
            Joint::Revolute {
                axis: a2,
                point: p2,
            },
        ],
    ) = (first, second)
    {
        if (p2 - p1).norm() < 1e-9 * size && a1.cross(a2).norm() > 1e-9 {
            // Two axes written through one point O (a spherical pair as published): any point
            // of each axis is carried by its link, so take each at distance `size` from O.
            return Some((p1 + a1 * size, p2 + a2 * size));
        }
        let coplanar = (p2 - p1).dot(&a1.cross(a2)).abs() < 1e-9 * size;
        return coplanar.then_some((*p1, *p2));
    }
    match first {
        [Joint::Revolute { .. }] => {
            let c = group_point(second, None, size)?;
            Some((group_point(first, Some(c), size)?, c))
        }
        _ => {
            let a = group_point(first, None, size)?;
            Some((a, group_point(second, Some(a), size)?))
        }
    }
}

fn distance_class(leg: &LegChain, home: &Isometry3<f64>, size: f64) -> Option<LegClass> {
    let actuator = leg.sole_actuator()?.joint;
    let Joint::Prismatic { axis } = leg.joints[actuator] else {
        return None;
    };
    let (before, after) = (&leg.joints[..actuator], &leg.joints[actuator + 1..]);
    let (a, c) = group_points(before, after, size)?;
    let along = c - a;
    let home_length = along.norm();
    if home_length < 1e-9 * size || along.cross(&axis).norm() > 1e-9 * home_length {
        return None;
    }
    Some(LegClass::Distance {
        base: a,
        platform: (home.inverse() * Point3::from(c)).coords,
        home_length,
        sign: along.dot(&axis).signum(),
    })
}

/// An arm leg's candidate splits after its actuated first joint, in order: the number `m` of
/// joints of its elbow group, the elbow point $E$ and the wrist point $C$ (base frame, at
/// home), for each split whose groups meet in points a rod apart.
fn arm_splits<'a>(
    leg: &'a LegChain,
    home: &'a Isometry3<f64>,
    size: f64,
) -> impl Iterator<Item = (usize, Vector3<f64>, Vector3<f64>)> + 'a {
    let rest = &leg.joints[leg.joints.len().min(1)..];
    let arm = leg.sole_actuator().map(|a| a.joint) == Some(0);
    (1..=rest.len()).filter(move |_| arm).filter_map(move |m| {
        let (elbow_group, wrist_group) = rest.split_at(m);
        let (e, c) = if wrist_group.is_empty() {
            let e = group_point(elbow_group, None, size)?;
            (e, platform_point_for(elbow_group, &e, home))
        } else {
            group_points(elbow_group, wrist_group, size)?
        };
        ((c - e).norm() >= 1e-9 * size).then_some((m, e, c))
    })
}

fn arm_class(leg: &LegChain, home: &Isometry3<f64>, size: f64) -> Option<LegClass> {
    let (_, e, c) = arm_split(leg, home, size)?;
    arm_of(leg, home, size, e, c)
}

/// The split of an arm leg that its class takes: the first of [`arm_splits`] that makes an
/// arm.
pub(crate) fn arm_split(
    leg: &LegChain,
    home: &Isometry3<f64>,
    size: f64,
) -> Option<(usize, Vector3<f64>, Vector3<f64>)> {
    arm_splits(leg, home, size).find(|&(_, e, c)| arm_of(leg, home, size, e, c).is_some())
}

/// The arm class of `leg` with elbow point `e` and wrist point `c`, if its first joint makes
/// one.
fn arm_of(
    leg: &LegChain,
    home: &Isometry3<f64>,
    size: f64,
    e: Vector3<f64>,
    c: Vector3<f64>,
) -> Option<LegClass> {
    let rod = (c - e).norm();
    let wrist = (home.inverse() * Point3::from(c)).coords;
    match leg.joints[0] {
        Joint::Revolute { axis, point } => {
            let foot = point + axis * (e - point).dot(&axis);
            let arm = e - foot;
            (arm.norm() > 1e-9 * size).then_some(LegClass::RevoluteArm {
                axis,
                foot,
                arm,
                wrist,
                rod,
            })
        }
        Joint::Prismatic { axis } => Some(LegClass::PrismaticArm {
            axis,
            elbow: e,
            wrist,
            rod,
        }),
        Joint::Spherical { .. } => None,
    }
}

/// With no wrist group the platform is the last link: its origin, moved into the plane of a
/// single elbow R joint through `e` (so the rod is perpendicular to the elbow axis).
fn platform_point_for(elbow: &[Joint], e: &Vector3<f64>, home: &Isometry3<f64>) -> Vector3<f64> {
    let origin = home.translation.vector;
    match elbow {
        [Joint::Revolute { axis, .. }] => origin - axis * (origin - e).dot(axis),
        _ => origin,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_angle_lands_in_half_open_interval() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!(wrap_angle(0.25).abs() - 0.25 < 1e-15);
    }
}
