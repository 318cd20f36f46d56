//! Rotation about an axis (Wolf & Shoham eq. 9).

use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::error::{ScrewError, require_finite, unit};

/// The skew matrix $\[n\]_\times$ with $\[n\]_\times v = n \times v$.
pub fn skew(n: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -n.z, n.y, n.z, 0.0, -n.x, -n.y, n.x, 0.0)
}

/// The rotation of `angle` radians about `axis` (normalised here), eq. 9:
/// $R = \exp(\alpha \[n\]_\times) = I + \sin\alpha\,\[n\]_\times + (1 - \cos\alpha)\,\[n\]_\times^2$
/// (Rodrigues). The paper prints the last row of $\[n\]_\times$ as $\[n_2, n_1, 0\]$; the correct
/// row is $\[-n_2, n_1, 0\]$ (erratum, immaterial for the paper's $n = z$ and $n = x$).
///
/// # Errors
/// [`ScrewError::NonFinite`] for a non-finite input, [`ScrewError::ZeroDirection`] for a zero
/// axis.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::rotation_from_axis_angle;
/// let r = rotation_from_axis_angle(&Vector3::new(0.0, 0.0, 2.0), std::f64::consts::FRAC_PI_2)?;
/// assert!((r * Vector3::x() - Vector3::y()).norm() < 1e-15);
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
pub fn rotation_from_axis_angle(
    axis: &Vector3<f64>,
    angle: f64,
) -> Result<Rotation3<f64>, ScrewError> {
    require_finite("rotation angle", [angle].iter())?;
    let k = skew(&unit("rotation axis", axis)?);
    let (sin, cos) = angle.sin_cos();
    let matrix = Matrix3::identity() + k * sin + k * k * (1.0 - cos);
    Ok(Rotation3::from_matrix_unchecked(matrix))
}
