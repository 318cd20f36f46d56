//! The skeleton of a mechanism at a pose: its joint points and the links between them, for
//! drawings (`pkm-draw`) and for checks that a drawing is the assembled robot.
//!
//! Each skeleton is built from the model's public getters and its closed-form inverse
//! kinematics only, so every link of kind [`LinkKind::Actuated`] or [`LinkKind::Passive`] has the
//! length of the design's link (arm, forearm, parallelogram, or the leg length the inverse
//! kinematics gives): the tests check this to 1e-12.

use crate::{
    ElbowMode, LegBranch, LinearDelta, LinearDeltaMode, RotaryDelta, StewartGough, ThreeUpu,
    Tsai3Dof, WrenchSystem,
};
use nalgebra::{Isometry3, Point3, Vector3};
use pkm_traits::{InverseKinematics, KinematicsError};
use serde::Serialize;

/// What a point of a skeleton is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum PointKind {
    /// A fixed point of the frame that is no joint (the end of a rail).
    Base,
    /// An actuated joint on the base: a motor axis, a carriage on its rail.
    Actuator,
    /// A passive joint fixed on the base (the lower universal joint of a prismatic leg).
    BaseJoint,
    /// A passive joint along a leg: an elbow or knee, a parallelogram joint.
    Passive,
    /// A joint on the moving platform (spherical, universal, or a parallelogram's end).
    Platform,
    /// The platform's reference point (the task position).
    Centre,
}

/// What a link of a skeleton is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum LinkKind {
    /// Part of the fixed frame (between base joints, a rail).
    Base,
    /// A link whose length or angle is actuated: a motor arm, a prismatic leg, a carriage's
    /// travel along its rail.
    Actuated,
    /// A passive link of fixed length: a forearm, a parallelogram.
    Passive,
    /// Part of the moving platform (between platform joints).
    Platform,
}

/// One point of a skeleton.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SkeletonPoint {
    /// A short name (`A1`, `B1`, `C1`, `p`), as the papers label their figures.
    pub label: String,
    /// What the point is.
    pub kind: PointKind,
    /// Position in the world (task) frame.
    pub position: Vector3<f64>,
}

/// A straight link between two points of a skeleton.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Link {
    /// Index of the first point in [`Skeleton::points`].
    pub from: usize,
    /// Index of the second point.
    pub to: usize,
    /// What the link is.
    pub kind: LinkKind,
}

/// The joint points of a mechanism at a pose and the links between them.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Skeleton {
    /// The points.
    pub points: Vec<SkeletonPoint>,
    /// The links, as indices into `points`.
    pub links: Vec<Link>,
}

impl Skeleton {
    /// The distance between the ends of link `k`; `None` when `k` or one of its ends is out of
    /// range.
    pub fn link_length(&self, k: usize) -> Option<f64> {
        let link = self.links.get(k)?;
        let a = self.points.get(link.from)?;
        let b = self.points.get(link.to)?;
        Some((b.position - a.position).norm())
    }

    /// The links of `kind`, in order.
    pub fn links_of(&self, kind: LinkKind) -> impl Iterator<Item = &Link> {
        self.links.iter().filter(move |l| l.kind == kind)
    }

    /// Adds a point and returns its index.
    fn point(&mut self, label: String, kind: PointKind, position: Vector3<f64>) -> usize {
        self.points.push(SkeletonPoint {
            label,
            kind,
            position,
        });
        self.points.len() - 1
    }

    fn link(&mut self, from: usize, to: usize, kind: LinkKind) {
        self.links.push(Link { from, to, kind });
    }

    /// Closes the points `ring` into a polygon of links of `kind`.
    fn ring(&mut self, ring: &[usize], kind: LinkKind) {
        for (k, &from) in ring.iter().enumerate() {
            self.link(from, ring[(k + 1) % ring.len()], kind);
        }
    }

    /// The rotary Delta / NUWAR at plate position `p` in elbow mode `mode`: motors $A_i$
    /// (actuators), elbows $B_i = A_i + L_a d_i(\theta_i)$ with $\theta$ from the inverse
    /// kinematics, plate joint-pair mid-points $C_i = p + c_i$ and the plate centre $p$. Links:
    /// the motor triangle (base), the arms $A_iB_i$ (actuated, length $L_a$), the forearms
    /// $B_iC_i$ (passive, length $L_b$), and the plate triangle $C_0C_1C_2$.
    ///
    /// # Errors
    /// The inverse kinematics' [`KinematicsError`] (non-finite or unreachable `p`).
    pub fn rotary_delta(
        robot: &RotaryDelta,
        p: &Vector3<f64>,
        mode: ElbowMode,
    ) -> Result<Self, KinematicsError> {
        let theta = robot.inverse_kinematics(p, mode)?;
        let mut s = Self::default();
        s.point("p".into(), PointKind::Centre, *p);
        let (mut motors, mut plate) = ([0; 3], [0; 3]);
        for (i, leg) in robot.legs().iter().enumerate() {
            let n = i + 1;
            motors[i] = s.point(format!("A{n}"), PointKind::Actuator, leg.motor);
            let elbow = s.point(
                format!("B{n}"),
                PointKind::Passive,
                robot.elbow(i, theta[i]),
            );
            plate[i] = s.point(format!("C{n}"), PointKind::Platform, p + leg.plate_offset);
            s.link(motors[i], elbow, LinkKind::Actuated);
            s.link(elbow, plate[i], LinkKind::Passive);
        }
        s.ring(&motors, LinkKind::Base);
        s.ring(&plate, LinkKind::Platform);
        Ok(s)
    }

    /// The Linear Delta at end-effector position `p` in `mode`: rail $i$ along $x$ through
    /// $(A_{iy}, A_{iz})$, drawn between its ends $x = \pm(\max_i |q_i| + \max_i L_i)$ (base),
    /// the rail origin $(0, A_{iy}, A_{iz})$ and the carriage at $x = q_i$ (actuated link of
    /// length $|q_i|$, the inverse kinematics' joint value), and the arm from the carriage to
    /// $p$ (passive, length $L_i$). The end effector is the point $p$.
    ///
    /// # Errors
    /// The inverse kinematics' [`KinematicsError`].
    pub fn linear_delta(
        robot: &LinearDelta,
        p: &Vector3<f64>,
        mode: LinearDeltaMode,
    ) -> Result<Self, KinematicsError> {
        let q = robot.inverse_kinematics(p, mode)?;
        let lengths = robot.arm_lengths();
        let half = q.amax().max(p.x.abs()) + lengths.iter().copied().fold(0.0, f64::max);
        let mut s = Self::default();
        let centre = s.point("p".into(), PointKind::Centre, *p);
        for (i, [y, z]) in robot.rails().into_iter().enumerate() {
            let n = i + 1;
            let start = s.point(format!("R{n}-"), PointKind::Base, Vector3::new(-half, y, z));
            let end = s.point(format!("R{n}+"), PointKind::Base, Vector3::new(half, y, z));
            s.link(start, end, LinkKind::Base);
            let origin = s.point(format!("O{n}"), PointKind::Base, Vector3::new(0.0, y, z));
            let carriage = s.point(
                format!("A{n}"),
                PointKind::Actuator,
                Vector3::new(q[i], y, z),
            );
            s.link(origin, carriage, LinkKind::Actuated);
            s.link(carriage, centre, LinkKind::Passive);
        }
        Ok(s)
    }

    /// The Tsai platform at position `p` with every leg in `branch`.
    ///
    /// The model fixes only $c - r$ (platform minus base radius) and $d + e$ (the two offsets of
    /// the parallelogram); the drawing takes the base radius $r = \max(a, r - c)$ (so that
    /// $c \ge 0$) and splits the offsets evenly, $d = e = (d + e)/2$. Leg $i$ (frame $u_i$ radial,
    /// $v_i$ tangential, $w = Z$): $A_i = r u_i$, $B_i = A_i + a(\cos\theta_1 u_i + \sin\theta_1 w)$,
    /// $C_i = B_i + d\,n_i$, $D_i = C_i + b(\sin\theta_3 n_i + \cos\theta_3 v_i)$, $E_i = D_i + e\,n_i$
    /// with $n_i = \cos\theta_2 u_i + \sin\theta_2 w$ and the angles of the leg's inverse
    /// kinematics: the chain closes at $E_i = p + c\,u_i$. Links: base and platform triangles,
    /// $A_iB_i$ (actuated, $a$), $B_iC_i$, $C_iD_i$, $D_iE_i$ (passive: $d$, $b$, $e$).
    ///
    /// # Errors
    /// The leg inverse kinematics' [`KinematicsError`].
    pub fn tsai(
        robot: &Tsai3Dof,
        p: &Vector3<f64>,
        branch: LegBranch,
    ) -> Result<Self, KinematicsError> {
        let base_radius = robot.a().max(-robot.c_minus_r());
        let offset = 0.5 * robot.d_plus_e();
        let mut s = Self::default();
        s.point("p".into(), PointKind::Centre, *p);
        let (mut base, mut plate) = ([0; 3], [0; 3]);
        for (i, phi) in robot.phi().into_iter().enumerate() {
            let angles = robot.leg_inverse_kinematics(i, p, branch)?;
            let u = Vector3::new(phi.cos(), phi.sin(), 0.0);
            let v = Vector3::new(-phi.sin(), phi.cos(), 0.0);
            let w = Vector3::z();
            let n = u * angles.theta2.cos() + w * angles.theta2.sin();
            let a = u * base_radius;
            let b = a + (u * angles.theta1.cos() + w * angles.theta1.sin()) * robot.a();
            let c = b + n * offset;
            let d = c + (n * angles.theta3.sin() + v * angles.theta3.cos()) * robot.b();
            let e = d + n * offset;
            let k = i + 1;
            base[i] = s.point(format!("A{k}"), PointKind::Actuator, a);
            let knee = s.point(format!("B{k}"), PointKind::Passive, b);
            let lower = s.point(format!("C{k}"), PointKind::Passive, c);
            let upper = s.point(format!("D{k}"), PointKind::Passive, d);
            plate[i] = s.point(format!("E{k}"), PointKind::Platform, e);
            s.link(base[i], knee, LinkKind::Actuated);
            s.link(knee, lower, LinkKind::Passive);
            s.link(lower, upper, LinkKind::Passive);
            s.link(upper, plate[i], LinkKind::Passive);
        }
        s.ring(&base, LinkKind::Base);
        s.ring(&plate, LinkKind::Platform);
        Ok(s)
    }

    /// The Stewart–Gough platform at `pose`: base joints $b_i$, platform joints
    /// $a_i = p + R r_i$, the platform centre $p$; the base and platform hexagons and the six
    /// legs $b_ia_i$ (actuated, of the inverse kinematics' leg lengths).
    ///
    /// # Errors
    /// The inverse kinematics' [`KinematicsError`] (a non-finite pose, a leg of zero length).
    pub fn stewart_gough(
        robot: &StewartGough,
        pose: &Isometry3<f64>,
    ) -> Result<Self, KinematicsError> {
        let x = task_of(pose)?;
        robot.inverse_kinematics(&x, ())?;
        Ok(Self::legs(
            robot.base_joints(),
            &robot.platform_joints_world(pose),
            &pose.translation.vector,
        ))
    }

    /// The 3-UPU at `pose`: base joints $b_i = a(\cos\theta_i, \sin\theta_i, 0)$, platform joints
    /// $p + R\,b(\cos\theta_i, \sin\theta_i, 0)$ of its design, the triangles and the three
    /// legs (actuated).
    ///
    /// # Errors
    /// [`KinematicsError::NonFinite`] for a non-finite pose; [`KinematicsError::Singular`] for a
    /// leg of zero length.
    pub fn three_upu(robot: &ThreeUpu, pose: &Isometry3<f64>) -> Result<Self, KinematicsError> {
        task_of(pose)?;
        robot.wrench_rows(pose)?;
        let design = robot.design();
        let at = |r: f64, t: f64| Vector3::new(r * t.cos(), r * t.sin(), 0.0);
        let base = design.azimuths.map(|t| at(design.base_radius, t));
        let plate = design
            .azimuths
            .map(|t| (pose * Point3::from(at(design.platform_radius, t))).coords);
        Ok(Self::legs(&base, &plate, &pose.translation.vector))
    }

    /// Base joints, platform joints and prismatic legs between them, with both polygons.
    fn legs<const N: usize>(
        base: &[Vector3<f64>; N],
        plate: &[Vector3<f64>; N],
        centre: &Vector3<f64>,
    ) -> Self {
        let mut s = Self::default();
        s.point("p".into(), PointKind::Centre, *centre);
        let (mut lower, mut upper) = ([0; N], [0; N]);
        for i in 0..N {
            let n = i + 1;
            lower[i] = s.point(format!("B{n}"), PointKind::BaseJoint, base[i]);
            upper[i] = s.point(format!("P{n}"), PointKind::Platform, plate[i]);
            s.link(lower[i], upper[i], LinkKind::Actuated);
        }
        s.ring(&lower, LinkKind::Base);
        s.ring(&upper, LinkKind::Platform);
        s
    }
}

/// The task coordinates $(p, w)$ of `pose`, refusing a non-finite one.
fn task_of(pose: &Isometry3<f64>) -> Result<pkm_traits::Task<6>, KinematicsError> {
    let p = pose.translation.vector;
    let w = pose.rotation.scaled_axis();
    let x = pkm_traits::Task::<6>::new(p.x, p.y, p.z, w.x, w.y, w.z);
    match x.iter().copied().find(|v| !v.is_finite()) {
        Some(value) => Err(KinematicsError::NonFinite {
            what: "pose",
            value,
        }),
        None => Ok(x),
    }
}
