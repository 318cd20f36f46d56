//! The task-based objective of Wolf & Shoham, eq. 14, and its gradients.

use nalgebra::{SMatrix, SVector, Vector6};

use crate::ray;
use crate::screws::Twist;

/// The residuals $r_i = L_i \wedge \chi$ of eq. 14, one per row $L_i$ of the Jacobian (each
/// row a wrench in ray order): $r = [L_1; \dots; L_N]\,\Delta\chi$.
pub fn task_residuals<const N: usize>(rows: &SMatrix<f64, N, 6>, twist: &Twist) -> SVector<f64, N> {
    rows * ray::swap_halves(twist.as_vector())
}

/// The objective of eq. 14,
/// $$F = \sum_{i=1}^N (L_i \wedge \chi)^2 = \sum_i (\bar j_i \cdot x + j_i \cdot \bar x)^2,$$
/// the sum of the squared virtual powers of the rows on the task twist $\chi$ (for a
/// Stewart–Gough platform: the sum of the squared leg rates). $F = 0$ iff $\chi$ is reciprocal to
/// every row. Plain arithmetic: NaN in, NaN out, and ±∞ when the squares overflow (the
/// mechanisms' `task_objective` methods return a typed error instead).
///
/// # Example
/// ```
/// use nalgebra::{SMatrix, Vector3};
/// use pkm_screw_theory::{task_objective, Twist};
/// let rows = SMatrix::<f64, 2, 6>::from_row_slice(&[
///     0.0, 0.0, 1.0, 0.0, 0.0, 0.0, // force along z through the origin
///     1.0, 0.0, 0.0, 0.0, 0.0, 0.0, // force along x through the origin
/// ]);
/// let translation = Twist::new(Vector3::zeros(), Vector3::new(3.0, 0.0, 4.0));
/// assert_eq!(task_objective(&rows, &translation), 25.0);
/// ```
pub fn task_objective<const N: usize>(rows: &SMatrix<f64, N, 6>, twist: &Twist) -> f64 {
    task_residuals(rows, twist).norm_squared()
}

/// The gradient of eq. 14 with respect to the rows: $\partial F/\partial L_i = 2\,(L_i \wedge
/// \chi)\,(\Delta\chi)^\top$, row $i$ of the result.
pub fn task_objective_gradient_rows<const N: usize>(
    rows: &SMatrix<f64, N, 6>,
    twist: &Twist,
) -> SMatrix<f64, N, 6> {
    let swapped = ray::swap_halves(twist.as_vector());
    (rows * swapped) * swapped.transpose() * 2.0
}

/// The gradient of eq. 14 with respect to the twist coordinates:
/// $\partial F/\partial \chi = 2\,\Delta\,[L_1; \dots; L_N]^\top r$.
pub fn task_objective_gradient_twist<const N: usize>(
    rows: &SMatrix<f64, N, 6>,
    twist: &Twist,
) -> Vector6<f64> {
    ray::swap_halves(&(rows.transpose() * task_residuals(rows, twist))) * 2.0
}
