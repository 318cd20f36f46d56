//! The closed-form path of robots whose legs all have a closed-form class and whose pose has no
//! dependent coordinates: actuators and $J$ without solving the passive joints.
//!
//! In every closed-form class the actuation wrench is the force along the leg's rod: the line
//! through $E$ and $C$ (arm classes) or $A$ and $C$ (distance class) meets every passive axis,
//! so it is reciprocal to every passive twist. Its work on the actuator twist is $D_{ii}$, and
//! row $i$ of $J = D^{-1}J_aT$ follows (the same $J$ as [`RobotModel::screw_jacobians`], which
//! the conformance tests check).

use crate::chain::stack;
use crate::leg_ik::{LegClass, Sphere};
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
    /// Whether the closed-form path applies: no dependent coordinate, every actuated leg
    /// closed-form (so with one actuator: actuator `i` is leg `i`'s on this path).
    pub(crate) fn has_closed_form(&self) -> bool {
        !self.roles.contains(&CoordinateRole::Dependent)
            && self.one_actuator_per_leg()
            && self.classes[..self.actuated]
                .iter()
                .all(|c| *c != LegClass::Numeric)
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
        for i in 0..self.actuator_count() {
            let q =
                self.actuator(i).1.offset + self.closed_form_motion(i, &pose, mode.branch(i))?;
            self.check_actuator_limits(i, q)?;
            set(i, q);
        }
        Ok(())
    }

    /// The working mode whose closed-form actuator of each leg at `x` is nearest `q` (see
    /// [`RobotModel::nearest_branch`]), those actuator coordinates handed to `set(leg, q)`:
    /// the $\mathrm{IK}_i$ of the reduced closure $\Phi_i = q_i - \mathrm{IK}_i(x)$. Actuator
    /// ranges are not checked (an iterate of the forward kinematics may leave them).
    pub(crate) fn closed_form_nearest_with(
        &self,
        x: &[f64],
        q: &[f64],
        mut set: impl FnMut(usize, f64),
    ) -> Result<WorkingMode, KinematicsError> {
        let pose = self.closed_form_pose(x)?;
        let mut mode = WorkingMode(0);
        for (i, &q_i) in q.iter().enumerate().take(self.actuator_count()) {
            let (branch, value) =
                self.nearest_branch(i, &pose, q_i)
                    .ok_or(KinematicsError::Unreachable {
                        leg: i,
                        discriminant: f64::NAN,
                    })?;
            mode = mode.with_branch(i, branch);
            set(i, value);
        }
        Ok(mode)
    }

    /// $J = D^{-1}J_aT$ on the closed-form path, entry $(i, k)$ handed to `set(i, k, J_ik)`.
    pub(crate) fn closed_form_jacobian_with(
        &self,
        x: &[f64],
        mode: WorkingMode,
        set: impl FnMut(usize, usize, f64),
    ) -> Result<(), KinematicsError> {
        self.closed_form_jacobian_rows(x, mode, true, set)
    }

    /// [`RobotModel::closed_form_jacobian_with`], the actuator ranges checked when
    /// `check_limits`.
    pub(crate) fn closed_form_jacobian_rows(
        &self,
        x: &[f64],
        mode: WorkingMode,
        check_limits: bool,
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
        for i in 0..self.actuator_count() {
            let leg = self.closed_form_leg(i, &pose, mode.branch(i))?;
            if check_limits {
                self.check_actuator_limits(i, self.actuator(i).1.offset + leg.motion)?;
            }
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

/// The algebraic loop closure of a robot whose legs all have a closed form, in the task
/// coordinates and the actuators alone:
/// $$\Phi_i(x, q) = \tfrac12\left(\lvert C_i(x) - E_i(q_i)\rvert^2 - L_i(q_i)^2\right),$$
/// with $C_i$ the leg's platform point, $E_i$ its base point $A$ (distance class) or its elbow
/// point moved by the actuator (arm classes), and $L_i$ the leg length $\lvert C_0 - A\rvert
/// \pm q_i$ or the rod. Unlike the reduced closure $q_i - \mathrm{IK}_i(x)$ it is defined at
/// every $x$, out of reach too, as the hand-written models' closures are: Newton on it steps
/// as theirs do, and stays on the guess's assembly mode where theirs does.
///
/// The forward kinematics holds the actuators fixed, so [`AlgebraicClosure::at_actuators`]
/// computes each leg's sphere once (an arm's elbow: a sine and a cosine) and uses it wherever
/// the closure is asked at exactly those coordinates; a robot whose orientation is not among its
/// task coordinates keeps its home rotation without recomputing it. Both give the bits of the
/// full computation.
pub(crate) struct AlgebraicClosure<'a> {
    model: &'a RobotModel,
    /// The actuator coordinates held and each leg's sphere there.
    fixed: Vec<(f64, Option<Sphere>)>,
}

/// One leg of [`AlgebraicClosure`]: $C - E$, $L$, $\partial E / \partial q$ and
/// $\partial L / \partial q$.
struct AlgebraicLeg {
    /// $C$.
    point: Vector3<f64>,
    rod: Vector3<f64>,
    length: f64,
    d_elbow: Vector3<f64>,
    d_length: f64,
}

impl<'a> AlgebraicClosure<'a> {
    /// The closure of `model`.
    pub(crate) fn new(model: &'a RobotModel) -> Self {
        Self {
            model,
            fixed: Vec::new(),
        }
    }

    /// The closure of `model` with the legs' spheres at the actuator coordinates `q` computed
    /// once.
    pub(crate) fn at_actuators(model: &'a RobotModel, q: &[f64]) -> Self {
        let fixed = q
            .iter()
            .enumerate()
            .map(|(i, &q_i)| (q_i, Self::new(model).sphere(i, q_i)))
            .collect();
        Self { model, fixed }
    }

    /// Leg `i`'s sphere with its actuator at `q_i`.
    fn sphere(&self, i: usize, q_i: f64) -> Option<Sphere> {
        match self.fixed.get(i) {
            Some(&(held, sphere)) if held.to_bits() == q_i.to_bits() => sphere,
            _ => self.model.classes[i].sphere(q_i - self.model.actuator(i).1.offset),
        }
    }

    /// The platform pose of the pose coordinates `coordinates`.
    fn pose(&self, coordinates: &crate::pose::PoseCoordinates) -> Isometry3<f64> {
        if self.model.task.iter().all(|&k| k < 3) {
            // The orientation is held at home: the home rotation, computed once.
            let t = nalgebra::Translation3::new(coordinates[0], coordinates[1], coordinates[2]);
            return Isometry3::from_parts(t, self.model.home_pose.rotation);
        }
        platform_pose(self.model.orientation, coordinates)
    }

    /// Leg `i` at platform pose `pose` with actuator coordinate `q_i`.
    fn leg(&self, i: usize, pose: &Isometry3<f64>, q_i: f64) -> AlgebraicLeg {
        let at = |p: &Vector3<f64>| (pose * Point3::from(*p)).coords;
        match self.sphere(i, q_i) {
            Some(sphere) => {
                let c = at(&sphere.point);
                AlgebraicLeg {
                    point: c,
                    rod: c - sphere.center,
                    length: sphere.length,
                    d_elbow: sphere.d_center,
                    d_length: sphere.d_length,
                }
            }
            None => AlgebraicLeg {
                point: Vector3::repeat(f64::NAN),
                rod: Vector3::repeat(f64::NAN),
                length: f64::NAN,
                d_elbow: Vector3::zeros(),
                d_length: f64::NAN,
            },
        }
    }

    /// The full pose coordinates of `x` (NaN where they are not valid).
    fn coordinates(&self, x: &[f64]) -> crate::pose::PoseCoordinates {
        self.model.pose_with_task(x).unwrap_or([f64::NAN; 6])
    }
}

impl<const N: usize> pkm_traits::ClosedChain<N, N> for AlgebraicClosure<'_> {
    fn closure(&self, x: &pkm_traits::Task<N>, q: &pkm_traits::Joints<N>) -> pkm_traits::Joints<N> {
        let pose = self.pose(&self.coordinates(x.as_slice()));
        pkm_traits::Joints::<N>::from_fn(|i, _| {
            let leg = self.leg(i, &pose, q[i]);
            0.5 * (leg.rod.norm_squared() - leg.length * leg.length)
        })
    }

    /// $\partial \Phi_i / \partial x_k = (C_i - E_i) \cdot \dot C_{i,k}$, the velocity of $C_i$
    /// per unit rate of task coordinate $k$.
    fn jacobian_x(
        &self,
        x: &pkm_traits::Task<N>,
        q: &pkm_traits::Joints<N>,
    ) -> nalgebra::SMatrix<f64, N, N> {
        let coordinates = self.coordinates(x.as_slice());
        let pose = self.pose(&coordinates);
        let mut j = nalgebra::SMatrix::<f64, N, N>::zeros();
        if self.model.task.iter().all(|&k| k < 3) {
            // A translation: C moves with the platform origin.
            for i in 0..N {
                let rod = self.leg(i, &pose, q[i]).rod;
                for (k, &coordinate) in self.model.task.iter().enumerate().take(N) {
                    j[(i, k)] = rod[coordinate];
                }
            }
            return j;
        }
        let h = hybrid_rates(self.model.orientation, &coordinates);
        let origin = Vector3::new(coordinates[0], coordinates[1], coordinates[2]);
        for i in 0..N {
            let leg = self.leg(i, &pose, q[i]);
            for (k, &coordinate) in self.model.task.iter().enumerate().take(N) {
                let w: Vector3<f64> = h.fixed_view::<3, 1>(0, coordinate).into();
                let v: Vector3<f64> = h.fixed_view::<3, 1>(3, coordinate).into();
                j[(i, k)] = leg.rod.dot(&(v + w.cross(&(leg.point - origin))));
            }
        }
        j
    }

    /// $\partial \Phi_i / \partial q_i = -(C_i - E_i) \cdot \partial E_i/\partial q_i - L_i\,
    /// \partial L_i / \partial q_i$.
    fn jacobian_q(
        &self,
        x: &pkm_traits::Task<N>,
        q: &pkm_traits::Joints<N>,
    ) -> nalgebra::SMatrix<f64, N, N> {
        let pose = self.pose(&self.coordinates(x.as_slice()));
        nalgebra::SMatrix::<f64, N, N>::from_fn(|i, k| {
            if i != k {
                return 0.0;
            }
            let leg = self.leg(i, &pose, q[i]);
            -leg.rod.dot(&leg.d_elbow) - leg.length * leg.d_length
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pkm_traits::{ClosedChain, InverseKinematics, Joints, Task};

    fn model(file: &str) -> RobotModel {
        let path = format!(
            "{}/../../examples/robots/{file}",
            env!("CARGO_MANIFEST_DIR")
        );
        RobotModel::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    /// $\Phi = 0$ at `x`, $J_x$ and $J_q$ equal central differences of $\Phi$ to 1e-7
    /// relative, and $-J_q^{-1}J_x$ is the velocity Jacobian of the screws to 1e-9 relative.
    fn check<const N: usize>(file: &str, x: Task<N>) {
        let robot = crate::Robot::<N>::new(model(file)).unwrap();
        let closure = AlgebraicClosure::new(robot.model());
        let mode = robot.model().home_mode();
        let q = robot.inverse_kinematics(&x, mode).unwrap();
        let phi = closure.closure(&x, &q);
        assert!(phi.amax() < 1e-12, "{file}: Φ = {phi}");
        let (j_x, j_q) = (closure.jacobian_x(&x, &q), closure.jacobian_q(&x, &q));
        let h = 1e-6;
        for k in 0..N {
            let e = Task::<N>::from_fn(|r, _| if r == k { h } else { 0.0 });
            let fd = (closure.closure(&(x + e), &q) - closure.closure(&(x - e), &q)) / (2.0 * h);
            assert!(
                (fd - j_x.column(k)).amax() < 1e-7 * j_x.amax(),
                "{file} J_x[:, {k}]"
            );
            let e = Joints::<N>::from_fn(|r, _| if r == k { h } else { 0.0 });
            let fd = (closure.closure(&x, &(q + e)) - closure.closure(&x, &(q - e))) / (2.0 * h);
            assert!(
                (fd - j_q.column(k)).amax() < 1e-7 * j_q.amax(),
                "{file} J_q[:, {k}]"
            );
        }
        let j = -(j_q.try_inverse().unwrap() * j_x);
        let screws = robot.velocity_jacobian_at(&x, mode).unwrap();
        assert!(
            (j - screws).amax() < 1e-9 * screws.amax(),
            "{file}:\n{j}\n{screws}"
        );
    }

    /// Every closed-form class (revolute arms: Tsai, Delta; prismatic arms: Orthoglide;
    /// distance legs: 3-UPU, 3-RPR with rotation, Stewart–Gough in six coordinates).
    #[test]
    fn the_algebraic_closure_vanishes_and_differentiates_to_the_screw_jacobian() {
        check("tsai.toml", Task::<3>::new(0.05, -0.04, 0.45));
        check("rotary_delta.toml", Task::<3>::new(0.05, -0.04, -0.7));
        check("orthoglide.toml", Task::<3>::new(0.02, -0.03, 0.04));
        check("three_upu.toml", Task::<3>::new(0.03, -0.02, 0.32));
        check("three_rpr.toml", Task::<3>::new(0.02, -0.03, 0.05));
        let x = Task::<6>::from_column_slice(&[0.01, -0.02, 0.31, 0.05, -0.03, 0.04]);
        check("stewart_gough.toml", x);
    }

    /// The closure with its spheres held at `q` gives the bits of the one that computes them
    /// each time, at `q` and (falling back) at another `q`, away from `x` too.
    fn held_equals_computed<const N: usize>(file: &str, x: Task<N>) {
        let robot = crate::Robot::<N>::new(model(file)).unwrap();
        let q = robot
            .inverse_kinematics(&x, robot.model().home_mode())
            .unwrap();
        let (computed, held) = (
            AlgebraicClosure::new(robot.model()),
            AlgebraicClosure::at_actuators(robot.model(), q.as_slice()),
        );
        let bits = |m: &[f64]| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for (dx, dq) in [(0.0, 0.0), (0.01, 0.0), (-0.02, 0.003)] {
            let (x, q) = (x.add_scalar(dx), q.add_scalar(dq));
            let pairs = [
                (
                    computed.closure(&x, &q).as_slice().to_vec(),
                    held.closure(&x, &q).as_slice().to_vec(),
                ),
                (
                    computed.jacobian_x(&x, &q).as_slice().to_vec(),
                    held.jacobian_x(&x, &q).as_slice().to_vec(),
                ),
                (
                    computed.jacobian_q(&x, &q).as_slice().to_vec(),
                    held.jacobian_q(&x, &q).as_slice().to_vec(),
                ),
            ];
            for (a, b) in pairs {
                assert_eq!(bits(&a), bits(&b), "{file} {dx} {dq}");
            }
        }
    }

    #[test]
    fn holding_the_actuators_gives_the_same_bits() {
        held_equals_computed("tsai.toml", Task::<3>::new(0.05, -0.04, 0.45));
        held_equals_computed("rotary_delta.toml", Task::<3>::new(0.05, -0.04, -0.7));
        held_equals_computed("three_rpr.toml", Task::<3>::new(0.02, -0.03, 0.05));
        let x = Task::<6>::from_column_slice(&[0.01, -0.02, 0.31, 0.05, -0.03, 0.04]);
        held_equals_computed("stewart_gough.toml", x);
    }
}
