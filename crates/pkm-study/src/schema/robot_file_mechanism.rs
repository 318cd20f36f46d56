//! [`RobotFileSpec`] as a study mechanism: its `[parameters]` the design variables, its
//! workspace in the platform position (translational studies), its drawing. Kept apart from
//! the table itself so that the registry can name the table without a module cycle.

use super::constraints::ConstraintsSpec;
use super::robot_file::{RobotFileSpec, position_task, robot_skeleton};
use crate::registry::{Actuation, StudyMechanism, Unit, Variable};
use crate::registry::{BuildError, ForwardVisitor, WorkspaceVisitor, visit};
use crate::{Infeasible, StudyError};
use nalgebra::Vector3;
use pkm_mechanisms::Skeleton;
use pkm_robot_file::{Robot, RobotModel, WorkingMode};
use pkm_traits::WorkspaceConstraint;
use pkm_workspace_indices::Region;
use std::borrow::Cow;
use toml::Value;

/// A robot file built for a study ([`RobotFileSpec`]'s [`StudyMechanism::build`]): its model in
/// the study's working modes, and the model as a translational robot when its task is the
/// platform position.
#[derive(Debug)]
pub struct BuiltRobotFile {
    robot: Frame,
    modes: Vec<WorkingMode>,
}

/// A robot file's model, as a translational robot when its task is the platform position.
#[derive(Debug)]
enum Frame {
    Position(Robot<3>),
    /// Another task, with the error that a translational study gives.
    Task {
        model: RobotModel,
        not_position: Infeasible,
    },
}

impl BuiltRobotFile {
    /// The validated model.
    pub fn model(&self) -> &RobotModel {
        match &self.robot {
            Frame::Position(robot) => robot.model(),
            Frame::Task { model, .. } => model,
        }
    }

    /// The study's working modes ([`RobotFileSpec::working_modes`]).
    pub fn modes(&self) -> &[WorkingMode] {
        &self.modes
    }

    /// The translational robot.
    ///
    /// # Errors
    /// [`BuildError::Design`] at `mechanism.robot_file.task` when its task is not the platform
    /// position.
    pub fn translational(&self) -> Result<&Robot<3>, BuildError> {
        match &self.robot {
            Frame::Position(robot) => Ok(robot),
            Frame::Task { not_position, .. } => Err(BuildError::Design(not_position.clone())),
        }
    }
}

impl StudyMechanism for RobotFileSpec {
    type Built = BuiltRobotFile;

    fn kind(&self) -> &'static str {
        "robot_file"
    }

    /// The model once, its working modes, and the translational robot of a position task.
    fn build(&self) -> Result<BuiltRobotFile, BuildError> {
        let model = self.model().map_err(design)?;
        let modes = self.working_modes(&model).map_err(design)?;
        let robot = match position_task(&model) {
            Ok(()) => Frame::Position(self.translational(model).map_err(design)?),
            Err(e) => Frame::Task {
                model,
                not_position: Infeasible::robot_file(e),
            },
        };
        Ok(BuiltRobotFile { robot, modes })
    }

    /// The robot in its platform position (a robot file whose task is `["x", "y", "z"]`):
    /// damped Newton on the closure of every leg.
    fn with_forward_kinematics<V: ForwardVisitor>(
        &self,
        built: &BuiltRobotFile,
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        Ok(visitor.visit(built.translational()?))
    }

    /// The names of `[parameters]`: metres, or degrees for a name ending in `_deg`.
    fn variables(&self) -> Cow<'static, [Variable]> {
        let names = self.parameters().into_iter().flat_map(|p| p.keys());
        let variables = names.map(|name| Variable {
            unit: if name.ends_with("_deg") {
                Unit::Angle
            } else {
                Unit::Length
            },
            name: Cow::Owned(name.clone()),
        });
        Cow::Owned(variables.collect())
    }

    fn get(&self, name: &str) -> Option<f64> {
        match self.parameters()?.get(name)? {
            Value::Float(v) => Some(*v),
            Value::Integer(v) => Some(*v as f64),
            _ => None,
        }
    }

    fn slot(&mut self, name: &str) -> Option<&mut f64> {
        let parameters = self.parameters_mut()?;
        let value = parameters.get_mut(name)?;
        if let Value::Integer(v) = *value {
            *value = Value::Float(v as f64);
        }
        match value {
            Value::Float(v) => Some(v),
            _ => None,
        }
    }

    /// Revolute when every actuator is an R joint, prismatic otherwise.
    fn actuation(&self) -> Actuation {
        if self.actuated_types().iter().all(|t| *t == "R") {
            Actuation::Revolute
        } else {
            Actuation::Prismatic
        }
    }

    /// The model and the working modes (a translational study checks the task where it builds
    /// the workspace; a task-space study takes any task).
    fn check(&self) -> Result<(), StudyError> {
        self.working_modes(&self.model()?).map(|_| ())
    }

    fn robot_file(&self) -> Option<&RobotFileSpec> {
        Some(self)
    }

    /// The study's working modes ([`RobotFileSpec::working_modes`]; by default the reference
    /// mode of the file, its home configuration's): a position belongs to the workspace when
    /// one of them assembles there.
    fn with_workspace<V: WorkspaceVisitor>(
        &self,
        built: &BuiltRobotFile,
        constraints: &[WorkspaceConstraint],
        visitor: V,
    ) -> Result<V::Output, BuildError> {
        visit(built.translational()?, &built.modes, constraints, visitor)
    }

    /// The box of [`pkm_robot_file::RobotModel::reach_box`]: the intersection of the legs' reach balls, each
    /// the chain's length from its first joint point (prismatic travel within the file's
    /// `limits` included), so it holds every reachable position. None when a prismatic joint
    /// has no limits (its reach is unbounded) or the boxes do not overlap; the study then needs
    /// `[sampling.region]`.
    fn reach_region(&self, built: &BuiltRobotFile) -> Option<Region> {
        built
            .translational()
            .ok()?
            .model()
            .reach_box()
            .filter(|[lower, upper]| (0..3).all(|a| lower[a] < upper[a]))
            .map(|[lower, upper]| Region::Box { lower, upper })
    }

    /// The robot drawn from its joints ([`robot_skeleton`]) in the first working mode of the
    /// study that reaches `p`.
    fn skeleton_at(&self, built: &BuiltRobotFile, p: &Vector3<f64>) -> Result<Skeleton, String> {
        let model = built.translational().map_err(|e| e.to_string())?.model();
        let mut last = None;
        for &mode in &built.modes {
            match model.inverse_kinematics_configuration(p.as_slice(), mode) {
                Ok(c) => return Ok(robot_skeleton(model, &c)),
                Err(e) => last = Some(e),
            }
        }
        let at = format!("p = [{}, {}, {}] m", p.x, p.y, p.z);
        Err(last.map_or_else(
            || format!("no working mode of the study can be drawn at {at}"),
            |e| format!("the skeleton at {at}: {e}"),
        ))
    }

    /// As for every mechanism, with joint ranges refused for a robot whose actuators are both
    /// revolute and prismatic (give them as the file's `limits`).
    fn constraints(&self, spec: &ConstraintsSpec) -> Result<Vec<WorkspaceConstraint>, String> {
        let types = self.actuated_types();
        let mixed = types.contains(&"R") && types.iter().any(|t| *t != "R");
        let ranges = spec.joint_range.is_some()
            || spec.joint_range_deg.is_some()
            || !spec.joint_ranges.is_empty()
            || !spec.joint_ranges_deg.is_empty();
        if mixed && ranges {
            return Err(
                "the actuators of this robot file are revolute and prismatic: give \
                        their ranges as `limits` in the robot file"
                    .into(),
            );
        }
        spec.to_library(self.kind(), self.actuation())
    }
}

/// A robot file's refusal of a design as an infeasible design (its key path kept).
fn design(e: StudyError) -> BuildError {
    BuildError::Design(Infeasible::robot_file(e))
}
