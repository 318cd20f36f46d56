//! Plücker lines (Wolf & Shoham eq. 1–2).

use nalgebra::{Vector3, Vector6};

use crate::error::{ScrewError, require_finite, scaled_norm, unit};
use crate::ray;

/// A line in Plücker ray coordinates $L = [d; m]$: a direction $d \ne 0$ and its moment
/// $m = p \times d$ about the world origin, for any point $p$ on the line.
///
/// Through two finite points $X \ne Y$ (eq. 1): $L = (Y - X;\; X \times Y)$. Every line
/// satisfies Klein's identity (eq. 2) $K(L) = d \cdot m = 0$.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::PluckerLine;
/// let line = PluckerLine::from_points(&Vector3::new(1.0, 0.0, 0.0), &Vector3::new(1.0, 2.0, 0.0))?;
/// assert_eq!(line.direction(), Vector3::new(0.0, 2.0, 0.0));
/// assert_eq!(line.moment(), Vector3::new(0.0, 0.0, 2.0));
/// assert_eq!(line.klein_form(), 0.0);
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PluckerLine {
    direction: Vector3<f64>,
    moment: Vector3<f64>,
}

impl PluckerLine {
    /// The line through `x` and `y`, eq. 1: $L = (Y - X;\; X \times Y)$. The direction is
    /// $Y - X$, not normalised (use [`PluckerLine::normalized`]).
    ///
    /// # Errors
    /// [`ScrewError::NonFinite`] for a non-finite coordinate or one that overflows ($Y - X$ or
    /// $X \times Y$ beyond `f64`), [`ScrewError::CoincidentPoints`] when $X = Y$.
    pub fn from_points(x: &Vector3<f64>, y: &Vector3<f64>) -> Result<Self, ScrewError> {
        require_finite("line point", x.iter().chain(y.iter()))?;
        let direction = y - x;
        let distance = direction.norm();
        if !(direction.amax() > 0.0) {
            return Err(ScrewError::CoincidentPoints { distance });
        }
        Self::checked(direction, x.cross(y))
    }

    /// The line through `p` with direction `d`: $L = (d;\; p \times d)$, `d` kept as given.
    ///
    /// # Errors
    /// [`ScrewError::NonFinite`] for a non-finite input, [`ScrewError::ZeroDirection`] when
    /// $d = 0$.
    pub fn from_direction_and_point(
        d: &Vector3<f64>,
        p: &Vector3<f64>,
    ) -> Result<Self, ScrewError> {
        require_finite("line point", p.iter())?;
        unit("line direction", d)?;
        Self::checked(*d, p.cross(d))
    }

    /// The line `[direction; moment]`, or [`ScrewError::NonFinite`] when a coordinate overflowed.
    fn checked(direction: Vector3<f64>, moment: Vector3<f64>) -> Result<Self, ScrewError> {
        require_finite("line direction (overflows)", direction.iter())?;
        require_finite("line moment (overflows)", moment.iter())?;
        Ok(Self { direction, moment })
    }

    /// The direction $d$ (the first three ray coordinates $p_{01}, p_{02}, p_{03}$).
    pub fn direction(&self) -> Vector3<f64> {
        self.direction
    }

    /// The moment $m$ about the world origin ($p_{23}, p_{31}, p_{12}$).
    pub fn moment(&self) -> Vector3<f64> {
        self.moment
    }

    /// Klein's quadratic form, eq. 2: $K(L) = L_0 L_3 + L_1 L_4 + L_2 L_5 = d \cdot m$, zero
    /// (up to rounding) for every line.
    pub fn klein_form(&self) -> f64 {
        self.direction.dot(&self.moment)
    }

    /// The ray coordinates $[d; m]$.
    pub fn to_vector(&self) -> Vector6<f64> {
        ray::stack(&self.direction, &self.moment)
    }

    /// The same line scaled so that $|d| = 1$; then $|m|$ is the distance from the origin.
    pub fn normalized(&self) -> Self {
        let scale = scaled_norm(&self.direction);
        Self {
            direction: self.direction / scale,
            moment: self.moment / scale,
        }
    }

    /// The point of the line closest to the world origin, $d \times m / |d|^2$; finite for
    /// every line (its distance $|m|/|d|$ is at most that of a point the line was built through).
    pub fn closest_point_to_origin(&self) -> Vector3<f64> {
        let norm_squared = self.direction.norm_squared();
        if norm_squared.is_normal() {
            let point = self.direction.cross(&self.moment) / norm_squared;
            if point.iter().all(|v| v.is_finite()) {
                return point;
            }
        }
        // |d|² or d × m overflows or underflows: (d/|d|) × (m/|d|) with a scaled norm.
        let norm = scaled_norm(&self.direction);
        (self.direction / norm).cross(&(self.moment / norm))
    }
}
