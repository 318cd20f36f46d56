//! Workspace and performance indices of parallel mechanisms: samplers, workspace volume with its
//! standard error, local and global condition indices, manipulability and space utilisation.
//!
//! Every estimator is deterministic: sample $i$ is a pure function of `(seed, i)` and parallel
//! sums use fixed-size chunks reduced serially in order ([`chunked_reduce`]), so results are
//! bit-for-bit identical whatever the number of rayon threads.
#![warn(missing_docs)]

mod condition;
mod condition_3x3;
mod condition_3x3_lanes;
mod cross_section_indices;
mod error;
mod gauss_legendre;
mod parallel;
mod sampler;
mod slice;
mod sobol;
mod space_utilization;
mod volume;

pub use condition::{Dim, FixedSvd, condition_number, inverse_condition_number};
pub use condition_3x3::inverse_condition_number_3x3;
pub use condition_3x3_lanes::{LANES, Matrix3Lanes, inverse_condition_number_3x3_lanes};
pub use cross_section_indices::{GridMean, GridRule, mean_by_grid, mean_by_quadrature};
pub use error::IndexError;
pub use gauss_legendre::GaussLegendre;
pub use parallel::{Accumulator, CHUNK_SIZE, chunked_reduce};
pub use sampler::Sampler;
pub use slice::Slice;
pub use space_utilization::space_utilization;
pub use volume::{HemisphereEstimate, hemisphere_estimate};
