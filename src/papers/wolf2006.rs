//! Wolf & Shoham (`003_788af3b033109bd5.txt`): screw theory and task-based design of the
//! Stewart–Gough platform and the 3-UPU.

use super::Experiment;

/// The experiments of this paper.
pub fn experiments() -> Vec<Experiment> {
    Vec::new()
}
