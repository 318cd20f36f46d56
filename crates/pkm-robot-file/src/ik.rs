//! Inverse kinematics of the whole robot: the dependent pose coordinates, then each leg's
//! actuator (closed form on the mode's branch, or damped Newton), then its passive joints.

use crate::chain::{Joint, JointValue};
use crate::closure::{ClosureProblem, Configuration, LegResidual};
use crate::leg_ik::LegClass;
use crate::lm::{SolverSettings, levenberg_marquardt, polish};
use crate::model::{RobotModel, WorkingMode};
use crate::pose::CoordinateRole;
use crate::pose::{PoseCoordinates, platform_pose};
use nalgebra::{DVector, Isometry3, Quaternion, UnitQuaternion, Vector3};
use pkm_traits::KinematicsError;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// Seeds tried for a numerical leg after its home values: a fixed number of ChaCha8 draws.
const NUMERIC_LEG_STARTS: u64 = 8;
/// Steps of the continuation from home when the dependent coordinates do not converge directly.
const CONTINUATION_STEPS: usize = 8;

/// Gauss–Newton steps that move solved dependent coordinates from the closure tolerance down
/// to rounding (see [`polish`]).
const POLISH_STEPS: usize = 3;

/// The memo of [`RobotModel::solve_dependent`]: per thread, the model's identity, the bits of
/// the task coordinates and the result.
type DependentMemo = Option<(u64, Vec<u64>, Result<Configuration, KinematicsError>)>;

thread_local! {
    static LAST_DEPENDENT: std::cell::RefCell<DependentMemo> = const { std::cell::RefCell::new(None) };
}

impl RobotModel {
    /// The full pose of the task coordinates `x`: task coordinates from `x`, constant and idle
    /// ones at home, dependent ones solved from the legs' constraints.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidInput`] for a wrong length, [`KinematicsError::NonFinite`] for a
    /// NaN or infinite coordinate, [`KinematicsError::NotConverged`] when the dependent
    /// coordinates cannot be solved (the pose is out of reach of the constraints).
    pub fn full_pose(&self, x: &[f64]) -> Result<PoseCoordinates, KinematicsError> {
        Ok(self.solve_dependent(x)?.pose)
    }

    /// Validates `x` and sets the task coordinates of the home pose to it.
    pub(crate) fn pose_with_task(&self, x: &[f64]) -> Result<PoseCoordinates, KinematicsError> {
        if x.len() != self.task.len() {
            return Err(pkm_traits::InvalidInput::new(
                "x.len()",
                x.len() as f64,
                "must equal the number of task coordinates",
            )
            .into());
        }
        if let Some(&value) = x.iter().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "x", value });
        }
        let mut pose = self.home;
        for (&k, &v) in self.task.iter().zip(x) {
            pose[k] = v;
        }
        let angle = self
            .orientation
            .rotation_angle(&Vector3::new(pose[3], pose[4], pose[5]));
        if !(angle <= PI) {
            return Err(pkm_traits::InvalidInput::new(
                "rotation angle of x",
                angle,
                "orientation coordinates within one turn: rotation (or tilt) angle and torsion at most π",
            )
            .into());
        }
        Ok(pose)
    }

    /// The configuration with the dependent coordinates solved (all joints free, from home).
    ///
    /// The solution does not depend on the working mode, and a study tries every mode of a
    /// point in turn on one thread: the last solution of each thread is kept, keyed by the
    /// model's identity and the bits of `x`, so the numerical solve (and, out of reach, its
    /// continuation) runs once per point instead of once per mode.
    fn solve_dependent(&self, x: &[f64]) -> Result<Configuration, KinematicsError> {
        let pose = self.pose_with_task(x)?;
        let dependent: Vec<usize> = (0..6)
            .filter(|&k| self.roles[k] == CoordinateRole::Dependent)
            .collect();
        let mut config = Configuration::home(self);
        config.pose = pose;
        if dependent.is_empty() {
            return Ok(config);
        }
        let key: Vec<u64> = x.iter().map(|v| v.to_bits()).collect();
        let id = self.identity.0;
        let hit = LAST_DEPENDENT.with(|last| {
            let last = last.borrow();
            last.as_ref()
                .filter(|(i, k, _)| *i == id && *k == key)
                .map(|(_, _, r)| r.clone())
        });
        if let Some(result) = hit {
            return result;
        }
        let result = self.solve_dependent_from(config, pose, dependent);
        LAST_DEPENDENT.with(|last| *last.borrow_mut() = Some((id, key, result.clone())));
        result
    }

    /// [`RobotModel::solve_dependent`] without the memo: in closed form by the pointing leg
    /// when there is one (see [`crate::pointing`]), else by damped Newton.
    fn solve_dependent_from(
        &self,
        mut config: Configuration,
        pose: PoseCoordinates,
        dependent: Vec<usize>,
    ) -> Result<Configuration, KinematicsError> {
        let position = Vector3::new(pose[0], pose[1], pose[2]);
        let pointed = self
            .pointing
            .and_then(|p| Some((p.leg, p.solve(&position, &self.home_pose.rotation.into())?)));
        if let Some((leg, pointing)) = pointed {
            let o = self.orientation.coordinates_of(&pointing.rotation);
            config.pose[3..].copy_from_slice(o.as_slice());
            config.joints[leg] = pointing.joints.map(JointValue::Scalar).to_vec();
            return Ok(config);
        }
        // Only the legs with constraint wrenches determine the dependent coordinates: a leg of
        // six freedoms (a UPS) closes at any pose within its reach, which its own solve checks.
        let problem = ClosureProblem {
            model: self,
            legs: self.constraining.clone(),
            free_pose: dependent,
            fixed_actuators: false,
            residual: LegResidual::Pose,
        };
        let settings = SolverSettings::default();
        if let Ok((c, r)) = levenberg_marquardt(&problem, config.clone(), &settings) {
            return Ok(polish(&problem, c, r, POLISH_STEPS).0);
        }
        // Continuation: walk the task coordinates from home in equal steps.
        let (mut c, mut r) = (Configuration::home(self), f64::INFINITY);
        for step in 1..=CONTINUATION_STEPS {
            let s = step as f64 / CONTINUATION_STEPS as f64;
            for &k in &self.task {
                c.pose[k] = self.home[k] + s * (pose[k] - self.home[k]);
            }
            (c, r) = levenberg_marquardt(&problem, c, &settings)?;
        }
        Ok(polish(&problem, c, r, POLISH_STEPS).0)
    }

    /// Inverse kinematics in working mode `mode`: the full configuration (pose, every joint).
    ///
    /// # Errors
    /// [`KinematicsError::Unreachable`] naming the leg that cannot reach the pose or would leave
    /// its actuator range; [`KinematicsError::NotConverged`] when the dependent coordinates
    /// cannot be solved; [`KinematicsError::LegNotConverged`] naming the leg and the stage when
    /// its joints cannot be solved; [`KinematicsError::NonFinite`] /
    /// [`KinematicsError::InvalidInput`] for a bad `x`.
    pub fn inverse_kinematics_configuration(
        &self,
        x: &[f64],
        mode: WorkingMode,
    ) -> Result<Configuration, KinematicsError> {
        let mut config = self.solve_dependent(x)?;
        let target = platform_pose(self.orientation, &config.pose);
        for i in 0..self.legs.len() {
            config.joints[i] = match self.classes[i] {
                // The pointing leg was solved with the pose.
                LegClass::Numeric if self.pointing.is_some_and(|p| p.leg == i) => {
                    config.joints[i].clone()
                }
                LegClass::Numeric => self.numeric_leg(i, &config)?,
                class => {
                    let motion = class.solve(&target, mode.branch(i)).map_err(|e| {
                        KinematicsError::Unreachable {
                            leg: i,
                            discriminant: e.0,
                        }
                    })?;
                    self.passive_joints(i, motion, &config)?
                }
            };
            self.check_limits(i, &config)?;
        }
        Ok(config)
    }

    /// The actuator coordinates (offset plus motion) at task coordinates `x` in `mode`.
    ///
    /// # Errors
    /// As [`RobotModel::inverse_kinematics_configuration`].
    pub fn inverse_kinematics(
        &self,
        x: &[f64],
        mode: WorkingMode,
    ) -> Result<DVector<f64>, KinematicsError> {
        if self.has_closed_form() {
            let mut q = DVector::zeros(self.actuator_count());
            self.closed_form_actuators_with(x, mode, |i, v| q[i] = v)?;
            return Ok(q);
        }
        let config = self.inverse_kinematics_configuration(x, mode)?;
        Ok(self.actuators_of(&config))
    }

    /// The actuator coordinates (offset plus motion) of a configuration; NaN for an actuator
    /// that a configuration of another robot does not have.
    pub fn actuators_of(&self, config: &Configuration) -> DVector<f64> {
        DVector::from_fn(self.actuator_count(), |i, _| {
            self.actuator(i).1.offset + config.actuator_motion(self, i)
        })
    }

    /// Actuator `a`'s coordinate on its leg's closed-form branch nearest `q_a`, or by damped
    /// Newton for a numerical leg, at the full pose of `config`.
    pub(crate) fn nearest_actuator(
        &self,
        a: usize,
        config: &Configuration,
        q_a: f64,
    ) -> Result<f64, KinematicsError> {
        let target = platform_pose(self.orientation, &config.pose);
        let (i, actuator) = self.actuator(a);
        if self.classes[i] == LegClass::Numeric {
            let joints = self.numeric_leg(i, config)?;
            let mut c = config.clone();
            c.joints[i] = joints;
            return Ok(actuator.offset + c.actuator_motion(self, a));
        }
        self.nearest_branch(i, &target, q_a)
            .map(|(_, q)| q)
            .ok_or(KinematicsError::Unreachable {
                leg: i,
                discriminant: f64::NAN,
            })
    }

    /// The closed-form branch of leg `i` at platform pose `target` whose actuator coordinate is
    /// nearest `q_i` (a revolute actuator compared modulo 2π and moved by whole turns to lie
    /// within π of `q_i`), and that coordinate; `None` when no branch reaches the pose.
    pub(crate) fn nearest_branch(
        &self,
        i: usize,
        target: &Isometry3<f64>,
        q_i: f64,
    ) -> Option<(u8, f64)> {
        let class = self.classes[i];
        let revolute = matches!(class, LegClass::RevoluteArm { .. });
        let offset = self.legs[i].sole_actuator()?.offset;
        // (branch, distance from q_i, coordinate)
        let near = |b: u8, m: f64| {
            let q = offset + m;
            if revolute {
                let d = crate::leg_ik::wrap_angle(q - q_i);
                (b, d.abs(), q_i + d)
            } else {
                (b, (q - q_i).abs(), q)
            }
        };
        (0..class.branch_count() as u8)
            .filter_map(|b| class.solve(target, b).ok().map(|m| near(b, m)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(b, _, q)| (b, q))
    }

    /// Leg `i`'s joints with its actuator at `motion`: the passive joints in closed form when
    /// the leg has one ([`crate::passive`]), else by damped Newton from home (then from seeded
    /// restarts).
    pub(crate) fn passive_joints(
        &self,
        i: usize,
        motion: f64,
        config: &Configuration,
    ) -> Result<Vec<JointValue>, KinematicsError> {
        let target = platform_pose(self.orientation, &config.pose) * self.home_pose.inverse();
        let closed = self.passive[i]
            .as_ref()
            .and_then(|layout| layout.solve(&self.legs[i], motion, &target, self.size));
        match closed {
            Some(values) => Ok(values),
            None => self.newton_leg(i, Some(motion), config),
        }
    }

    /// Leg `i` solved whole by damped Newton from its home values, then seeded restarts.
    pub(crate) fn numeric_leg(
        &self,
        i: usize,
        config: &Configuration,
    ) -> Result<Vec<JointValue>, KinematicsError> {
        self.newton_leg(i, None, config)
    }

    /// Leg `i` by damped Newton from its home values (its actuator held at `motion` when given),
    /// then in two stages from there (see [`RobotModel::staged_leg_solve`]), then in two stages
    /// from [`NUMERIC_LEG_STARTS`] seeded starts spread over each joint's whole range: revolute
    /// angles in $[-\pi, \pi)$, prismatic travels within 1.5 robot sizes, spherical joints over
    /// the rotation group.
    ///
    /// # Errors
    /// [`KinematicsError::LegNotConverged`] naming the leg, the stage and the best residual.
    pub(crate) fn newton_leg(
        &self,
        i: usize,
        motion: Option<f64>,
        config: &Configuration,
    ) -> Result<Vec<JointValue>, KinematicsError> {
        let problem = ClosureProblem {
            model: self,
            legs: vec![i],
            free_pose: vec![],
            fixed_actuators: motion.is_some(),
            residual: LegResidual::Pose,
        };
        let mut start = config.clone();
        start.joints[i] = self.legs[i].home_values();
        if let (Some(motion), Some(a)) = (motion, self.legs[i].sole_actuator()) {
            start.joints[i][a.joint] = JointValue::Scalar(motion);
        }
        let settings = SolverSettings::default();
        let mut rng = ChaCha8Rng::seed_from_u64(i as u64);
        let mut best = f64::NAN;
        for k in 0..=NUMERIC_LEG_STARTS {
            let seed = if k == 0 {
                start.clone()
            } else {
                self.seeded_leg(i, &start, problem.fixed_actuators, &mut rng)
            };
            let direct = || levenberg_marquardt(&problem, seed.clone(), &settings).map(|(c, _)| c);
            let solved = match k {
                0 => direct().or_else(|_| self.staged_leg_solve(&problem, seed.clone(), &settings)),
                _ => self.staged_leg_solve(&problem, seed.clone(), &settings),
            };
            match solved {
                Ok(c) => return Ok(c.joints[i].clone()),
                Err(KinematicsError::NotConverged { residual, .. }) => best = best.min(residual),
                Err(_) => {}
            }
        }
        Err(KinematicsError::LegNotConverged {
            leg: i,
            stage: if motion.is_some() {
                "passive joints"
            } else {
                "joints"
            },
            starts: NUMERIC_LEG_STARTS as usize + 1,
            residual: best,
        })
    }

    /// The closure `problem` of one leg from `start`. A leg whose closed form places a platform
    /// point $C$ is solved in two stages: first the position of $C$ alone (the joints through
    /// $C$ do not move it, and placing a point by the joints before it has one local minimum
    /// up to the antipodal maximum), then the whole pose from there. Closing the whole pose
    /// directly from a far start can stall in a local minimum of the mixed rotation and
    /// position residual (a 3-RPR at a far assembly mode did from every start in a quarter
    /// turn of home).
    fn staged_leg_solve(
        &self,
        problem: &ClosureProblem<'_>,
        start: Configuration,
        settings: &SolverSettings,
    ) -> Result<Configuration, KinematicsError> {
        let point = problem
            .legs
            .first()
            .and_then(|&i| self.classes[i].platform_point());
        let Some(p) = point.filter(|_| problem.fixed_actuators) else {
            return Ok(levenberg_marquardt(problem, start, settings)?.0);
        };
        let stage = |residual| ClosureProblem {
            residual,
            ..problem.clone()
        };
        // The first stage only starts the second: placed to 1e-6 robot sizes, the second ends
        // in its quadratic convergence instead of at the first's tolerance.
        let rough = SolverSettings {
            tolerance: settings.tolerance.max(1e-6 * self.size),
            ..*settings
        };
        let placed = levenberg_marquardt(&stage(LegResidual::PositionOf(p)), start, &rough)?.0;
        Ok(levenberg_marquardt(&stage(LegResidual::PoseAt(p)), placed, settings)?.0)
    }

    /// `start` with leg `i`'s joints (but its actuator when `hold_actuator`) drawn from `rng`.
    fn seeded_leg(
        &self,
        i: usize,
        start: &Configuration,
        hold_actuator: bool,
        rng: &mut ChaCha8Rng,
    ) -> Configuration {
        let mut seed = start.clone();
        for (j, (value, joint)) in seed.joints[i]
            .iter_mut()
            .zip(&self.legs[i].joints)
            .enumerate()
        {
            if hold_actuator && self.legs[i].is_actuated(j) {
                continue;
            }
            *value = match joint {
                Joint::Revolute { .. } => JointValue::Scalar(rng.random_range(-PI..PI)),
                Joint::Prismatic { .. } => {
                    JointValue::Scalar(self.size * rng.random_range(-1.5..1.5))
                }
                Joint::Spherical { .. } => {
                    let q = Quaternion::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    JointValue::Ball(UnitQuaternion::from_quaternion(q).to_rotation_matrix())
                }
            };
        }
        seed
    }

    /// `Err(Unreachable)` when an actuator of leg `i` in `config` is outside its range.
    fn check_limits(&self, i: usize, config: &Configuration) -> Result<(), KinematicsError> {
        for (a, &(leg, _)) in self.actuators.iter().enumerate() {
            if leg == i {
                let offset = self.actuator(a).1.offset;
                self.check_actuator_limits(a, offset + config.actuator_motion(self, a))?;
            }
        }
        Ok(())
    }

    /// `Err(Unreachable)` naming its leg when coordinate `q` of actuator `a` is outside its
    /// range.
    pub(crate) fn check_actuator_limits(&self, a: usize, q: f64) -> Result<(), KinematicsError> {
        let (leg, actuator) = self.actuator(a);
        let Some([lo, hi]) = actuator.limits else {
            return Ok(());
        };
        if (lo..=hi).contains(&q) {
            Ok(())
        } else {
            Err(KinematicsError::Unreachable {
                leg,
                discriminant: -(lo - q).max(q - hi),
            })
        }
    }
}
