//! Space utilisation $\eta_2$ (Miller 2004, eq. 2) of a translation-invariant workspace.

use crate::IndexError;
use pkm_traits::{InvalidInput, SlicedRegion};

/// $\eta_2 = A_W / A_{bb}$: the cross-section area over the area of the smallest axis-aligned
/// rectangle containing the workspace and every fixed actuator point `(y, z)` (Miller 2004,
/// eq. 2, with infinite rails so that volumes become cross-section areas).
///
/// # Errors
/// [`IndexError::Invalid`] when the region is empty, a point is not finite, or the points lie
/// so far out that the ratio overflows or underflows.
///
/// # Example
/// ```
/// # use pkm_traits::{Extents, SlicedRegion};
/// struct Square;
/// impl SlicedRegion for Square {
///     fn slice(&self, y: f64) -> Option<(f64, f64)> { (0.0..=1.0).contains(&y).then_some((0.0, 1.0)) }
///     fn breakpoints(&self) -> &[f64] { &[0.0, 1.0] }
///     fn extents(&self) -> Extents { Extents { y_min: 0.0, y_max: 1.0, z_min: 0.0, z_max: 1.0 } }
///     fn area(&self) -> f64 { 1.0 }
/// }
/// let eta2 = pkm_workspace_indices::space_utilization(&Square, &[[2.0, 0.0]]).unwrap();
/// assert!((eta2 - 0.5).abs() < 1e-15);
/// ```
pub fn space_utilization(
    region: &impl SlicedRegion,
    fixed_points: &[[f64; 2]],
) -> Result<f64, IndexError> {
    let area = region.area();
    if !(area > 0.0 && area.is_finite()) {
        return Err(InvalidInput::new(
            "workspace cross-section area",
            area,
            "must be > 0 (the workspace is empty)",
        )
        .into());
    }
    let mut bounding_box = region.extents();
    for p in fixed_points {
        if let Some(&value) = p.iter().find(|v| !v.is_finite()) {
            return Err(InvalidInput::new("actuator position", value, "must be finite").into());
        }
        bounding_box = bounding_box.including(p[0], p[1]);
    }
    let utilisation = area / bounding_box.area();
    if !(utilisation > 0.0 && utilisation.is_finite()) {
        return Err(InvalidInput::new(
            "bounding box area",
            bounding_box.area(),
            "must be finite and small enough that area / box area is representable",
        )
        .into());
    }
    Ok(utilisation)
}
