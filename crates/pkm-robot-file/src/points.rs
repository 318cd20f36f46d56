//! The joint points of a leg at a configuration, for drawings, and a bound on the reachable
//! platform positions derived from the same points.
//!
//! A leg's **stations** are, from the base: the zero of its leading prismatic joints (the rail
//! origin, when the leg starts with P joints), the point of every R and S joint (the two R of a
//! U, and consecutive joints through one point, make one station), and the platform anchor
//! $c$, the last joint point (carried by the platform after trailing P joints, if any). Station
//! $k$ of joint $j$ (home point $h_j$) is at $g_{1..j-1}\,h_j$, the product of the joint
//! displacements before it applied to its home point (Lynch & Park eq. 4.14): the point is fixed
//! by joint $j$ itself, so it lies on the two bodies joint $j$ joins.
//!
//! Between two consecutive stations $a$, $b$ there are only prismatic joints $k$ (values $d_k$,
//! zero at home), so with $g = g_{1..a}$
//! $$P_b - P_a = R_g\,\big(h_b - h_a + \textstyle\sum_k d_k u_k\big), \qquad
//!   \lvert P_b - P_a\rvert \le \lvert h_b - h_a\rvert + \textstyle\sum_k \lvert d_k\rvert, \tag{1}$$
//! with equality to the home length when no P joint lies between them (a rigid link).

use crate::chain::{Joint, LegChain};
use crate::closure::Configuration;
use crate::model::RobotModel;
use crate::pose::platform_pose;
use nalgebra::{Isometry3, Point3, Vector3};

/// What a station of a leg is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegPointKind {
    /// The zero of the leg's leading prismatic joints (a rail's origin), fixed on the base.
    RailOrigin,
    /// A passive joint fixed on the base (the leg's first joint point).
    BaseJoint,
    /// The actuated revolute joint's point, or the joint carried by an actuated prismatic
    /// joint (a carriage).
    Actuator,
    /// A passive joint along the leg.
    Joint,
    /// The platform anchor: the leg's last joint point, on the platform.
    Platform,
}

/// A station of a leg at a configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegPoint {
    /// What the station is.
    pub kind: LegPointKind,
    /// Position in the base frame (m).
    pub position: Vector3<f64>,
}

/// The straight segment between two consecutive stations of a leg.
#[derive(Debug, Clone, PartialEq)]
pub struct LegSegment {
    /// Index of its first station.
    pub from: usize,
    /// Index of its second station.
    pub to: usize,
    /// The prismatic joints between its ends (indices into the leg's elementary joints):
    /// none for a rigid link, whose length is `home_length` at every configuration.
    pub prismatic: Vec<usize>,
    /// Whether the actuator moves it: an actuated R at its first station or an actuated P in
    /// between.
    pub actuated: bool,
    /// Its length at home (m); for the segment from a rail origin, the actuators' offsets.
    pub home_length: f64,
}

/// The stations of one leg and the segments between them.
#[derive(Debug, Clone, PartialEq)]
pub struct LegPoints {
    /// From the base to the platform anchor (the last one).
    pub points: Vec<LegPoint>,
    /// Between consecutive points.
    pub segments: Vec<LegSegment>,
}

/// Where a station is at a configuration.
#[derive(Debug, Clone, Copy)]
enum Placement {
    /// Fixed on the base.
    Fixed(Vector3<f64>),
    /// The home point of joint `j`, moved by the joints before it.
    Joint(usize, Vector3<f64>),
    /// A point of the platform at home, moved by the whole leg.
    End(Vector3<f64>),
}

/// A station of a leg's layout: where it is, what it is, its home position and the joints
/// it holds.
#[derive(Debug, Clone)]
struct Station {
    placement: Placement,
    kind: LegPointKind,
    home: Vector3<f64>,
    /// The prismatic joints between the previous station and this one.
    prismatic: Vec<usize>,
    /// Whether it holds the actuated revolute joint.
    actuator: bool,
    /// Whether it is a ball or universal joint: a spherical joint, or two or more revolute
    /// joints through its point.
    ball: bool,
}

impl RobotModel {
    /// The stations of leg `leg` at home, independent of the configuration.
    fn leg_layout(&self, leg: usize) -> Vec<Station> {
        let chain = &self.legs[leg];
        let tolerance = 1e-12 * self.size;
        let mut stations: Vec<Station> = Vec::new();
        let mut pending: Vec<usize> = Vec::new();
        for (j, joint) in chain.joints.iter().enumerate() {
            let point = match joint {
                Joint::Revolute { point, .. } => *point,
                Joint::Spherical { center } => *center,
                Joint::Prismatic { .. } => {
                    pending.push(j);
                    continue;
                }
            };
            let actuator = chain.is_actuated(j);
            let spherical = matches!(joint, Joint::Spherical { .. });
            if stations.is_empty() && !pending.is_empty() {
                stations.push(self.rail_origin(leg, &pending, point));
            }
            let after_actuated_p = pending.iter().any(|&k| chain.is_actuated(k));
            match stations.last_mut() {
                Some(last) if pending.is_empty() && (last.home - point).norm() <= tolerance => {
                    last.actuator |= actuator;
                    last.ball = true;
                    if actuator {
                        last.kind = LegPointKind::Actuator;
                    }
                }
                last => {
                    let kind = if actuator || after_actuated_p {
                        LegPointKind::Actuator
                    } else if last.is_none() {
                        LegPointKind::BaseJoint
                    } else {
                        LegPointKind::Joint
                    };
                    stations.push(Station {
                        placement: Placement::Joint(j, point),
                        kind,
                        home: point,
                        prismatic: std::mem::take(&mut pending),
                        actuator,
                        ball: spherical,
                    });
                }
            }
        }
        self.close_layout(leg, stations, pending)
    }

    /// The zero of the leading prismatic joints `pending` of leg `leg`, whose first joint point
    /// is at `first` at home: the actuated one's offset taken back along its axis.
    fn rail_origin(&self, leg: usize, pending: &[usize], first: Vector3<f64>) -> Station {
        let chain = &self.legs[leg];
        let mut origin = first;
        for &k in pending {
            if let (Some(actuator), Joint::Prismatic { axis }) =
                (chain.actuator_at(k), &chain.joints[k])
            {
                origin -= axis * actuator.offset;
            }
        }
        Station {
            placement: Placement::Fixed(origin),
            kind: LegPointKind::RailOrigin,
            home: origin,
            prismatic: Vec::new(),
            actuator: false,
            ball: false,
        }
    }

    /// Ends the layout with the platform anchor: the last joint point; after trailing P joints,
    /// the foot of the platform origin on the last one's axis through the last joint point
    /// (the platform's point on the slider's line, as the Tricept's central leg carries it);
    /// for a leg without joint points, the platform origin.
    fn close_layout(
        &self,
        leg: usize,
        mut stations: Vec<Station>,
        pending: Vec<usize>,
    ) -> Vec<Station> {
        let origin = self.home_pose.translation.vector;
        let anchor = match (
            stations.last(),
            pending.last().map(|&k| self.legs[leg].joints[k]),
        ) {
            (Some(last), Some(Joint::Prismatic { axis })) => {
                last.home + axis * (origin - last.home).dot(&axis)
            }
            (Some(last), _) => last.home,
            (None, _) => origin,
        };
        if stations.is_empty() {
            stations.push(self.rail_origin(leg, &pending, anchor));
        }
        if pending.is_empty() {
            if let Some(last) = stations.last_mut() {
                last.kind = LegPointKind::Platform;
            }
        } else {
            stations.push(Station {
                placement: Placement::End(anchor),
                kind: LegPointKind::Platform,
                home: anchor,
                prismatic: pending,
                actuator: false,
                ball: false,
            });
        }
        stations
    }

    /// The stations of leg `leg` at configuration `config` and the segments between them
    /// (module documentation): every rigid segment keeps its home length, and the platform
    /// anchor is the platform pose applied to the anchor's position in the platform frame.
    ///
    /// # Example
    /// ```
    /// use pkm_robot_file::RobotModel;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/robots/tsai.toml")).unwrap();
    /// let robot = RobotModel::from_toml(&text).unwrap();
    /// let c = robot.inverse_kinematics_configuration(&[0.1, 0.2, 0.6], robot.home_mode()).unwrap();
    /// let leg = robot.leg_points(0, &c).unwrap();
    /// for s in leg.segments.iter().filter(|s| s.prismatic.is_empty()) {
    ///     let length = (leg.points[s.to].position - leg.points[s.from].position).norm();
    ///     assert!((length - s.home_length).abs() < 1e-9);
    /// }
    /// ```
    ///
    /// Returns `None` for a leg index out of range or a configuration of another robot.
    pub fn leg_points(&self, leg: usize, config: &Configuration) -> Option<LegPoints> {
        let (layout, prefixes) = self.placed_layout(leg, config)?;
        let points = layout
            .iter()
            .map(|s| LegPoint {
                kind: s.kind,
                position: position(s, &prefixes),
            })
            .collect();
        Some(LegPoints {
            points,
            segments: segments(&layout, &self.legs[leg]),
        })
    }

    /// The layout of leg `leg` and the products $g_{1..j-1}$ of its joint displacements at
    /// `config`, $j = 1, \dots, n + 1$.
    fn placed_layout(
        &self,
        leg: usize,
        config: &Configuration,
    ) -> Option<(Vec<Station>, Vec<Isometry3<f64>>)> {
        let values = config.joints.get(leg)?;
        let chain = self.legs.get(leg)?;
        if values.len() != chain.joints.len() {
            return None;
        }
        let mut prefixes = Vec::with_capacity(values.len() + 1);
        let mut g = Isometry3::identity();
        for (joint, value) in chain.joints.iter().zip(values) {
            prefixes.push(g);
            g *= joint.displacement(value);
        }
        prefixes.push(g);
        Some((self.leg_layout(leg), prefixes))
    }

    /// The bend (rad) of every leg at `config`: the largest over its ball and universal joints
    /// (a spherical joint, or two or more revolute joints through one point) of the angle by
    /// which the link leaving the joint has turned, seen from the body it leaves, since home:
    /// $\angle(R_j^{\top} d,\ d_0)$ with $d$ the next segment, $d_0$ its home value and
    /// $R_j$ the rotation of the displacements before the joint (the identity for a joint on
    /// the base). At the platform anchor the link entering the joint is seen from the
    /// platform: $\angle((R_X R_M^{\top})^{\top} d,\ d_0)$ with the previous segment. Each
    /// angle is the cone angle of a socket whose axis is the link's direction at home; a leg
    /// without such joints bends 0. `None` for a configuration of another robot or a segment
    /// of zero length.
    pub fn passive_bends(&self, config: &Configuration) -> Option<Vec<f64>> {
        let turn = self.platform_pose_of(config).rotation * self.home_pose.rotation.inverse();
        (0..self.legs.len())
            .map(|leg| {
                let (layout, prefixes) = self.placed_layout(leg, config)?;
                let at: Vec<Vector3<f64>> = layout.iter().map(|s| position(s, &prefixes)).collect();
                let last = layout.len() - 1;
                let mut bend = 0.0_f64;
                for (k, station) in layout.iter().enumerate().filter(|(_, s)| s.ball) {
                    let angle = if k < last {
                        let Placement::Joint(j, _) = station.placement else {
                            continue;
                        };
                        let d = prefixes[j].rotation.inverse() * (at[k + 1] - at[k]);
                        angle_between(&d, &(layout[k + 1].home - station.home))?
                    } else if k > 0 {
                        let d = turn.inverse() * (at[k] - at[k - 1]);
                        angle_between(&d, &(station.home - layout[k - 1].home))?
                    } else {
                        0.0
                    };
                    bend = bend.max(angle);
                }
                Some(bend)
            })
            .collect()
    }

    /// A ball, centre and radius (m), that holds the platform origin at every configuration
    /// where leg `leg` is closed; `None` when one of its prismatic joints has no travel limit
    /// (a passive one, or an actuated one without `limits`).
    ///
    /// The centre is the leg's first station $P_0$, fixed on the base. By the triangle
    /// inequality over its stations and eq. (1) of the module,
    /// $$\lvert p - P_0\rvert \le \sum_{\text{segments}} \Big(\lvert h_b - h_a\rvert +
    ///   \sum_k \max_{d_k} \lvert d_k\rvert\Big) + \lvert p_0 - c\rvert,$$
    /// where the last term is the rigid platform vector from the anchor $c$ to the platform
    /// origin $p$ (home $p_0$), and an actuated P joint moves by at most
    /// $\max(\lvert l - o\rvert, \lvert u - o\rvert)$ from home within `limits` $= [l, u]$ and
    /// `offset` $o$. For the segment from a rail origin, $h_b - h_a$ is the actuator's offset
    /// along its axis. Every reachable platform position closes every leg, so it lies in every
    /// leg's ball.
    pub fn leg_reach_ball(&self, leg: usize) -> Option<(Vector3<f64>, f64)> {
        let chain = self.legs.get(leg)?;
        let layout = self.leg_layout(leg);
        let travel = |k: usize| {
            let actuator = chain.actuator_at(k)?;
            let [lo, hi] = actuator.limits?;
            Some(
                (lo - actuator.offset)
                    .abs()
                    .max((hi - actuator.offset).abs()),
            )
        };
        let mut radius = 0.0;
        for pair in layout.windows(2) {
            radius += (pair[1].home - pair[0].home).norm();
            for &k in &pair[1].prismatic {
                radius += travel(k)?;
            }
        }
        let (first, anchor) = (layout.first()?, layout.last()?);
        radius += (self.home_pose.translation.vector - anchor.home).norm();
        Some((first.home, radius))
    }

    /// An axis-aligned box `[lower, upper]` (m) that holds every reachable platform position:
    /// the intersection of the boxes around the legs' reach balls
    /// ([`RobotModel::leg_reach_ball`]). `None` when no leg has a bounded ball; an empty
    /// intersection (lower above upper on some axis) means no position is reachable.
    pub fn reach_box(&self) -> Option<[Vector3<f64>; 2]> {
        let balls = (0..self.legs.len()).filter_map(|i| self.leg_reach_ball(i));
        balls
            .map(|(c, r)| [c.add_scalar(-r), c.add_scalar(r)])
            .reduce(|[lo, hi], [l, u]| [lo.sup(&l), hi.inf(&u)])
    }

    /// The platform pose of a configuration, as an isometry (base frame).
    pub fn platform_pose_of(&self, config: &Configuration) -> Isometry3<f64> {
        platform_pose(self.orientation, &config.pose)
    }

    /// The home platform pose.
    pub fn home_platform_pose(&self) -> Isometry3<f64> {
        self.home_pose
    }
}

/// Where station `s` is, given the displacement products `prefixes` of its leg.
fn position(s: &Station, prefixes: &[Isometry3<f64>]) -> Vector3<f64> {
    match s.placement {
        Placement::Fixed(p) => p,
        Placement::Joint(j, h) => (prefixes[j] * Point3::from(h)).coords,
        Placement::End(h) => (prefixes[prefixes.len() - 1] * Point3::from(h)).coords,
    }
}

/// The angle (rad) between `a` and `b`, `None` when one has zero length.
fn angle_between(a: &Vector3<f64>, b: &Vector3<f64>) -> Option<f64> {
    let (na, nb) = (a.norm(), b.norm());
    (na > 0.0 && nb > 0.0 && na.is_finite() && nb.is_finite())
        .then(|| a.cross(b).norm().atan2(a.dot(b)))
}

/// The segments between consecutive stations of a layout of leg `chain`.
fn segments(layout: &[Station], chain: &LegChain) -> Vec<LegSegment> {
    (1..layout.len())
        .map(|b| LegSegment {
            from: b - 1,
            to: b,
            prismatic: layout[b].prismatic.clone(),
            actuated: layout[b - 1].actuator
                || layout[b].prismatic.iter().any(|&k| chain.is_actuated(k)),
            home_length: (layout[b].home - layout[b - 1].home).norm(),
        })
        .collect()
}
