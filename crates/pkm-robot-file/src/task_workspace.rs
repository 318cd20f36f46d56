//! The workspace of a robot file in its own task space, whatever its task: membership, the
//! homogenised condition index and the singularity margins at task coordinates, and the
//! orientation sets of a dexterous workspace.
//!
//! **Membership.** Task coordinates $x$ belong to the workspace when one of the working modes
//! assembles there (actuator `limits` of the file included) with every constraint holding
//! (half-spaces on the platform position, actuator ranges, passive-joint cones, leg clearance:
//! [`pkm_traits::WorkspaceConstraint::holds_at`]) and every singularity margin at or above
//! its stated minimum ([`MarginLimits`]).
//!
//! **Homogenised condition index.** $J$ ($\dot q = J\dot x$) mixes units when the task holds
//! angles or the actuators are revolute. With the characteristic length $L$ of the robot file,
//! $$J_h = S_q\,J\,S_x^{-1},\quad S_x = \mathrm{diag}(1 \text{ (length)},\ L \text{ (angle)}),
//! \quad S_q = \mathrm{diag}(L \text{ (revolute actuator)},\ 1 \text{ (prismatic)}),$$
//! so every task rate is a velocity (an angular rate times $L$) and every actuator rate a
//! velocity; $1/\kappa = \sigma_{\min}(J_h)/\sigma_{\max}(J_h)$ (Angeles, *Fundamentals of
//! Robotic Mechanical Systems*, 3rd ed. 2007, §5.7, the characteristic length; Khan & Angeles,
//! ASME J. Mech. Des. 128(1):168–178, 2006). A uniform scale of all rows or all columns leaves
//! $\kappa$ unchanged, so for a translational robot with one kind of actuator $1/\kappa(J_h) =
//! 1/\kappa(J)$.
//!
//! **Orientation sets.** An [`OrientationSet`] is every rotation $R = \mathrm{Rot}(a_\phi,
//! \theta)\,R_z(\sigma)$ with tilt $\theta \le \theta_{\max}$ about a horizontal axis
//! $a_\phi = (\cos\phi, \sin\phi, 0)$ at any azimuth $\phi$ and torsion $\sigma$ in a range (Bonev's
//! tilt and torsion). It is tested on nested grids ([`OrientationSet::grid`]): level $\ell$ has
//! the tilts $\theta_{\max} k/\ell$, $4k$ azimuths on ring $k$ and the torsions $\sigma_{lo} +
//! (\sigma_{hi} - \sigma_{lo}) j/\ell$; level $2\ell$ holds every orientation of level $\ell$.

use crate::chain::Joint;
use crate::closure::Configuration;
use crate::error::RobotFileError;
use crate::jacobian::SingularityMargins;
use crate::model::{RobotModel, WorkingMode};
use nalgebra::{DMatrix, Rotation3, Unit, Vector3};
use pkm_traits::{ConstraintKind, KinematicsError, WorkspaceConstraint};
use std::f64::consts::{PI, TAU};

/// Lower bounds on the singularity margins ([`SingularityMargins`]); `None` sets no bound.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MarginLimits {
    /// Least inverse-kinematic margin.
    pub inverse: Option<f64>,
    /// Least direct (type II) margin.
    pub direct: Option<f64>,
    /// Least constraint margin (robots with constraint wrenches).
    pub constraint: Option<f64>,
}

impl MarginLimits {
    /// Whether any bound is set.
    pub fn any(&self) -> bool {
        self.inverse.is_some() || self.direct.is_some() || self.constraint.is_some()
    }

    /// Whether `m` meets every bound (a robot without constraint wrenches meets that one).
    pub fn hold(&self, m: &SingularityMargins) -> bool {
        let at_least = |bound: Option<f64>, v: f64| bound.is_none_or(|b| v >= b);
        at_least(self.inverse, m.inverse)
            && at_least(self.direct, m.direct)
            && m.constraint.is_none_or(|c| at_least(self.constraint, c))
    }

    fn check(&self) -> Result<(), RobotFileError> {
        let bounds = [
            ("inverse", self.inverse),
            ("direct", self.direct),
            ("constraint", self.constraint),
        ];
        for (name, bound) in bounds {
            if let Some(b) = bound
                && !(b >= 0.0 && b.is_finite())
            {
                return Err(invalid(
                    &format!("min_{name}_margin"),
                    b,
                    "a finite margin of at least 0",
                ));
            }
        }
        Ok(())
    }
}

fn invalid(key: &str, value: f64, requirement: &str) -> RobotFileError {
    RobotFileError::Invalid {
        key: key.into(),
        value: value.to_string(),
        requirement: requirement.into(),
    }
}

/// The workspace of a robot in its task space (module documentation).
#[derive(Debug, Clone)]
pub struct TaskWorkspace<'m> {
    model: &'m RobotModel,
    modes: Vec<WorkingMode>,
    constraints: Vec<WorkspaceConstraint>,
    margins: MarginLimits,
    /// Whether membership needs the whole configuration (not only the actuators).
    needs_configuration: bool,
}

impl<'m> TaskWorkspace<'m> {
    /// The workspace of `model` in any of `modes` under `constraints` and `margins`.
    ///
    /// # Errors
    /// [`RobotFileError::Invalid`] for no mode, a joint range of an actuator the robot does
    /// not have, or a negative, NaN or infinite margin bound.
    pub fn new(
        model: &'m RobotModel,
        modes: &[WorkingMode],
        constraints: &[WorkspaceConstraint],
        margins: MarginLimits,
    ) -> Result<Self, RobotFileError> {
        if modes.is_empty() {
            return Err(invalid("modes", 0.0, "at least one working mode"));
        }
        margins.check()?;
        let legs = model.legs().len();
        if let Some(joint) = constraints
            .iter()
            .filter_map(WorkspaceConstraint::joint)
            .find(|&j| j >= legs)
        {
            return Err(invalid(
                "constraints.joint_ranges",
                joint as f64,
                "an actuator of the robot (one per leg, counted from 0)",
            ));
        }
        let needs_configuration = margins.any()
            || !model.has_closed_form()
            || constraints.iter().any(|c| {
                matches!(
                    c.kind(),
                    ConstraintKind::PassiveCone | ConstraintKind::LegClearance
                )
            });
        Ok(Self {
            model,
            modes: modes.to_vec(),
            constraints: constraints.to_vec(),
            margins,
            needs_configuration,
        })
    }

    /// The robot.
    pub fn model(&self) -> &RobotModel {
        self.model
    }

    /// Whether the task coordinates `x` belong to the workspace.
    pub fn contains(&self, x: &[f64]) -> bool {
        self.modes.iter().any(|&mode| self.assembles(x, mode))
    }

    /// The first working mode (in the order given) that assembles at `x` within every
    /// constraint and margin bound.
    pub fn mode_at(&self, x: &[f64]) -> Option<WorkingMode> {
        self.modes
            .iter()
            .copied()
            .find(|&mode| self.assembles(x, mode))
    }

    /// $1/\kappa(J_h)$ at `x` in the first mode that assembles there (0 where $J$ is singular),
    /// `None` outside the workspace.
    pub fn inverse_condition(&self, x: &[f64]) -> Option<f64> {
        let mode = self.mode_at(x)?;
        Some(
            self.model
                .homogenised_inverse_condition(x, mode)
                .unwrap_or(0.0),
        )
    }

    /// The singularity margins at `x` in the first mode that assembles there, `None` outside
    /// the workspace (margins that cannot be computed read as 0).
    pub fn margins(&self, x: &[f64]) -> Option<SingularityMargins> {
        let mode = self.mode_at(x)?;
        let zero = SingularityMargins {
            inverse: 0.0,
            direct: 0.0,
            constraint: Some(0.0),
        };
        let config = self.model.inverse_kinematics_configuration(x, mode).ok()?;
        Some(self.model.singularity_margins(&config).unwrap_or(zero))
    }

    /// Whether `mode` assembles at `x` within every constraint and margin bound.
    fn assembles(&self, x: &[f64], mode: WorkingMode) -> bool {
        if !self.needs_configuration {
            let mut q = [0.0; crate::MAX_LEGS];
            let reached = self
                .model
                .closed_form_actuators_with(x, mode, |i, v| q[i] = v)
                .is_ok();
            let legs = self.model.legs().len();
            return reached && self.position_and_actuators_allowed(x, &q[..legs]);
        }
        let Ok(config) = self.model.inverse_kinematics_configuration(x, mode) else {
            return false;
        };
        let q = self.model.actuators_of(&config);
        let position = position_of(&config);
        let constraints = self.constraints.iter().all(|c| {
            c.holds_at(
                &position,
                q.as_slice(),
                || self.model.passive_bends(&config),
                || self.model.leg_clearance(&config),
            )
        });
        constraints && (!self.margins.any() || self.margins_hold(&config))
    }

    fn margins_hold(&self, config: &Configuration) -> bool {
        self.model
            .singularity_margins(config)
            .is_ok_and(|m| self.margins.hold(&m))
    }

    /// The half-spaces and actuator ranges at `x` with actuators `q` (no dependent coordinate:
    /// the platform position is read from the task or home).
    fn position_and_actuators_allowed(&self, x: &[f64], q: &[f64]) -> bool {
        if self.constraints.is_empty() {
            return true;
        }
        let Ok(pose) = self.model.pose_with_task(x) else {
            return false;
        };
        let position = Vector3::new(pose[0], pose[1], pose[2]);
        self.constraints
            .iter()
            .all(|c| c.holds_at(&position, q, || None, || None))
    }
}

fn position_of(config: &Configuration) -> Vector3<f64> {
    let pose = config.pose();
    Vector3::new(pose[0], pose[1], pose[2])
}

impl RobotModel {
    /// Whether task coordinate `k` (in task order) is an angle (rad) rather than a length (m).
    pub fn task_is_angle(&self, k: usize) -> bool {
        self.task.get(k).is_some_and(|&c| c >= 3)
    }

    /// $1/\kappa$ of the homogenised Jacobian $J_h = S_q J S_x^{-1}$ (module documentation) at
    /// task coordinates `x` in `mode`.
    ///
    /// # Errors
    /// As [`RobotModel::inverse_kinematics_configuration`] and
    /// [`RobotModel::screw_jacobians`]; [`KinematicsError::Singular`] when the singular values
    /// of $J_h$ cannot be computed (a non-finite entry).
    pub fn homogenised_inverse_condition(
        &self,
        x: &[f64],
        mode: WorkingMode,
    ) -> Result<f64, KinematicsError> {
        let n = self.actuator_count();
        let mut j = DMatrix::zeros(n, self.task.len());
        if self.has_closed_form() {
            self.closed_form_jacobian_with(x, mode, |i, k, v| j[(i, k)] = v)?;
        } else {
            let config = self.inverse_kinematics_configuration(x, mode)?;
            j = self.screw_jacobians(&config)?.j;
        }
        let l = self.characteristic_length;
        for (i, mut row) in j.row_iter_mut().enumerate() {
            let (leg, actuator) = self.actuator(i);
            if matches!(
                self.legs[leg].joints[actuator.joint],
                Joint::Revolute { .. }
            ) {
                row *= l;
            }
        }
        for (k, mut column) in j.column_iter_mut().enumerate() {
            if self.task_is_angle(k) {
                column /= l;
            }
        }
        inverse_condition_of(&j)
    }
}

/// $\sigma_{\min}/\sigma_{\max}$ of a square matrix, by an SVD with a bounded iteration count
/// after a finiteness check (0 for a zero matrix).
fn inverse_condition_of(j: &DMatrix<f64>) -> Result<f64, KinematicsError> {
    let singular = KinematicsError::Singular {
        matrix: "J_h",
        sigma_min: 0.0,
    };
    if !j.iter().all(|v| v.is_finite()) {
        return Err(singular);
    }
    // The common square sizes on the stack (the same decomposition, without a heap matrix).
    macro_rules! fixed {
        ($n:literal) => {
            nalgebra::SMatrix::<f64, $n, $n>::from_fn(|r, c| j[(r, c)])
                .try_svd(false, false, f64::EPSILON, crate::svd::MAX_SVD_SWEEPS)
                .map(|svd| svd.singular_values.as_slice().to_vec())
        };
    }
    let singular_values = match (j.nrows(), j.ncols()) {
        (3, 3) => fixed!(3),
        (6, 6) => fixed!(6),
        _ => j
            .clone()
            .try_svd(false, false, f64::EPSILON, crate::svd::MAX_SVD_SWEEPS)
            .map(|svd| svd.singular_values.as_slice().to_vec()),
    }
    .ok_or(singular)?;
    let min = singular_values
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let max = singular_values.iter().copied().fold(0.0, f64::max);
    Ok(if max > 0.0 { min / max } else { 0.0 })
}

/// Rotations of tilt at most `max_tilt` and torsion in `torsion` (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientationSet {
    max_tilt: f64,
    torsion: [f64; 2],
}

impl OrientationSet {
    /// The set of tilts up to `max_tilt` (rad) at every azimuth and torsions in
    /// `torsion = [lo, hi]` (rad).
    ///
    /// # Errors
    /// [`RobotFileError::Invalid`] for a tilt outside $[0, \pi]$ or a torsion range outside
    /// $[-\pi, \pi]$ or with $lo > hi$ (NaN included).
    pub fn new(max_tilt: f64, torsion: [f64; 2]) -> Result<Self, RobotFileError> {
        if !(0.0..=PI).contains(&max_tilt) {
            return Err(invalid(
                "max_tilt",
                max_tilt,
                "a tilt from 0 to π rad (180°)",
            ));
        }
        let [lo, hi] = torsion;
        if !((-PI..=PI).contains(&lo) && (-PI..=PI).contains(&hi) && lo <= hi) {
            return Err(invalid(
                "torsion",
                if (-PI..=PI).contains(&lo) { hi } else { lo },
                "[lo, hi] with -π ≤ lo ≤ hi ≤ π rad (±180°)",
            ));
        }
        Ok(Self { max_tilt, torsion })
    }

    /// The largest tilt (rad).
    pub fn max_tilt(&self) -> f64 {
        self.max_tilt
    }

    /// The torsion range (rad).
    pub fn torsion(&self) -> [f64; 2] {
        self.torsion
    }

    /// The rotations of grid level `level` ≥ 1 (level 0 is read as 1): tilt rings
    /// $k = 0..\ell$ (one rotation on ring 0, $4k$ on ring $k$; one ring when the tilt is 0)
    /// times the torsions ($\ell + 1$, one when the range is a point).
    pub fn grid(&self, level: u32) -> Vec<Rotation3<f64>> {
        let l = level.max(1);
        let rings = if self.max_tilt > 0.0 { l } else { 0 };
        let [lo, hi] = self.torsion;
        let torsions = if hi > lo { l } else { 0 };
        let mut out = Vec::new();
        for j in 0..=torsions {
            let sigma = if torsions == 0 {
                lo
            } else {
                lo + (hi - lo) * f64::from(j) / f64::from(torsions)
            };
            let twist = Rotation3::from_axis_angle(&Vector3::z_axis(), sigma);
            for k in 0..=rings {
                let theta = if rings == 0 {
                    0.0
                } else {
                    self.max_tilt * f64::from(k) / f64::from(rings)
                };
                let azimuths = if k == 0 { 1 } else { 4 * k };
                for a in 0..azimuths {
                    let phi = TAU * f64::from(a) / f64::from(azimuths);
                    let axis = Unit::new_unchecked(Vector3::new(phi.cos(), phi.sin(), 0.0));
                    out.push(Rotation3::from_axis_angle(&axis, theta) * twist);
                }
            }
        }
        out
    }
}

/// The task-coordinate values of the orientations of nested grids, level by level, each level
/// holding only the orientations its predecessor does not ([`TaskWorkspace::dexterous_levels`]).
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationLevels {
    /// The grid level $\ell$ of each nested level (1, 2, 4, ...).
    pub grid_levels: Vec<u32>,
    /// The number of orientations of each level's whole grid.
    pub orientations: Vec<usize>,
    /// Per level, the new orientations as the values of the task's orientation coordinates
    /// (pairs of task index and value).
    new: Vec<Vec<Vec<(usize, f64)>>>,
}

impl RobotModel {
    /// The grids of `set` at levels $1, 2, 4, \dots, 2^{L-1}$ ($L$ = `levels`) as values of this
    /// robot's task orientation coordinates.
    ///
    /// # Errors
    /// [`RobotFileError::Invalid`] at `orientations` when the set moves an orientation
    /// coordinate that is not a task coordinate (a torsion range for a robot whose task has no
    /// torsion, a tilt for a planar robot), or when the task has no orientation coordinate.
    pub fn orientation_levels(
        &self,
        set: &OrientationSet,
        levels: u32,
    ) -> Result<OrientationLevels, RobotFileError> {
        let angles: Vec<usize> = (0..self.task.len())
            .filter(|&k| self.task_is_angle(k))
            .collect();
        if angles.is_empty() {
            return Err(invalid(
                "orientations",
                0.0,
                "a task with orientation coordinates: this robot's task has none",
            ));
        }
        let names = self.orientation.coordinate_names();
        let mut out = OrientationLevels {
            grid_levels: Vec::new(),
            orientations: Vec::new(),
            new: Vec::new(),
        };
        let mut seen: Vec<[f64; 3]> = Vec::new();
        for level in (0..levels.max(1)).map(|k| 1u32 << k.min(8)) {
            let grid = self.orientation_values(&set.grid(level), &names)?;
            out.orientations.push(grid.len());
            let fresh: Vec<[f64; 3]> = grid
                .into_iter()
                .filter(|g| !seen.iter().any(|s| same(s, g)))
                .collect();
            let pairs = fresh
                .iter()
                .map(|o| angles.iter().map(|&k| (k, o[self.task[k] - 3])).collect())
                .collect();
            seen.extend(fresh);
            out.grid_levels.push(level);
            out.new.push(pairs);
        }
        Ok(out)
    }

    /// The three orientation coordinates of each rotation, checked to move only task
    /// coordinates.
    fn orientation_values(
        &self,
        rotations: &[Rotation3<f64>],
        names: &[&str; 6],
    ) -> Result<Vec<[f64; 3]>, RobotFileError> {
        let home = [self.home[3], self.home[4], self.home[5]];
        rotations
            .iter()
            .map(|r| {
                let o = self.orientation.coordinates_of(r);
                for c in 0..3 {
                    if !self.task.contains(&(c + 3)) && (o[c] - home[c]).abs() > 1e-12 {
                        return Err(RobotFileError::Invalid {
                            key: "orientations".into(),
                            value: format!("{} = {:.6} rad", names[c + 3], o[c]),
                            requirement: format!(
                                "the set may move only the task's orientation coordinates {:?}",
                                self.task_names()
                            ),
                        });
                    }
                }
                Ok([o[0], o[1], o[2]])
            })
            .collect()
    }
}

fn same(a: &[f64; 3], b: &[f64; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12)
}

impl TaskWorkspace<'_> {
    /// How many nested levels of `levels` hold at task coordinates `x` (the orientation
    /// coordinates of `x` are replaced by each grid orientation's): $L$ when the robot
    /// reaches every orientation of the finest grid there, $k$ when level $k$ is the first
    /// with an orientation it cannot reach.
    pub fn dexterous_levels(&self, x: &[f64], levels: &OrientationLevels) -> usize {
        let mut pose = x.to_vec();
        for (k, new) in levels.new.iter().enumerate() {
            for orientation in new {
                for &(i, v) in orientation {
                    pose[i] = v;
                }
                if !self.contains(&pose) {
                    return k;
                }
            }
        }
        levels.new.len()
    }

    /// The least $1/\kappa(J_h)$ over the first level's orientations at the position of `x`
    /// (the local index of a dexterous workspace: its worst orientation), `None` where one is
    /// unreachable.
    pub fn dexterous_inverse_condition(
        &self,
        x: &[f64],
        levels: &OrientationLevels,
    ) -> Option<f64> {
        let mut pose = x.to_vec();
        let mut least = f64::INFINITY;
        for orientation in levels.new.first()? {
            for &(i, v) in orientation {
                pose[i] = v;
            }
            least = least.min(self.inverse_condition(&pose)?);
        }
        least.is_finite().then_some(least)
    }
}
