//! The kernels of `pkm.Mechanism` for a robot file whose task is not the platform position:
//! rows of its own n task coordinates (m and rad, in the file's `task` order), the working
//! modes, constraints and homogenised 1/κ of its task-space workspace studies
//! ([`pkm_robot_file::TaskWorkspace`]), mapped over the rows on rayon threads (each row
//! independent, so the same bits for any thread count).

use crate::kernels::{Op, map_rows};
use numpy::ndarray::ArrayView2;
use pkm_robot_file::{MarginLimits, Robot, RobotModel, TaskWorkspace, WorkingMode};
use pkm_traits::{ForwardKinematics, Joints, NewtonSettings, Task, WorkspaceConstraint};

/// A robot file in its task space: the model, the study's working modes and constraints.
pub(crate) struct TaskSpaceModel {
    pub(crate) model: RobotModel,
    pub(crate) modes: Vec<WorkingMode>,
    pub(crate) constraints: Vec<WorkspaceConstraint>,
}

/// Largest actuator residual (m or rad) of a redundant robot's forward kinematics that counts
/// as consistent actuator values.
const CONSISTENT: f64 = 1e-9;

impl TaskSpaceModel {
    /// The number of task coordinates n.
    pub(crate) fn dimension(&self) -> usize {
        self.model.task_names().len()
    }

    /// The number of actuators.
    pub(crate) fn joints(&self) -> usize {
        self.model.actuator_count()
    }

    /// The workspace of the studies (no margin bound).
    ///
    /// # Errors
    /// The library's message for constraints that do not fit the robot.
    fn workspace(&self) -> Result<TaskWorkspace<'_>, String> {
        TaskWorkspace::new(
            &self.model,
            &self.modes,
            &self.constraints,
            MarginLimits::default(),
        )
        .map_err(|e| e.to_string())
    }

    /// `op` at every row of the N × n `points`: the values (row-major) and the mask.
    ///
    /// # Errors
    /// As [`TaskSpaceModel::workspace`].
    pub(crate) fn run(
        &self,
        points: &ArrayView2<'_, f64>,
        op: Op,
    ) -> Result<(Vec<f64>, Vec<bool>), String> {
        let ws = self.workspace()?;
        let (n, legs) = (self.dimension(), self.joints());
        let x = |i: usize| points.row(i).to_vec();
        let model = &self.model;
        let rows = points.nrows();
        Ok(match op {
            Op::Inverse => map_rows(rows, legs, |i, out| {
                let x = x(i);
                let q = model.inverse_kinematics(&x, ws.mode_at(&x)?).ok()?;
                out.copy_from_slice(q.as_slice());
                Some(())
            }),
            Op::Jacobian => map_rows(rows, legs * n, |i, out| {
                let x = x(i);
                let config = model.inverse_kinematics_configuration(&x, ws.mode_at(&x)?);
                let j = model.screw_jacobians(&config.ok()?).ok()?.j;
                for (k, v) in out.iter_mut().enumerate() {
                    *v = j[(k / n, k % n)];
                }
                Some(())
            }),
            Op::InverseCondition => map_rows(rows, 1, |i, out| {
                out[0] = ws.inverse_condition(&x(i))?;
                Some(())
            }),
            Op::Contains => map_rows(rows, 1, |i, out| ws.contains(&x(i)).then(|| out[0] = 0.0)),
        })
    }

    /// The singularity margins (inverse, direct, constraint: NaN for a robot without
    /// constraint wrenches) at every row, N × 3, and the mask of the rows inside the workspace.
    ///
    /// # Errors
    /// As [`TaskSpaceModel::workspace`].
    pub(crate) fn margins(
        &self,
        points: &ArrayView2<'_, f64>,
    ) -> Result<(Vec<f64>, Vec<bool>), String> {
        let ws = self.workspace()?;
        Ok(map_rows(points.nrows(), 3, |i, out| {
            let m = ws.margins(&points.row(i).to_vec())?;
            out.copy_from_slice(&[m.inverse, m.direct, m.constraint.unwrap_or(f64::NAN)]);
            Some(())
        }))
    }

    /// Task coordinates that close the loops for the N × legs `joints`, by damped Newton from
    /// the N × n `guess` (the assembly at the guess on the branches nearest the joints), with
    /// the mask of the rows where it converged.
    ///
    /// # Errors
    /// A message for a model the solver cannot take.
    pub(crate) fn forward(
        &self,
        joints: &ArrayView2<'_, f64>,
        guess: &ArrayView2<'_, f64>,
    ) -> Result<(Vec<f64>, Vec<bool>), String> {
        if self.joints() > self.dimension() {
            return Ok(self.forward_least_squares(joints, guess));
        }
        match self.dimension() {
            1 => self.forward_n::<1>(joints, guess),
            2 => self.forward_n::<2>(joints, guess),
            3 => self.forward_n::<3>(joints, guess),
            4 => self.forward_n::<4>(joints, guess),
            5 => self.forward_n::<5>(joints, guess),
            6 => self.forward_n::<6>(joints, guess),
            n => Err(format!("a task of {n} coordinates (expected 1 to 6)")),
        }
    }

    /// A redundantly actuated robot's pose from all its actuators: the least-squares pose
    /// (`RobotModel::forward_kinematics_least_squares`), kept where the actuator values are
    /// consistent (residual at most [`CONSISTENT`] per actuator), masked elsewhere.
    fn forward_least_squares(
        &self,
        joints: &ArrayView2<'_, f64>,
        guess: &ArrayView2<'_, f64>,
    ) -> (Vec<f64>, Vec<bool>) {
        map_rows(joints.nrows(), self.dimension(), |i, out| {
            let q: Vec<f64> = joints.row(i).iter().copied().collect();
            let g: Vec<f64> = guess.row(i).iter().copied().collect();
            let pose = self.model.forward_kinematics_least_squares(&q, &g).ok()?;
            (pose.residual.amax() <= CONSISTENT).then_some(())?;
            out.copy_from_slice(&pose.task);
            Some(())
        })
    }

    fn forward_n<const N: usize>(
        &self,
        joints: &ArrayView2<'_, f64>,
        guess: &ArrayView2<'_, f64>,
    ) -> Result<(Vec<f64>, Vec<bool>), String> {
        let robot = Robot::<N>::new(self.model.clone()).map_err(|e| e.to_string())?;
        let settings = NewtonSettings::default();
        Ok(map_rows(joints.nrows(), N, |i, out| {
            let q = Joints::<N>::from_iterator(joints.row(i).iter().copied());
            let g = Task::<N>::from_iterator(guess.row(i).iter().copied());
            let x = robot.forward_kinematics(&q, &g, &settings).ok()?;
            out.copy_from_slice(x.as_slice());
            Some(())
        }))
    }
}
