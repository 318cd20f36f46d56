//! Time integrators for $\dot z = f(t, z)$ implementing [`pkm_traits::Integrator`]: classical
//! RK4, the embedded Dormand–Prince 5(4) pair with step-size control and dense output (MATLAB's
//! `ode45`, which Miller 2004 used), and a symplectic method for long conservative runs.
#![warn(missing_docs)]
