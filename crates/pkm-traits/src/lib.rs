//! Shared vocabulary of pkm.
//!
//! This crate holds traits and error types only; algorithms live in the crates that own them
//! (see `docs/ARCHITECTURE.md`). Everything is `f64`, and hot paths use fixed-size nalgebra types.
//!
//! | module | what it names |
//! |---|---|
//! | [`kinematics`] | closed-chain loop closure $\Phi(x, q) = 0$, $J_x$, $J_q$, inverse and forward kinematics |
//! | [`objective`] | objectives, residuals and inequality constraints for optimisers |
//! | [`dynamics`] | vector fields $\dot z = f(t, z)$, integrator steps, extended-space inertia models |
//! | [`region`] | planar regions by vertical slices, and mechanisms whose workspace is such a cross-section |
//! | [`workspace`] | workspace constraints (half-spaces, joint ranges, cone limits, clearance) |
//! | [`progress`] | progress reporting and cooperative cancellation |
//! | [`error`] | typed errors that carry the offending numbers |
//! | [`checked`] | NaN- and overflow-safe checks, the memory budget |
//!
//! With the `testkit` feature, the `testkit` module provides the conformance checks that every mechanism
//! passes in its tests.
//!
//! # Example
//! ```
//! use pkm_traits::{ClosedChain, Joints, Task};
//! use nalgebra::{SMatrix, Vector1};
//!
//! /// A prismatic actuator that tracks x directly: Φ(x, q) = q − x.
//! struct Slider;
//! impl ClosedChain<1, 1> for Slider {
//!     fn closure(&self, x: &Task<1>, q: &Joints<1>) -> Joints<1> { q - x }
//!     fn jacobian_x(&self, _: &Task<1>, _: &Joints<1>) -> SMatrix<f64, 1, 1> { SMatrix::identity() * -1.0 }
//!     fn jacobian_q(&self, _: &Task<1>, _: &Joints<1>) -> SMatrix<f64, 1, 1> { SMatrix::identity() }
//! }
//! let j = Slider.jacobian(&Vector1::new(0.3), &Vector1::new(0.3)).unwrap();
//! assert!((j[(0, 0)] - 1.0).abs() < 1e-15);
//! ```
// docs.rs (nightly, `--cfg docsrs`) marks the `testkit` items with the feature they need.
#![cfg_attr(docsrs, feature(doc_cfg))]

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

pub mod checked;
pub mod dynamics;
pub mod error;
pub mod kinematics;
pub mod lanes;
pub mod objective;
pub mod progress;
pub mod region;
#[cfg(feature = "testkit")]
pub mod testkit;
pub mod vector_path;
pub mod workspace;

pub use checked::MEMORY_BUDGET_BYTES;
pub use dynamics::{IntegrationError, Integrator, RhsError, StepReport, VectorField};
pub use error::{DesignError, InfeasibleCause, InvalidInput, KinematicsError, ObjectiveError};
pub use kinematics::{
    ClosedChain, ForwardKinematics, InverseKinematics, Joints, NewtonSettings, Task,
    newton_forward_kinematics,
};
pub use lanes::{JacobianLanes, Lanes};
pub use objective::{Bounds, Constraints, Objective, Residuals};
pub use progress::{CancelOnly, Cancelled, Progress, Silent};
pub use region::{CrossSectionWorkspace, Extents, SlicedRegion};
pub use vector_path::{BlockKernel, VECTOR_PATH_VARIABLE, VectorPath, run_block, run_block_on};
pub use workspace::{
    ConstrainedWorkspace, ConstraintError, ConstraintKind, PLATFORM_LINK_CLEARANCE_SPAN,
    WorkspaceConstraint, links_distance, segment_distance,
};
