//! Design optimisers. They see only the [`pkm_traits::Objective`] family of traits, never a
//! mechanism, and every objective is minimised (maximisation negates).
//!
//! - [`grid_search`] and [`refined_grid_search`]: exhaustive N-dimensional grid search, parallel
//!   and deterministic, with the whole landscape on request and coarse-to-fine refinement
//!   (Miller 2004 §2.2's 4-D search).
//! - [`uniform_start_points`] and [`run_multistart`]: seeded starts for local optimisers, run in
//!   parallel with outcomes in start order.
//! - [`levenberg_marquardt`] and [`augmented_lagrangian`]: local solvers whose results say why
//!   they stopped ([`Termination`]: converged and by which test, iteration limit, or stalled).
#![warn(missing_docs)]

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod augmented_lagrangian;
mod error;
mod grid_search;
mod lattice_refinement;
mod levenberg_marquardt;
mod multistart;
mod spg;
mod termination;
mod weighted_combination;

pub use augmented_lagrangian::{
    AugmentedLagrangianSettings, ConstrainedResult, augmented_lagrangian,
};
pub use error::OptimizeError;
pub use grid_search::{
    GridAxis, GridResult, Landscape, MAX_GRID_NODES, RefinementSettings, grid_search,
    refined_grid_search,
};
pub use lattice_refinement::{LatticeLevel, lattice_refined_search, lattice_window};
pub use levenberg_marquardt::{
    ActiveBound, LmSettings, LocalOptimum, Sense, levenberg_marquardt,
    multistart_levenberg_marquardt,
};
pub use multistart::{MAX_STARTS, run_multistart, uniform_start_points};
pub use termination::Termination;
pub use weighted_combination::{WeightedMean, weighted_combination};
