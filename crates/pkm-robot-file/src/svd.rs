//! The one bounded SVD of the crate: every decomposition goes through it (or its bound), so an
//! infinite or NaN entry can never make one loop.

use nalgebra::DMatrix;

/// Most sweeps of an SVD of the robot file (nalgebra's `SVD::try_new`): a matrix that does not
/// converge within them is reported, never iterated forever.
pub(crate) const MAX_SVD_SWEEPS: usize = 1000;

/// The SVD of `m` when every entry is finite and it converges within [`MAX_SVD_SWEEPS`];
/// `None` otherwise. Every decomposition of the crate goes through it (or an explicit bound),
/// so an infinite or NaN entry can never make one loop.
pub(crate) fn bounded_svd(
    m: DMatrix<f64>,
    compute_u: bool,
    compute_v: bool,
) -> Option<nalgebra::SVD<f64, nalgebra::Dyn, nalgebra::Dyn>> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    // nalgebra's own tolerance of `Matrix::svd` (5 ε), so a bounded SVD gives its bits.
    let eps = 5.0 * f64::EPSILON;
    nalgebra::SVD::try_new(m, compute_u, compute_v, eps, MAX_SVD_SWEEPS)
}
