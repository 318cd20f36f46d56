//! Rank and reciprocal system of a set of screws (singularities, linear complexes).

use nalgebra::{DMatrix, Vector6};

use crate::error::{ScrewError, require_finite};
use crate::ray;

/// Singular values and right singular vectors of $A = [L_1; \dots; L_n]\,\Delta$, padded with
/// zero rows to at least 6 rows so that all six right singular vectors are returned.
fn svd_of_rows(
    rows: &[Vector6<f64>],
    rel_tol: f64,
) -> Result<(Vec<f64>, DMatrix<f64>), ScrewError> {
    if !(rel_tol.is_finite() && (0.0..1.0).contains(&rel_tol)) {
        return Err(ScrewError::InvalidTolerance { value: rel_tol });
    }
    require_finite("line set row", rows.iter().flat_map(|r| r.iter()))?;
    let mut a = DMatrix::zeros(rows.len().max(6), 6);
    for (i, row) in rows.iter().enumerate() {
        a.row_mut(i).copy_from(&ray::swap_halves(row).transpose());
    }
    let svd = nalgebra::SVD::try_new(a, false, true, f64::EPSILON, 1000)
        .ok_or(ScrewError::SvdNotConverged { rows: rows.len() })?;
    let v_t = svd
        .v_t
        .ok_or(ScrewError::SvdNotConverged { rows: rows.len() })?;
    Ok((svd.singular_values.iter().copied().collect(), v_t))
}

/// The threshold below which a singular value counts as zero.
fn threshold(singular_values: &[f64], rel_tol: f64) -> f64 {
    rel_tol * singular_values.iter().copied().fold(0.0, f64::max)
}

/// The rank of a set of screws (rows $L_i$ in ray order): the number of singular values of
/// $[L_1; \dots; L_n]$ above `rel_tol` times the largest. A Stewart–Gough Jacobian of rank
/// below 6 is a singular configuration; rank 5 means the lines belong to a linear complex.
///
/// # Errors
/// [`ScrewError::InvalidTolerance`] unless $0 \le$ `rel_tol` $< 1$, [`ScrewError::NonFinite`]
/// for a non-finite row, [`ScrewError::SvdNotConverged`] if the SVD fails.
///
/// # Example
/// ```
/// use nalgebra::{Vector3, Vector6};
/// use pkm_screw_theory::{line_set_rank, PluckerLine};
/// // Three parallel vertical lines span only a 3-system.
/// let rows: Vec<Vector6<f64>> = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
///     .iter()
///     .map(|&(x, y)| PluckerLine::from_direction_and_point(&Vector3::z(), &Vector3::new(x, y, 0.0)))
///     .map(|l| l.map(|l| l.to_vector()))
///     .collect::<Result<_, _>>()?;
/// assert_eq!(line_set_rank(&rows, 1e-9)?, 3);
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
pub fn line_set_rank(rows: &[Vector6<f64>], rel_tol: f64) -> Result<usize, ScrewError> {
    let (singular_values, _) = svd_of_rows(rows, rel_tol)?;
    let tol = threshold(&singular_values, rel_tol);
    Ok(singular_values
        .iter()
        .filter(|&&s| s > tol && s > 0.0)
        .count())
}

/// A basis (orthonormal in $\mathbb{R}^6$) of the screws $\chi$ reciprocal to every row,
/// $L_i \wedge \chi = 0$: the null space of $[L_1; \dots; L_n]\,\Delta$, where $\Delta$ swaps
/// the halves. Its dimension is $6 - $ [`line_set_rank`]. For the rows of a parallel robot
/// these are the twists the legs cannot resist (F = 0 in eq. 14).
///
/// # Errors
/// As [`line_set_rank`].
///
/// # Example
/// ```
/// use nalgebra::Vector6;
/// use pkm_screw_theory::{reciprocal_product_vectors, reciprocal_screw_system};
/// let rows = [Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0)]; // a force along z through the origin
/// let system = reciprocal_screw_system(&rows, 1e-12)?;
/// assert_eq!(system.len(), 5);
/// assert!(system.iter().all(|x| reciprocal_product_vectors(&rows[0], x).abs() < 1e-15));
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
pub fn reciprocal_screw_system(
    rows: &[Vector6<f64>],
    rel_tol: f64,
) -> Result<Vec<Vector6<f64>>, ScrewError> {
    let (singular_values, v_t) = svd_of_rows(rows, rel_tol)?;
    let tol = threshold(&singular_values, rel_tol);
    Ok(singular_values
        .iter()
        .enumerate()
        .filter(|&(_, &s)| !(s > tol && s > 0.0))
        .map(|(k, _)| v_t.row(k).transpose().fixed_rows::<6>(0).into())
        .collect())
}
