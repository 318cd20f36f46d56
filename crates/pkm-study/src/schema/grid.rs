//! The schema of the grid studies (`sweep` and `pareto`): the base design, its named design
//! variables with their grids, the indices and their settings, and each kind's section. One
//! study may hold both sections; each kind reads its own.

use super::mechanism::{ConstraintsSpec, MechanismSpec};
use super::sampling::SamplingSpec;
use super::units::Real;
use crate::registry::StudyMechanism;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A study over a grid of designs, read by [`sweep`](crate::sweep()) (its `[sweep]` section) and
/// [`pareto`](crate::pareto()) (its `[pareto]` section), of a mechanism of the registry `M` (the
/// papers' mechanisms by default).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GridStudy<M = MechanismSpec> {
    /// Free text.
    pub title: Option<String>,
    /// The base design; the variables override its parameters.
    pub mechanism: M,
    /// Workspace limits (for the workspace indices).
    pub constraints: Option<ConstraintsSpec>,
    /// Common points of the workspace indices (needed for `volume`, `eta`, `gci`).
    pub sampling: Option<SamplingSpec>,
    /// The workspace indices of a robot file in its own task space ([`crate::task_space`]):
    /// `volume`, `eta` and `gci` of its kind over the box, on the common points of
    /// `[sampling]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub task_space: Option<crate::task_space::TaskSpaceSpec>,
    /// Settings of the indices.
    #[serde(default)]
    pub indices: IndexSettings,
    /// The design variables: one `[[variables]]` table each.
    pub variables: Vec<VariableSpec>,
    /// The section of [`sweep`](crate::sweep()).
    pub sweep: Option<SweepSection>,
    /// The section of [`pareto`](crate::pareto()).
    pub pareto: Option<ParetoSection>,
}

/// One `[[variables]]` table: a parameter of the mechanism and its grid.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct VariableSpec {
    /// A parameter key of the mechanism table (its unit).
    pub name: String,
    /// First node.
    pub from: Real,
    /// Last node.
    pub to: Real,
    /// Node spacing (give `step` or `steps`).
    pub step: Option<f64>,
    /// Number of nodes (give `step` or `steps`).
    pub steps: Option<usize>,
}

pub use super::index::IndexName;

impl IndexName {
    /// Whether `mechanism` has it.
    pub fn applies_to<M: StudyMechanism>(self, mechanism: &M) -> bool {
        self.needs_points() || mechanism.with_cross_section(HasCrossSection).is_some()
    }
}

/// Asks only whether a mechanism has a cross-section (nothing is built).
struct HasCrossSection;

impl crate::registry::CrossSectionVisitor for HasCrossSection {
    type Output = ();

    fn visit<M: pkm_traits::CrossSectionWorkspace>(
        self,
        _key: &[f64],
        _mode: M::WorkingMode,
        _build: impl FnOnce() -> Result<M, pkm_traits::DesignError>,
    ) {
    }
}

/// The `[indices]` settings (and the overrides of a refinement level).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct IndexSettings {
    /// Gauss–Legendre points per axis and piece of the Linear Delta's η1 (default 16: the
    /// accurate rule of Miller 2004's reproduction; 1 to
    /// [`GaussLegendre::MAX_ORDER`](pkm_workspace_indices::GaussLegendre::MAX_ORDER)).
    #[serde(default = "default_eta1_points")]
    pub eta1_points: usize,
    /// η1 by the paper's uniform grid (eq. 4, N_a > 5000) instead of Gauss–Legendre.
    #[serde(default)]
    pub eta1_paper_grid: bool,
}

fn default_eta1_points() -> usize {
    16
}

impl Default for IndexSettings {
    fn default() -> Self {
        Self {
            eta1_points: default_eta1_points(),
            eta1_paper_grid: false,
        }
    }
}

/// The `[sweep]` section.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// Weights wᵢ of the utility Σ wᵢ ηᵢ, maximised (a negative weight minimises).
    pub objective: BTreeMap<IndexName, Real>,
    /// Further indices for the landscape.
    #[serde(default)]
    pub report: Vec<IndexName>,
    /// Refinement levels around the grid optimum, in order.
    #[serde(default)]
    pub refine: Vec<RefineLevel>,
    /// Heat maps of two variables through the optimum (default: the first two variables).
    #[serde(default)]
    pub heatmaps: Vec<HeatmapSpec>,
}

/// One `[[sweep.refine]]` level.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RefineLevel {
    /// Lattice step, in every variable's unit.
    pub step: f64,
    /// Window half-width in steps.
    pub half_width: usize,
    /// Override of `[indices] eta1_points` from this level on.
    pub eta1_points: Option<usize>,
    /// Override of `[indices] eta1_paper_grid` from this level on.
    pub eta1_paper_grid: Option<bool>,
}

/// A `[[sweep.heatmaps]]` pair.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HeatmapSpec {
    /// Variable along x.
    pub x: String,
    /// Variable along y.
    pub y: String,
}

/// The `[pareto]` section.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ParetoSection {
    /// Two or more indices, all maximised, in this order.
    pub objectives: Vec<IndexName>,
    /// Weightings whose optima are reported and marked, one weight per objective.
    #[serde(default)]
    pub weights: Vec<Vec<Real>>,
}
