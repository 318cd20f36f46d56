//! The error type of the crate.

/// Why a screw-theory object could not be built or evaluated.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::{PluckerLine, ScrewError};
/// let p = Vector3::new(1.0, 2.0, 3.0);
/// let err = PluckerLine::from_points(&p, &p).unwrap_err();
/// assert!(matches!(err, ScrewError::CoincidentPoints { .. }));
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ScrewError {
    /// The two points that should define a line (eq. 1) coincide.
    #[error("points coincide: distance {distance} is not positive")]
    CoincidentPoints {
        /// Distance between the two points.
        distance: f64,
    },
    /// A direction (line, screw axis, rotation axis) has zero length.
    #[error("direction has zero norm ({norm})")]
    ZeroDirection {
        /// Norm of the offending direction.
        norm: f64,
    },
    /// An input contained a NaN or an infinity.
    #[error("{what} is not finite: {value}")]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// First non-finite component found.
        value: f64,
    },
    /// A twist (or wrench) is zero, so it has no axis and no pitch.
    #[error("screw has zero norm ({norm}): no axis and no pitch")]
    ZeroScrew {
        /// Norm of the 6-vector.
        norm: f64,
    },
    /// A relative tolerance outside `[0, 1)` or not finite.
    #[error("relative tolerance {value} is outside [0, 1)")]
    InvalidTolerance {
        /// The tolerance given.
        value: f64,
    },
    /// The singular value decomposition of a line set did not converge.
    #[error("singular value decomposition of {rows} rows did not converge")]
    SvdNotConverged {
        /// Number of rows of the line set.
        rows: usize,
    },
}

/// Checks that every entry of `values` is finite.
pub(crate) fn require_finite<'a>(
    what: &'static str,
    values: impl IntoIterator<Item = &'a f64>,
) -> Result<(), ScrewError> {
    match values.into_iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(ScrewError::NonFinite { what, value }),
        None => Ok(()),
    }
}

/// Returns `v / |v|`, or an error for a zero or non-finite `v`.
///
/// When $|v|$ overflows or underflows (components near 1e±300), `v` is first divided by its
/// largest component, so every finite non-zero `v` has a unit direction.
pub(crate) fn unit(
    what: &'static str,
    v: &nalgebra::Vector3<f64>,
) -> Result<nalgebra::Vector3<f64>, ScrewError> {
    require_finite(what, v.iter())?;
    let norm = v.norm();
    if norm.is_normal() {
        return Ok(v / norm);
    }
    let largest = v.amax();
    if largest > 0.0 {
        let w = v / largest;
        Ok(w / w.norm())
    } else {
        Err(ScrewError::ZeroDirection { norm })
    }
}

/// $|v|$ without overflow or underflow of $v \cdot v$: the plain norm when it is a normal
/// number, else $\max_i |v_i| \cdot |v / \max_i |v_i||$ (infinite only when $|v|$ itself is).
pub(crate) fn scaled_norm(v: &nalgebra::Vector3<f64>) -> f64 {
    let norm = v.norm();
    if norm.is_normal() {
        return norm;
    }
    let largest = v.amax();
    if largest > 0.0 {
        largest * (v / largest).norm()
    } else {
        norm
    }
}
