//! Time integrators for $\dot z = f(t, z)$ implementing [`pkm_traits::Integrator`]: classical
//! RK4, the embedded Dormand–Prince 5(4) pair with step-size control and dense output (MATLAB's
//! `ode45`, which Miller 2004 used), and the symplectic implicit midpoint rule for long
//! conservative runs.
//!
//! | item | what it is |
//! |---|---|
//! | [`Rk4`] | classical fourth-order Runge–Kutta, fixed step |
//! | [`DormandPrince54`] + [`AdaptiveSettings`] | embedded 5(4) pair, error control, dense output |
//! | [`ImplicitMidpoint`] | symplectic, second order, fixed step, stage solved by fixed-point iteration |
//! | [`integrate`] + [`OutputTimes`] | driver that samples a run at requested times: [`Solution`], [`Stats`] |
//! | [`test_problems`] | canonical problems with closed forms, shared by tests and benches |
//!
//! # Example
//! A harmonic oscillator over one period, sampled every 1 ms:
//! ```
//! use pkm_integrators::{AdaptiveSettings, DormandPrince54, OutputTimes, integrate};
//! use pkm_integrators::test_problems::HarmonicOscillator;
//! use pkm_traits::Silent;
//! use std::f64::consts::TAU;
//!
//! let oscillator = HarmonicOscillator::new(TAU)?; // period 1 s
//! let settings = AdaptiveSettings::default().with_rtol(1e-8)?.with_atol(1e-10)?;
//! let mut dopri = DormandPrince54::new(settings);
//! let z0 = oscillator.initial_state();
//! let run = integrate(&oscillator, &mut dopri, (0.0, 1.0), &z0, &OutputTimes::Uniform(1e-3), &Silent)?;
//! assert_eq!(run.times.len(), 1001);
//! let error = (run.states[1000] - oscillator.exact(1.0, &z0)).norm();
//! assert!(error < 1e-6, "error {error:.3e}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Running a 12-state Hamiltonian
//! A [`VectorField<12>`](pkm_traits::VectorField) over $z = (p, x)$ (6 momenta, 6 coordinates)
//! is integrated over a 0.5–1 s cycle and sampled every 1 ms with
//! `integrate(&field, &mut DormandPrince54::<12>::new(settings), (0.0, 0.5), &z0,
//! &OutputTimes::Uniform(1e-3), progress)`: 501 states, interpolated by the dense output, with
//! the [`Stats`] of the run. With [`ImplicitMidpoint::new(1e-3)`](ImplicitMidpoint::new) or
//! [`Rk4::new(1e-3)`](Rk4::new) the same call gives step-aligned samples. Every step works on
//! fixed-size `SVector<f64, 12>` without allocating; only the returned vectors are allocated,
//! once.

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod dense;
mod dormand_prince;
mod driver;
mod implicit_midpoint;
mod output;
mod rk4;
mod scheme;
mod settings;
mod tableau;
pub mod test_problems;

pub use dense::DenseSegment;
pub use dormand_prince::DormandPrince54;
pub use driver::integrate;
pub use implicit_midpoint::ImplicitMidpoint;
pub use output::{MAX_SAMPLES, OutputTimes, Solution, Stats};
pub use rk4::Rk4;
pub use scheme::{DEFAULT_MAX_FIXED_STEPS, Scheme, Start};
pub use settings::AdaptiveSettings;

use nalgebra::SVector;
use pkm_traits::{IntegrationError, InvalidInput};

/// `Err(NonFinite { t })` unless every component of `z` is finite.
fn require_finite_state<const M: usize>(
    t: f64,
    z: &SVector<f64, M>,
) -> Result<(), IntegrationError> {
    if z.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(IntegrationError::NonFinite { t })
    }
}

/// A step of `h` from `t` must be finite, non-zero and move `t` (`t + h != t`); `h < 0`
/// integrates backwards.
fn require_step(t: f64, h: f64) -> Result<(), IntegrationError> {
    if !t.is_finite() {
        return Err(InvalidInput::new("t", t, "must be finite").into());
    }
    let advance = (t + h) - t;
    if !(h.is_finite() && advance.abs() > 0.0) {
        return Err(
            InvalidInput::new("h", h, "must be finite and large enough that t + h != t").into(),
        );
    }
    Ok(())
}
