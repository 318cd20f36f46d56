//! The numbers of one workspace estimate as a study reports them: W ± its standard error,
//! η = ∫ 1/κ dW ± its standard error and GCI = η/W (Stamper, Tsai & Walsh 1997, eq. 8–10), in
//! the units of the sampled coordinates.

use pkm_workspace_indices::{ErrorModel, VolumeEstimate};
use serde::{Deserialize, Serialize};

/// The numbers of one workspace estimate. Measures are in m³ for a translational study and in
/// the unit of the sampled task coordinates for a task-space one
/// ([`crate::task_space::TaskSpaceResult::unit`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Workspace volume W (m³).
    pub volume: f64,
    /// Its standard error (m³).
    pub volume_se: f64,
    /// η = ∫ 1/κ dW (m³).
    pub eta: f64,
    /// Its standard error (m³).
    pub eta_se: f64,
    /// GCI = η/W (dimensionless); absent for an empty workspace.
    pub gci: Option<f64>,
    /// Points sampled.
    pub n_points: u64,
    /// Points inside.
    pub n_inside: u64,
    /// `iid` or `replicates`.
    pub error_model: String,
    /// W of each replicate (m³).
    pub replicate_volumes: Vec<f64>,
}

impl From<&VolumeEstimate> for Estimate {
    fn from(e: &VolumeEstimate) -> Self {
        Self {
            volume: e.volume,
            volume_se: e.volume_se,
            eta: e.eta.unwrap_or(0.0),
            eta_se: e.eta_se.unwrap_or(0.0),
            gci: e.gci(),
            n_points: e.n_points,
            n_inside: e.n_inside,
            error_model: match e.error_model {
                ErrorModel::Iid => "iid".into(),
                ErrorModel::Replicates(r) => format!("replicates({r})"),
            },
            replicate_volumes: e.replicate_volumes.clone(),
        }
    }
}

impl Estimate {
    /// The warning of an estimate with no sample inside the workspace, over a domain of
    /// measure `domain` (in `unit`): zero hits of N bound the inside fraction by 3/N at 95 %
    /// confidence (the rule of three), so the workspace measures less than about 3·domain/N,
    /// which says nothing when the domain is far larger than the robot. `None` when some
    /// sample is inside.
    pub fn resolution_warning(&self, domain: f64, unit: &str) -> Option<String> {
        (self.n_inside == 0 && self.n_points > 0).then(|| {
            let bound = 3.0 * domain / self.n_points as f64;
            format!(
                "warning: no sample fell inside the workspace: its measure is below about \
                 {bound:.3e} {unit} (95 %), not 0; sample a region near the robot \
                 ([sampling.region] or a smaller [task_space] box) to measure it"
            )
        })
    }
}
