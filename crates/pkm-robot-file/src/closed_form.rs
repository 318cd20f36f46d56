//! The closed-form path of robots whose legs all have a closed-form class and whose pose has no
//! dependent coordinates: actuators and $J$ without solving the passive joints.
//!
//! In every closed-form class the actuation wrench is the force along the leg's rod: the line
//! through $E$ and $C$ (arm classes) or $A$ and $C$ (distance class) meets every passive axis,
//! so it is reciprocal to every passive twist. Its work on the actuator twist is $D_{ii}$, and
//! row $i$ of $J = D^{-1}J_aT$ follows (the same $J$ as [`RobotModel::screw_jacobians`], which
//! the conformance tests check).

use crate::chain::stack;
use crate::leg_ik::LegClass;
use crate::model::{RobotModel, WorkingMode};
use crate::pose::CoordinateRole;
use crate::pose::{hybrid_rates, platform_pose};
use nalgebra::{Isometry3, Point3, Rotation3, Unit, Vector3, Vector6};
use pkm_screw_theory::reciprocal_product_vectors;
use pkm_traits::KinematicsError;

/// One leg on its closed-form branch: actuator motion, actuation wrench (unit force along the
/// rod) and the actuator's unit twist.
struct ClosedFormLeg {
    motion: f64,
    wrench: Vector6<f64>,
    actuator_twist: Vector6<f64>,
}

impl RobotModel {
    /// Whether the closed-form path applies: no dependent coordinate, every leg closed-form.
    pub(crate) fn has_closed_form(&self) -> bool {
        !self.roles.contains(&CoordinateRole::Dependent)
            && self.classes.iter().all(|c| *c != LegClass::Numeric)
    }

    /// Leg `i` at platform pose `pose` on `branch`.
    fn closed_form_leg(
        &self,
        i: usize,
        pose: &Isometry3<f64>,
        branch: u8,
    ) -> Result<ClosedFormLeg, KinematicsError> {
        let class = self.classes[i];
        let motion = self.closed_form_motion(i, pose, branch)?;
        let at = |p: &Vector3<f64>| (pose * Point3::from(*p)).coords;
        let (start, end, actuator_twist) = match class {
            LegClass::Distance {
                base,
                platform,
                sign,
                ..
            } => {
                let c = at(&platform);
                (
                    base,
                    c,
                    stack(&Vector3::zeros(), &((c - base).normalize() * sign)),
                )
            }
            LegClass::RevoluteArm {
                axis,
                foot,
                arm,
                wrist,
                ..
            } => {
                let elbow =
                    foot + Rotation3::from_axis_angle(&Unit::new_unchecked(axis), motion) * arm;
                (elbow, at(&wrist), stack(&axis, &foot.cross(&axis)))
            }
            LegClass::PrismaticArm {
                axis, elbow, wrist, ..
            } => (
                elbow + axis * motion,
                at(&wrist),
                stack(&Vector3::zeros(), &axis),
            ),
            LegClass::Numeric => {
                return Err(KinematicsError::Unreachable {
                    leg: i,
                    discriminant: f64::NAN,
                });
            }
        };
        let rod = end - start;
        let length = rod.norm();
        if !(length.is_finite() && length > 1e-12 * self.size) {
            return Err(KinematicsError::Singular {
                matrix: "rod direction",
                sigma_min: length,
            });
        }
        let s = rod / length;
        Ok(ClosedFormLeg {
            motion,
            wrench: stack(&s, &start.cross(&s)),
            actuator_twist,
        })
    }

    /// The full pose of task coordinates `x` when there are no dependent coordinates.
    fn closed_form_pose(&self, x: &[f64]) -> Result<Isometry3<f64>, KinematicsError> {
        Ok(platform_pose(self.orientation, &self.pose_with_task(x)?))
    }

    /// The actuator motion of leg `i` at `pose` on `branch` alone (membership needs no wrench).
    fn closed_form_motion(
        &self,
        i: usize,
        pose: &Isometry3<f64>,
        branch: u8,
    ) -> Result<f64, KinematicsError> {
        self.classes[i]
            .solve(pose, branch)
            .map_err(|e| KinematicsError::Unreachable {
                leg: i,
                discriminant: e.0,
            })
    }

    /// Actuator coordinates on the closed-form path, handed to `set(leg, q)`.
    pub(crate) fn closed_form_actuators_with(
        &self,
        x: &[f64],
        mode: WorkingMode,
        mut set: impl FnMut(usize, f64),
    ) -> Result<(), KinematicsError> {
        let pose = self.closed_form_pose(x)?;
        for i in 0..self.legs.len() {
            let q = self.legs[i].offset + self.closed_form_motion(i, &pose, mode.branch(i))?;
            self.check_actuator_limits(i, q)?;
            set(i, q);
        }
        Ok(())
    }

    /// $J = D^{-1}J_aT$ on the closed-form path, entry $(i, k)$ handed to `set(i, k, J_ik)`.
    pub(crate) fn closed_form_jacobian_with(
        &self,
        x: &[f64],
        mode: WorkingMode,
        mut set: impl FnMut(usize, usize, f64),
    ) -> Result<(), KinematicsError> {
        let coordinates = self.pose_with_task(x)?;
        let pose = platform_pose(self.orientation, &coordinates);
        let h = hybrid_rates(self.orientation, &coordinates);
        let p = Vector3::new(coordinates[0], coordinates[1], coordinates[2]);
        // At most six task coordinates: their platform twists on the stack.
        let mut twists = [Vector6::zeros(); 6];
        for (t, &k) in twists.iter_mut().zip(&self.task) {
            let w: Vector3<f64> = h.fixed_view::<3, 1>(0, k).into();
            let pd: Vector3<f64> = h.fixed_view::<3, 1>(3, k).into();
            *t = stack(&w, &(pd - w.cross(&p)));
        }
        for i in 0..self.legs.len() {
            let leg = self.closed_form_leg(i, &pose, mode.branch(i))?;
            self.check_actuator_limits(i, self.legs[i].offset + leg.motion)?;
            let d = reciprocal_product_vectors(&leg.wrench, &leg.actuator_twist);
            if !(d.abs() > 1e-12 * self.size) {
                return Err(KinematicsError::Singular {
                    matrix: "D",
                    sigma_min: d.abs(),
                });
            }
            for (k, t) in twists.iter().take(self.task.len()).enumerate() {
                set(i, k, reciprocal_product_vectors(&leg.wrench, t) / d);
            }
        }
        Ok(())
    }
}
