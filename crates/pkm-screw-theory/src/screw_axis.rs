//! Screw axes with a finite pitch (Wolf & Shoham eq. 3–4).

use nalgebra::{Vector3, Vector6};

use crate::error::{ScrewError, require_finite, unit};
use crate::ray;

/// A screw axis: a unit direction $s$, a point $s_0$ on the axis and a finite pitch $\lambda$.
/// Its unit screw is (eq. 3, 4, 12)
/// $$\hat{\$} = \begin{bmatrix} s \\ s_0 \times s + \lambda s \end{bmatrix}.$$
/// A pitch of zero gives a line (a pure rotation or a pure force); infinite pitch is
/// [`Twist::translation`](crate::Twist::translation) or [`Wrench::couple`](crate::Wrench::couple).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::ScrewAxis;
/// // Wolf & Shoham §4.1: k = [2, 2, 1], k0 = [2, 3, 6] cm, λ = 1.
/// let axis = ScrewAxis::new(&Vector3::new(2.0, 2.0, 1.0), &Vector3::new(2.0, 3.0, 6.0), 1.0)?;
/// let chi = axis.unit_screw();
/// assert!((chi[3] + 7.0 / 3.0).abs() < 1e-12);
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScrewAxis {
    direction: Vector3<f64>,
    point: Vector3<f64>,
    pitch: f64,
}

impl ScrewAxis {
    /// The axis through `point` along `direction` (normalised here) with pitch `pitch`.
    ///
    /// # Errors
    /// [`ScrewError::NonFinite`] for a non-finite input (use the infinite-pitch constructors
    /// for pure translations and couples), [`ScrewError::ZeroDirection`] for a zero direction.
    pub fn new(
        direction: &Vector3<f64>,
        point: &Vector3<f64>,
        pitch: f64,
    ) -> Result<Self, ScrewError> {
        require_finite(
            "screw axis point or pitch",
            point.iter().chain([pitch].iter()),
        )?;
        Ok(Self {
            direction: unit("screw axis direction", direction)?,
            point: *point,
            pitch,
        })
    }

    /// The unit direction $s$.
    pub fn direction(&self) -> Vector3<f64> {
        self.direction
    }

    /// The point $s_0$ given at construction.
    pub fn point(&self) -> Vector3<f64> {
        self.point
    }

    /// The pitch $\lambda$.
    pub fn pitch(&self) -> f64 {
        self.pitch
    }

    /// The unit screw $[s;\; s_0 \times s + \lambda s]$ of eq. 3.
    pub fn unit_screw(&self) -> Vector6<f64> {
        let s = self.direction;
        ray::stack(&s, &(self.point.cross(&s) + self.pitch * s))
    }
}
