//! The indices of a grid study at one design (see [`IndexName`] for the table): the base
//! mechanism with the design variables set, under the study's constraints, on its common
//! points.
//!
//! The Linear Delta's cross-section indices are the library's
//! ([`SectionIndices`](pkm_workspace_indices::SectionIndices), the same as the paper
//! experiments), cached per exact design for the one study ([`SectionIndexCache`]): a design is
//! never given another design's values, however close the nodes of a sweep.

use crate::StudyError;
use crate::registry::{CrossSectionVisitor, StudyMechanism};
use crate::schema::grid::{IndexName, IndexSettings};
use crate::schema::mechanism::{BuildError, MechanismSpec, WorkspaceVisitor};
use crate::task_space::TaskSpaceEvaluator;
use pkm_traits::{
    ConstrainedWorkspace, CrossSectionWorkspace, DesignError, InvalidInput, ObjectiveError, Silent,
    WorkspaceConstraint,
};
use pkm_workspace_indices::{
    Dim, Eta1Rule, IndexError, PointSet, SectionIndex, SectionIndexCache, TranslationalCondition,
    Workspace,
};

/// A design's workspace volume W and, when asked for, its η = ∫ 1/κ dW.
type VolumeAndEtaValues = (f64, Option<f64>);

/// Why a design has no value: recorded with the node (in the result and the landscape), never
/// an abort.
pub type Infeasible = String;

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
    ) -> Result<Result<Vec<f64>, Infeasible>, StudyError> {
        let spec = match self.mechanism_at(design) {
            Ok(spec) => spec,
            Err(reason) => return Ok(Err(reason)),
        };
        let workspace = match self.workspace_indices(&spec, indices)? {
            Ok(values) => values,
            Err(reason) => return Ok(Err(reason)),
        };
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

    /// W and η of `spec` when `indices` ask for a workspace index.
    fn workspace_indices(
        &self,
        spec: &M,
        indices: &[IndexName],
    ) -> Result<Result<Option<VolumeAndEtaValues>, Infeasible>, StudyError> {
        if !indices.iter().any(|i| i.needs_points()) {
            return Ok(Ok(None));
        }
        if let Some(task_space) = &self.task_space {
            let robot = spec.robot_file().ok_or_else(|| {
                StudyError::invalid("task_space", "a [task_space] study takes a robot file")
            })?;
            // Silent: a grid study reports progress per design, not per point.
            let indices = task_space.indices(robot, &self.constraints, false, &Silent)?;
            return Ok(indices.map(|i| Some((i.volume, Some(i.eta)))));
        }
        let points = self.points.as_ref().ok_or_else(|| {
            StudyError::invalid("sampling", "workspace indices need a [sampling] section")
        })?;
        let with_eta = indices
            .iter()
            .any(|i| matches!(i, IndexName::Eta | IndexName::Gci));
        match spec.with_workspace(&self.constraints, VolumeAndEta { points, with_eta }) {
            Ok(values) => Ok(Ok(Some(values?))),
            Err(BuildError::Design(reason)) => Ok(Err(reason)),
            Err(e @ BuildError::Constraint(_)) => {
                Err(StudyError::invalid("constraints", e.to_string()))
            }
        }
    }

    fn cross_section_index(
        &self,
        spec: &M,
        index: IndexName,
        settings: IndexSettings,
    ) -> Result<f64, Infeasible> {
        let index = match index {
            IndexName::Eta1 => SectionIndex::Eta1(settings.eta1_rule()),
            IndexName::Eta2 => SectionIndex::Eta2,
            IndexName::Area => SectionIndex::Area,
            IndexName::Volume | IndexName::Eta | IndexName::Gci => {
                return Err("workspace index without points".to_owned());
            }
        };
        let visitor = SectionValue {
            cache: &self.cache,
            index,
        };
        let value = spec.with_cross_section(visitor).ok_or_else(|| {
            format!(
                "{} is an index of a mechanism with an exact cross-section (linear_delta), \
                 not of {}",
                index_key(index),
                spec.kind()
            )
        })?;
        value.map_err(|e| infeasible(e).to_string())
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

/// An index failure as an infeasible design (an invalid design keeps its typed cause).
fn infeasible(e: IndexError) -> ObjectiveError {
    match e {
        IndexError::Design(design) => design.into(),
        e => ObjectiveError::infeasible(e.to_string()),
    }
}
