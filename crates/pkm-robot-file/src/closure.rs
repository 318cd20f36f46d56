//! The SE(3) loop-closure residual of the legs and its Jacobian, the one least-squares problem
//! behind the numerical leg IK, the dependent pose coordinates and the forward kinematics.
//!
//! Leg $i$ closes when $D_i(\theta_i)\,M = X(c)$. The residual of the leg is
//! $r_i = [\log(R_{E} R_X^\top)^\vee;\ p_E - p_X]$ with $E = D_i M$: the rotation error as a
//! rotation vector (no Euler angles) and the position error of the platform origin. A joint
//! twist $[\omega; v_O]$ moves it by $[\omega;\ v_O + \omega \times p_E]$, a pose coordinate
//! by minus its rates $[\omega_k; \dot p_k]$ (exact at $r = 0$, where the Newton steps end).

use crate::chain::{JointValue, stack};
use crate::lm::LeastSquares;
use crate::model::RobotModel;
use crate::pose::{OrientationKind, PoseCoordinates, hybrid_rates, platform_pose};
use nalgebra::{DMatrix, DVector, Point3, Rotation3, Vector3};
use pkm_traits::KinematicsError;

/// A full configuration: the six pose coordinates and every joint value of every leg.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    pub(crate) pose: PoseCoordinates,
    pub(crate) joints: Vec<Vec<JointValue>>,
}

impl Configuration {
    /// The home configuration of `model`.
    pub(crate) fn home(model: &RobotModel) -> Self {
        Self {
            pose: model.home,
            joints: model.legs.iter().map(|l| l.home_values()).collect(),
        }
    }

    /// The six pose coordinates.
    pub fn pose(&self) -> PoseCoordinates {
        self.pose
    }

    /// The motion of actuator `i` from home (rad or m); NaN for an actuator the model lacks.
    pub(crate) fn actuator_motion(&self, model: &RobotModel, i: usize) -> f64 {
        let value = model.actuators.get(i).and_then(|&(leg, k)| {
            self.joints
                .get(leg)?
                .get(model.legs[leg].actuators[k].joint)
        });
        match value {
            Some(JointValue::Scalar(v)) => *v,
            _ => f64::NAN,
        }
    }
}

impl RobotModel {
    /// `Err(InvalidInput)` unless `config` is a configuration of this robot: one list of
    /// joint values per leg, one value per joint, of the joint's kind.
    pub(crate) fn check_configuration(
        &self,
        config: &Configuration,
    ) -> Result<(), KinematicsError> {
        let fits = config.joints.len() == self.legs.len()
            && self.legs.iter().zip(&config.joints).all(|(leg, values)| {
                values.len() == leg.joints.len()
                    && leg.joints.iter().zip(values).all(|(joint, value)| {
                        matches!(
                            (joint, value),
                            (crate::chain::Joint::Spherical { .. }, JointValue::Ball(_))
                                | (
                                    crate::chain::Joint::Revolute { .. }
                                        | crate::chain::Joint::Prismatic { .. },
                                    JointValue::Scalar(_)
                                )
                        )
                    })
            });
        if fits {
            Ok(())
        } else {
            Err(pkm_traits::InvalidInput::new(
                "configuration",
                config.joints.len() as f64,
                "must be a configuration of this robot (its legs and joints)",
            )
            .into())
        }
    }
}

/// Which unknowns a closure problem solves for.
#[derive(Debug, Clone)]
pub(crate) struct ClosureProblem<'a> {
    pub model: &'a RobotModel,
    /// The legs whose closure is solved.
    pub legs: Vec<usize>,
    /// The pose coordinates that are unknown.
    pub free_pose: Vec<usize>,
    /// Whether the actuators are held at their values.
    pub fixed_actuators: bool,
    /// What each leg's residual measures.
    pub residual: LegResidual,
}

/// The residual of one leg's closure. Every form vanishes exactly when the leg closes (the
/// last two measure the position at a point $p$ of the platform, platform frame, instead of
/// its origin), but their landscapes differ far from a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum LegResidual {
    /// $[\log(R_E R_X^\top)^\vee;\ p_E - p_X]$: the pose error at the platform origin.
    Pose,
    /// $[\log(R_E R_X^\top)^\vee;\ E\,p - X\,p]$: the pose error at a point $p$ that the
    /// leg's last joints pass through, so they turn the platform about it without moving it.
    PoseAt(Vector3<f64>),
    /// $[0;\ E\,p - X\,p]$: the position of $p$ alone (with no free pose coordinate).
    PositionOf(Vector3<f64>),
}

impl ClosureProblem<'_> {
    fn is_free(&self, leg: usize, joint: usize) -> bool {
        !(self.fixed_actuators && self.model.legs[leg].is_actuated(joint))
    }

    fn unknowns(&self) -> usize {
        let joints: usize = self
            .legs
            .iter()
            .map(|&i| {
                let leg = &self.model.legs[i];
                leg.dof()
                    - if self.fixed_actuators {
                        leg.actuators.len()
                    } else {
                        0
                    }
            })
            .sum();
        self.free_pose.len() + joints
    }
}

impl LeastSquares for ClosureProblem<'_> {
    type State = Configuration;

    fn evaluate(&self, c: &Configuration) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let model = self.model;
        let target = platform_pose(model.orientation, &c.pose);
        let rates = hybrid_rates(model.orientation, &c.pose);
        let mut r = DVector::zeros(6 * self.legs.len());
        let mut jac = DMatrix::zeros(6 * self.legs.len(), self.unknowns());
        let mut col = self.free_pose.len();
        for (block, &i) in self.legs.iter().enumerate() {
            let leg = &model.legs[i];
            let lt = leg.twists(&c.joints[i]);
            let end = lt.displacement * model.home_pose;
            let at = |p: &Vector3<f64>| {
                let (e, x) = (
                    (end * Point3::from(*p)).coords,
                    (target * Point3::from(*p)).coords,
                );
                (e - x, e)
            };
            let rotation = || (end.rotation * target.rotation.inverse()).scaled_axis();
            let (rot, (pos, p_end)) = match &self.residual {
                LegResidual::Pose => (rotation(), at(&Vector3::zeros())),
                LegResidual::PoseAt(p) => (rotation(), at(p)),
                LegResidual::PositionOf(p) => (Vector3::zeros(), at(p)),
            };
            r.fixed_rows_mut::<6>(6 * block)
                .copy_from(&stack(&rot, &pos));
            for (k, &pose_k) in self.free_pose.iter().enumerate() {
                jac.fixed_view_mut::<6, 1>(6 * block, k)
                    .copy_from(&(-rates.column(pose_k)));
            }
            for (joint, twist) in &lt.twists {
                if !self.is_free(i, *joint) {
                    continue;
                }
                let w: Vector3<f64> = twist.fixed_rows::<3>(0).into();
                let v: Vector3<f64> = twist.fixed_rows::<3>(3).into();
                let w_rows = match self.residual {
                    LegResidual::PositionOf(_) => Vector3::zeros(),
                    _ => w,
                };
                jac.fixed_view_mut::<6, 1>(6 * block, col)
                    .copy_from(&stack(&w_rows, &(v + w.cross(&p_end))));
                col += 1;
            }
        }
        let finite = r.iter().chain(jac.iter()).all(|v| v.is_finite());
        finite.then_some((r, jac))
    }

    fn step_limits(&self) -> DVector<f64> {
        let (angle, length) = (0.5, 0.25 * self.model.size);
        let mut limits: Vec<f64> = self
            .free_pose
            .iter()
            .map(|&k| if k < 3 { length } else { angle })
            .collect();
        for &i in &self.legs {
            for (j, joint) in self.model.legs[i].joints.iter().enumerate() {
                if !self.is_free(i, j) {
                    continue;
                }
                let limit = match joint {
                    crate::chain::Joint::Prismatic { .. } => length,
                    _ => angle,
                };
                limits.extend(std::iter::repeat_n(limit, joint.dof()));
            }
        }
        DVector::from_vec(limits)
    }

    fn apply(&self, c: &Configuration, delta: &DVector<f64>) -> Configuration {
        let mut next = c.clone();
        for (k, &pose_k) in self.free_pose.iter().enumerate() {
            next.pose[pose_k] += delta[k];
        }
        let mut col = self.free_pose.len();
        for &i in &self.legs {
            for (j, value) in next.joints[i].iter_mut().enumerate() {
                if !self.is_free(i, j) {
                    continue;
                }
                match value {
                    JointValue::Scalar(v) => {
                        *v += delta[col];
                        col += 1;
                    }
                    JointValue::Ball(r) => {
                        let d = Vector3::new(delta[col], delta[col + 1], delta[col + 2]);
                        *r = Rotation3::new(d) * *r;
                        col += 3;
                    }
                }
            }
        }
        next
    }
}

/// Whether two configurations have the same platform pose (rotations compared as matrices, so
/// two coordinate sets of one rotation are one mode).
pub(crate) fn same_pose(
    kind: OrientationKind,
    a: &Configuration,
    b: &Configuration,
    tol: f64,
) -> bool {
    let position = (0..3).all(|k| (a.pose[k] - b.pose[k]).abs() < tol);
    let rotation =
        |c: &Configuration| kind.rotation(&Vector3::new(c.pose[3], c.pose[4], c.pose[5]));
    position && (rotation(a).matrix() - rotation(b).matrix()).amax() < tol
}
