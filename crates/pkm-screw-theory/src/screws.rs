//! Twists and wrenches: 6-vectors in ray order with their physical meaning (eq. 3–5, 12–13).

use nalgebra::{Isometry3, Vector3, Vector6};

use crate::error::{ScrewError, require_finite, unit};
use crate::line::PluckerLine;
use crate::ray;
use crate::screw_axis::ScrewAxis;

/// Methods shared by [`Twist`] and [`Wrench`] (both are ray-order 6-vectors).
macro_rules! ray_screw {
    ($ty:ident, $top:literal, $bottom:literal) => {
        impl $ty {
            #[doc = concat!("The screw `[", $top, "; ", $bottom, "]`.")]
            pub fn new(top: Vector3<f64>, bottom: Vector3<f64>) -> Self {
                Self(ray::stack(&top, &bottom))
            }

            /// Wraps a ray-order 6-vector as it is.
            pub fn from_vector(v: Vector6<f64>) -> Self {
                Self(v)
            }

            /// The screw of intensity `intensity` on `axis`: `intensity · [s; s0 × s + λ s]` (eq. 3/4).
            pub fn on_axis(axis: &ScrewAxis, intensity: f64) -> Self {
                Self(axis.unit_screw() * intensity)
            }

            /// The screw of intensity `intensity` about the axis through `point_on_axis` along
            /// `direction` (normalised) with pitch `pitch` (eq. 3/4/12).
            ///
            /// # Errors
            /// [`ScrewError::NonFinite`] for a non-finite input or a screw that overflows,
            /// [`ScrewError::ZeroDirection`] for a zero direction.
            pub fn from_screw(
                direction: &Vector3<f64>,
                point_on_axis: &Vector3<f64>,
                pitch: f64,
                intensity: f64,
            ) -> Result<Self, ScrewError> {
                require_finite("screw intensity", [intensity].iter())?;
                let screw =
                    Self::on_axis(&ScrewAxis::new(direction, point_on_axis, pitch)?, intensity);
                require_finite("screw (overflows)", screw.0.iter())?;
                Ok(screw)
            }

            /// The ray-order 6-vector.
            pub fn as_vector(&self) -> &Vector6<f64> {
                &self.0
            }

            /// The pitch $\lambda = (u \cdot v)/(u \cdot u)$ of `[u; v]`; `+∞` for `u = 0`.
            ///
            /// # Errors
            /// [`ScrewError::ZeroScrew`] for the zero screw, [`ScrewError::NonFinite`] for a
            /// non-finite one.
            pub fn pitch(&self) -> Result<f64, ScrewError> {
                ray::pitch(&self.0)
            }

            /// The same screw seen after the rigid motion `g = (R, t)` is applied to it (adjoint
            /// action): `[R u; R v + t × R u]`. The reciprocal product is invariant when twist and
            /// wrench are both transformed.
            pub fn transformed(&self, g: &Isometry3<f64>) -> Self {
                Self(ray::transform(g, &self.0))
            }
        }
    };
}

/// A twist $\chi = [x; \bar x]$ (eq. 12): angular velocity $x$ and linear velocity $\bar x$ of
/// the body point at the world origin. For a screw motion of rate $\dot q$ about the axis
/// $(s, s_0)$ with pitch $\lambda$: $\chi = \dot q\,[s;\; s_0 \times s + \lambda s]$ (eq. 3).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::Twist;
/// let chi = Twist::from_screw(&Vector3::z(), &Vector3::new(1.0, 0.0, 0.0), 0.5, 2.0)?;
/// assert!((chi.pitch()? - 0.5).abs() < 1e-15);
/// // The origin is 1 away from the axis: it moves at 2 along -y, plus the pitch part along z.
/// assert_eq!(chi.linear(), Vector3::new(0.0, -2.0, 1.0));
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Twist(Vector6<f64>);

ray_screw!(Twist, "angular", "linear");

impl Twist {
    /// A pure translation (λ = ∞): $[0;\; v s]$ with $s$ the normalised `direction`.
    ///
    /// # Errors
    /// [`ScrewError::NonFinite`] for a non-finite input, [`ScrewError::ZeroDirection`] for a
    /// zero direction.
    pub fn translation(direction: &Vector3<f64>, speed: f64) -> Result<Self, ScrewError> {
        require_finite("translation speed", [speed].iter())?;
        Ok(Self::new(
            Vector3::zeros(),
            unit("translation direction", direction)? * speed,
        ))
    }

    /// The angular velocity $x$.
    pub fn angular(&self) -> Vector3<f64> {
        ray::halves(&self.0).0
    }

    /// The linear velocity $\bar x$ of the body point at the world origin.
    pub fn linear(&self) -> Vector3<f64> {
        ray::halves(&self.0).1
    }

    /// The velocity of the body point at `p`: $\bar x + x \times p$.
    pub fn velocity_at(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.linear() + self.angular().cross(p)
    }
}

/// A wrench $L = [j; \bar j]$ (eq. 13): force $j$ and moment $\bar j$ about the world origin.
/// For a wrench of intensity $\rho$ on the axis $(s_r, s_{r0})$ with pitch $\lambda_r$:
/// $\rho\,[s_r;\; s_{r0} \times s_r + \lambda_r s_r]$ (eq. 4).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_screw_theory::{PluckerLine, Wrench};
/// let leg = PluckerLine::from_points(&Vector3::new(1.0, 0.0, 0.0), &Vector3::new(1.0, 0.0, 3.0))?;
/// let w = Wrench::along_line(&leg, 2.0);
/// assert_eq!(w.force(), Vector3::new(0.0, 0.0, 2.0));
/// assert_eq!(w.moment(), Vector3::new(0.0, -2.0, 0.0));
/// # Ok::<(), pkm_screw_theory::ScrewError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrench(Vector6<f64>);

ray_screw!(Wrench, "force", "moment about the origin");

impl Wrench {
    /// A pure force of magnitude `intensity` along `line` (λ_r = 0): `intensity` times the
    /// normalised line.
    pub fn along_line(line: &PluckerLine, intensity: f64) -> Self {
        Self(line.normalized().to_vector() * intensity)
    }

    /// A pure couple (λ_r = ∞): $[0;\; c\, u]$ with $u$ the normalised `axis`.
    ///
    /// # Errors
    /// [`ScrewError::NonFinite`] for a non-finite input, [`ScrewError::ZeroDirection`] for a
    /// zero axis.
    pub fn couple(axis: &Vector3<f64>, magnitude: f64) -> Result<Self, ScrewError> {
        require_finite("couple magnitude", [magnitude].iter())?;
        Ok(Self::new(
            Vector3::zeros(),
            unit("couple axis", axis)? * magnitude,
        ))
    }

    /// The force $j$.
    pub fn force(&self) -> Vector3<f64> {
        ray::halves(&self.0).0
    }

    /// The moment $\bar j$ about the world origin.
    pub fn moment(&self) -> Vector3<f64> {
        ray::halves(&self.0).1
    }
}
