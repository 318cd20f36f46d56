//! Hamilton's canonical equations in the extended space $s = (x, q)$ of task and joint
//! coordinates (Miller 2004, §3), with Baumgarte stabilisation, and the acceleration-based
//! Lagrange formulation in the same coordinates for comparison.
//!
//! | module | what |
//! |---|---|
//! | [`trajectory`] | motion laws × path shapes (§3.5), Miller's cycle in [`trajectory::presets`] |
//! | [`mass`] | the mass model of the rotary Delta family (rod or lumped forearms) |
//! | [`model`] | $M(q)$, $L_q$, $\Phi$, $\Phi_q$, $\dot\Phi_q$ in $q = (x, y, z, \theta_1, \theta_2, \theta_3)$ |
//! | [`inverse`] | inverse dynamics: Hamilton's three steps (§3.3) and Lagrange, from a trajectory or from sampled positions |
//! | [`forward`] | forward dynamics: eqs. 16–19 with Baumgarte, the acceleration form, and the retrace with drift and energy balance |

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod error;
pub mod forward;
pub mod inverse;
mod kernel;
pub mod mass;
pub mod model;
pub mod trajectory;

pub use error::{ConfigurationError, DynamicsError};
pub use mass::{ForearmModel, MassParameters};
pub use model::{Configuration, ExtendedModel, ExtendedState};
