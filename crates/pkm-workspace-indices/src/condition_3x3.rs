//! Closed-form $1/\kappa$ of a $3\times3$ matrix, for hot loops (about ten times faster than the
//! SVD behind [`crate::inverse_condition_number`], which it matches to ~1e-11 where the matrix
//! is well conditioned, and which it calls below [`SVD_BELOW`]).

use nalgebra::Matrix3;

/// $1/\kappa = \sigma_{\min}/\sigma_{\max}$ of a $3\times3$ matrix from the eigenvalues of
/// $J^\top J$ (trigonometric method), with $\lambda_{\min} = \det(J)^2/(\lambda_{\max}\lambda_{\mathrm{mid}})$
/// so that nearly singular matrices keep their relative accuracy.
///
/// Below [`SVD_BELOW`] the value is the SVD's ([`crate::inverse_condition_number`]). Accuracy
/// (property test `closed_form_inverse_condition_matches_the_singular_values`, matrices of known
/// singular values, the middle one anywhere): relative error below $10^{-7}$ for every
/// $1/\kappa \ge 10^{-6}$; the 3×3 SVD's relative error grows as $\varepsilon\kappa$ beyond.
///
/// Returns 0 for a singular or non-finite matrix, like [`crate::inverse_condition_number`].
/// A matrix whose largest entry lies outside $[2^{-40}, 2^{40}]$ is first scaled by a power
/// of two, so $J^\top J$ and $\det(J)^2$ neither overflow nor underflow.
///
/// # Example
/// ```
/// use nalgebra::Matrix3;
/// let j = Matrix3::from_diagonal(&[2.0, 1.0, 0.5].into());
/// let r = pkm_workspace_indices::inverse_condition_number_3x3(&j);
/// assert!((r - 0.25).abs() < 1e-14);
/// ```
pub fn inverse_condition_number_3x3(j: &Matrix3<f64>) -> f64 {
    if !j.iter().all(|v| v.is_finite()) {
        return 0.0;
    }
    // det(J)² grows like the 6th power of the entries: keep them near 1 (exact scaling).
    let j = &crate::condition::scaled_to_unit(j, 40);
    let m = j.transpose() * j;
    let p1 = m[(0, 1)].powi(2) + m[(0, 2)].powi(2) + m[(1, 2)].powi(2);
    let q = m.trace() / 3.0;
    let p2 = (m[(0, 0)] - q).powi(2) + (m[(1, 1)] - q).powi(2) + (m[(2, 2)] - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    if !(q > 0.0) {
        return 0.0;
    }
    if !(p > 1e-15 * q) {
        return 1.0;
    }
    let b = (m - Matrix3::identity() * q) / p;
    let r = (0.5 * b.determinant()).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let lambda_max = q + 2.0 * p * phi.cos();
    let lambda_low = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let lambda_mid = 3.0 * q - lambda_max - lambda_low;
    let det = j.determinant();
    let lambda_min = if lambda_mid > 0.0 {
        det * det / (lambda_max * lambda_mid)
    } else {
        0.0
    };
    let closed = (lambda_min / lambda_max).max(0.0).sqrt().min(1.0);
    if closed < SVD_BELOW {
        crate::inverse_condition_number(j)
    } else {
        closed
    }
}

/// Below this $1/\kappa$ the closed form gives way to the SVD
/// ([`crate::inverse_condition_number`]): there $\lambda_{\mathrm{mid}} = 3q - \lambda_{\max} -
/// \lambda_{\mathrm{low}}$ can lose its digits (the arccos is $\sqrt\varepsilon$-sensitive when
/// the two small eigenvalues are close: 41 % off at $1/\kappa \approx 10^{-4}$), while the SVD
/// keeps an absolute error of about $\varepsilon$, a relative one of $\varepsilon\kappa$.
pub const SVD_BELOW: f64 = 1e-2;
