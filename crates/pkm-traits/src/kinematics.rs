//! Closed-chain kinematics: loop closure, its Jacobians, inverse and forward kinematics.
//!
//! A parallel mechanism with task coordinates $x \in \mathbb{R}^{NX}$ and actuated joint
//! coordinates $q \in \mathbb{R}^{NQ}$ is described by its loop-closure equations, one row per leg,
//!
//! $$ \Phi(x, q) = 0, \qquad J_x = \frac{\partial \Phi}{\partial x}, \qquad
//!    J_q = \frac{\partial \Phi}{\partial q}. $$
//!
//! Differentiating along a motion gives $J_x \dot x + J_q \dot q = 0$, hence the velocity relation
//! $\dot q = J \dot x$ with $J = -J_q^{-1} J_x$ (the convention of every `jacobian` in pkm; each
//! paper's own sign convention is mapped onto it in `docs/conventions.md`).

use crate::error::{InvalidInput, KinematicsError};
use nalgebra::{SMatrix, SVector};
use std::fmt::Debug;

/// Task coordinates $x$ (platform position, or pose), length `NX`.
pub type Task<const NX: usize> = SVector<f64, NX>;
/// Actuated joint coordinates $q$, length `NQ`.
pub type Joints<const NQ: usize> = SVector<f64, NQ>;

/// Loop-closure model $\Phi(x, q) = 0$ of a closed-chain mechanism, one row per leg.
pub trait ClosedChain<const NX: usize, const NQ: usize> {
    /// The residual $\Phi(x, q)$; zero exactly on assembled configurations.
    fn closure(&self, x: &Task<NX>, q: &Joints<NQ>) -> Joints<NQ>;

    /// $J_x = \partial \Phi / \partial x$, `NQ × NX`.
    fn jacobian_x(&self, x: &Task<NX>, q: &Joints<NQ>) -> SMatrix<f64, NQ, NX>;

    /// $J_q = \partial \Phi / \partial q$, `NQ × NQ`.
    fn jacobian_q(&self, x: &Task<NX>, q: &Joints<NQ>) -> SMatrix<f64, NQ, NQ>;

    /// The velocity Jacobian $J = -J_q^{-1} J_x$, so that $\dot q = J \dot x$.
    ///
    /// # Errors
    /// [`KinematicsError::Singular`] when $J_q$ cannot be inverted (an inverse-kinematic
    /// singularity: a leg is stretched out or folded) or $J$ is not finite;
    /// [`KinematicsError::NonFinite`] for a non-finite `x` or `q`.
    fn jacobian(
        &self,
        x: &Task<NX>,
        q: &Joints<NQ>,
    ) -> Result<SMatrix<f64, NQ, NX>, KinematicsError> {
        require_finite("x", x.iter())?;
        require_finite("q", q.iter())?;
        let singular = KinematicsError::Singular {
            matrix: "J_q",
            sigma_min: 0.0,
        };
        let j_q_inv = self
            .jacobian_q(x, q)
            .try_inverse()
            .ok_or(singular.clone())?;
        let j = -(j_q_inv * self.jacobian_x(x, q));
        // A NaN or an overflow in J_q, J_x or the inverse is a (numerically) singular J_q here.
        if j.iter().all(|v| v.is_finite()) {
            Ok(j)
        } else {
            Err(singular)
        }
    }
}

/// Closed-form inverse kinematics $q = \mathrm{IK}(x)$ for one working mode.
pub trait InverseKinematics<const NX: usize, const NQ: usize>: ClosedChain<NX, NQ> {
    /// Which branch each leg takes (elbow out/in, ...); documented per mechanism in
    /// `docs/conventions.md`.
    type WorkingMode: Copy + Debug + Send + Sync;

    /// The joint coordinates that assemble the mechanism at `x` in `mode`.
    ///
    /// # Errors
    /// [`KinematicsError::Unreachable`] when a leg cannot reach `x`;
    /// [`KinematicsError::NonFinite`] for NaN or infinite input.
    fn inverse_kinematics(
        &self,
        x: &Task<NX>,
        mode: Self::WorkingMode,
    ) -> Result<Joints<NQ>, KinematicsError>;

    /// The velocity Jacobian $J = -J_q^{-1} J_x$ at the pose `x` assembled in `mode`, so that
    /// $\dot q = J \dot x$: the one entry point of every index that needs $J$ at a pose.
    ///
    /// The default solves the inverse kinematics and calls [`ClosedChain::jacobian`]; a
    /// mechanism with a closed form of $J$ (no $J_q^{-1}$, fewer square roots) overrides it,
    /// and its tests check the override against this default.
    ///
    /// # Errors
    /// As [`InverseKinematics::inverse_kinematics`] where `x` does not assemble in `mode`
    /// ([`KinematicsError::Unreachable`], [`KinematicsError::NonFinite`]);
    /// [`KinematicsError::Singular`] where it assembles but $J$ is not defined (an
    /// inverse-kinematic singularity: $J_q$ singular or $J$ not finite).
    fn velocity_jacobian_at(
        &self,
        x: &Task<NX>,
        mode: Self::WorkingMode,
    ) -> Result<SMatrix<f64, NQ, NX>, KinematicsError> {
        let q = self.inverse_kinematics(x, mode)?;
        self.jacobian(x, &q)
    }
}

/// Forward kinematics of a non-redundant mechanism ($NX = NQ$): the task coordinates that close
/// the loops for given joints. The assembly mode is selected by the starting guess.
pub trait ForwardKinematics<const N: usize>: ClosedChain<N, N> {
    /// Solves $\Phi(x, q) = 0$ for $x$ from `guess`. The default is Newton's method
    /// ([`newton_forward_kinematics`]); a mechanism may override it with a closed form.
    ///
    /// # Errors
    /// [`KinematicsError::NotConverged`] or [`KinematicsError::Singular`] (a direct-kinematic
    /// singularity, $J_x$ singular).
    fn forward_kinematics(
        &self,
        q: &Joints<N>,
        guess: &Task<N>,
        settings: &NewtonSettings,
    ) -> Result<Task<N>, KinematicsError> {
        newton_forward_kinematics(self, q, guess, settings)
    }
}

/// Settings of Newton's method for forward kinematics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Stop when $\|\Phi\|_\infty$ falls below this. Default 1e-12: well below the 1e-9 pose
    /// tolerance that the conformance tests use, and above the round-off of $\Phi$ for
    /// metre-sized machines.
    pub tolerance: f64,
    /// Give up after this many iterations. Default 50: Newton converges quadratically in under
    /// 10 from any guess inside the basin of the assembly mode.
    pub max_iterations: usize,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            max_iterations: 50,
        }
    }
}

/// Newton's method on $\Phi(\cdot, q) = 0$: $x_{k+1} = x_k - J_x^{-1} \Phi(x_k, q)$.
///
/// # Errors
/// [`KinematicsError::NonFinite`] for a non-finite `q` or `guess`,
/// [`KinematicsError::InvalidInput`] for a tolerance that is not finite and positive,
/// [`KinematicsError::Singular`] when
/// $J_x$ cannot be inverted at an iterate, [`KinematicsError::NotConverged`] when the residual
/// stays above the tolerance after `max_iterations`, or stagnates (no new best residual in 32
/// iterations: a tolerance below round-off ends by itself, whatever the iteration limit).
pub fn newton_forward_kinematics<M, const N: usize>(
    mechanism: &M,
    q: &Joints<N>,
    guess: &Task<N>,
    settings: &NewtonSettings,
) -> Result<Task<N>, KinematicsError>
where
    M: ClosedChain<N, N> + ?Sized,
{
    require_finite("q", q.iter())?;
    require_finite("guess", guess.iter())?;
    InvalidInput::require_positive("tolerance", settings.tolerance)?;
    let mut x = *guess;
    let mut residual = f64::INFINITY;
    let mut stagnation = Stagnation::default();
    let mut iterations = 0;
    while iterations < settings.max_iterations {
        let phi = mechanism.closure(&x, q);
        residual = phi.amax();
        if !residual.is_finite() {
            break;
        }
        if residual < settings.tolerance {
            return Ok(x);
        }
        if stagnation.stalled(residual) {
            break;
        }
        let j_x_inv =
            mechanism
                .jacobian_x(&x, q)
                .try_inverse()
                .ok_or(KinematicsError::Singular {
                    matrix: "J_x",
                    sigma_min: 0.0,
                })?;
        x -= j_x_inv * phi;
        iterations += 1;
    }
    if !x.iter().all(|v| v.is_finite()) {
        residual = f64::INFINITY;
    }
    Err(KinematicsError::NotConverged {
        iterations,
        residual,
    })
}

/// Newton's stagnation test: the residual has not fallen below its best for
/// [`Stagnation::WINDOW`] = 32 iterations in a row (a tolerance below the round-off of $\Phi$, or a
/// cycle), so more iterations cannot help. Newton improves at every step inside its basin, and
/// 32 steps without a new best is beyond the wandering of a run that then converges within the
/// default 50 iterations.
#[derive(Debug)]
struct Stagnation {
    best: f64,
    without_progress: usize,
}

impl Default for Stagnation {
    fn default() -> Self {
        Self {
            best: f64::INFINITY,
            without_progress: 0,
        }
    }
}

impl Stagnation {
    const WINDOW: usize = 32;

    fn stalled(&mut self, residual: f64) -> bool {
        if residual < self.best {
            self.best = residual;
            self.without_progress = 0;
        } else {
            self.without_progress += 1;
        }
        self.without_progress >= Self::WINDOW
    }
}

/// `Err(NonFinite { what, value })` for the first NaN or infinite entry of `values`.
fn require_finite<'a>(
    what: &'static str,
    mut values: impl Iterator<Item = &'a f64>,
) -> Result<(), KinematicsError> {
    match values.find(|v| !v.is_finite()) {
        Some(&value) => Err(KinematicsError::NonFinite { what, value }),
        None => Ok(()),
    }
}
