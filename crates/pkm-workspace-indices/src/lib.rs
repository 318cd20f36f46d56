//! Workspace and performance indices of parallel mechanisms: samplers, workspace volume with its
//! standard error, local and global condition indices, manipulability and space utilisation.
//!
//! Every estimator is deterministic: sample $i$ is a pure function of `(seed, i)` and parallel
//! sums use fixed-size chunks reduced serially in order ([`chunked_reduce`]), so results are
//! bit-for-bit identical whatever the number of rayon threads.
#![warn(missing_docs)]

mod condition;
mod error;
mod parallel;

pub use condition::{Dim, FixedSvd, condition_number, inverse_condition_number};
pub use error::IndexError;
pub use parallel::{Accumulator, CHUNK_SIZE, chunked_reduce};

mod condition3;
mod sampler;
mod slice;
mod sobol;
mod volume;

pub use condition3::inverse_condition_number_3x3;
pub use sampler::Sampler;
pub use slice::Slice;
pub use volume::{HemisphereEstimate, hemisphere_estimate};
