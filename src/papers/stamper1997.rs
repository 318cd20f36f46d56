//! Stamper, Tsai & Walsh 1997 (`001_d243aef4a9524698.txt`): Monte Carlo workspace volume and
//! global condition index of the Tsai translational platform.

use super::Experiment;

/// The experiments of this paper.
pub fn experiments() -> Vec<Experiment> {
    Vec::new()
}
