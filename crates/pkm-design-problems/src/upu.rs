//! The 3-UPU's task-synthesis problem (Wolf & Shoham §4.4): over any subset of its 14
//! variables (the radii, the six tilts of the upper U-joint axes from Park's, the pose), make
//! the actuation and constraint wrenches of eq. 18 reciprocal to the task twists $\chi_k$
//! (the residuals $\sqrt{w_k}\,(L_i \wedge \chi_k)$ of eq. 14, least squares), or drive the
//! eq. 18 matrix singular ($\sigma_{min}$ or $\det$).
//!
//! One problem serves the `task` study of the study layer and the reproduction of §4.4 in
//! `pkm::papers`.

use nalgebra::{Isometry3, Matrix6};
use pkm_mechanisms::{ThreeUpu, ThreeUpuDesign, UJointAxes, WrenchSystem, pose_from_task};
use pkm_screw_theory::{Twist, task_residuals};
use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals, Task};

/// The 3-UPU variables in design-vector order, as named in `[mechanism.three_upu]` (the first
/// eight, lengths in m and tilts in degrees) and in a task study's `[task.pose]` (position in
/// m, rotation vector in degrees).
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

/// What the residuals are.
#[derive(Debug, Clone, PartialEq)]
pub enum UpuGoal {
    /// $\sqrt{w_k}\,(L_i \wedge \chi_k)$ for each weighted task twist $(w_k, \chi_k)$, six per
    /// twist (eq. 14).
    Task(Vec<(f64, Twist)>),
    /// $\sigma_{min}$ of the eq. 18 matrix.
    SigmaMin,
    /// $\det$ of the eq. 18 matrix.
    Det,
}

/// Park's axes $(u_1, u_2)$ of the joints at `azimuths` (radians), joint $i$ tilted by
/// $\beta_i$ about the radial $u_2$, then by $\gamma_i$ about the tangent $u_1$
/// (`tilts_deg = [β1, γ1, β2, γ2, β3, γ3]`, degrees), as in Wolf & Shoham §4.4:
/// $u_j' = R_{u_2}(\beta_i)\,R_{u_1}(\gamma_i)\,u_j$.
pub fn tilted_axes(azimuths: [f64; 3], tilts_deg: &[f64; 6]) -> [UJointAxes; 3] {
    std::array::from_fn(|i| {
        let (beta, gamma) = (tilts_deg[2 * i], tilts_deg[2 * i + 1]);
        UJointAxes::park_tilted(azimuths[i], beta.to_radians(), gamma.to_radians())
    })
}

/// The 3-UPU over any subset of [`UPU_VARIABLES`].
#[derive(Debug, Clone)]
pub struct UpuProblem {
    /// The joints' azimuths (radians).
    azimuths: [f64; 3],
    values: [f64; 14],
    free: Vec<usize>,
    bounds: Vec<Bounds>,
    goal: UpuGoal,
}

impl UpuProblem {
    /// The problem with the variables `free` (indices into [`UPU_VARIABLES`] with their
    /// bounds), the others at `nominal`; the joints at `azimuths` (radians).
    pub fn new(
        azimuths: [f64; 3],
        nominal: [f64; 14],
        free: &[(usize, Bounds)],
        goal: UpuGoal,
    ) -> Self {
        let goal = match goal {
            UpuGoal::Task(twists) => {
                UpuGoal::Task(twists.into_iter().map(|(w, t)| (w.sqrt(), t)).collect())
            }
            g => g,
        };
        Self {
            azimuths,
            values: nominal,
            free: free.iter().map(|(k, _)| *k).collect(),
            bounds: free.iter().map(|(_, b)| *b).collect(),
            goal,
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
        match &self.goal {
            UpuGoal::Task(t) => 6 * t.len(),
            UpuGoal::SigmaMin | UpuGoal::Det => 1,
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
        match &self.goal {
            UpuGoal::Task(twists) => {
                for (chunk, (w, twist)) in r.chunks_mut(6).zip(twists) {
                    let rates = task_residuals(&rows, twist);
                    for (ri, rate) in chunk.iter_mut().zip(rates.iter()) {
                        *ri = w * rate;
                    }
                }
            }
            UpuGoal::SigmaMin => r[0] = smallest_singular_value(&rows)?,
            UpuGoal::Det => r[0] = rows.determinant(),
        }
        Ok(())
    }
}

/// Sweeps of the SVD before it gives up (it converges in a few dozen on any finite matrix).
const MAX_SVD_ITERATIONS: usize = 1000;

/// $\sigma_{min}$ of a 6×6 matrix, with a bounded iteration.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] when the SVD does not converge (a non-finite matrix).
fn smallest_singular_value(rows: &Matrix6<f64>) -> Result<f64, ObjectiveError> {
    // nalgebra's own tolerance of `Matrix::singular_values` (5ε), so the bounded SVD gives its
    // bits.
    let svd = rows
        .try_svd(false, false, 5.0 * f64::EPSILON, MAX_SVD_ITERATIONS)
        .ok_or_else(|| {
            ObjectiveError::infeasible("the SVD of the eq. 18 matrix did not converge")
        })?;
    Ok(svd
        .singular_values
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min))
}
