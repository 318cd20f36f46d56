//! Ray-coordinate helpers shared by lines, twists and wrenches.

use nalgebra::{Isometry3, Vector3, Vector6};

/// Splits a 6-vector `[top; bottom]` into its two halves.
pub(crate) fn halves(v: &Vector6<f64>) -> (Vector3<f64>, Vector3<f64>) {
    (v.fixed_rows::<3>(0).into(), v.fixed_rows::<3>(3).into())
}

/// Stacks `[top; bottom]`.
pub(crate) fn stack(top: &Vector3<f64>, bottom: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(top.x, top.y, top.z, bottom.x, bottom.y, bottom.z)
}

/// $\Delta v$: swaps the halves of a 6-vector, so that $a \wedge b = a^\top \Delta b$.
pub(crate) fn swap_halves(v: &Vector6<f64>) -> Vector6<f64> {
    let (top, bottom) = halves(v);
    stack(&bottom, &top)
}

/// The adjoint action of a rigid motion $g = (R, t)$ on ray coordinates $[u; v]$:
/// $[R u;\; R v + t \times R u]$. Lines, twists `[ω; v_O]` and wrenches `[f; m_O]` all
/// transform this way when the moment is taken about the world origin.
pub(crate) fn transform(iso: &Isometry3<f64>, v: &Vector6<f64>) -> Vector6<f64> {
    let (top, bottom) = halves(v);
    let top = iso.rotation * top;
    let bottom = iso.rotation * bottom + iso.translation.vector.cross(&top);
    stack(&top, &bottom)
}

/// The pitch $(u \cdot v)/(u \cdot u)$ of `[u; v]`, `+∞` when `u = 0` and `v ≠ 0`.
///
/// Where $u \cdot u$ would overflow or underflow, the pitch is computed as
/// $(\hat u \cdot v) / |u|$ with a scaled norm; a pitch too large for `f64` is an error.
pub(crate) fn pitch(v: &Vector6<f64>) -> Result<f64, crate::ScrewError> {
    crate::error::require_finite("screw", v.iter())?;
    let (top, bottom) = halves(v);
    let top_sq = top.norm_squared();
    let plain = top.dot(&bottom) / top_sq;
    if top_sq.is_normal() && plain.is_finite() {
        return Ok(plain);
    }
    if top.amax() > 0.0 {
        let norm = crate::error::scaled_norm(&top);
        let largest = top.amax();
        let direction = (top / largest) / (norm / largest);
        let pitch = direction.dot(&bottom) / norm;
        return if pitch.is_finite() {
            Ok(pitch)
        } else {
            Err(crate::ScrewError::NonFinite {
                what: "pitch (overflows)",
                value: pitch,
            })
        };
    }
    if bottom.amax() > 0.0 {
        Ok(f64::INFINITY)
    } else {
        Err(crate::ScrewError::ZeroScrew { norm: 0.0 })
    }
}
