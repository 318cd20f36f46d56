//! Leg chains as products of exponentials (Lynch & Park, *Modern Robotics*, eq. 4.14): each
//! joint a screw axis at the home pose, the leg displacement
//! $D(\theta) = e^{[\xi_1]\theta_1} \cdots e^{[\xi_n]\theta_n}$, and the leg closes when
//! $D(\theta)\,M = X$, with $M$ the platform pose at home and $X$ the platform pose.
//!
//! A spherical joint is one joint with a rotation as its value (no three-angle gimbal), so its
//! twists always span the rotations about its centre.

use crate::mass::Body;
use nalgebra::{Isometry3, Rotation3, Translation3, Unit, Vector3, Vector6};

/// An elementary joint of a leg, at the home pose (base frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Joint {
    /// Revolute about the line through `point` along the unit `axis`.
    Revolute {
        /// Unit axis direction.
        axis: Vector3<f64>,
        /// A point on the axis (m).
        point: Vector3<f64>,
    },
    /// Prismatic along the unit `axis`.
    Prismatic {
        /// Unit axis direction.
        axis: Vector3<f64>,
    },
    /// Spherical about `center`.
    Spherical {
        /// Centre (m).
        center: Vector3<f64>,
    },
}

/// The value of one joint: a coordinate for R and P (rad, m; 0 at home), a rotation for S.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum JointValue {
    Scalar(f64),
    Ball(Rotation3<f64>),
}

impl Joint {
    /// Coordinates of the joint: 1 for R and P, 3 for S.
    pub(crate) fn dof(&self) -> usize {
        match self {
            Self::Spherical { .. } => 3,
            _ => 1,
        }
    }

    /// The value at home.
    pub(crate) fn home_value(&self) -> JointValue {
        match self {
            Self::Spherical { .. } => JointValue::Ball(Rotation3::identity()),
            _ => JointValue::Scalar(0.0),
        }
    }

    /// The rigid displacement $e^{[\xi]\theta}$ of the joint at `value`.
    pub(crate) fn displacement(&self, value: &JointValue) -> Isometry3<f64> {
        match (self, value) {
            (Self::Revolute { axis, point }, JointValue::Scalar(t)) => {
                let r = Rotation3::from_axis_angle(&Unit::new_unchecked(*axis), *t);
                about_point(r, point)
            }
            (Self::Prismatic { axis }, JointValue::Scalar(d)) => {
                Isometry3::from_parts(Translation3::from(axis * *d), Default::default())
            }
            (Self::Spherical { center }, JointValue::Ball(r)) => about_point(*r, center),
            _ => Isometry3::identity(),
        }
    }

    /// The unit twists `[ω; v_O]` of the joint's coordinates at home (one, or three for S).
    fn home_twists(&self) -> [Option<Vector6<f64>>; 3] {
        let rotation_about = |w: Vector3<f64>, p: &Vector3<f64>| stack(&w, &p.cross(&w));
        match self {
            Self::Revolute { axis, point } => [Some(rotation_about(*axis, point)), None, None],
            Self::Prismatic { axis } => [Some(stack(&Vector3::zeros(), axis)), None, None],
            Self::Spherical { center } => {
                [Vector3::x(), Vector3::y(), Vector3::z()].map(|w| Some(rotation_about(w, center)))
            }
        }
    }
}

/// The rotation `r` about `point`: $x \mapsto r(x - p) + p$.
fn about_point(r: Rotation3<f64>, point: &Vector3<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::from(point - r * point), r.into())
}

/// `[top; bottom]`.
pub(crate) fn stack(top: &Vector3<f64>, bottom: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(top.x, top.y, top.z, bottom.x, bottom.y, bottom.z)
}

/// The adjoint action of `g = (R, t)` on a twist `[ω; v_O]`: $[R\omega;\ R v + t \times R\omega]$.
pub(crate) fn adjoint(g: &Isometry3<f64>, twist: &Vector6<f64>) -> Vector6<f64> {
    let w = g.rotation * twist.fixed_rows::<3>(0).into_owned();
    let v = g.rotation * twist.fixed_rows::<3>(3).into_owned() + g.translation.vector.cross(&w);
    stack(&w, &v)
}

/// One actuated joint of a leg: which joint it is, its home value and its range.
#[derive(Debug, Clone, PartialEq)]
pub struct LegActuator {
    /// Index of the actuated joint in [`LegChain::joints`] (an R or a P joint).
    pub joint: usize,
    /// Actuator coordinate at home (rad or m).
    pub offset: f64,
    /// Actuator range, if any.
    pub limits: Option<[f64; 2]>,
    /// The key path of the joint in the file (`legs[1].joints[2]`), the actuator's name.
    pub name: String,
    /// The motor rotor's inertia reflected to the joint, `rotor_inertia * gear_ratio²`
    /// (kg m² for R, kg for P); 0 without a rotor.
    pub reflected_inertia: f64,
}

/// One leg: its elementary joints and its actuators.
#[derive(Debug, Clone, PartialEq)]
pub struct LegChain {
    /// Joints from the base to the platform.
    pub joints: Vec<Joint>,
    /// The actuated joints in joint order: none for a passive leg, which constrains the
    /// platform and drives nothing; one for most legs; several for a leg that carries several
    /// actuators (each an actuator of its own).
    pub actuators: Vec<LegActuator>,
    /// The joint letters as written (`UPS`), for the name check.
    pub letters: String,
    /// The leg's massive bodies (links and point masses), each with the number of joints
    /// that move it; one moved by every joint rides on the platform.
    pub bodies: Vec<Body>,
}

/// Twists of a leg's joint coordinates at a configuration, and its displacement.
pub(crate) struct LegTwists {
    /// $D(\theta)$.
    pub displacement: Isometry3<f64>,
    /// One entry per coordinate: the joint index and the unit twist `[ω; v_O]` (space frame).
    pub twists: Vec<(usize, Vector6<f64>)>,
    /// The displacement of the first `j + 1` joints, for each joint `j` (the last is
    /// `displacement`).
    pub prefixes: Vec<Isometry3<f64>>,
}

impl LegChain {
    /// The actuator of joint `j`, if it is actuated.
    pub fn actuator_at(&self, j: usize) -> Option<&LegActuator> {
        self.actuators.iter().find(|a| a.joint == j)
    }

    /// Whether joint `j` is actuated.
    pub fn is_actuated(&self, j: usize) -> bool {
        self.actuator_at(j).is_some()
    }

    /// The leg's actuator when it has exactly one (the legs with closed forms).
    pub(crate) fn sole_actuator(&self) -> Option<&LegActuator> {
        match self.actuators.as_slice() {
            [one] => Some(one),
            _ => None,
        }
    }

    /// The home values of every joint.
    pub(crate) fn home_values(&self) -> Vec<JointValue> {
        self.joints.iter().map(Joint::home_value).collect()
    }

    /// The leg displacement $D(\theta)$ and the space-frame twists of every coordinate: twist
    /// $j$ is $\mathrm{Ad}_{e^{[\xi_1]\theta_1} \cdots e^{[\xi_{j-1}]\theta_{j-1}}}\,\xi_j$.
    pub(crate) fn twists(&self, values: &[JointValue]) -> LegTwists {
        let mut prefix = Isometry3::identity();
        let mut twists = Vec::with_capacity(self.joints.len() + 2);
        let mut prefixes = Vec::with_capacity(self.joints.len());
        for (j, (joint, value)) in self.joints.iter().zip(values).enumerate() {
            for twist in joint.home_twists().into_iter().flatten() {
                twists.push((j, adjoint(&prefix, &twist)));
            }
            prefix *= joint.displacement(value);
            prefixes.push(prefix);
        }
        LegTwists {
            displacement: prefix,
            twists,
            prefixes,
        }
    }

    /// The leg displacement $D(\theta)$ alone.
    #[cfg(test)]
    fn displacement(&self, values: &[JointValue]) -> Isometry3<f64> {
        self.joints
            .iter()
            .zip(values)
            .fold(Isometry3::identity(), |g, (joint, v)| {
                g * joint.displacement(v)
            })
    }

    /// Coordinates of the whole leg.
    pub(crate) fn dof(&self) -> usize {
        self.joints.iter().map(Joint::dof).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each twist moves the leg end as a central difference of the displacement says.
    #[test]
    fn twists_match_central_differences() {
        let leg = LegChain {
            joints: vec![
                Joint::Revolute {
                    axis: Vector3::z(),
                    point: Vector3::new(0.3, 0.0, 0.0),
                },
                Joint::Prismatic {
                    axis: Vector3::new(0.0, 0.6, 0.8),
                },
                Joint::Spherical {
                    center: Vector3::new(0.1, 0.2, 0.5),
                },
            ],
            actuators: vec![LegActuator {
                joint: 1,
                offset: 0.0,
                limits: None,
                name: "legs[0].joints[1]".into(),
                reflected_inertia: 0.0,
            }],
            bodies: vec![],
            letters: "RPS".into(),
        };
        let values = [
            JointValue::Scalar(0.4),
            JointValue::Scalar(0.2),
            JointValue::Ball(Rotation3::new(Vector3::new(0.1, -0.2, 0.3))),
        ];
        let t = leg.twists(&values);
        let h = 1e-6;
        for (k, (j, twist)) in t.twists.iter().enumerate() {
            let perturbed = |s: f64| {
                let mut v = values;
                v[*j] = match v[*j] {
                    JointValue::Scalar(x) => JointValue::Scalar(x + s),
                    JointValue::Ball(r) => {
                        let mut d = Vector3::zeros();
                        d[k - 2] = s;
                        // Space-frame perturbation about the centre: D' = exp(ξ s) D.
                        JointValue::Ball(Rotation3::new(d) * r)
                    }
                };
                leg.displacement(&v)
            };
            let (gp, gm) = (perturbed(h), perturbed(-h));
            // D(θ) moves its translation point t at v_O + ω × t, and turns at ω.
            let v = (gp.translation.vector - gm.translation.vector) / (2.0 * h);
            let w = (gp.rotation * gm.rotation.inverse()).scaled_axis() / (2.0 * h);
            let omega: Vector3<f64> = twist.fixed_rows::<3>(0).into();
            let v_o: Vector3<f64> = twist.fixed_rows::<3>(3).into();
            let expected_v = v_o + omega.cross(&t.displacement.translation.vector);
            assert!((w - omega).amax() < 1e-8, "ω of coordinate {k}");
            assert!((v - expected_v).amax() < 1e-8, "v of coordinate {k}");
        }
    }
}
