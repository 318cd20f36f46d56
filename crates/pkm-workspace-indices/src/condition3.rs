//! Closed-form $1/\kappa$ of a $3\times3$ matrix from the eigenvalues of $J^TJ$ (the hot loop
//! of the global condition index; about 5× faster than the SVD).

use nalgebra::Matrix3;
use std::f64::consts::PI;

/// $1/\kappa = \sigma_{\min}/\sigma_{\max}$ of a $3\times3$ matrix, 0 when singular or not finite.
///
/// The eigenvalues $\lambda_1 \ge \lambda_2$ of $A = J^TJ$ come from the trigonometric solution
/// of the characteristic cubic; the smallest is $\lambda_3 = \det(J)^2/(\lambda_1\lambda_2)$,
/// which keeps full relative accuracy near singularities. Agrees with
/// [`crate::inverse_condition_number`] to about 1e-12.
///
/// # Example
/// ```
/// use nalgebra::Matrix3;
/// let j = Matrix3::new(2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5);
/// assert!((pkm_workspace_indices::inverse_condition_number_3x3(&j) - 0.25).abs() < 1e-14);
/// ```
pub fn inverse_condition_number_3x3(j: &Matrix3<f64>) -> f64 {
    let a = j.transpose() * j;
    let q = a.trace() / 3.0;
    let p1 = a[(0, 1)].powi(2) + a[(0, 2)].powi(2) + a[(1, 2)].powi(2);
    let p2 = (a[(0, 0)] - q).powi(2) + (a[(1, 1)] - q).powi(2) + (a[(2, 2)] - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    let (l1, l2) = if p > 0.0 {
        let b = (a - Matrix3::from_diagonal_element(q)) / p;
        let phi = (b.determinant() / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
        let l1 = q + 2.0 * p * phi.cos();
        let l3 = q + 2.0 * p * (phi + 2.0 * PI / 3.0).cos();
        (l1, 3.0 * q - l1 - l3)
    } else {
        (q, q)
    };
    let det = j.determinant();
    let l3 = det * det / (l1 * l2);
    let inv = (l3 / l1).sqrt();
    if inv.is_finite() {
        inv.clamp(0.0, 1.0)
    } else {
        0.0
    }
}
