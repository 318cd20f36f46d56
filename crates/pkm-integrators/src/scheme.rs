//! What the [`crate::integrate`] driver needs from a method beyond one step.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, Integrator, VectorField};

use crate::DenseSegment;

/// Step budget of the fixed-step methods ([`crate::Rk4`], [`crate::ImplicitMidpoint`]) unless
/// set otherwise: a run that would need more steps is refused before it starts, so a tiny step
/// cannot turn into a hang.
pub const DEFAULT_MAX_FIXED_STEPS: usize = 100_000_000;

/// The first step of a run and what choosing it cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    /// Step size to try first (positive).
    pub h: f64,
    /// Right-hand-side evaluations spent choosing it.
    pub evaluations: usize,
}

/// An [`Integrator`] that the [`crate::integrate`] driver can run over an interval.
pub trait Scheme<const M: usize>: Integrator<M> {
    /// Resets per-run state and chooses the first step for a run from `(t0, z0)` to `t1 > t0`.
    ///
    /// # Errors
    /// [`IntegrationError`] when the vector field fails at the start or a setting does not fit
    /// the interval.
    fn start<F: VectorField<M> + ?Sized>(
        &mut self,
        field: &F,
        t0: f64,
        z0: &SVector<f64, M>,
        t1: f64,
    ) -> Result<Start, IntegrationError>;

    /// Largest number of accepted steps a run may take.
    fn max_steps(&self) -> usize {
        usize::MAX
    }

    /// `true` when [`Scheme::dense_output`] is available after every accepted step.
    fn has_dense_output(&self) -> bool {
        false
    }

    /// Continuous extension over the last accepted step, or `None` for methods without one
    /// (the driver then shortens steps to land on every output time).
    fn dense_output(&self) -> Option<&DenseSegment<M>> {
        None
    }
}
