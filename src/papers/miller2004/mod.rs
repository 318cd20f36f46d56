//! Miller 2004 (`000_3af296716aa60595.txt`): NUWAR vs Delta (§2.1), the Linear Delta design
//! search (§2.2, Table 2) and Hamilton's canonical equations in extended space (§3).

use super::Experiment;

pub mod dynamics;
pub mod linear_delta;
pub mod workspace;

/// The experiments of this paper.
pub fn experiments() -> Vec<Experiment> {
    let mut experiments = workspace::experiments();
    experiments.extend(linear_delta::experiments());
    experiments.extend(dynamics::experiments());
    experiments
}
