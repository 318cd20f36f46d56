//! Design optimisers. They see only the [`pkm_traits::Objective`] family of traits, never a
//! mechanism.
//!
//! One set of rules holds for every solver:
//! - *Direction.* Every solver takes a [`Sense`] (minimise or maximise); an objective is never
//!   negated to be maximised (Levenberg–Marquardt maximises $\lVert r \rVert^2$, which no
//!   negation of residuals can express).
//! - *Settings.* Counts, seeds and switches come in settings structs ([`LmSettings`],
//!   [`Multistart`], [`GridSearch`], [`RefinementSettings`], [`AugmentedLagrangianSettings`],
//!   [`kkt::KktSettings`]), each with a `validate` (or a checked constructor) that refuses NaN,
//!   infinite, zero, negative and oversized values with [`OptimizeError::Invalid`]. They are
//!   serde types with snake_case keys, unknown keys refused and every key with a default
//!   optional, so a study file embeds them as they are (e.g. `[optimize.solver]`,
//!   `[optimize.starts]`).
//! - *Progress and cancellation.* Every solver takes a [`pkm_traits::Progress`], reports its
//!   work through it and checks [`pkm_traits::Progress::is_cancelled`] at least once per
//!   iteration (or per evaluation). A cancelled run returns [`OptimizeError::Cancelled`], never
//!   a partial result, so `?` carries a Ctrl-C through a whole study.
//! - *Why it stopped.* The result of every solver carries a [`Termination`] and its counts
//!   (iterations and evaluations; nodes for the grid searches).
//! - *The best of many.* Whatever compares values in order (the starts of a multistart, the
//!   nodes of a grid) picks its best by [`Sense::best`]: NaN never best, a tie to the first, so
//!   no result depends on the thread count.
//! - *Derivatives.* Every finite difference goes through [`finite_differences`].
//! - *Scaling.* The local solvers (Levenberg–Marquardt, the augmented Lagrangian and its
//!   spectral projected gradient) iterate in the scaled variables $z_j = x_j / s_j$ of
//!   [`scaling`], $s_j$ the width of variable $j$'s box side or a user-given
//!   [`CharacteristicScale`] (the settings' `scale`); their stopping tolerances are in scaled
//!   units and their results in the user's variables. Variables that differ by $10^6$ in scale
//!   then converge alike (tests `tests/it/scaling.rs`).
//!
//! The solvers and tools:
//! - [`grid_search`] and [`refined_grid_search`]: exhaustive N-dimensional grid search, parallel
//!   and deterministic, with the whole landscape on request and coarse-to-fine refinement
//!   (Miller 2004 §2.2's 4-D search); [`GridSearch::evaluate_range`] evaluates any part of a
//!   grid (a shard of a study split over several runs).
//! - [`levenberg_marquardt`] and [`augmented_lagrangian`]: local solvers whose results say why
//!   they stopped ([`Termination`]: converged and by which test, iteration limit, or stalled).
//! - [`compass_search`]: a derivative-free local search (Kolda, Lewis & Torczon 2003) for
//!   objectives that cannot be differenced, such as Monte Carlo estimates on common random
//!   numbers.
//! - [`multistart`]: any local solver from the seeded starts of a [`Multistart`], in parallel,
//!   keeping every start's outcome ([`MultistartRun`]); [`multistart_levenberg_marquardt`] is
//!   its best for Levenberg–Marquardt.
//! - [`kkt::check`]: first- and second-order optimality at a design of any constrained problem.
//! - [`pareto_front`]: the non-dominated designs of two or more objectives, and for two the
//!   weights that select each.
//! - [`WeightedSum`]: least-squares problems over the same variables, weighted and stacked.

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod augmented_lagrangian;
mod compass_search;
mod error;
pub mod finite_differences;
mod grid_axis;
mod grid_search;
pub mod kkt;
mod lattice_refinement;
mod levenberg_marquardt;
mod multistart;
mod pareto;
pub mod scaling;
mod sense;
mod spg;
mod termination;
mod weighted_combination;
mod weighted_sum;

pub use augmented_lagrangian::{
    AugmentedLagrangianSettings, ConstrainedResult, FIRST_VIOLATION_TARGET, INITIAL_PENALTY,
    MAX_PENALTY, MAX_STALLED_OUTER, MULTIPLIER_TOLERANCE, PENALTY_GROWTH,
    REQUIRED_VIOLATION_DECREASE, STALL_DECREASE, augmented_lagrangian,
};
pub use compass_search::{CompassResult, CompassSettings, compass_search};
pub use error::OptimizeError;
pub use grid_axis::GridAxis;
pub use grid_search::{
    GridResult, GridSearch, Landscape, MAX_GRID_NODES, RefinementSettings, grid_search,
    refined_grid_search,
};
pub use lattice_refinement::{
    LatticeLevel, lattice_refine_from, lattice_refined_search, lattice_window,
};
pub use levenberg_marquardt::{
    ActiveBound, BOUND_TOLERANCE, DAMPING_DECREASE, DAMPING_INCREASE, INITIAL_DAMPING_SCALE,
    LmSettings, LocalOptimum, MAX_DAMPING, MIN_NORMAL_DIAGONAL, MultistartOptimum,
    levenberg_marquardt, multistart_levenberg_marquardt,
};
pub use multistart::{
    LocalResult, MAX_STARTS, Multistart, MultistartRun, multistart, uniform_start_points,
};
pub use pareto::{ParetoFront, pareto_front};
pub use scaling::{CharacteristicScale, variable_scales};
pub use sense::Sense;
pub use termination::Termination;
pub use weighted_combination::weighted_combination;
pub use weighted_sum::WeightedSum;
