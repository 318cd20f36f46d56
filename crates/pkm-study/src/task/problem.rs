//! The optimisation problems of a task study: the Stewart–Gough platform through the library's
//! [`StewartTaskProblem`] (one per twist, combined by [`pkm_optimizers::WeightedSum`]), and the
//! 3-UPU over any subset of its 14 variables (radii, U-joint tilts, pose) with the residuals
//! $\sqrt{w_k}\,(L_i \wedge \chi_k)$ (eq. 14), $\sigma_{min}$ or $\det$ of the eq. 18 matrix.

use super::schema::{Goal, PoseSpec};
use crate::schema::mechanism::{StewartSpec, ThreeUpuSpec, stewart_layout, tilted_axes};
use crate::schema::units::Degrees;
use crate::{KeyPath, StudyError};
use nalgebra::{Isometry3, Matrix6, Vector3};
use pkm_mechanisms::{
    StewartDesign, StewartDesignVariable, StewartTaskProblem, ThreeUpu, ThreeUpuDesign,
    WrenchSystem, pose_from_task,
};
use pkm_screw_theory::{Twist, task_residuals};
use pkm_traits::{Bounds, DesignError, Objective, ObjectiveError, Residuals, Task};

/// The library's design variables behind the first four names of [`STEWART_VARIABLES`], in
/// the study's units (lengths, and separations in degrees).
const STEWART_DESIGN_VARIABLES: [StewartDesignVariable; 4] = [
    StewartDesignVariable::BaseRadius,
    StewartDesignVariable::PlatformRadius,
    StewartDesignVariable::BaseSeparationDeg,
    StewartDesignVariable::PlatformSeparationDeg,
];

/// The Stewart–Gough variables a task may optimise, in [`StewartTaskProblem`] slot order.
pub const STEWART_VARIABLES: [&str; 7] = [
    "base_radius",
    "platform_radius",
    "base_separation_deg",
    "platform_separation_deg",
    "x",
    "y",
    "z",
];

/// The 3-UPU variables, in [`UpuProblem`] order.
pub const UPU_VARIABLES: [&str; 14] = [
    "base_radius",
    "platform_radius",
    "beta1_deg",
    "gamma1_deg",
    "beta2_deg",
    "gamma2_deg",
    "beta3_deg",
    "gamma3_deg",
    "x",
    "y",
    "z",
    "rx_deg",
    "ry_deg",
    "rz_deg",
];

/// The library problem of one twist: the nominal design and pose of the study with the
/// variables `free` (indices into [`STEWART_VARIABLES`]) and, with `max_angle` (radians), the
/// orientation freed.
///
/// # Errors
/// The library's reason for an invalid design or pose (at `mechanism`), position range (at
/// `task.variables.<name>`) or angle (at `task.max_angle_deg`).
pub fn stewart_problem(
    spec: &StewartSpec,
    pose: &PoseSpec,
    free: &[(usize, Bounds)],
    max_angle: Option<f64>,
    twist: Twist,
) -> Result<StewartTaskProblem, StudyError> {
    let design = StewartDesign {
        layout: stewart_layout(spec),
        ..StewartDesign::from_deg(
            spec.base_radius.0,
            spec.platform_radius.0,
            spec.base_separation_deg.0,
            spec.platform_separation_deg.0,
        )
    };
    let position = Vector3::from(pose.position.map(|x| x.0));
    let rotation = Vector3::from(pose.rotation_deg.map(Degrees::radians));
    let refused = |path: KeyPath| move |e: DesignError| StudyError::invalid(path, e.to_string());
    let mut problem = StewartTaskProblem::new(design, position, rotation, twist)
        .map_err(refused(KeyPath::parse("mechanism")))?;
    for &(k, bounds) in free {
        problem = match STEWART_DESIGN_VARIABLES.get(k) {
            Some(&variable) => problem.free_design(variable, bounds),
            None => {
                let path = KeyPath::parse("task.variables").field(STEWART_VARIABLES[k]);
                problem
                    .free_position(k - 4, bounds)
                    .map_err(refused(path))?
            }
        };
    }
    if let Some(angle) = max_angle {
        problem = problem
            .free_rotation(angle)
            .map_err(refused(KeyPath::parse("task.max_angle_deg")))?;
    }
    Ok(problem)
}

/// What the 3-UPU problem's residuals are.
#[derive(Debug, Clone)]
enum UpuResiduals {
    /// $\sqrt{w_k}\,(L_i \wedge \chi_k)$, with $\sqrt{w_k}$ stored.
    Task(Vec<(f64, Twist)>),
    /// $\sigma_{min}$.
    SigmaMin,
    /// $\det$.
    Det,
}

/// The 3-UPU over any subset of [`UPU_VARIABLES`].
#[derive(Debug, Clone)]
pub struct UpuProblem {
    /// The joints' azimuths (radians).
    azimuths: [f64; 3],
    values: [f64; 14],
    free: Vec<usize>,
    bounds: Vec<Bounds>,
    residuals: UpuResiduals,
}

impl UpuProblem {
    /// The 3-UPU problem of the study for `goal` and the weighted twists, with the variables
    /// `free` (indices into [`UPU_VARIABLES`]).
    pub fn new(
        spec: &ThreeUpuSpec,
        pose: &PoseSpec,
        free: &[(usize, Bounds)],
        goal: Goal,
        twists: &[(f64, Twist)],
    ) -> Self {
        let [x, y, z] = pose.position.map(|v| v.0);
        let [rx, ry, rz] = pose.rotation_deg.map(|v| v.0);
        let [b1, g1, b2, g2, b3, g3] = spec.tilts_deg();
        let values = [
            spec.base_radius.0,
            spec.platform_radius.0,
            b1,
            g1,
            b2,
            g2,
            b3,
            g3,
            x,
            y,
            z,
            rx,
            ry,
            rz,
        ];
        let residuals = match goal {
            Goal::Maximise | Goal::Minimise => {
                UpuResiduals::Task(twists.iter().map(|(w, t)| (w.sqrt(), *t)).collect())
            }
            Goal::SingularitySigmaMin => UpuResiduals::SigmaMin,
            Goal::SingularityDet => UpuResiduals::Det,
        };
        Self {
            azimuths: spec.azimuths_deg.map(Degrees::radians),
            values,
            free: free.iter().map(|(k, _)| *k).collect(),
            bounds: free.iter().map(|(_, b)| *b).collect(),
            residuals,
        }
    }

    /// All 14 values at a design vector of the free ones.
    pub fn full(&self, v: &[f64]) -> [f64; 14] {
        let mut all = self.values;
        for (k, value) in self.free.iter().zip(v) {
            all[*k] = *value;
        }
        all
    }

    /// The mechanism and pose at `v`.
    ///
    /// # Errors
    /// A design vector of the wrong length, an invalid design or pose.
    pub fn evaluate(&self, v: &[f64]) -> Result<(ThreeUpu, Isometry3<f64>), ObjectiveError> {
        self.check_dimension(v)?;
        let all = self.full(v);
        let tilts = [all[2], all[3], all[4], all[5], all[6], all[7]];
        let upu = ThreeUpu::new(ThreeUpuDesign {
            base_radius: all[0],
            platform_radius: all[1],
            azimuths: self.azimuths,
            upper: tilted_axes(self.azimuths, &tilts),
        })?;
        let [x, y, z, rx, ry, rz] = [all[8], all[9], all[10], all[11], all[12], all[13]];
        let (rx, ry, rz) = (rx.to_radians(), ry.to_radians(), rz.to_radians());
        let pose = pose_from_task(&Task::<6>::new(x, y, z, rx, ry, rz))?;
        Ok((upu, pose))
    }

    /// The eq. 18 matrix at `v`.
    ///
    /// # Errors
    /// As [`UpuProblem::evaluate`], or a leg of zero length.
    pub fn wrench_rows(&self, v: &[f64]) -> Result<Matrix6<f64>, ObjectiveError> {
        let (upu, pose) = self.evaluate(v)?;
        Ok(upu.wrench_rows(&pose)?)
    }
}

impl Objective for UpuProblem {
    fn dimension(&self) -> usize {
        self.free.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, v: &[f64]) -> Result<f64, ObjectiveError> {
        self.sum_of_squares(v)
    }
}

impl Residuals for UpuProblem {
    fn n_residuals(&self) -> usize {
        match &self.residuals {
            UpuResiduals::Task(t) => 6 * t.len(),
            UpuResiduals::SigmaMin | UpuResiduals::Det => 1,
        }
    }
    fn residuals(&self, v: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        let n = self.n_residuals();
        if r.len() != n {
            return Err(ObjectiveError::Dimension {
                expected: n,
                got: r.len(),
            });
        }
        let rows = self.wrench_rows(v)?;
        match &self.residuals {
            UpuResiduals::Task(twists) => {
                for (chunk, (w, twist)) in r.chunks_mut(6).zip(twists) {
                    let rates = task_residuals(&rows, twist);
                    for (ri, rate) in chunk.iter_mut().zip(rates.iter()) {
                        *ri = w * rate;
                    }
                }
            }
            UpuResiduals::SigmaMin => r[0] = smallest_singular_value(&rows),
            UpuResiduals::Det => r[0] = rows.determinant(),
        }
        Ok(())
    }
}

/// $\sigma_{min}$ of a 6×6 matrix.
pub(super) fn smallest_singular_value(rows: &Matrix6<f64>) -> f64 {
    rows.singular_values()
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
}
