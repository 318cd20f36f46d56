//! The robot as a fixed-size model of the shared kinematics traits.
//!
//! The loop closure is the reduced one of `spec/general-robots.md` §7.10: with the passive
//! joints and dependent pose coordinates solved internally (implicit function),
//! $$\Phi_i(x, q) = q_i - \mathrm{IK}_i(x),$$
//! where $\mathrm{IK}_i$ takes the closed-form branch nearest $q_i$. Hence $J_q = I$ and
//! $J_x = -D^{-1} J_a T$ (the screw Jacobians), so $J = -J_q^{-1}J_x = D^{-1}J_aT$.

use crate::closure::Configuration;
use crate::error::RobotFileError;
use crate::lm::SolverSettings;
use crate::model::{RobotModel, WorkingMode};
use nalgebra::{DVector, SMatrix};
use pkm_traits::{
    ClosedChain, ForwardKinematics, InvalidInput, InverseKinematics, Joints, KinematicsError,
    NewtonSettings, Task,
};

/// A robot from a file with `N` task coordinates (= actuators), for the kinematics traits.
///
/// # Example
/// ```
/// use pkm_robot_file::Robot;
/// use pkm_traits::InverseKinematics;
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/robots/five_bar.toml")).unwrap();
/// let robot = Robot::<2>::from_toml(&text).unwrap();
/// let mode = robot.model().home_mode();
/// let j = robot.velocity_jacobian_at(&[0.0, 0.25].into(), mode).unwrap();
/// assert!(j.iter().all(|v| v.is_finite()));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Robot<const N: usize> {
    model: RobotModel,
}

impl<const N: usize> Robot<N> {
    /// Wraps `model`.
    ///
    /// # Errors
    /// [`RobotFileError::Dimension`] unless the model has `N` task coordinates;
    /// [`RobotFileError::Redundant`] when it has more actuators than that.
    pub fn new(model: RobotModel) -> Result<Self, RobotFileError> {
        if model.dof() != N {
            return Err(RobotFileError::Dimension {
                expected: N,
                found: model.dof(),
            });
        }
        if model.actuator_count() != N {
            return Err(RobotFileError::Redundant {
                actuators: model.actuator_count(),
                task: N,
            });
        }
        Ok(Self { model })
    }

    /// Reads a robot file with `N` task coordinates.
    ///
    /// # Errors
    /// As [`RobotModel::from_toml`] and [`Robot::new`].
    pub fn from_toml(text: &str) -> Result<Self, RobotFileError> {
        Self::new(RobotModel::from_toml(text)?)
    }

    /// The general model.
    pub fn model(&self) -> &RobotModel {
        &self.model
    }

    /// The configuration at `x` whose actuators are on the branches nearest `q`.
    fn configuration_near(
        &self,
        x: &Task<N>,
        q: &Joints<N>,
    ) -> Result<Configuration, KinematicsError> {
        self.model.configuration_near(x.as_slice(), q.as_slice())
    }
}

impl RobotModel {
    /// The configuration at task coordinates `x` with each leg on the closed-form branch
    /// nearest `q` (numerical legs: the solution reached from home).
    ///
    /// # Errors
    /// As [`RobotModel::inverse_kinematics_configuration`].
    pub fn configuration_near(
        &self,
        x: &[f64],
        q: &[f64],
    ) -> Result<Configuration, KinematicsError> {
        if q.len() != self.actuator_count() {
            return Err(InvalidInput::new(
                "q.len()",
                q.len() as f64,
                "must equal the number of actuators",
            )
            .into());
        }
        let mut config = self
            .inverse_kinematics_configuration(x, self.home_mode)
            .or_else(|_| {
                // The home mode may not reach x while the branches near q do: start from the pose.
                let mut c = Configuration::home(self);
                c.pose = self.full_pose(x)?;
                Ok::<_, KinematicsError>(c)
            })?;
        for (a, &q_a) in q.iter().enumerate() {
            let (i, actuator) = self.actuator(a);
            if self.legs[i].actuators.len() > 1 {
                // Several actuators: the leg is numerical, solved whole from home.
                config.joints[i] = self.numeric_leg(i, &config)?;
                continue;
            }
            let motion = self.nearest_actuator(a, &config, q_a)? - actuator.offset;
            config.joints[i] = self.passive_joints(i, motion, &config)?;
        }
        Ok(config)
    }
}

impl<const N: usize> ClosedChain<N, N> for Robot<N> {
    /// $\Phi_i = q_i - \mathrm{IK}_i(x)$ on the branch nearest $q_i$; NaN where $x$ is out of
    /// reach.
    fn closure(&self, x: &Task<N>, q: &Joints<N>) -> Joints<N> {
        if self.model.has_closed_form() {
            let mut ik = Joints::<N>::zeros();
            return match self
                .model
                .closed_form_nearest_with(x.as_slice(), q.as_slice(), |i, v| ik[i] = v)
            {
                Ok(_) => q - ik,
                Err(_) => Joints::repeat(f64::NAN),
            };
        }
        match self.configuration_near(x, q) {
            Ok(c) => q - Joints::<N>::from_column_slice(self.model.actuators_of(&c).as_slice()),
            Err(_) => Joints::repeat(f64::NAN),
        }
    }

    /// $J_x = -D^{-1}J_aT$; NaN where $x$ is out of reach or singular.
    fn jacobian_x(&self, x: &Task<N>, q: &Joints<N>) -> SMatrix<f64, N, N> {
        if self.model.has_closed_form() {
            let mut j = SMatrix::<f64, N, N>::zeros();
            let rows = self
                .model
                .closed_form_nearest_with(x.as_slice(), q.as_slice(), |_, _| ())
                .and_then(|mode| {
                    self.model
                        .closed_form_jacobian_rows(x.as_slice(), mode, false, |i, k, v| {
                            j[(i, k)] = -v;
                        })
                });
            return if rows.is_ok() {
                j
            } else {
                SMatrix::repeat(f64::NAN)
            };
        }
        self.configuration_near(x, q)
            .and_then(|c| self.model.screw_jacobians(&c))
            .map_or(SMatrix::repeat(f64::NAN), |j| {
                -SMatrix::<f64, N, N>::from_column_slice(j.j.as_slice())
            })
    }

    /// $J_q = I$.
    fn jacobian_q(&self, _x: &Task<N>, _q: &Joints<N>) -> SMatrix<f64, N, N> {
        SMatrix::identity()
    }
}

impl<const N: usize> InverseKinematics<N, N> for Robot<N> {
    type WorkingMode = WorkingMode;

    fn inverse_kinematics(
        &self,
        x: &Task<N>,
        mode: WorkingMode,
    ) -> Result<Joints<N>, KinematicsError> {
        if self.model.has_closed_form() {
            let mut q = Joints::<N>::zeros();
            self.model
                .closed_form_actuators_with(x.as_slice(), mode, |i, v| q[i] = v)?;
            return Ok(q);
        }
        let q = self.model.inverse_kinematics(x.as_slice(), mode)?;
        Ok(Joints::<N>::from_column_slice(q.as_slice()))
    }

    /// $J = D^{-1}J_aT$ at the configuration of the mode, from screws (from the rods alone
    /// when every leg has a closed form and no pose coordinate is dependent).
    fn velocity_jacobian_at(
        &self,
        x: &Task<N>,
        mode: WorkingMode,
    ) -> Result<SMatrix<f64, N, N>, KinematicsError> {
        if self.model.has_closed_form() {
            let mut j = SMatrix::<f64, N, N>::zeros();
            self.model
                .closed_form_jacobian_with(x.as_slice(), mode, |i, k, v| j[(i, k)] = v)?;
            return Ok(j);
        }
        let c = self
            .model
            .inverse_kinematics_configuration(x.as_slice(), mode)?;
        let j = self.model.screw_jacobians(&c)?;
        Ok(SMatrix::<f64, N, N>::from_column_slice(j.j.as_slice()))
    }
}

impl<const N: usize> ForwardKinematics<N> for Robot<N> {
    /// Newton on the reduced closure $\Phi_i = q_i - \mathrm{IK}_i(x)$ (the closed forms, as
    /// the hand-written models do) when every leg has a closed form and no pose coordinate is
    /// dependent; otherwise damped Newton on the full closure, the passive joints started from
    /// the IK at `guess` on the branches nearest `q` (or from home where the guess is out of
    /// reach).
    ///
    /// The reduced closure has the task coordinates alone as unknowns, and its Newton steps are
    /// those of the hand-written models: near a singularity, the damped full-closure steps of
    /// the passive joints could walk to another assembly mode (on the Tsai file, 410 of 24,148
    /// rows near the workspace boundary ended on the mirror mode, 0.8 m from the guess, where
    /// the hand-written model returned the pose of the guess).
    fn forward_kinematics(
        &self,
        q: &Joints<N>,
        guess: &Task<N>,
        settings: &NewtonSettings,
    ) -> Result<Task<N>, KinematicsError> {
        InvalidInput::require_positive("tolerance", settings.tolerance)?;
        if self.model.has_closed_form() {
            let closure =
                crate::closed_form::AlgebraicClosure::at_actuators(&self.model, q.as_slice());
            if let Ok(x) = pkm_traits::newton_forward_kinematics(&closure, q, guess, settings) {
                return Ok(x);
            }
        }
        let seed = self
            .model
            .configuration_near(guess.as_slice(), q.as_slice())
            .or_else(|_| {
                let mut c = Configuration::home(&self.model);
                c.pose = self.model.pose_with_task(guess.as_slice())?;
                Ok::<_, KinematicsError>(c)
            })?;
        let solver = SolverSettings {
            tolerance: settings.tolerance,
            max_evaluations: 4 * settings.max_iterations.max(1),
        };
        let c = self
            .model
            .forward_kinematics_with(q.as_slice(), &seed, &solver)?;
        Ok(Task::<N>::from_iterator(
            self.model.task.iter().map(|&k| c.pose[k]),
        ))
    }
}

/// The task coordinates of a configuration as a vector.
pub fn task_of(model: &RobotModel, c: &Configuration) -> DVector<f64> {
    DVector::from_iterator(model.task.len(), model.task.iter().map(|&k| c.pose[k]))
}
