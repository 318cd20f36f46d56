//! Forward dynamics of the rotary Delta family as vector fields for any pkm integrator.
//!
//! **Hamilton form** (Miller 2004 eqs. 16–19), state $z = (q, p, W)$ with the momenta $p$ and
//! the motor work $W$: at each evaluation solve
//! $$ \begin{pmatrix} M & \Phi_q^\top \\ \Phi_q & 0 \end{pmatrix}
//!    \begin{pmatrix} \dot q \\ -\sigma \end{pmatrix} =
//!    \begin{pmatrix} p \\ -\kappa\Phi \end{pmatrix} $$
//! ($\kappa = 0$ is eq. 19; $\kappa > 0$ is velocity-level Baumgarte, $\dot\Phi + \kappa\Phi = 0$),
//! then $\dot p = L_q + Q - \dot\Phi_q^\top\sigma$ (eq. 17), $Q = (0, 0, 0, \tau(t))$,
//! $\dot W = \tau\cdot\dot\theta$.
//!
//! **Acceleration form** (index 3 reduced to 1), state $z = (q, \dot q, W)$:
//! $$ \begin{pmatrix} M & \Phi_q^\top \\ \Phi_q & 0 \end{pmatrix}
//!    \begin{pmatrix} \ddot q \\ \lambda \end{pmatrix} =
//!    \begin{pmatrix} L_q + Q - \dot M\dot q \\ -\gamma - 2\omega\Phi_q\dot q - \omega^2\Phi \end{pmatrix}. $$
//!
//! Both saddle-point systems are solved through a 3×3 Schur complement (module `saddle`), never
//! as a dense 9×9 system.
//!
//! Both carry $W$ so that the energy balance $E(t) - E(0) - W(t)$ is known to the integrator's
//! tolerance. [`retrace`] runs a form with any `pkm_integrators` scheme and samples it with
//! these diagnostics; [`retrace_sampled`] feeds the Hamilton form with the torques of an
//! inverse-dynamics run (the retrace of Fig. 9).

mod fields;
mod retrace;
mod saddle;
mod torque;

pub use fields::{AccelerationForm, ForwardForm, HamiltonForm, SADDLE_MATRIX};
pub use retrace::{Retrace, retrace, retrace_sampled};
pub use torque::SampledTorques;
