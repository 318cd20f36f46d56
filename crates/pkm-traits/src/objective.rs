//! Objectives for optimisers: value, residuals, inequality constraints and bounds.
//!
//! Optimisers never see a mechanism; they see these traits over a design vector `&[f64]`.
//! By convention every objective is *minimised*; a maximisation problem negates its value.
//! A design for which the model cannot be evaluated returns
//! [`ObjectiveError::Infeasible`], which searches record and skip.

use crate::error::{InvalidInput, ObjectiveError};

/// Closed interval $[\text{lower}, \text{upper}]$ of one design variable: both ends finite,
/// `lower <= upper`, and a finite width. The fields are private, so every `Bounds` went through
/// [`Bounds::new`]:
///
/// ```compile_fail
/// let b = pkm_traits::Bounds { lower: 1.0, upper: 0.0 };
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    lower: f64,
    upper: f64,
}

impl Bounds {
    /// The interval $[-1, 1]$.
    pub const SYMMETRIC_UNIT: Self = Self {
        lower: -1.0,
        upper: 1.0,
    };

    /// The interval `[lower, upper]`.
    ///
    /// # Errors
    /// [`ObjectiveError::InvalidInput`] when a bound is not finite, `lower > upper`, or the width
    /// `upper − lower` overflows.
    pub fn new(lower: f64, upper: f64) -> Result<Self, ObjectiveError> {
        for (name, value) in [("lower", lower), ("upper", upper)] {
            if !value.is_finite() {
                return Err(InvalidInput::new(name, value, "a bound must be finite").into());
            }
        }
        if !(lower <= upper && (upper - lower).is_finite()) {
            return Err(InvalidInput::new(
                "upper",
                upper,
                "must be >= lower, with a finite width upper - lower",
            )
            .into());
        }
        Ok(Self { lower, upper })
    }

    /// Smallest admissible value.
    pub fn lower(&self) -> f64 {
        self.lower
    }

    /// Largest admissible value.
    pub fn upper(&self) -> f64 {
        self.upper
    }

    /// Width `upper − lower`.
    pub fn width(&self) -> f64 {
        self.upper - self.lower
    }

    /// `value` moved into the interval.
    pub fn clamp(&self, value: f64) -> f64 {
        value.clamp(self.lower, self.upper)
    }

    /// Whether `value` lies in the interval.
    pub fn contains(&self, value: f64) -> bool {
        (self.lower..=self.upper).contains(&value)
    }

    /// Default relative step $\epsilon$ of a first central difference, of the order of
    /// $\varepsilon_{\mathrm{mach}}^{1/3} \approx 6\cdot10^{-6}$, where the $O(h^2)$ truncation
    /// and the $O(\varepsilon_{\mathrm{mach}}/h)$ rounding balance. The one default of every
    /// finite difference in pkm (`pkm_optimizers::finite_differences::RELATIVE_STEP`).
    pub const DEFAULT_RELATIVE_STEP: f64 = 1e-6;

    /// Smallest width used to scale a step, so that a zero-width interval still gets a positive
    /// step.
    pub const MIN_DIFFERENCE_WIDTH: f64 = 1e-8;

    /// The two points `(x + h, x − h)` of a central difference at `x`, with
    /// $h$ = `relative_step` × max(width, [`Bounds::MIN_DIFFERENCE_WIDTH`]), each clamped into the interval: one-sided at a
    /// bound, and equal for a variable fixed by `lower = upper` (whose difference is then 0).
    ///
    /// ```
    /// use pkm_traits::Bounds;
    /// let b = Bounds::new(0.0, 2.0).unwrap();
    /// assert_eq!(b.difference_points(1.0, 0.25), (1.5, 0.5));
    /// assert_eq!(b.difference_points(2.0, 0.25), (2.0, 1.5));
    /// ```
    pub fn difference_points(&self, x: f64, relative_step: f64) -> (f64, f64) {
        let h = relative_step * self.width().max(Self::MIN_DIFFERENCE_WIDTH);
        (self.clamp(x + h), self.clamp(x - h))
    }
}

/// A scalar objective $f(p)$ to minimise over a box.
pub trait Objective: Sync {
    /// Number of design variables.
    fn dimension(&self) -> usize;

    /// The box of admissible designs, one [`Bounds`] per variable.
    fn bounds(&self) -> &[Bounds];

    /// $f(p)$, to be minimised.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for designs outside the feasible set (recorded by searches,
    /// not fatal); [`ObjectiveError::Dimension`] for a design of the wrong length.
    fn value(&self, design: &[f64]) -> Result<f64, ObjectiveError>;

    /// Checks the length of `design`.
    ///
    /// # Errors
    /// [`ObjectiveError::Dimension`] when it differs from [`Objective::dimension`].
    fn check_dimension(&self, design: &[f64]) -> Result<(), ObjectiveError> {
        if design.len() == self.dimension() {
            Ok(())
        } else {
            Err(ObjectiveError::Dimension {
                expected: self.dimension(),
                got: design.len(),
            })
        }
    }
}

/// A least-squares objective $f(p) = \sum_i r_i(p)^2$, for Gauss–Newton and
/// Levenberg–Marquardt.
pub trait Residuals: Objective {
    /// Number of residuals $r_i$.
    fn n_residuals(&self) -> usize;

    /// Writes $r(p)$ into `r` (length [`Residuals::n_residuals`]).
    ///
    /// # Errors
    /// As [`Objective::value`].
    fn residuals(&self, design: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError>;

    /// $f(p) = \sum_i r_i(p)^2$ from [`Residuals::residuals`], summed in order: what
    /// [`Objective::value`] of a least-squares problem returns, so an implementation writes
    /// `fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> { self.sum_of_squares(p) }`.
    ///
    /// # Errors
    /// As [`Residuals::residuals`].
    fn sum_of_squares(&self, design: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = vec![0.0; self.n_residuals()];
        self.residuals(design, &mut r)?;
        Ok(r.iter().map(|x| x * x).sum())
    }

    /// Writes $r(p)$ into `r` and, when the problem provides it, the Jacobian
    /// $A_{ij} = \partial r_i / \partial p_j$ into `jacobian`, row-major
    /// ([`Residuals::n_residuals`] rows × [`Objective::dimension`] columns, $A_{ij}$ at
    /// `i * dimension + j`), and returns `Ok(true)`.
    ///
    /// The default returns `Ok(false)` ("not provided") and leaves both buffers untouched; the
    /// optimisers then use finite differences of [`Residuals::residuals`]. An implementation must
    /// write the same `r` as [`Residuals::residuals`].
    ///
    /// # Errors
    /// As [`Objective::value`]; [`ObjectiveError::Dimension`] for buffers of the wrong length.
    fn residual_jacobian(
        &self,
        design: &[f64],
        r: &mut [f64],
        jacobian: &mut [f64],
    ) -> Result<bool, ObjectiveError> {
        let _ = (design, r, jacobian);
        Ok(false)
    }
}

/// Inequality constraints $g(p) \le 0$ (in addition to the bounds).
pub trait Constraints: Objective {
    /// Number of inequality constraints.
    fn n_constraints(&self) -> usize;

    /// Writes $g(p)$ into `g` (length [`Constraints::n_constraints`]); the design is feasible
    /// when every entry is $\le 0$.
    ///
    /// # Errors
    /// As [`Objective::value`].
    fn inequalities(&self, design: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError>;
}
