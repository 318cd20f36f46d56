//! The screw view of a mechanism (Wolf & Shoham, eq. 10, 14 and 18): at a platform pose, the
//! six wrenches the legs and joints can exert on the platform, one Plücker row
//! $[f ; m]$ each (moment about the world origin), and the task objective
//! $$ F(\chi) = \sum_i (L_i \wedge \chi)^2, $$
//! the sum of the squared virtual powers of the rows on a task twist $\chi$: $F = 0$ exactly when
//! $\chi$ is reciprocal to every row, i.e. an instantaneous motion the rows do not resist.

use nalgebra::{Isometry3, Matrix6};
use pkm_screw_theory::{Twist, task_objective};
use pkm_traits::KinematicsError;

/// A mechanism whose platform is held by six wrench rows (the Stewart–Gough platform's six leg
/// forces; the 3-UPU's three leg forces and three constraint couples).
///
/// # Example
/// ```
/// use nalgebra::{Isometry3, Vector3};
/// use pkm_mechanisms::{StewartDesign, StewartGough, ThreeUpu, WrenchSystem, presets};
/// use pkm_screw_theory::Twist;
/// let lift = Twist::new(Vector3::zeros(), Vector3::z());
/// let pose = Isometry3::translation(0.0, 0.0, 40.0);
/// let sg = StewartGough::new(StewartDesign::from_deg(12.0, 8.0, 8.0, 8.0))?;
/// let upu = ThreeUpu::new(presets::park_3upu())?;
/// let systems: [&dyn WrenchSystem; 2] = [&sg, &upu];
/// for m in systems {
///     // Every leg resists a vertical lift: F > 0.
///     assert!(m.task_objective(&pose, &lift)? > 0.0);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub trait WrenchSystem {
    /// The $6 \times 6$ matrix whose rows are the wrenches $[f_i ; m_i]$ (unit force directions
    /// or unit couples; moments about the world origin) at `pose`.
    ///
    /// # Errors
    /// [`KinematicsError::Singular`] when a row is undefined at `pose` (a leg of (numerically)
    /// zero length, a non-finite pose).
    fn wrench_rows(&self, pose: &Isometry3<f64>) -> Result<Matrix6<f64>, KinematicsError>;

    /// The task objective $F = \sum_i (L_i \wedge \chi)^2$ over the six rows (eq. 14).
    ///
    /// # Errors
    /// As [`WrenchSystem::wrench_rows`].
    fn task_objective(&self, pose: &Isometry3<f64>, twist: &Twist) -> Result<f64, KinematicsError> {
        Ok(task_objective(&self.wrench_rows(pose)?, twist))
    }
}
