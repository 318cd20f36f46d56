//! Inverse dynamics of any robot file with mass properties (issue 31), in two formulations
//! that must agree:
//!
//! - **Extended space with Lagrange multipliers** (Miller 2004 §3, generalised to any leg
//!   chain): every leg is a serial chain cut from the platform, every joint coordinate a
//!   coordinate of its own, and the closure of leg $i$ holds by a multiplier wrench
//!   $\lambda_i$ (what the leg exerts on the platform). Joint coordinate $j$ of leg $i$ with
//!   twist $\xi_{ij}$ balances (eq. D1)
//!   $$\tau_{ij} = Q_{ij} + \xi_{ij}\cdot\lambda_i,\qquad Q_{ij} = \sum_{b \succ j} \xi_{ij}\cdot W_b + I_{r}\ddot\theta_{ij},$$
//!   with $\tau_{ij} = 0$ for a passive coordinate, $W_b$ the wrench body $b$ needs (its
//!   inertia and weight) summed over the leg's bodies beyond the joint, and $I_r$ a reflected
//!   rotor inertia; the platform balances $\sum_i \lambda_i = W_P$ (eq. D2). The linear
//!   system in $(\lambda, \tau)$ is solved by least squares (the multipliers of an
//!   overconstrained robot are not unique; its efforts are).
//! - **Virtual work**: the power of the efforts equals the power the bodies need for every
//!   admissible velocity, so with $V_b^k$ the twist of body $b$ per unit rate of task
//!   coordinate $k$, (eq. D3)
//!   $$J^\top\tau = Q,\qquad Q_k = \sum_b W_b\cdot V_b^k + \sum_a I_{r,a}\ddot\theta_a\,\dot\theta_a^k,$$
//!   with $J_{ak} = \dot\theta_a^k$; for more actuators than task coordinates the efforts of
//!   least norm.
//!
//! Both take the same motion of every coordinate, solved from the task motion
//! $(x, \dot x, \ddot x)$: the configuration by the inverse kinematics; the rates of the
//! dependent pose coordinates and of every joint from the differentiated closure of each leg,
//! $\sum_j c_{ij}\dot\theta_{ij} = H(c)\,\dot c$ (columns $c_{ij} = [\omega_{ij};\ v_{ij} +
//! \omega_{ij}\times p]$, $H$ the pose-coordinate rates of [`crate::pose`]); the accelerations
//! from its derivative $\sum_j (c_{ij}\ddot\theta_{ij} + \dot c_{ij}\dot\theta_{ij}) = H\ddot
//! c + \dot H\dot c$, where $\dot\xi_{ij} = \sum_{l \prec j}\dot\theta_{il}[\xi_{il},
//! \xi_{ij}]$ with the Lie bracket $[\xi_1, \xi_2] = [\omega_1\times\omega_2;\ \omega_1\times
//! v_2 - \omega_2\times v_1]$, and $\dot H\dot c$, the derivative of the orientation rates
//! along $\dot c$, is a fourth-order central difference (step 1e-3 rad, error below 1e-11 of
//! $\lvert\dot c\rvert^2$).
//!
//! A body with centre $c$, inertia $I$ (both moved with it), twist $[\omega; v_O]$ and its
//! derivative needs $F = m(a_c - g)$ with $a_c = \dot v_O + \dot\omega\times c +
//! \omega\times(v_O + \omega\times c)$, and $M_O = I\dot\omega + \omega\times I\omega +
//! c\times F$ (Newton–Euler about its centre, moved to O).

use crate::chain::{LegTwists, stack};
use crate::closure::Configuration;
use crate::mass::Body;
use crate::model::{RobotModel, WorkingMode};
use crate::pose::{CoordinateRole, hybrid_rates, platform_pose};
use nalgebra::{DMatrix, DVector, Isometry3, Point3, Vector3, Vector6};
use pkm_traits::{KinematicsError, RhsError, VectorField};
use thiserror::Error;

/// Why the dynamics of a robot file cannot be computed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// The file lacks what the dynamics needs.
    #[error(
        "the robot file has no `{0}`: the dynamics needs it (`gravity = [0.0, 0.0, -9.81]` \
         with z up, `[0.0, 0.0, 0.0]` to switch it off; masses in `[platform]`, `links` and \
         joint `mass`, see docs/robots.md)"
    )]
    Missing(&'static str),
    /// The task motion is not one of this robot (wrong length, not finite).
    #[error("{what}: {reason}")]
    Motion {
        /// Which input.
        what: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The configuration is singular (within 1e-9 of an inverse or direct singularity):
    /// efforts there would be huge or undefined.
    #[error(
        "singular configuration (inverse margin {inverse:.3e}, direct margin {direct:.3e}): \
         the efforts are unbounded there"
    )]
    Singular {
        /// The inverse-kinematic margin.
        inverse: f64,
        /// The direct-kinematic margin.
        direct: f64,
    },
    /// The task-space mass matrix is not positive definite: some task direction moves no
    /// mass (a massless robot), so efforts do not determine the accelerations.
    #[error(
        "the task-space mass matrix is not positive definite: give the bodies that the task \
         coordinates move a mass"
    )]
    Massless,
    /// A kinematic failure (out of reach, not converged).
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
}

/// The actuator efforts at one sample, by both formulations.
#[derive(Debug, Clone, PartialEq)]
pub struct InverseDynamics {
    /// The six pose coordinates (the dependent ones solved).
    pub pose: [f64; 6],
    /// Actuator efforts by virtual work (N for a prismatic actuator, N·m for a revolute one),
    /// in the order of [`RobotModel::actuator_names`].
    pub efforts: DVector<f64>,
    /// The same by the extended space with multipliers.
    pub efforts_multipliers: DVector<f64>,
    /// The multiplier wrench $\lambda_i = [f; m_O]$ each leg exerts on the platform.
    pub multipliers: Vec<Vector6<f64>>,
    /// The actuator rates $\dot q$ (rad/s or m/s).
    pub actuator_rates: DVector<f64>,
    /// Kinetic energy (J).
    pub kinetic_energy: f64,
    /// Potential energy of gravity (J), zero at the base origin.
    pub potential_energy: f64,
}

/// The task accelerations under given efforts, with the task-space mass matrix and the
/// energies at the state.
#[derive(Debug, Clone, PartialEq)]
pub struct ForwardDynamics {
    /// $\ddot x$ (m/s², rad/s²).
    pub acceleration: DVector<f64>,
    /// $M_x$, the kinetic energy $\tfrac12\dot x^\top M_x\dot x$'s matrix (rotors included).
    pub mass_matrix: DMatrix<f64>,
    /// The actuator rates $\dot q$.
    pub actuator_rates: DVector<f64>,
    /// Kinetic energy (J).
    pub kinetic_energy: f64,
    /// Potential energy of gravity (J).
    pub potential_energy: f64,
}

/// A configuration ready for the dynamics: its closure factored, and per unit rate of each
/// task coordinate every joint's rate and the platform's twist, with $J^\top$
/// ($J_{ak} = \dot\theta_a^k$), which depend on the configuration alone.
struct Prepared {
    gravity: Vector3<f64>,
    config: Configuration,
    closure: ClosureRates,
    /// Per task coordinate: the joint rates per leg, and the platform twist.
    unit_rates: Vec<(Vec<Vec<f64>>, Vector6<f64>)>,
    jt: DMatrix<f64>,
}

/// Eq. D3 at one motion, with what the multipliers need.
struct Balance {
    motion: Motion,
    bodies: Vec<Vec<(usize, BodyState)>>,
    /// $Q_l$ of eq. D1 per leg, per coordinate.
    joint_forces: Vec<Vec<f64>>,
    /// $W_P$: the wrench the platform and the bodies riding on it need.
    platform_wrench: Vector6<f64>,
    forces: DVector<f64>,
}

/// `Err(Motion)` unless `v` has `len` finite entries within ±1e9.
fn check_motion(len: usize, what: &'static str, v: &[f64]) -> Result<(), DynamicsError> {
    if v.len() == len && v.iter().all(|e| e.is_finite() && e.abs() <= 1e9) {
        Ok(())
    } else {
        Err(DynamicsError::Motion {
            what,
            reason: format!("must have {len} finite entries within ±1e9"),
        })
    }
}

/// The rates and accelerations of every coordinate at one sample.
struct Motion {
    config: Configuration,
    /// $\dot c$, $\ddot c$ of the six pose coordinates.
    pose_rate: Vector6<f64>,
    pose_acceleration: Vector6<f64>,
    /// Per leg, per coordinate.
    joint_rates: Vec<Vec<f64>>,
    joint_accelerations: Vec<Vec<f64>>,
}

/// A body's state: where it is and how it moves.
struct BodyState {
    mass: f64,
    center: Vector3<f64>,
    inertia: nalgebra::Matrix3<f64>,
    twist: Vector6<f64>,
    acceleration: Vector6<f64>,
}

/// $[\xi_1, \xi_2]$ of twists `[ω; v]`.
fn bracket(a: &Vector6<f64>, b: &Vector6<f64>) -> Vector6<f64> {
    let (wa, va) = split(a);
    let (wb, vb) = split(b);
    stack(&wa.cross(&wb), &(wa.cross(&vb) - wb.cross(&va)))
}

fn split(s: &Vector6<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (s.fixed_rows::<3>(0).into(), s.fixed_rows::<3>(3).into())
}

/// The power of wrench `w = [f; m_O]` on twist `t = [ω; v_O]`.
fn power(w: &Vector6<f64>, t: &Vector6<f64>) -> f64 {
    let (f, m) = split(w);
    let (omega, v) = split(t);
    f.dot(&v) + m.dot(&omega)
}

impl BodyState {
    fn place(
        body: &Body,
        g: &Isometry3<f64>,
        twist: Vector6<f64>,
        acceleration: Vector6<f64>,
    ) -> Self {
        let r = g.rotation.to_rotation_matrix();
        Self {
            mass: body.mass,
            center: (g * Point3::from(body.center)).coords,
            inertia: r.matrix() * body.inertia * r.matrix().transpose(),
            twist,
            acceleration,
        }
    }

    /// The wrench `[F; M_O]` the body needs for its motion under `gravity`.
    fn wrench(&self, gravity: &Vector3<f64>) -> Vector6<f64> {
        let (omega, v_o) = split(&self.twist);
        let (alpha, a_o) = split(&self.acceleration);
        let c = self.center;
        let v_c = v_o + omega.cross(&c);
        let a_c = a_o + alpha.cross(&c) + omega.cross(&v_c);
        let force = (a_c - gravity) * self.mass;
        let moment_c = self.inertia * alpha + omega.cross(&(self.inertia * omega));
        stack(&force, &(moment_c + c.cross(&force)))
    }

    fn kinetic_energy(&self) -> f64 {
        let (omega, v_o) = split(&self.twist);
        let v_c = v_o + omega.cross(&self.center);
        0.5 * (self.mass * v_c.norm_squared() + omega.dot(&(self.inertia * omega)))
    }
}

impl RobotModel {
    /// The actuator efforts that drive the task motion $(x, \dot x, \ddot x)$ in working mode
    /// `mode`, by both formulations of the module documentation, with the energies.
    ///
    /// # Errors
    /// [`DynamicsError::Missing`] without `gravity`; [`DynamicsError::Motion`] for inputs of
    /// the wrong length or not finite; [`DynamicsError::Singular`] within 1e-9 of a
    /// singularity; [`DynamicsError::Kinematics`] out of reach.
    pub fn inverse_dynamics(
        &self,
        x: &[f64],
        velocity: &[f64],
        acceleration: &[f64],
        mode: WorkingMode,
    ) -> Result<InverseDynamics, DynamicsError> {
        check_motion(self.task.len(), "acceleration", acceleration)?;
        let prepared = self.prepare(x, velocity, mode)?;
        let balance = self.balance(&prepared, velocity, acceleration)?;
        let efforts = least_squares(prepared.jt.clone(), &balance.forces, "J^T")?;
        let (efforts_multipliers, multipliers) =
            self.multiplier_efforts(&balance, &prepared.closure.twists)?;
        let actuator_rates = self.actuator_rates(&balance.motion);
        let (kinetic_energy, potential_energy) =
            self.energies(&balance.motion, &balance.bodies, &prepared.gravity);
        Ok(InverseDynamics {
            pose: balance.motion.config.pose,
            efforts,
            efforts_multipliers,
            multipliers,
            actuator_rates,
            kinetic_energy,
            potential_energy,
        })
    }

    /// The actuator efforts alone, by virtual work (eq. D3): what
    /// [`RobotModel::inverse_dynamics`] returns as `efforts`, to the same bits, without the
    /// second formulation, the multipliers and the energies (the path of a study's samples and
    /// effort maps when the check is not asked for).
    ///
    /// # Errors
    /// As [`RobotModel::inverse_dynamics`].
    pub fn actuator_efforts(
        &self,
        x: &[f64],
        velocity: &[f64],
        acceleration: &[f64],
        mode: WorkingMode,
    ) -> Result<DVector<f64>, DynamicsError> {
        check_motion(self.task.len(), "acceleration", acceleration)?;
        let prepared = self.prepare(x, velocity, mode)?;
        let balance = self.balance(&prepared, velocity, acceleration)?;
        least_squares(prepared.jt, &balance.forces, "J^T")
    }

    /// The task accelerations $\ddot x$ that the actuator efforts `efforts` give at $(x,
    /// \dot x)$ in working mode `mode`: with the generalised task forces $Q(\ddot x) = M_x\ddot
    /// x + b$ of eq. D3 (affine in $\ddot x$), $M_x e_k = Q(e_k) - Q(0)$, $b = Q(0)$, and (eq. D4)
    /// $$M_x\ddot x = J^\top\tau - b,$$
    /// solved by Cholesky ($M_x$ is the kinetic energy's matrix in the task rates, symmetric
    /// positive definite when every task direction moves some mass).
    ///
    /// # Errors
    /// As [`RobotModel::inverse_dynamics`]; [`DynamicsError::Motion`] for efforts of the wrong
    /// length or not finite; [`DynamicsError::Massless`] when $M_x$ is not positive definite.
    pub fn forward_dynamics(
        &self,
        x: &[f64],
        velocity: &[f64],
        efforts: &[f64],
        mode: WorkingMode,
    ) -> Result<ForwardDynamics, DynamicsError> {
        check_motion(self.actuator_count(), "efforts", efforts)?;
        let prepared = self.prepare(x, velocity, mode)?;
        let n = self.task.len();
        let zero = vec![0.0; n];
        let bias = self.balance(&prepared, velocity, &zero)?;
        let mut mass_matrix = DMatrix::zeros(n, n);
        for k in 0..n {
            let mut e = zero.clone();
            e[k] = 1.0;
            let column = self.balance(&prepared, velocity, &e)?.forces - &bias.forces;
            mass_matrix.set_column(k, &column);
        }
        let symmetric = (&mass_matrix + mass_matrix.transpose()) * 0.5;
        let forces = &prepared.jt * DVector::from_column_slice(efforts) - &bias.forces;
        let acceleration = symmetric
            .clone()
            .cholesky()
            .map(|c| c.solve(&forces))
            .filter(|a| a.iter().all(|v| v.is_finite()))
            .ok_or(DynamicsError::Massless)?;
        let (kinetic_energy, potential_energy) =
            self.energies(&bias.motion, &bias.bodies, &prepared.gravity);
        Ok(ForwardDynamics {
            acceleration,
            mass_matrix: symmetric,
            actuator_rates: self.actuator_rates(&bias.motion),
            kinetic_energy,
            potential_energy,
        })
    }

    /// The largest |effort| of each actuator at rest at `x` over the task accelerations
    /// $\lvert\ddot x_k\rvert \le a_k$ (`accelerations`, m/s² or rad/s²): the efforts are
    /// affine in $\ddot x$ at rest, $\tau = \tau_0 + \sum_k \ddot x_k\,\tau_k$ (eq. D3), so the
    /// largest over the box is exactly (eq. D5)
    /// $$\max\lvert\tau_a\rvert = \lvert\tau_{0a}\rvert + \sum_k a_k\lvert\tau_{ka}\rvert:$$
    /// how hard the robot is to drive there, its weight included.
    ///
    /// # Errors
    /// As [`RobotModel::inverse_dynamics`]; [`DynamicsError::Motion`] for accelerations of the
    /// wrong length, negative or not finite.
    pub fn peak_efforts_at_rest(
        &self,
        x: &[f64],
        accelerations: &[f64],
        mode: WorkingMode,
    ) -> Result<DVector<f64>, DynamicsError> {
        check_motion(self.task.len(), "accelerations", accelerations)?;
        if accelerations.iter().any(|a| *a < 0.0) {
            return Err(DynamicsError::Motion {
                what: "accelerations",
                reason: "bounds must be at least 0".into(),
            });
        }
        let n = self.task.len();
        let zero = vec![0.0; n];
        let prepared = self.prepare(x, &zero, mode)?;
        let jt = Factored::new(prepared.jt.clone(), "J^T")?;
        let efforts = |acceleration: &[f64]| -> Result<DVector<f64>, DynamicsError> {
            jt.solve(&self.balance(&prepared, &zero, acceleration)?.forces)
        };
        let at_rest = efforts(&zero)?;
        let mut peak = at_rest.abs();
        for (k, &bound) in accelerations.iter().enumerate() {
            let mut e = zero.clone();
            e[k] = 1.0;
            peak += (efforts(&e)? - &at_rest).abs() * bound;
        }
        Ok(peak)
    }

    /// Gravity, the configuration at `x` checked away from singularities, and its closure.
    fn prepare(
        &self,
        x: &[f64],
        velocity: &[f64],
        mode: WorkingMode,
    ) -> Result<Prepared, DynamicsError> {
        let gravity = self.mass.gravity.ok_or(DynamicsError::Missing("gravity"))?;
        check_motion(self.task.len(), "velocity", velocity)?;
        let config = self.inverse_kinematics_configuration(x, mode)?;
        let margins = self.singularity_margins(&config)?;
        if !(margins.inverse > 1e-9 && margins.direct > 1e-9) {
            return Err(DynamicsError::Singular {
                inverse: margins.inverse,
                direct: margins.direct,
            });
        }
        let closure = ClosureRates::new(self, &config)?;
        let n = self.task.len();
        let mut unit_rates = Vec::with_capacity(n);
        let mut jt = DMatrix::zeros(n, self.actuator_count());
        for k in 0..n {
            let mut e = vec![0.0; n];
            e[k] = 1.0;
            let unit = closure.rates(self, config.clone(), &e)?;
            jt.set_row(k, &self.actuator_rates(&unit).transpose());
            let platform = self.platform_motion(&unit).0;
            unit_rates.push((unit.joint_rates, platform));
        }
        Ok(Prepared {
            gravity,
            config,
            closure,
            unit_rates,
            jt,
        })
    }

    /// The motion of every body for the task motion, the wrenches they need, and eq. D3's
    /// generalised task forces $Q$ with $J^\top$.
    fn balance(
        &self,
        prepared: &Prepared,
        velocity: &[f64],
        acceleration: &[f64],
    ) -> Result<Balance, DynamicsError> {
        let closure = &prepared.closure;
        let motion = closure.motion(self, prepared.config.clone(), velocity, acceleration)?;
        let bodies = self.body_states(&motion, &closure.twists);
        let wrenches: Vec<Vec<Vector6<f64>>> = bodies
            .iter()
            .map(|leg| {
                leg.iter()
                    .map(|(_, b)| b.wrench(&prepared.gravity))
                    .collect()
            })
            .collect();
        let joint_forces = self.joint_forces(&bodies, &wrenches, &closure.twists);
        let platform_wrench: Vector6<f64> = wrenches[self.legs.len()].iter().sum();
        let forces = self.task_forces(&motion, &joint_forces, &platform_wrench, prepared);
        Ok(Balance {
            motion,
            bodies,
            joint_forces,
            platform_wrench,
            forces,
        })
    }

    /// $\dot q$ of every actuator.
    fn actuator_rates(&self, motion: &Motion) -> DVector<f64> {
        DVector::from_fn(self.actuator_count(), |a, _| {
            let (leg, actuator) = self.actuator(a);
            motion.joint_rates[leg][self.coordinate_of(leg, actuator.joint)]
        })
    }

    /// The coordinate index within leg `leg` of its (scalar) joint `joint`.
    fn coordinate_of(&self, leg: usize, joint: usize) -> usize {
        self.legs[leg].joints[..joint].iter().map(|j| j.dof()).sum()
    }

    /// Every massive body with its state, per leg (the bodies riding on the platform and the
    /// platform itself in a last group), each with the number of its leg's coordinates that
    /// move it (`usize::MAX` for the platform group).
    fn body_states(&self, motion: &Motion, twists: &[LegTwists]) -> Vec<Vec<(usize, BodyState)>> {
        let mut out = Vec::with_capacity(self.legs.len() + 1);
        let mut riding = Vec::new();
        let (platform_twist, platform_acceleration) = self.platform_motion(motion);
        let pose = platform_pose(self.orientation, &motion.config.pose);
        let platform_move = pose * self.home_pose.inverse();
        for (i, (leg, lt)) in self.legs.iter().zip(twists).enumerate() {
            let (rates, accelerations) = (&motion.joint_rates[i], &motion.joint_accelerations[i]);
            let twist_derivatives = twist_derivatives(&lt.twists, rates);
            let mut group = Vec::new();
            for body in &leg.bodies {
                if body.after >= leg.joints.len() {
                    riding.push((
                        usize::MAX,
                        BodyState::place(
                            body,
                            &platform_move,
                            platform_twist,
                            platform_acceleration,
                        ),
                    ));
                    continue;
                }
                let moving = lt
                    .twists
                    .iter()
                    .take_while(|(j, _)| *j < body.after)
                    .count();
                let mut twist = Vector6::zeros();
                let mut acceleration = Vector6::zeros();
                for l in 0..moving {
                    twist += lt.twists[l].1 * rates[l];
                    acceleration +=
                        lt.twists[l].1 * accelerations[l] + twist_derivatives[l] * rates[l];
                }
                let g = if body.after == 0 {
                    Isometry3::identity()
                } else {
                    lt.prefixes[body.after - 1]
                };
                group.push((moving, BodyState::place(body, &g, twist, acceleration)));
            }
            out.push(group);
        }
        if let Some(platform) = &self.mass.platform {
            riding.push((
                usize::MAX,
                BodyState::place(
                    platform,
                    &platform_move,
                    platform_twist,
                    platform_acceleration,
                ),
            ));
        }
        out.push(riding);
        out
    }

    /// The platform's space twist $[\omega;\ \dot p - \omega\times p]$ and its derivative.
    fn platform_motion(&self, motion: &Motion) -> (Vector6<f64>, Vector6<f64>) {
        let c = &motion.config.pose;
        let h = hybrid_rates(self.orientation, c);
        let rate = h * motion.pose_rate;
        let acc = h * motion.pose_acceleration + self.rates_derivative(c, &motion.pose_rate);
        let p = Vector3::new(c[0], c[1], c[2]);
        let (omega, p_dot) = split(&rate);
        let (alpha, p_ddot) = split(&acc);
        (
            stack(&omega, &(p_dot - omega.cross(&p))),
            stack(&alpha, &(p_ddot - alpha.cross(&p) - omega.cross(&p_dot))),
        )
    }

    /// $\dot H\dot c$: the derivative of $H(c)\,\dot c$ along $\dot c$ at fixed $\dot c$ (the
    /// orientation rows only; the position rows of $H$ are constant), by the fourth-order
    /// central difference with step $h = 10^{-3}$ along the unit direction of $\dot c$.
    fn rates_derivative(&self, c: &[f64; 6], rate: &Vector6<f64>) -> Vector6<f64> {
        let direction = Vector3::new(rate[3], rate[4], rate[5]);
        let speed = direction.norm();
        if !(speed > 0.0) {
            return Vector6::zeros();
        }
        let u = direction / speed;
        let h = 1e-3;
        let at = |s: f64| {
            let mut moved = *c;
            for k in 0..3 {
                moved[3 + k] += s * u[k];
            }
            hybrid_rates(self.orientation, &moved) * rate
        };
        (8.0 * (at(h) - at(-h)) - (at(2.0 * h) - at(-2.0 * h))) * (speed / (12.0 * h))
    }

    /// Eq. D3's generalised task forces $Q_k = \sum_b W_b\cdot V_b^k + \sum_a
    /// I_{r,a}\ddot\theta_a\dot\theta_a^k$, with a leg body's unit twist
    /// $V_b^k = \sum_{l \prec b}\xi_l\dot\theta_l^k$ gathered per joint (eq. D6):
    /// $$\sum_{b \in \text{leg}} W_b\cdot V_b^k = \sum_l Q_l\,\dot\theta_l^k,\qquad
    /// Q_l = \sum_{b \succ l}\xi_l\cdot W_b,$$
    /// the joint forces of eq. D1, and the bodies riding on the platform by its unit twist.
    fn task_forces(
        &self,
        motion: &Motion,
        joint_forces: &[Vec<f64>],
        riding: &Vector6<f64>,
        prepared: &Prepared,
    ) -> DVector<f64> {
        DVector::from_fn(self.task.len(), |k, _| {
            let (rates, platform) = &prepared.unit_rates[k];
            let legs: f64 = joint_forces
                .iter()
                .zip(rates)
                .flat_map(|(forces, rates)| forces.iter().zip(rates))
                .map(|(q, rate)| q * rate)
                .sum();
            let rotors: f64 = (0..self.actuator_count())
                .map(|a| {
                    let (leg, actuator) = self.actuator(a);
                    let coordinate = self.coordinate_of(leg, actuator.joint);
                    actuator.reflected_inertia
                        * motion.joint_accelerations[leg][coordinate]
                        * prepared.jt[(k, a)]
                })
                .sum();
            legs + power(riding, platform) + rotors
        })
    }

    /// $Q_l = \sum_{b \succ l}\xi_l\cdot W_b$ of every joint coordinate of every leg (eq. D1):
    /// the power of the wrenches its leg's bodies beyond it need, per unit rate.
    fn joint_forces(
        &self,
        bodies: &[Vec<(usize, BodyState)>],
        wrenches: &[Vec<Vector6<f64>>],
        twists: &[LegTwists],
    ) -> Vec<Vec<f64>> {
        twists
            .iter()
            .enumerate()
            .map(|(i, lt)| {
                lt.twists
                    .iter()
                    .enumerate()
                    .map(|(coordinate, (_, xi))| {
                        bodies[i]
                            .iter()
                            .zip(&wrenches[i])
                            .filter(|((moving, _), _)| coordinate < *moving)
                            .map(|(_, w)| power(w, xi))
                            .sum()
                    })
                    .collect()
            })
            .collect()
    }

    /// Eqs. D1–D2 in $(\lambda, \tau)$ by least squares.
    fn multiplier_efforts(
        &self,
        balance: &Balance,
        twists: &[LegTwists],
    ) -> Result<(DVector<f64>, Vec<Vector6<f64>>), DynamicsError> {
        let motion = &balance.motion;
        let legs = self.legs.len();
        let m = self.actuator_count();
        let rows: usize = self.legs.iter().map(|l| l.dof()).sum::<usize>() + 6;
        let mut a = DMatrix::zeros(rows, 6 * legs + m);
        let mut b = DVector::zeros(rows);
        let mut row = 0;
        for (i, (leg, lt)) in self.legs.iter().zip(twists).enumerate() {
            for (coordinate, (joint, xi)) in lt.twists.iter().enumerate() {
                // ξ·λ_i − τ = −Q_ij.
                for r in 0..6 {
                    // power(λ, ξ) = f·v + m·ω: λ = [f; m], ξ = [ω; v].
                    a[(row, 6 * i + r)] = if r < 3 { xi[3 + r] } else { xi[r - 3] };
                }
                let mut need = balance.joint_forces[i][coordinate];
                if let Some(actuator) = leg.actuator_at(*joint) {
                    let index = self
                        .actuators
                        .iter()
                        .position(|&(l, k)| l == i && leg.actuators[k].joint == *joint)
                        .unwrap_or(0);
                    a[(row, 6 * legs + index)] = -1.0;
                    need += actuator.reflected_inertia * motion.joint_accelerations[i][coordinate];
                }
                b[row] = -need;
                row += 1;
            }
        }
        // Σ λ_i = W_P.
        let platform = balance.platform_wrench;
        for r in 0..6 {
            for i in 0..legs {
                a[(row + r, 6 * i + r)] = 1.0;
            }
            b[row + r] = platform[r];
        }
        let solution = least_squares(a, &b, "extended-space balance")?;
        let efforts = solution.rows(6 * legs, m).into_owned();
        let multipliers = (0..legs)
            .map(|i| solution.fixed_rows::<6>(6 * i).into_owned())
            .collect();
        Ok((efforts, multipliers))
    }

    /// Kinetic energy (bodies and rotors) and the potential energy of gravity.
    fn energies(
        &self,
        motion: &Motion,
        bodies: &[Vec<(usize, BodyState)>],
        gravity: &Vector3<f64>,
    ) -> (f64, f64) {
        let states = bodies.iter().flatten().map(|(_, s)| s);
        let kinetic: f64 = states.clone().map(BodyState::kinetic_energy).sum();
        let potential: f64 = states.map(|s| -s.mass * gravity.dot(&s.center)).sum();
        let rotors: f64 = (0..self.actuator_count())
            .map(|a| {
                let (leg, actuator) = self.actuator(a);
                let rate = motion.joint_rates[leg][self.coordinate_of(leg, actuator.joint)];
                0.5 * actuator.reflected_inertia * rate * rate
            })
            .sum();
        (kinetic + rotors, potential)
    }
}

/// $\dot\xi_l = \sum_{m \prec l}\dot\theta_m[\xi_m, \xi_l]$ for each coordinate: the
/// coordinates of earlier joints only (a ball's three twists move with the joints before it,
/// not with each other).
fn twist_derivatives(twists: &[(usize, Vector6<f64>)], rates: &[f64]) -> Vec<Vector6<f64>> {
    twists
        .iter()
        .map(|(joint, xi)| {
            twists
                .iter()
                .zip(rates)
                .take_while(|((j, _), _)| j < joint)
                .map(|((_, earlier), rate)| bracket(earlier, xi) * *rate)
                .sum()
        })
        .collect()
}

/// The least-squares solution of `a x = b` of least norm, checked (see [`Factored::solve`]).
fn least_squares(
    a: DMatrix<f64>,
    b: &DVector<f64>,
    matrix: &'static str,
) -> Result<DVector<f64>, DynamicsError> {
    Factored::new(a, matrix)?.solve(b)
}

/// A matrix factored for least-squares solves of least norm against several right-hand sides:
/// by LU when it is square and its pivots are within 1e-10 of each other (its solution is then
/// the unique, so least-norm, one, at a fraction of an SVD's cost: the Stewart–Gough's 36 × 36
/// closure and 42 × 42 balance), else by its SVD.
struct Factored {
    a: DMatrix<f64>,
    decomposition: Decomposition,
    matrix: &'static str,
}

enum Decomposition {
    Lu(nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>),
    Svd(nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>),
}

impl Factored {
    fn new(a: DMatrix<f64>, matrix: &'static str) -> Result<Self, DynamicsError> {
        if a.is_square() && a.iter().all(|v| v.is_finite()) {
            let lu = a.clone().lu();
            let pivots = lu.u().diagonal().abs();
            if pivots.min() > 1e-10 * pivots.max() {
                return Ok(Self {
                    a,
                    decomposition: Decomposition::Lu(lu),
                    matrix,
                });
            }
        }
        let svd = crate::svd::bounded_svd(a.clone(), true, true).ok_or(
            DynamicsError::Kinematics(KinematicsError::Singular {
                matrix,
                sigma_min: f64::NAN,
            }),
        )?;
        Ok(Self {
            a,
            decomposition: Decomposition::Svd(svd),
            matrix,
        })
    }

    /// `Singular` naming the matrix with its smallest singular value.
    fn singular(&self) -> DynamicsError {
        let sigma_min = match &self.decomposition {
            Decomposition::Svd(svd) => svd.singular_values.min(),
            Decomposition::Lu(_) => crate::svd::bounded_svd(self.a.clone(), false, false)
                .map_or(f64::NAN, |svd| svd.singular_values.min()),
        };
        DynamicsError::Kinematics(KinematicsError::Singular {
            matrix: self.matrix,
            sigma_min,
        })
    }

    /// One solve of the decomposition: $A^{-1}b$ or $A^{+}b$.
    fn apply(&self, rhs: &DVector<f64>) -> Result<DVector<f64>, DynamicsError> {
        match &self.decomposition {
            Decomposition::Lu(lu) => lu.solve(rhs).ok_or_else(|| self.singular()),
            Decomposition::Svd(svd) => svd
                .solve(rhs, 1e-12 * svd.singular_values.max())
                .map_err(|_| self.singular()),
        }
    }

    /// The least-norm least-squares solution of $Ax = b$, checked: a residual above 1e-6 of
    /// the right-hand side (an inconsistent system) or a non-finite entry is
    /// [`DynamicsError::Kinematics`] (`Singular`, naming the matrix).
    ///
    /// The solve is refined by up to three steps $x \leftarrow x + A^{+}(b - Ax)$ (each in
    /// the row space, so the least-norm property holds): nalgebra's SVD can leave a relative
    /// error of 1e-6 in the solve of a well-conditioned 42 × 42 system (measured on the
    /// Stewart–Gough's balance at home, condition 760), which the refinement removes.
    fn solve(&self, b: &DVector<f64>) -> Result<DVector<f64>, DynamicsError> {
        let mut x = self.apply(b)?;
        // The configuration closes to its solver's tolerance, not to rounding (a passive joint
        // of the Orthoglide left the unit-rate system inconsistent by 6e-8 of its right-hand
        // side at one pose of a smooth motion); a singular configuration leaves O(1).
        let bound = 1e-6 * b.amax().max(1e-300) + 1e-12;
        let mut r = b - &self.a * &x;
        for _ in 0..3 {
            if r.amax() <= 1e-14 * b.amax() {
                break;
            }
            x += self.apply(&r)?;
            r = b - &self.a * &x;
        }
        let residual = r.amax();
        if !(x.iter().all(|v| v.is_finite()) && residual <= bound) {
            return Err(self.singular());
        }
        Ok(x)
    }
}

/// The closure's rate matrix at one configuration: rows of 6 per leg, columns the dependent
/// pose coordinates and every joint coordinate, factored once for the velocities, the
/// accelerations and the unit task rates; with the legs' twists there.
struct ClosureRates {
    factored: ClosureFactor,
    dependent: Vec<usize>,
    offsets: Vec<usize>,
    twists: Vec<LegTwists>,
}

/// Without dependent coordinates each leg's rows involve its own joints alone: the matrix is
/// block diagonal and each leg's 6 × dof block is factored by itself (six 6 × 6 LUs for a
/// 6-UPS instead of one 36 × 36).
enum ClosureFactor {
    Whole(Factored),
    PerLeg(Vec<Factored>),
}

impl ClosureRates {
    fn new(model: &RobotModel, config: &Configuration) -> Result<Self, DynamicsError> {
        let dependent: Vec<usize> = (0..6)
            .filter(|&k| model.roles[k] == CoordinateRole::Dependent)
            .collect();
        let mut offsets = Vec::with_capacity(model.legs.len());
        let mut columns = dependent.len();
        for leg in &model.legs {
            offsets.push(columns);
            columns += leg.dof();
        }
        let twists: Vec<LegTwists> = model
            .legs
            .iter()
            .zip(&config.joints)
            .map(|(leg, values)| leg.twists(values))
            .collect();
        let h = hybrid_rates(model.orientation, &config.pose);
        let p = Vector3::new(config.pose[0], config.pose[1], config.pose[2]);
        // Leg i's block: the dependent columns −H e_k, then its joints' columns.
        let block = |i: usize| {
            let lt = &twists[i];
            let mut m = DMatrix::zeros(6, dependent.len() + lt.twists.len());
            for (c, &k) in dependent.iter().enumerate() {
                m.fixed_view_mut::<6, 1>(0, c).copy_from(&(-h.column(k)));
            }
            for (c, (_, xi)) in lt.twists.iter().enumerate() {
                let (w, v) = split(xi);
                m.fixed_view_mut::<6, 1>(0, dependent.len() + c)
                    .copy_from(&stack(&w, &(v + w.cross(&p))));
            }
            m
        };
        let factored = if dependent.is_empty() {
            let blocks = (0..model.legs.len())
                .map(|i| Factored::new(block(i), "closure rates"))
                .collect::<Result<_, _>>()?;
            ClosureFactor::PerLeg(blocks)
        } else {
            let mut matrix = DMatrix::zeros(6 * model.legs.len(), columns);
            for (i, &offset) in offsets.iter().enumerate() {
                let b = block(i);
                let d = dependent.len();
                matrix
                    .view_mut((6 * i, 0), (6, d))
                    .copy_from(&b.columns(0, d));
                matrix
                    .view_mut((6 * i, offset), (6, b.ncols() - d))
                    .copy_from(&b.columns(d, b.ncols() - d));
            }
            ClosureFactor::Whole(Factored::new(matrix, "closure rates")?)
        };
        Ok(Self {
            factored,
            dependent,
            offsets,
            twists,
        })
    }

    /// The pose-coordinate vector with the task entries `task` and the dependent ones from
    /// `unknowns`.
    fn pose_vector(
        &self,
        model: &RobotModel,
        task: &[f64],
        unknowns: &DVector<f64>,
    ) -> Vector6<f64> {
        let mut c = Vector6::zeros();
        for (&k, &v) in model.task.iter().zip(task) {
            c[k] = v;
        }
        for (i, &k) in self.dependent.iter().enumerate() {
            c[k] = unknowns[i];
        }
        c
    }

    /// Solves the closure for `rhs` (stacked per leg): the dependent rates, then every leg's.
    fn solve(&self, rhs: &DVector<f64>) -> Result<DVector<f64>, DynamicsError> {
        match &self.factored {
            ClosureFactor::Whole(factored) => factored.solve(rhs),
            ClosureFactor::PerLeg(blocks) => {
                let columns = self
                    .offsets
                    .last()
                    .map_or(0, |&o| o + blocks.last().map_or(0, |b| b.a.ncols()));
                let mut u = DVector::zeros(columns);
                for (i, (factored, &offset)) in blocks.iter().zip(&self.offsets).enumerate() {
                    let leg = factored.solve(&rhs.rows(6 * i, 6).into_owned())?;
                    u.rows_mut(offset, leg.len()).copy_from(&leg);
                }
                Ok(u)
            }
        }
    }

    fn per_leg(&self, model: &RobotModel, u: &DVector<f64>) -> Vec<Vec<f64>> {
        model
            .legs
            .iter()
            .zip(&self.offsets)
            .map(|(leg, &o)| u.rows(o, leg.dof()).iter().copied().collect())
            .collect()
    }

    /// The rates at `config` for task rates `velocity` (accelerations zero).
    fn rates(
        &self,
        model: &RobotModel,
        config: Configuration,
        velocity: &[f64],
    ) -> Result<Motion, DynamicsError> {
        let h = hybrid_rates(model.orientation, &config.pose);
        let task_rate = self.pose_vector(model, velocity, &DVector::zeros(self.dependent.len()));
        let per_leg = h * task_rate;
        let rhs = DVector::from_fn(6 * model.legs.len(), |r, _| per_leg[r % 6]);
        let u = self.solve(&rhs)?;
        let pose_rate = self.pose_vector(model, velocity, &u);
        let joint_rates = self.per_leg(model, &u);
        let joint_accelerations = joint_rates.iter().map(|r| vec![0.0; r.len()]).collect();
        Ok(Motion {
            config,
            pose_rate,
            pose_acceleration: Vector6::zeros(),
            joint_rates,
            joint_accelerations,
        })
    }

    /// The rates and accelerations at `config` for the task motion.
    fn motion(
        &self,
        model: &RobotModel,
        config: Configuration,
        velocity: &[f64],
        acceleration: &[f64],
    ) -> Result<Motion, DynamicsError> {
        let mut motion = self.rates(model, config, velocity)?;
        let c = motion.config.pose;
        let h = hybrid_rates(model.orientation, &c);
        let p = Vector3::new(c[0], c[1], c[2]);
        let platform_rate = h * motion.pose_rate;
        let (_, p_dot) = split(&platform_rate);
        let common =
            h * self.pose_vector(model, acceleration, &DVector::zeros(self.dependent.len()))
                + model.rates_derivative(&c, &motion.pose_rate);
        let mut rhs = DVector::zeros(6 * model.legs.len());
        for (i, lt) in self.twists.iter().enumerate() {
            let rates = &motion.joint_rates[i];
            let derivatives = twist_derivatives(&lt.twists, rates);
            let mut column_rates = Vector6::zeros();
            for (((_, xi), d), rate) in lt.twists.iter().zip(&derivatives).zip(rates) {
                let (w, _) = split(xi);
                let (dw, dv) = split(d);
                column_rates += stack(&dw, &(dv + dw.cross(&p) + w.cross(&p_dot))) * *rate;
            }
            rhs.fixed_rows_mut::<6>(6 * i)
                .copy_from(&(common - column_rates));
        }
        let u = self.solve(&rhs)?;
        motion.pose_acceleration = self.pose_vector(model, acceleration, &u);
        motion.joint_accelerations = self.per_leg(model, &u);
        Ok(motion)
    }
}

/// The robot's motion $\dot z = [\dot x;\ \ddot x]$ in its task coordinates under the
/// actuator efforts `efforts(t)` (eq. D4): a vector field of the project's integrators on the
/// state $z = [x; \dot x]$ of $M = 2n$ entries. The configuration is solved from $x$ at every
/// evaluation (minimal coordinates), so the loop closure holds to the inverse kinematics'
/// 1e-12 at every state and does not drift.
pub struct TaskDynamics<'a, E> {
    model: &'a RobotModel,
    mode: WorkingMode,
    efforts: E,
}

impl<E> std::fmt::Debug for TaskDynamics<'_, E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TaskDynamics")
            .field("robot", &self.model.name())
            .field("mode", &self.mode)
            .finish_non_exhaustive()
    }
}

impl<'a, E: Fn(f64) -> DVector<f64>> TaskDynamics<'a, E> {
    /// The field of `model` in working mode `mode` under `efforts(t)`.
    pub fn new(model: &'a RobotModel, mode: WorkingMode, efforts: E) -> Self {
        Self {
            model,
            mode,
            efforts,
        }
    }
}

impl<E: Fn(f64) -> DVector<f64>, const M: usize> VectorField<M> for TaskDynamics<'_, E> {
    fn rhs(
        &self,
        t: f64,
        z: &nalgebra::SVector<f64, M>,
        dz: &mut nalgebra::SVector<f64, M>,
    ) -> Result<(), RhsError> {
        let n = self.model.dof();
        if M != 2 * n {
            return Err(RhsError {
                t,
                reason: format!(
                    "a state of {M} entries for {n} task coordinates (expected {})",
                    2 * n
                ),
            });
        }
        let (x, v) = (&z.as_slice()[..n], &z.as_slice()[n..]);
        let forward = self
            .model
            .forward_dynamics(x, v, (self.efforts)(t).as_slice(), self.mode)
            .map_err(|e| RhsError {
                t,
                reason: e.to_string(),
            })?;
        dz.as_mut_slice()[..n].copy_from_slice(v);
        dz.as_mut_slice()[n..].copy_from_slice(forward.acceleration.as_slice());
        Ok(())
    }
}
