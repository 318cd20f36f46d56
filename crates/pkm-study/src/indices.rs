//! The indices of a grid study at one design (see [`IndexName`] for the table): the base
//! mechanism with the design variables set, under the study's constraints, on its common
//! points.
//!
//! The Linear Delta's cross-section indices are the library's
//! ([`SectionIndices`](pkm_workspace_indices::SectionIndices), the same as the paper
//! experiments), cached per exact design for the one study ([`SectionIndexCache`]): a design is
//! never given another design's values, however close the nodes of a sweep.

use crate::registry::{Built, CrossSectionVisitor, StudyMechanism};
use crate::schema::grid::{IndexName, IndexSettings};
use crate::schema::mechanism::{BuildError, MechanismSpec, WorkspaceVisitor};
use crate::task_space::TaskSpaceEvaluator;
use crate::{Infeasible, StudyError};
use pkm_traits::{
    ConstrainedWorkspace, CrossSectionWorkspace, DesignError, InvalidInput, Silent,
    WorkspaceConstraint,
};
use pkm_workspace_indices::{
    Dim, Eta1Rule, IndexError, PointSet, SectionIndex, SectionIndexCache, TranslationalCondition,
    Workspace,
};

/// A design's workspace volume W and, when asked for, its η = ∫ 1/κ dW.
type VolumeAndEtaValues = (f64, Option<f64>);

impl IndexSettings {
    fn eta1_rule(self) -> Eta1Rule {
        if self.eta1_paper_grid {
            Eta1Rule::Grid
        } else {
            Eta1Rule::Quadrature(self.eta1_points)
        }
    }
}

/// Evaluates indices at designs of one study.
#[derive(Debug)]
pub struct Evaluator<M = MechanismSpec> {
    base: M,
    variables: Vec<String>,
    constraints: Vec<WorkspaceConstraint>,
    points: Option<PointSet>,
    task_space: Option<TaskSpaceEvaluator>,
    cache: SectionIndexCache,
}

/// W and η of one design's workspace over the study's points.
struct VolumeAndEta<'a> {
    points: &'a PointSet,
    with_eta: bool,
}

impl WorkspaceVisitor for VolumeAndEta<'_> {
    type Output = Result<(f64, Option<f64>), StudyError>;

    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        // Silent: a grid study reports progress per design, not per point.
        let e = if self.with_eta {
            workspace.volume_and_eta(self.points, &Silent)?
        } else {
            workspace.volume(self.points, &Silent)?
        };
        Ok((e.volume, e.eta))
    }
}

impl<M: StudyMechanism> Evaluator<M> {
    /// An evaluator of `base` with `variables` (names already checked) under `constraints`,
    /// on `points` (needed for the workspace indices), with an empty cache.
    pub fn new(
        base: M,
        variables: Vec<String>,
        constraints: Vec<WorkspaceConstraint>,
        points: Option<PointSet>,
    ) -> Self {
        Self {
            base,
            variables,
            constraints,
            points,
            task_space: None,
            cache: SectionIndexCache::new(),
        }
    }

    /// The evaluator whose workspace indices are those of a robot file in its task space.
    #[must_use]
    pub fn with_task_space(mut self, task_space: TaskSpaceEvaluator) -> Self {
        self.task_space = Some(task_space);
        self
    }

    /// The mechanism at `design` (values of the variables in order).
    ///
    /// # Errors
    /// The mechanism's message for an unknown variable (checked before any run, so not reached
    /// then).
    pub fn mechanism_at(&self, design: &[f64]) -> Result<M, Infeasible> {
        let mut spec = self.base.clone();
        for (name, value) in self.variables.iter().zip(design) {
            spec.set(name, *value).map_err(Infeasible::Variable)?;
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
    ) -> Result<Result<Vec<f64>, Infeasible>, StudyError> {
        let spec = match self.mechanism_at(design) {
            Ok(spec) => spec,
            Err(reason) => return Ok(Err(reason)),
        };
        let with_eta = indices
            .iter()
            .any(|i| matches!(i, IndexName::Eta | IndexName::Gci));
        // W and η once, at the first workspace index.
        let mut workspace = None;
        let mut values = Vec::with_capacity(indices.len());
        for index in indices {
            let value = match section_index(*index, settings) {
                Some(section) => self.cross_section_index(&spec, section),
                None => {
                    let (w, eta) = match workspace {
                        Some(values) => values,
                        None => match self.workspace_indices(&spec, with_eta)? {
                            Ok(values) => *workspace.insert(values),
                            Err(reason) => return Ok(Err(reason)),
                        },
                    };
                    workspace_index(*index, w, eta)
                }
            };
            match value {
                Ok(v) => values.push(v),
                Err(reason) => return Ok(Err(reason)),
            }
        }
        Ok(Ok(values))
    }

    /// W and, `with_eta`, η of `spec`.
    fn workspace_indices(
        &self,
        spec: &M,
        with_eta: bool,
    ) -> Result<Result<VolumeAndEtaValues, Infeasible>, StudyError> {
        if let Some(task_space) = &self.task_space {
            let robot = spec.robot_file().ok_or_else(|| {
                StudyError::invalid("task_space", "a [task_space] study takes a robot file")
            })?;
            // Silent: a grid study reports progress per design, not per point.
            let indices = task_space.indices(robot, &self.constraints, false, &Silent)?;
            return Ok(indices.map(|i| (i.volume, Some(i.eta))));
        }
        let points = self.points.as_ref().ok_or_else(|| {
            StudyError::invalid("sampling", "workspace indices need a [sampling] section")
        })?;
        let built = match Built::new(spec.clone()) {
            Ok(built) => built,
            Err(BuildError::Design(reason)) => return Ok(Err(reason)),
            Err(e) => return Err(StudyError::invalid("mechanism", e.to_string())),
        };
        match built.with_workspace(&self.constraints, VolumeAndEta { points, with_eta }) {
            Ok(values) => Ok(Ok(values?)),
            Err(BuildError::Design(reason)) => Ok(Err(reason)),
            Err(e @ (BuildError::Constraint(_) | BuildError::Unsupported(_))) => {
                Err(StudyError::invalid("constraints", e.to_string()))
            }
        }
    }

    fn cross_section_index(&self, spec: &M, index: SectionIndex) -> Result<f64, Infeasible> {
        let visitor = SectionValue {
            cache: &self.cache,
            index,
        };
        let value = spec
            .with_cross_section(visitor)
            .ok_or_else(|| Infeasible::NoCrossSection {
                index: index_key(index),
                kind: spec.kind(),
            })?;
        value.map_err(Infeasible::from)
    }
}

/// The cross-section index of `index`; `None` for a workspace index.
fn section_index(index: IndexName, settings: IndexSettings) -> Option<SectionIndex> {
    match index {
        IndexName::Eta1 => Some(SectionIndex::Eta1(settings.eta1_rule())),
        IndexName::Eta2 => Some(SectionIndex::Eta2),
        IndexName::Area => Some(SectionIndex::Area),
        IndexName::Volume | IndexName::Eta | IndexName::Gci => None,
    }
}

/// A workspace index from W and η: η of an empty workspace is 0, its GCI = η/W has no value.
fn workspace_index(index: IndexName, w: f64, eta: Option<f64>) -> Result<f64, Infeasible> {
    match index {
        IndexName::Volume => Ok(w),
        IndexName::Gci => match eta {
            Some(eta) if w > 0.0 => Ok(eta / w),
            _ => Err(Infeasible::EmptyWorkspace { index: "GCI" }),
        },
        _ => Ok(eta.unwrap_or(0.0)),
    }
}

/// The key of a cross-section index in a study.
fn index_key(index: SectionIndex) -> &'static str {
    match index {
        SectionIndex::Eta1(_) => IndexName::Eta1.key(),
        SectionIndex::Eta2 => IndexName::Eta2.key(),
        SectionIndex::Area => IndexName::Area.key(),
    }
}

/// One cross-section index of a mechanism, through the study's cache (keyed by the design and
/// the working mode the mechanism gives).
struct SectionValue<'a> {
    cache: &'a SectionIndexCache,
    index: SectionIndex,
}

impl CrossSectionVisitor for SectionValue<'_> {
    type Output = Result<f64, IndexError>;

    fn visit<M: CrossSectionWorkspace>(
        self,
        key: &[f64],
        mode: M::WorkingMode,
        build: impl FnOnce() -> Result<M, DesignError>,
    ) -> Self::Output {
        // One value per index asked for.
        let values = self.cache.values(key, &[self.index], mode, build);
        values
            .into_iter()
            .next()
            .unwrap_or_else(|| Err(InvalidInput::new("indices", 0.0, "one value per index").into()))
    }
}
