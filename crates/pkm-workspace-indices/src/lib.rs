//! Workspace and performance indices of parallel mechanisms: samplers, workspace volume with its
//! standard error, local and global condition indices, manipulability and space utilisation.
//!
//! # Generic entry points over the kinematics traits
//!
//! Every index reaches a mechanism through [`pkm_traits::InverseKinematics`] and its velocity
//! Jacobian [`velocity_jacobian_at`](pkm_traits::InverseKinematics::velocity_jacobian_at)
//! (a closed form where the mechanism has one), so the path mechanism → Jacobian → $1/\kappa$ →
//! estimator is written once:
//!
//! | question | entry point |
//! |---|---|
//! | $1/\kappa$ at a pose | [`inverse_condition_at`] |
//! | $1/\kappa$, $\sigma_{\min}$, $\sigma_{\max}$, manipulability $\sqrt{\det JJ^\top}$ at a pose | [`local_indices`] |
//! | volume $W$, $\eta = \int 1/\kappa\,dW$ and GCI $= \eta/W$ over a [`Domain`] | [`Workspace::volume`], [`Workspace::volume_and_eta`], [`VolumeEstimate::gci`] |
//! | the same on unit points scaled per design (Stamper's hemisphere) | [`Workspace::hemisphere_estimate`], [`HemisphereEstimate::gci`] |
//! | $1/\kappa$ on a coordinate plane $x$, $y$ or $z = c$ | [`Workspace::inverse_condition_slice`] |
//! | $\eta_1$, $\eta_2$ and the area of a workspace cross-section (Miller 2004, eqs. 1–2) | [`SectionIndices`], cached per exact design by [`SectionIndexCache`] |
//!
//! ```
//! use nalgebra::Vector3;
//! use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
//! use pkm_traits::Silent;
//! use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, Workspace, local_indices};
//! let tsai = Tsai3Dof::new(presets::stamper_max_gci())?;
//! let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[])?;
//! let hemisphere = Region::Hemisphere { center: Vector3::zeros(), radius: tsai.reach() };
//! let points = PointSet::new(Domain::new(hemisphere)?, Sampler::Sobol { seed: 7 }, 4096, 4)?;
//! let e = ws.volume_and_eta(&points, &Silent)?;
//! let gci = e.gci().unwrap(); // η / W, the mean of 1/κ over the workspace
//! assert!(gci > 0.0 && gci < 1.0 && e.eta.unwrap() < e.volume);
//! let centre = local_indices(&tsai, &Vector3::new(0.0, 0.0, 0.5), [Elbow::Out; 3])?;
//! assert!((centre.inverse_condition - 0.803344).abs() < 1e-6); // spec §1 closed form
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The workspace-volume estimator works for any translational mechanism with closed-form
//! inverse kinematics: a bounding [`Region`] (box, cylinder, hemisphere, ball; optionally one
//! sector of an $n$-fold symmetric robot) as a [`Domain`], a [`Sampler`] (midpoint grid,
//! randomly shifted Sobol in replicates, Monte Carlo) filling a [`PointSet`] that every design of
//! a study shares (common random points), and a membership test, either a closure
//! ([`workspace_volume`]) or a mechanism with its working modes and
//! [`pkm_traits::WorkspaceConstraint`]s ([`Workspace`]). It returns the volume with its standard
//! error ([`VolumeEstimate`]) and, on request, $\eta = \int 1/\kappa\, dW$.
//!
//! Every estimator is deterministic: sample $i$ is a pure function of `(seed, i)` and parallel
//! sums use fixed-size chunks reduced serially in order ([`chunked_reduce`]), so results are
//! bit-for-bit identical whatever the number of rayon threads. A lane kernel (a batch
//! Jacobian and [`inverse_condition_number_3x3_lanes`] on [`LANES`] points, as a
//! [`LaneKernel`]) runs through [`evaluate`] compiled for the widest vector unit the processor
//! offers ([`VectorPath`]), with the same bits on every path; a [`BlockKernel`] runs a whole
//! loop of them through [`run_block`] the same way.
//!
//! [`Workspace`] asks the mechanism's lane kernels where it has them:
//! - volumes count through [`pkm_traits::ConstrainedWorkspace::reachable_in_any_lanes`]
//!   ([`Workspace::count_inside`], [`Workspace::volume`], [`sweep_workspace_volumes`]), the
//!   same counts as the point test, exactly;
//! - $1/\kappa$ through [`pkm_traits::ConstrainedWorkspace::velocity_jacobian_lanes`] and
//!   [`inverse_condition_number_3x3_lanes`] ([`Workspace::inverse_condition_lanes`],
//!   [`Workspace::volume_and_eta`], [`Workspace::hemisphere_estimate`]), equal to the point
//!   by point values to rounding.
//!
//! The rotary Delta and the Tsai platform have lane kernels; any other mechanism is asked point
//! by point, as are the closure estimators ([`workspace_volume`], [`hemisphere_estimate`]).
//! The cross-section indices run [`inverse_condition_number_3x3_lanes`] on the selected path too.

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod condition;
mod condition_3x3;
mod condition_3x3_lanes;
mod cross_section_indices;
mod error;
mod estimator;
mod gauss_legendre;
mod local;
mod parallel;
mod point_groups;
mod points;
mod region;
mod sampler;
mod section_cache;
mod section_indices;
mod slice;
mod sobol;
mod space_utilization;
mod sweep;
mod task_space;
mod vector_path;
mod volume;
mod workspace;

pub use condition::{
    Dim, FixedSvd, TranslationalCondition, condition_number, inverse_condition_number,
    inverse_condition_number_tall,
};
pub use condition_3x3::{SVD_BELOW, inverse_condition_number_3x3};
pub use condition_3x3_lanes::{
    LANES, Matrix3Lanes, inverse_condition_number_3x3_lanes, inverse_condition_of_reachable_lanes,
};
pub use cross_section_indices::{
    GridMean, GridRule, mean_by_grid, mean_by_grid_lanes, mean_by_quadrature,
    mean_by_quadrature_lanes,
};
pub use error::IndexError;
pub use estimator::{ErrorModel, VolumeEstimate, workspace_volume, workspace_volume_and_eta};
pub use gauss_legendre::GaussLegendre;
pub use local::{LocalIndices, inverse_condition_at, local_indices};
pub use parallel::{Accumulator, CHUNK_SIZE, chunked_reduce, chunked_reduce_ranges};
pub use pkm_traits::vector_path::{
    BlockKernel, VECTOR_PATH_VARIABLE, VectorPath, run_block, run_block_on,
};
pub use points::{MAX_POINTS, MAX_REPLICATES, PointSet, PointSource, PointStream};
pub use region::{BoundingBox, Domain, Region};
pub use sampler::Sampler;
pub use section_cache::SectionIndexCache;
pub use section_indices::{Eta1Rule, SectionIndex, SectionIndices};
pub use slice::{Plane, Slice};
pub use space_utilization::space_utilization;
pub use sweep::{ratio_standard_error, sweep_volumes, sweep_workspace_volumes};
pub use task_space::{
    ConnectedVolume, MAX_GRID_CELLS, MAX_TASK_DIMENSION, TaskBox, TaskPoints,
    connected_task_volume, nested_task_volumes, task_volume_and_eta,
};
pub use vector_path::{LaneKernel, evaluate, evaluate_on};
pub use volume::{HemisphereEstimate, hemisphere_estimate};
pub use workspace::Workspace;
