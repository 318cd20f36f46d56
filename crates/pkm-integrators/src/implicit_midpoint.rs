//! The implicit midpoint rule, symplectic and of order 2.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, Integrator, InvalidInput, StepReport, VectorField};

use crate::{DEFAULT_MAX_FIXED_STEPS, Scheme, Start, require_finite_state};

/// The implicit midpoint rule with a fixed step,
/// $$ z_1 = z_0 + h\, f\!\left(t_0 + \tfrac h2,\ \tfrac{z_0 + z_1}{2}\right), $$
/// the one-stage Gauss collocation method (Hairer, Lubich & Wanner, *Geometric Numerical
/// Integration*, 2nd ed., §I.1 and §VI.3). It is symplectic for every Hamiltonian system,
/// separable or not, conserves quadratic invariants exactly (up to the stage solve) and keeps the
/// energy error bounded over exponentially long times; it is symmetric, so a step with $-h$
/// undoes a step with $h$.
///
/// The stage $k = f(t_0 + h/2,\ z_0 + \tfrac h2 k)$ is solved by fixed-point iteration from the
/// explicit Euler predictor $k = f(t_0, z_0)$, until the stage point moves by at most
/// `tolerance · max(1, ‖z_0‖_∞)` in the max norm. This converges when $\tfrac{|h|}{2} L < 1$ for
/// a Lipschitz constant $L$ of $f$, i.e. for steps well below the fastest time scale: the regime
/// of accurate conservative runs (a 1 ms step on a robot whose eigenfrequencies are below
/// ~100 Hz). Defaults: `tolerance = 1e-13` (a few hundred ulps of an O(1) state, so quadratic
/// invariants drift by round-off only), `max_iterations = 50`.
///
/// # Example
/// ```
/// use pkm_integrators::{ImplicitMidpoint, test_problems::HarmonicOscillator};
/// use pkm_traits::Integrator;
/// let oscillator = HarmonicOscillator::new(1.0)?;
/// let mut z = oscillator.initial_state();
/// let e0 = oscillator.energy(&z);
/// let mut midpoint = ImplicitMidpoint::new(0.1)?;
/// for i in 0..1000 {
///     midpoint.step(&oscillator, 0.1 * f64::from(i), &mut z, 0.1)?;
/// }
/// assert!((oscillator.energy(&z) - e0).abs() < 1e-10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImplicitMidpoint {
    h: f64,
    tolerance: f64,
    max_iterations: usize,
    max_steps: usize,
}

impl ImplicitMidpoint {
    /// Implicit midpoint with step size `h` for the driver and default stage-solver settings.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless `h` is finite and `> 0`.
    pub fn new(h: f64) -> Result<Self, IntegrationError> {
        Ok(Self {
            h: InvalidInput::require_positive("h", h)?,
            tolerance: 1e-13,
            max_iterations: 50,
            max_steps: DEFAULT_MAX_FIXED_STEPS,
        })
    }

    /// Budget of steps per run (default [`DEFAULT_MAX_FIXED_STEPS`]): the driver refuses a run
    /// that needs more before it starts.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] when 0.
    pub fn with_max_steps(self, max_steps: usize) -> Result<Self, IntegrationError> {
        Ok(Self {
            max_steps: InvalidInput::require_nonzero_count("max_steps", max_steps)?,
            ..self
        })
    }

    /// Stopping tolerance of the fixed-point stage solve (relative to `max(1, ‖z‖_∞)`).
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless finite and `> 0`.
    pub fn with_tolerance(self, tolerance: f64) -> Result<Self, IntegrationError> {
        Ok(Self {
            tolerance: InvalidInput::require_positive("tolerance", tolerance)?,
            ..self
        })
    }

    /// Iteration budget of the stage solve.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] when 0.
    pub fn with_max_iterations(self, max_iterations: usize) -> Result<Self, IntegrationError> {
        InvalidInput::require_nonzero_count("max_iterations", max_iterations)?;
        Ok(Self {
            max_iterations,
            ..self
        })
    }

    /// The step size the driver uses.
    pub fn step_size(&self) -> f64 {
        self.h
    }
    /// Stopping tolerance of the stage solve.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }
    /// Iteration budget of the stage solve.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }
}

impl<const M: usize> Integrator<M> for ImplicitMidpoint {
    /// One implicit midpoint step of size `h` (negative `h` integrates backwards).
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] for a zero or non-finite `h` or `t`;
    /// [`IntegrationError::Rhs`] when the field fails, [`IntegrationError::NonFinite`] when the
    /// state or a stage is not finite, [`IntegrationError::NotConverged`] when the stage solve
    /// exceeds its iteration budget (reduce `h`).
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
        let t_mid = t + half;
        let threshold = self.tolerance * z.amax().max(1.0);
        let mut k = SVector::zeros();
        field.rhs(t, z, &mut k)?;
        let mut k_next = SVector::zeros();
        let mut residual = f64::INFINITY;
        for iteration in 1..=self.max_iterations {
            field.rhs(t_mid, &(*z + k * half), &mut k_next)?;
            require_finite_state(t_mid, &k_next)?;
            residual = (k_next - k).amax() * half.abs();
            k = k_next;
            if residual <= threshold {
                *z += k * h;
                return Ok(StepReport {
                    h_taken: h,
                    h_next: self.h,
                    error_estimate: 0.0,
                    evaluations: iteration + 1,
                    rejections: 0,
                });
            }
        }
        Err(IntegrationError::NotConverged {
            t,
            iterations: self.max_iterations,
            residual,
        })
    }
}

impl<const M: usize> Scheme<M> for ImplicitMidpoint {
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
