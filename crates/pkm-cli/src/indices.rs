//! The indices a sweep or a Pareto study can ask for, and their evaluation at one design.
//!
//! | index | meaning | unit | mechanisms |
//! |---|---|---|---|
//! | `volume` | workspace volume W over the study's points | m³ | all |
//! | `eta` | η = ∫ 1/κ dW | m³ | all |
//! | `gci` | GCI = η / W (Gosselin & Angeles) | – | all |
//! | `eta1` | mean 1/κ over the y–z cross-section (Miller 2004 eq. 1) | – | linear_delta |
//! | `eta2` | space utilisation (Miller 2004 eq. 2) | – | linear_delta |
//! | `area` | cross-section area A_W / Y_R² | – | linear_delta |
//!
//! The Linear Delta's cross-section indices are the library's
//! (`pkm_workspace_indices::SectionIndices`, the same as the paper experiments), cached per
//! exact design for the study (`SectionIndexCache`): a design is never given another design's
//! values, however close the nodes of a sweep.

use crate::CliError;
use crate::study::mechanism::{BuildError, MechanismSpec, WorkspaceVisitor};
use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
use pkm_study::StudyMechanism as _;
use pkm_traits::{ConstrainedWorkspace, ObjectiveError, Silent, WorkspaceConstraint};
use pkm_workspace_indices::{
    Dim, Eta1Rule, IndexError, PointSet, SectionIndex, SectionIndexCache, TranslationalCondition,
    Workspace,
};
use serde::{Deserialize, Serialize};

/// An index (see the module table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IndexName {
    /// Workspace volume (m³).
    Volume,
    /// η = ∫ 1/κ dW (m³).
    Eta,
    /// η / W.
    Gci,
    /// Linear Delta manipulability, eq. 1.
    Eta1,
    /// Linear Delta space utilisation, eq. 2.
    Eta2,
    /// Linear Delta cross-section area over Y_R².
    Area,
}

impl IndexName {
    /// The name in study files and CSV headers.
    pub fn key(self) -> &'static str {
        match self {
            Self::Volume => "volume",
            Self::Eta => "eta",
            Self::Gci => "gci",
            Self::Eta1 => "eta1",
            Self::Eta2 => "eta2",
            Self::Area => "area",
        }
    }

    /// Whether it is estimated over the study's workspace points.
    pub fn needs_points(self) -> bool {
        matches!(self, Self::Volume | Self::Eta | Self::Gci)
    }

    /// Whether `mechanism` has it.
    pub fn applies_to(self, mechanism: &MechanismSpec) -> bool {
        self.needs_points() || mechanism.section_ratios().is_some()
    }
}

/// The `[indices]` settings (and the overrides of a refinement level).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct IndexSettings {
    /// Gauss–Legendre points per axis and piece of the Linear Delta's η1 (default 16).
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

impl IndexSettings {
    fn eta1_rule(self) -> Eta1Rule {
        if self.eta1_paper_grid {
            Eta1Rule::Grid
        } else {
            Eta1Rule::Quadrature(self.eta1_points)
        }
    }
}

/// Why a design has no value: recorded, never an abort.
pub type Infeasible = String;

/// Evaluates indices at designs of one study: the base mechanism with the design variables
/// set, under the study's constraints, on its common points.
#[derive(Debug)]
pub struct Evaluator {
    base: MechanismSpec,
    variables: Vec<String>,
    constraints: Vec<WorkspaceConstraint>,
    points: Option<PointSet>,
    cache: SectionIndexCache,
}

struct VolumeAndEta<'a> {
    points: &'a PointSet,
    with_eta: bool,
}

impl WorkspaceVisitor for VolumeAndEta<'_> {
    type Output = Result<(f64, Option<f64>), CliError>;

    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        // Silent: a sweep reports progress per design, not per point.
        let e = if self.with_eta {
            workspace.volume_and_eta(self.points, &Silent)?
        } else {
            workspace.volume(self.points, &Silent)?
        };
        Ok((e.volume, e.eta))
    }
}

impl Evaluator {
    /// An evaluator of `base` with `variables` (names already checked) under `constraints`,
    /// on `points` (needed for the workspace indices).
    pub fn new(
        base: MechanismSpec,
        variables: Vec<String>,
        constraints: Vec<WorkspaceConstraint>,
        points: Option<PointSet>,
    ) -> Self {
        Self {
            base,
            variables,
            constraints,
            points,
            cache: SectionIndexCache::new(),
        }
    }

    /// The mechanism at `design` (values of the variables in order).
    ///
    /// # Errors
    /// A message for an unknown variable (checked before any run, so not reached then).
    pub fn mechanism_at(&self, design: &[f64]) -> Result<MechanismSpec, Infeasible> {
        let mut spec = self.base.clone();
        for (name, value) in self.variables.iter().zip(design) {
            spec.set(name, *value)?;
        }
        Ok(spec)
    }

    /// The study's workspace constraints.
    pub fn constraints(&self) -> &[WorkspaceConstraint] {
        &self.constraints
    }

    /// The values of `indices` (in that order) at `design` with `settings`.
    ///
    /// # Errors
    /// `Ok(Err(reason))` for an infeasible design (invalid parameters, empty cross-section,
    /// no GCI of an empty workspace); `Err` for a study error (a constraint the mechanism
    /// cannot evaluate, no points for a workspace index) or cancellation.
    pub fn evaluate(
        &self,
        design: &[f64],
        indices: &[IndexName],
        settings: IndexSettings,
    ) -> Result<Result<Vec<f64>, Infeasible>, CliError> {
        let spec = match self.mechanism_at(design) {
            Ok(spec) => spec,
            Err(reason) => return Ok(Err(reason)),
        };
        let mut workspace: Option<(f64, Option<f64>)> = None;
        if indices.iter().any(|i| i.needs_points()) {
            let points = self.points.as_ref().ok_or_else(|| {
                CliError::Invalid("workspace indices need a [sampling] section".into())
            })?;
            let with_eta = indices
                .iter()
                .any(|i| matches!(i, IndexName::Eta | IndexName::Gci));
            match spec.with_workspace(&self.constraints, VolumeAndEta { points, with_eta }) {
                Ok(values) => workspace = Some(values?),
                Err(BuildError::Design(reason)) => return Ok(Err(reason)),
                Err(e @ BuildError::Constraint(_)) => return Err(CliError::Invalid(e.to_string())),
            }
        }
        let mut values = Vec::with_capacity(indices.len());
        for index in indices {
            let value = match (index, workspace) {
                (IndexName::Volume, Some((w, _))) => Ok(w),
                (IndexName::Eta, Some((_, eta))) => Ok(eta.unwrap_or(0.0)),
                (IndexName::Gci, Some((w, eta))) => match eta {
                    Some(eta) if w > 0.0 => Ok(eta / w),
                    _ => Err("empty workspace: no GCI".to_owned()),
                },
                (cross_section, _) => self.cross_section_index(&spec, *cross_section, settings),
            };
            match value {
                Ok(v) => values.push(v),
                Err(reason) => return Ok(Err(reason)),
            }
        }
        Ok(Ok(values))
    }

    fn cross_section_index(
        &self,
        spec: &MechanismSpec,
        index: IndexName,
        settings: IndexSettings,
    ) -> Result<f64, Infeasible> {
        let ratios = spec
            .section_ratios()
            .ok_or_else(|| format!("{} is an index of linear_delta only", index.key()))?;
        let index = match index {
            IndexName::Eta1 => SectionIndex::Eta1(settings.eta1_rule()),
            IndexName::Eta2 => SectionIndex::Eta2,
            IndexName::Area => SectionIndex::Area,
            IndexName::Volume | IndexName::Eta | IndexName::Gci => {
                return Err("workspace index without points".to_owned());
            }
        };
        // The study's design of Y_R = 1 (the ratios are the design variables).
        let build = || {
            let ratios = LinearDeltaRatios::from_slice(&ratios);
            LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 })
        };
        let values = self
            .cache
            .values(&ratios, &[index], LinearDeltaMode::PAPER, build);
        match values.into_iter().next() {
            Some(value) => value.map_err(|e| infeasible(e).to_string()),
            None => Err("no value".to_owned()),
        }
    }
}

/// An index failure as an infeasible design (an invalid design keeps its typed cause).
fn infeasible(e: IndexError) -> ObjectiveError {
    match e {
        IndexError::Design(design) => design.into(),
        e => ObjectiveError::infeasible(e.to_string()),
    }
}
