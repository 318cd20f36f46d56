//! Wolf & Shoham (`003_788af3b033109bd5.txt`): screw theory and task-based design of the
//! Stewart–Gough platform and the 3-UPU.

use super::Experiment;

pub mod screw_checks;

/// The experiments of this paper.
pub fn experiments() -> Vec<Experiment> {
    vec![screw_checks::experiment()]
}
