//! Miller 2004 (dynamics).

use crate::papers::Experiment;

/// The experiments of this part of the paper.
pub fn experiments() -> Vec<Experiment> {
    Vec::new()
}
