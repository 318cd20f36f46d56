//! The dense linear algebra of the optimality check: least-squares multipliers (SVD), a null
//! space basis and ascending symmetric eigenvalues. nalgebra's iterative decompositions loop
//! until convergence by default and may not end on NaN input, so every one here is called with
//! finite input and an iteration limit, and a failure is a typed error.

use crate::OptimizeError;
use nalgebra::{DMatrix, DVector};

/// Iteration limit of every decomposition (the implicit QR sweeps converge in a few per
/// eigenvalue on finite input; the limit only stops a pathological case).
const MAX_SWEEPS: usize = 10_000;

/// Singular values at most this are treated as zero by the least-squares solve.
const LEAST_SQUARES_CUTOFF: f64 = 1e-12;

/// An eigenvalue of $A^\top A$ at most this fraction of the largest spans the null space.
const NULL_SPACE_RELATIVE: f64 = 1e-10;

/// `Err(Numerical)` unless every entry of `m` is finite (a decomposition of a NaN may not end).
fn finite(m: &DMatrix<f64>, what: &'static str) -> Result<(), OptimizeError> {
    if m.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(OptimizeError::Numerical { what })
    }
}

/// The least-squares solution $y$ of $A y \approx b$ (minimum norm, singular values below
/// [`LEAST_SQUARES_CUTOFF`] dropped); zero when $A$ has no row or no column.
pub(super) fn least_squares(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
) -> Result<DVector<f64>, OptimizeError> {
    if a.nrows() == 0 || a.ncols() == 0 {
        return Ok(DVector::zeros(a.ncols()));
    }
    finite(a, "the active constraint gradients are not finite")?;
    let svd = a
        .clone()
        .try_svd(true, true, f64::EPSILON, MAX_SWEEPS)
        .ok_or(OptimizeError::Numerical {
            what: "the SVD of the active constraint gradients did not converge",
        })?;
    svd.solve(b, LEAST_SQUARES_CUTOFF)
        .map_err(|what| OptimizeError::Numerical { what })
}

/// An orthonormal basis (columns) of the null space of `a`: the eigenvectors of $A^\top A$
/// whose eigenvalues are at most [`NULL_SPACE_RELATIVE`] of the largest. With no row it is the
/// identity; with no column (no free variable) it is empty.
pub(super) fn null_space(a: &DMatrix<f64>) -> Result<DMatrix<f64>, OptimizeError> {
    let n = a.ncols();
    if a.nrows() == 0 {
        return Ok(DMatrix::identity(n, n));
    }
    if n == 0 {
        return Ok(DMatrix::zeros(0, 0));
    }
    let normal = a.transpose() * a;
    finite(&normal, "the active constraint gradients overflow")?;
    let eig =
        normal
            .try_symmetric_eigen(f64::EPSILON, MAX_SWEEPS)
            .ok_or(OptimizeError::Numerical {
                what: "the eigenvectors of the active constraint gradients did not converge",
            })?;
    let largest = eig.eigenvalues.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let keep: Vec<usize> = (0..n)
        .filter(|&k| eig.eigenvalues[k].abs() <= NULL_SPACE_RELATIVE * largest)
        .collect();
    Ok(DMatrix::from_fn(n, keep.len(), |r, c| {
        eig.eigenvectors[(r, keep[c])]
    }))
}

/// The eigenvalues of the symmetric `m`, ascending; none for an empty matrix.
pub(super) fn ascending_eigenvalues(m: DMatrix<f64>) -> Result<Vec<f64>, OptimizeError> {
    if m.nrows() == 0 {
        return Ok(Vec::new());
    }
    finite(&m, "the Hessian is not finite")?;
    let eig = m
        .try_symmetric_eigen(f64::EPSILON, MAX_SWEEPS)
        .ok_or(OptimizeError::Numerical {
            what: "the eigenvalues of the Hessian did not converge",
        })?;
    let mut v = eig.eigenvalues.as_slice().to_vec();
    v.sort_by(f64::total_cmp);
    Ok(v)
}
