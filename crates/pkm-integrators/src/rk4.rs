//! The classical fourth-order Runge–Kutta method.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, Integrator, InvalidInput, StepReport, VectorField};

use crate::{DEFAULT_MAX_FIXED_STEPS, Scheme, Start, require_finite_state};

/// Classical Runge–Kutta method of order 4 with a fixed step (Hairer, Nørsett & Wanner,
/// *Solving ODEs I*, §II.1, Table 1.2, "the" Runge–Kutta method):
/// $$ \begin{array}{c|cccc} 0 \\\\ \tfrac12 & \tfrac12 \\\\ \tfrac12 & 0 & \tfrac12 \\\\ 1 & 0 & 0 & 1 \\\\ \hline
/// & \tfrac16 & \tfrac13 & \tfrac13 & \tfrac16 \end{array} $$
///
/// [`Integrator::step`] takes the step it is given (4 evaluations, no error estimate);
/// [`crate::integrate`] runs it with the step size of [`Rk4::new`] and shortens a step only to
/// land on an output time.
///
/// # Example
/// ```
/// use pkm_integrators::{Rk4, test_problems::ExponentialDecay};
/// use pkm_traits::Integrator;
/// let decay = ExponentialDecay::new(1.0)?;
/// let mut z = nalgebra::Vector1::new(1.0);
/// Rk4::new(0.1)?.step(&decay, 0.0, &mut z, 0.1)?;
/// assert!((z[0] - (-0.1f64).exp()).abs() < 1e-7);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4 {
    h: f64,
    max_steps: usize,
}

impl Rk4 {
    /// RK4 with step size `h` for the driver and a budget of [`DEFAULT_MAX_FIXED_STEPS`] steps.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless `h` is finite and `> 0`.
    pub fn new(h: f64) -> Result<Self, IntegrationError> {
        Ok(Self {
            h: InvalidInput::require_positive("h", h)?,
            max_steps: DEFAULT_MAX_FIXED_STEPS,
        })
    }

    /// Budget of steps per run: the driver refuses a run that needs more before it starts.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] when 0.
    pub fn with_max_steps(self, max_steps: usize) -> Result<Self, IntegrationError> {
        Ok(Self {
            max_steps: InvalidInput::require_nonzero_count("max_steps", max_steps)?,
            ..self
        })
    }

    /// The step size the driver uses.
    pub fn step_size(&self) -> f64 {
        self.h
    }
}

impl<const M: usize> Integrator<M> for Rk4 {
    /// One RK4 step of size `h` (negative `h` integrates backwards). The report's `h_next` is
    /// the configured step size.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] for a zero or non-finite `h` or `t`;
    /// [`IntegrationError::Rhs`] when the field fails, [`IntegrationError::NonFinite`] when the
    /// state or a stage is not finite.
    fn step<F: VectorField<M> + ?Sized>(
        &mut self,
        field: &F,
        t: f64,
        z: &mut SVector<f64, M>,
        h: f64,
    ) -> Result<StepReport, IntegrationError> {
        crate::require_step(t, h)?;
        require_finite_state(t, z)?;
        let half = 0.5 * h;
        let mut k1 = SVector::zeros();
        let mut k2 = SVector::zeros();
        let mut k3 = SVector::zeros();
        let mut k4 = SVector::zeros();
        field.rhs(t, z, &mut k1)?;
        field.rhs(t + half, &(*z + k1 * half), &mut k2)?;
        field.rhs(t + half, &(*z + k2 * half), &mut k3)?;
        field.rhs(t + h, &(*z + k3 * h), &mut k4)?;
        let z1 = *z + (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0);
        require_finite_state(t + h, &z1)?;
        *z = z1;
        Ok(StepReport {
            h_taken: h,
            h_next: self.h,
            error_estimate: 0.0,
            evaluations: 4,
            rejections: 0,
        })
    }
}

impl<const M: usize> Scheme<M> for Rk4 {
    fn start<F: VectorField<M> + ?Sized>(
        &mut self,
        _field: &F,
        _t0: f64,
        _z0: &SVector<f64, M>,
        _t1: f64,
    ) -> Result<Start, IntegrationError> {
        Ok(Start {
            h: self.h,
            evaluations: 0,
        })
    }

    fn max_steps(&self) -> usize {
        self.max_steps
    }
}
