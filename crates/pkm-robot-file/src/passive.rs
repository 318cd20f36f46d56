//! Closed-form passive joints of the distance and arm leg classes (issues 30 and 31): with the
//! actuator known, the joints that rotate the leg about two points.
//!
//! Such a leg is, in the product of exponentials $D = e^{[\xi_1]\theta_1}\cdots$
//! ([`crate::chain`]), a known prefix $T_0$ (an arm's actuated joint), a first group of
//! revolute joints (or one ball) through a point $P_1$, an optional slide $s$ along $u$ (a
//! distance leg's actuated P), and a second group through $P_2$:
//! $D = T_0\, G_1\, e^{[u] s}\, G_2$, each $G_k$ a rotation $R_k$ about $P_k$. Closing it on
//! the displacement $T = X M^{-1}$ asked by the platform pose ($T' = T_0^{-1} T$) leaves (eq. P1)
//! $$R_1 R_2 = R_{T'},\qquad R_1 r_0 = r,\quad r_0 = P_2 + s\,u - P_1,\ r = T' P_2 - P_1,$$
//! the second because $G_2$ fixes $P_2$. So the group of one or two revolute joints points
//! $r_0$ along $r$ (Paden–Kahan subproblems 1 and 2, [`crate::paden_kahan`], the root nearer
//! home) and the other group takes the rest of the rotation; a first group that is a ball
//! leaves the pointing to the second: $R_2$ turns $R_{T'}^\top r$ onto $r_0$, then
//! $R_1 = R_{T'} R_2^\top$. Two balls (an SPS leg) leave the spin about the rod free, and
//! legs of other shapes have no closed form here: the damped Newton of [`crate::ik`] solves
//! them. Every closed-form solution is checked to close the leg to $10^{-10}$ of the robot's
//! size, and falls back to the numerical solve otherwise.

use crate::chain::{Joint, JointValue, LegChain};
use crate::leg_ik::{LegClass, arm_split, group_points};
use crate::paden_kahan::{perpendicular, turn, two_axes};
use nalgebra::{Isometry3, Point3, Rotation3, Unit, Vector3};

/// The rotations a group of joints through one point can make.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// No joint: the identity.
    Empty,
    /// One revolute joint about unit `axis`.
    One(Vector3<f64>),
    /// Two revolute joints on non-parallel unit axes, in chain order.
    Two(Vector3<f64>, Vector3<f64>),
    /// One spherical joint.
    Ball,
}

/// A group of consecutive joints through one point.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Group {
    /// Index of its first joint in the leg.
    start: usize,
    /// The common point (base frame, at home).
    point: Vector3<f64>,
    kind: Kind,
}

impl Group {
    /// `joints` (starting at leg joint `start`) through `point`, when they make one of the
    /// kinds above.
    fn of(joints: &[Joint], start: usize, point: Vector3<f64>) -> Option<Self> {
        let kind = match joints {
            [] => Kind::Empty,
            [Joint::Revolute { axis, .. }] => Kind::One(*axis),
            [
                Joint::Revolute { axis: a, .. },
                Joint::Revolute { axis: b, .. },
            ] if a.cross(b).norm() > 1e-6 => Kind::Two(*a, *b),
            [Joint::Spherical { .. }] => Kind::Ball,
            _ => return None,
        };
        Some(Self { start, point, kind })
    }

    /// The group's values making rotation `r` (already known to be one it can make; checked
    /// with the whole leg).
    fn values_of(&self, r: &Rotation3<f64>) -> Vec<JointValue> {
        match self.kind {
            Kind::Empty => vec![],
            Kind::One(w) => {
                let v = perpendicular(&w);
                vec![JointValue::Scalar(turn(&w, &v, &(r * v)))]
            }
            Kind::Two(w1, w2) => {
                // e^{w1 α} e^{w2 β} w2 = e^{w1 α} w2 = R w2.
                let alpha = turn(&w1, &w2, &(r * w2));
                let rest = Rotation3::from_axis_angle(&Unit::new_unchecked(w1), -alpha) * r;
                let v = perpendicular(&w2);
                let beta = turn(&w2, &v, &(rest * v));
                vec![JointValue::Scalar(alpha), JointValue::Scalar(beta)]
            }
            Kind::Ball => vec![JointValue::Ball(*r)],
        }
    }

    /// The group's rotation turning `from` onto `to`, for a group of one or two revolute
    /// joints (the nearer-home root); `None` for the other kinds or out of reach.
    fn pointing(&self, from: &Vector3<f64>, to: &Vector3<f64>) -> Option<Rotation3<f64>> {
        let about =
            |w: &Vector3<f64>, t: f64| Rotation3::from_axis_angle(&Unit::new_unchecked(*w), t);
        match self.kind {
            Kind::One(w) => Some(about(&w, turn(&w, from, to))),
            Kind::Two(w1, w2) => {
                let (alpha, beta) = two_axes(&w1, &w2, from, to)?;
                Some(about(&w1, alpha) * about(&w2, beta))
            }
            Kind::Empty => Some(Rotation3::identity()),
            Kind::Ball => None,
        }
    }
}

/// A leg whose passive joints have a closed form (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PassiveLayout {
    /// Joints before the first group, all actuated (their values known).
    prefix: usize,
    first: Group,
    /// The actuated P joint between the groups (a distance leg): its index and unit axis.
    slide: Option<(usize, Vector3<f64>)>,
    second: Group,
}

impl PassiveLayout {
    /// The layout of `leg` of class `class` (platform at `home`), if it has one.
    pub(crate) fn new(
        leg: &LegChain,
        class: &LegClass,
        home: &Isometry3<f64>,
        size: f64,
    ) -> Option<Self> {
        let joints = &leg.joints;
        match class {
            LegClass::Distance { .. } => {
                let a = leg.sole_actuator()?.joint;
                let Joint::Prismatic { axis } = joints[a] else {
                    return None;
                };
                let (p1, p2) = group_points(&joints[..a], &joints[a + 1..], size)?;
                Some(Self {
                    prefix: 0,
                    first: Group::of(&joints[..a], 0, p1)?,
                    slide: Some((a, axis)),
                    second: Group::of(&joints[a + 1..], a + 1, p2)?,
                })
            }
            LegClass::RevoluteArm { .. } | LegClass::PrismaticArm { .. } => {
                let (m, e, c) = arm_split(leg, home, size)?;
                Some(Self {
                    prefix: 1,
                    first: Group::of(&joints[1..=m], 1, e)?,
                    slide: None,
                    second: Group::of(&joints[m + 1..], m + 1, c)?,
                })
            }
            LegClass::Numeric => None,
        }
    }

    /// The joint values of `leg` with its actuator at `motion` that close it on the leg
    /// displacement `target` ($D(\theta) = T$, eq. P1), checked to $10^{-10}$ `size`; `None`
    /// where the closed form does not apply (two balls, out of reach) or does not close.
    pub(crate) fn solve(
        &self,
        leg: &LegChain,
        motion: f64,
        target: &Isometry3<f64>,
        size: f64,
    ) -> Option<Vec<JointValue>> {
        let actuator = leg.sole_actuator()?.joint;
        let mut values = leg.home_values();
        values[actuator] = JointValue::Scalar(motion);
        let prefix = leg.joints[..self.prefix]
            .iter()
            .zip(&values)
            .fold(Isometry3::identity(), |g, (j, v)| g * j.displacement(v));
        let relative = prefix.inverse() * target;
        let slide = self.slide.map_or(Vector3::zeros(), |(_, u)| u * motion);
        let (p1, p2) = (self.first.point, self.second.point);
        let r0 = p2 + slide - p1;
        let r = (relative * Point3::from(p2)).coords - p1;
        let total = relative.rotation.to_rotation_matrix();
        let (r1, r2) = match self.first.kind {
            Kind::Ball => {
                let r2 = self.second.pointing(&(total.inverse() * r), &r0)?;
                (total * r2.inverse(), r2)
            }
            _ => {
                let r1 = self.first.pointing(&r0, &r)?;
                (r1, r1.inverse() * total)
            }
        };
        for (group, rotation) in [(&self.first, r1), (&self.second, r2)] {
            for (k, v) in group.values_of(&rotation).into_iter().enumerate() {
                values[group.start + k] = v;
            }
        }
        let reached = leg
            .joints
            .iter()
            .zip(&values)
            .fold(Isometry3::identity(), |g, (j, v)| g * j.displacement(v));
        let turned = reached.rotation.to_rotation_matrix().into_inner()
            - target.rotation.to_rotation_matrix().into_inner();
        let gap =
            (reached.translation.vector - target.translation.vector).norm() + size * turned.amax();
        (gap <= 1e-10 * size).then_some(values)
    }
}

#[cfg(test)]
mod tests {
    use crate::RobotModel;
    use crate::chain::JointValue;
    use crate::pose::platform_pose;

    fn gap(a: &JointValue, b: &JointValue) -> f64 {
        match (a, b) {
            (JointValue::Scalar(x), JointValue::Scalar(y)) => {
                crate::leg_ik::wrap_angle(x - y).abs().min((x - y).abs())
            }
            (JointValue::Ball(r), JointValue::Ball(s)) => (r.matrix() - s.matrix()).amax(),
            _ => f64::INFINITY,
        }
    }

    /// On every example robot, at 20 task poses around home, the closed-form passive joints
    /// equal the damped-Newton solve from home to 1e-9 (the same branch), and the legs that
    /// have a closed form are the ones expected.
    #[test]
    fn closed_form_passive_joints_equal_the_numerical_solve() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/robots");
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        entries.sort();
        let mut closed_legs = std::collections::BTreeMap::new();
        for path in entries {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            let model = RobotModel::from_toml(&std::fs::read_to_string(&path).unwrap()).unwrap();
            let with_layout: Vec<usize> = (0..model.legs.len())
                .filter(|&i| model.passive[i].is_some())
                .collect();
            let mut compared = 0;
            for k in 0..20 {
                let x: Vec<f64> = model
                    .task
                    .iter()
                    .enumerate()
                    .map(|(c, &t)| {
                        let s = (f64::from(k) * (0.7 + 0.9 * c as f64)).sin();
                        model.home[t] + s * if t < 3 { 0.05 * model.size } else { 0.1 }
                    })
                    .collect();
                let Ok(config) = model.inverse_kinematics_configuration(&x, model.home_mode())
                else {
                    continue;
                };
                let target =
                    platform_pose(model.orientation, &config.pose) * model.home_pose.inverse();
                for &i in &with_layout {
                    let motion = config.actuator_motion(
                        &model,
                        model.actuators.iter().position(|&(l, _)| l == i).unwrap(),
                    );
                    let closed = model.passive[i]
                        .as_ref()
                        .unwrap()
                        .solve(&model.legs[i], motion, &target, model.size)
                        .unwrap_or_else(|| panic!("{name}: leg {i} at {x:?}"));
                    let newton = model.newton_leg(i, Some(motion), &config).unwrap();
                    let worst = closed
                        .iter()
                        .zip(&newton)
                        .map(|(a, b)| gap(a, b))
                        .fold(0.0, f64::max);
                    assert!(worst < 1e-9, "{name}: leg {i} at {x:?}: {worst:e}");
                    compared += 1;
                }
            }
            assert!(with_layout.is_empty() || compared > 0, "{name}");
            closed_legs.insert(name, with_layout.len());
        }
        for (name, legs) in [
            ("stewart_gough", 6),
            ("hexa", 6),
            ("rotary_delta", 3),
            ("three_prs", 3),
            ("exechon", 3),
            ("five_bar", 2),
            ("four_rrr", 4),
            ("agile_eye", 3),
        ] {
            assert_eq!(closed_legs[name], legs, "{name}: {closed_legs:?}");
        }
    }
}
