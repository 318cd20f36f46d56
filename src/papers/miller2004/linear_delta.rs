//! Miller 2004 (linear_delta).

use crate::papers::Experiment;

/// The experiments of this part of the paper.
pub fn experiments() -> Vec<Experiment> {
    Vec::new()
}
