//! The workspace study: the workspace of one design under its constraints: volume ± standard
//! error, η = ∫ 1/κ dW and GCI = η/W over common random points (Stamper, Tsai & Walsh 1997,
//! eq. 8–10), and planar slices of 1/κ as tables and heat maps.

use crate::StudyError;
pub use crate::estimate::Estimate;
use crate::outcome::{Artifact, Outcome, Table};
use crate::registry::{Built, StudyMechanism};
use crate::scene;
use crate::schema::mechanism::{BuildError, ConstraintsSpec, MechanismSpec, WorkspaceVisitor};
use crate::schema::robot_file::RobotFileSpec;
use crate::schema::sampling::SamplingSpec;
use crate::schema::units::Metres;
use crate::task_space::{self, TaskSpaceResult, TaskSpaceSpec};
use pkm_draw::chart::{self, Chart};
use pkm_traits::{ConstrainedWorkspace, Progress, WorkspaceConstraint};
use pkm_workspace_indices::{
    BoundingBox, Dim, Plane, PointSource, PointStream, Slice, TranslationalCondition,
    VolumeEstimate, Workspace,
};
use serde::{Deserialize, Serialize};

/// A workspace study of a mechanism of the registry `M` (the papers' mechanisms by default).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceStudy<M = MechanismSpec> {
    /// Free text.
    pub title: Option<String>,
    /// The design.
    pub mechanism: M,
    /// Its workspace limits.
    pub constraints: Option<ConstraintsSpec>,
    /// The points of the estimate.
    #[serde(default)]
    pub sampling: SamplingSpec,
    /// What to report.
    #[serde(default)]
    pub workspace: WorkspaceSection,
    /// The workspace of a robot file in its own task coordinates ([`crate::task_space`]);
    /// absent for a translational study of the platform position.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub task_space: Option<TaskSpaceSpec>,
}

/// The `[workspace]` section.
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceSection {
    /// Planar sections of 1/κ.
    #[serde(default)]
    pub slices: Vec<SliceSpec>,
}

/// One `[[workspace.slices]]` entry.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SliceSpec {
    /// The plane.
    pub plane: Plane,
    /// Its offset along the normal axis (m).
    pub at: Metres,
    /// Cells per side (default 60, at most [`MAX_SLICE_CELLS`]).
    #[serde(default = "default_cells")]
    pub cells: usize,
}

fn default_cells() -> usize {
    60
}

/// Largest number of cells per slice side.
pub const MAX_SLICE_CELLS: usize = 1024;

/// A slice's summary.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SliceSummary {
    /// The plane.
    pub plane: Plane,
    /// Offset along its normal (m).
    pub at: f64,
    /// Cells per side.
    pub cells: usize,
    /// Fraction of cells inside the workspace.
    pub inside_fraction: f64,
    /// Largest 1/κ on the slice.
    pub max_inverse_condition: Option<f64>,
    /// The table's artifact name.
    pub csv: String,
    /// The heat map's artifact name.
    pub svg: String,
}

/// The result of a workspace study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkspaceResult {
    /// The study's title.
    pub title: Option<String>,
    /// The mechanism kind.
    pub mechanism: String,
    /// Volume of the sampled domain (m³, all sectors).
    pub domain_volume: f64,
    /// The estimate.
    pub estimate: Estimate,
    /// The slices.
    pub slices: Vec<SliceSummary>,
    /// What a task-space study reports beside the estimate (absent for a translational one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub task_space: Option<TaskSpaceResult>,
}

/// The library constraints of a study's `[constraints]` table, checked against the mechanism.
///
/// # Errors
/// [`StudyError::Invalid`] at `constraints` for a constraint that does not fit the mechanism.
pub fn constraints_of<M: StudyMechanism>(
    mechanism: &M,
    spec: Option<&ConstraintsSpec>,
) -> Result<Vec<WorkspaceConstraint>, StudyError> {
    mechanism.check()?;
    match (Built::new(mechanism.clone()), spec) {
        (Ok(built), _) => checked_constraints(&built, spec),
        // An invalid base design is reported where it is used (a sweep varies it).
        (Err(_), Some(spec)) => mechanism.constraints(spec).map_err(at_constraints),
        (Err(_), None) => Ok(Vec::new()),
    }
}

/// The library constraints of a study's `[constraints]` table, checked against `built`.
///
/// # Errors
/// [`StudyError::Invalid`] at `constraints` for a constraint that does not fit the mechanism.
pub fn checked_constraints<M: StudyMechanism>(
    built: &Built<M>,
    spec: Option<&ConstraintsSpec>,
) -> Result<Vec<WorkspaceConstraint>, StudyError> {
    let Some(spec) = spec else {
        return Ok(Vec::new());
    };
    let constraints = built.spec().constraints(spec).map_err(at_constraints)?;
    match built.with_workspace(&constraints, CheckOnly) {
        Err(BuildError::Constraint(m) | BuildError::Unsupported(m)) => Err(at_constraints(m)),
        // A robot file whose task is not the position has no workspace in it.
        Ok(()) | Err(BuildError::Design(_)) => Ok(constraints),
    }
}

fn at_constraints(message: String) -> StudyError {
    StudyError::invalid("constraints", message)
}

/// Builds the workspace only to check that its constraints apply.
struct CheckOnly;

impl WorkspaceVisitor for CheckOnly {
    type Output = ();
    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(self, _: &Workspace<'_, M, NQ>)
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
    }
}

/// What the workspace study computes on a built workspace.
struct Compute<'a> {
    points: &'a PointStream,
    slices: &'a [(Plane, f64, usize)],
    bounds: BoundingBox,
    progress: &'a dyn Progress,
}

impl WorkspaceVisitor for Compute<'_> {
    type Output = Result<(VolumeEstimate, Vec<Slice>), StudyError>;

    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        self.progress.start("workspace points", self.points.count());
        let estimate = workspace.volume_and_eta(self.points, self.progress);
        self.progress.finish();
        let estimate = estimate?;
        let slices = self
            .slices
            .iter()
            .map(|&(plane, at, n)| {
                self.progress.check()?;
                Ok(workspace.inverse_condition_slice(plane, at, &self.bounds, n)?)
            })
            .collect::<Result<Vec<_>, StudyError>>()?;
        Ok((estimate, slices))
    }
}

/// Checks every slice setting: `(plane, at, cells)` of each.
fn slice_settings(section: &WorkspaceSection) -> Result<Vec<(Plane, f64, usize)>, StudyError> {
    let mut slices = Vec::new();
    for (k, s) in section.slices.iter().enumerate() {
        if s.cells == 0 || s.cells > MAX_SLICE_CELLS {
            return Err(StudyError::invalid(
                format!("workspace.slices[{k}].cells").as_str(),
                format!("expected a count of cells per side in 1..={MAX_SLICE_CELLS}"),
            ));
        }
        slices.push((s.plane, s.at.0, s.cells));
    }
    Ok(slices)
}

/// Runs a workspace study: the estimate, the slices (a table and a heat map each) and the
/// drawing of the design in its workspace.
///
/// # Errors
/// [`StudyError::Invalid`] for a setting that cannot be used (checked before any computation),
/// [`StudyError::Index`] when the index computation refuses its input,
/// [`StudyError::Cancelled`] when `progress` asks to stop.
pub fn workspace<M: StudyMechanism>(
    study: &WorkspaceStudy<M>,
    progress: &dyn Progress,
) -> Result<Outcome<WorkspaceResult>, StudyError> {
    study.mechanism.check()?;
    let built = Built::new(study.mechanism.clone())?;
    let constraints = checked_constraints(&built, study.constraints.as_ref())?;
    if let Some((robot, spec)) = task_space_of(study)? {
        return task_space_workspace(study, robot, spec, &constraints, progress);
    }
    let slices = slice_settings(&study.workspace)?;
    let domain = study.sampling.domain(built.reach_region())?;
    let points = study.sampling.point_stream(domain)?;
    let compute = Compute {
        points: &points,
        slices: &slices,
        bounds: domain.region().bounding_box(),
        progress,
    };
    let (estimate, values) = built.with_workspace(&constraints, compute)??;
    let mut artifacts = Vec::new();
    let mut summaries = Vec::new();
    for (k, ((plane, at, n), values)) in slices.iter().zip(&values).enumerate() {
        summaries.push(slice_artifacts(
            &mut artifacts,
            k + 1,
            *plane,
            *at,
            *n,
            values,
        ));
    }
    let estimate = Estimate::from(&estimate);
    let kind = study.mechanism.kind();
    let mut outcome = Outcome::new(WorkspaceResult {
        title: study.title.clone(),
        mechanism: kind.into(),
        domain_volume: domain.volume(),
        estimate,
        slices: summaries,
        task_space: None,
    });
    outcome.artifacts = artifacts;
    summarise(&mut outcome);
    let scene = scene::design_scene(&built, &constraints, Some(domain.region()));
    outcome.robot(format!("{kind} in its workspace"), scene);
    Ok(outcome)
}

/// A workspace study in the task space of a robot file ([`task_space::workspace`]), without
/// slices (they cut x, y, z).
fn task_space_workspace<M>(
    study: &WorkspaceStudy<M>,
    robot: &RobotFileSpec,
    spec: &TaskSpaceSpec,
    constraints: &[WorkspaceConstraint],
    progress: &dyn Progress,
) -> Result<Outcome<WorkspaceResult>, StudyError> {
    if !study.workspace.slices.is_empty() {
        return Err(StudyError::invalid(
            "workspace.slices",
            "slices in x, y, z belong to translational studies; a [task_space] study maps its \
             own coordinates with [[task_space.maps]]",
        ));
    }
    let run = task_space::workspace(robot, spec, &study.sampling, constraints, progress)?;
    Ok(Outcome {
        result: WorkspaceResult {
            title: study.title.clone(),
            mechanism: robot.kind().into(),
            domain_volume: run.result.domain_volume,
            estimate: run.result.estimate,
            slices: Vec::new(),
            task_space: Some(run.result.task_space),
        },
        artifacts: run.artifacts,
        summary: run.summary,
    })
}

/// The robot file and `[task_space]` section of a task-space study: `None` for a translational
/// study (no section, a mechanism whose task is the platform position).
///
/// # Errors
/// [`StudyError::Invalid`] at `task_space` for a section with a mechanism that is not a robot
/// file, or for a robot file whose task is not `["x", "y", "z"]` without one.
fn task_space_of<M: StudyMechanism>(
    study: &WorkspaceStudy<M>,
) -> Result<Option<(&RobotFileSpec, &TaskSpaceSpec)>, StudyError> {
    let robot = study.mechanism.robot_file();
    match (robot, &study.task_space) {
        (Some(robot), Some(spec)) => Ok(Some((robot, spec))),
        (None, Some(_)) => Err(StudyError::invalid(
            "task_space",
            format!(
                "a [task_space] study takes a robot file ([mechanism.robot_file]); {} is \
                 studied by platform position",
                study.mechanism.kind()
            ),
        )),
        (Some(robot), None) => {
            let task = robot.model()?.task_names();
            if task == ["x", "y", "z"] {
                Ok(None)
            } else {
                Err(StudyError::invalid(
                    "task_space",
                    format!(
                        "this robot's task is {task:?}: give [task_space] with its kind and the \
                         box of the sampled coordinates (docs/studies.md)"
                    ),
                ))
            }
        }
        (None, None) => Ok(None),
    }
}

fn summarise(outcome: &mut Outcome<WorkspaceResult>) {
    let r = &outcome.result;
    let e = &r.estimate;
    let lines = [
        format!(
            "{}: W = {:.6e} ± {:.2e} m³, η = {:.6e} ± {:.2e} m³, GCI = {}",
            r.mechanism,
            e.volume,
            e.volume_se,
            e.eta,
            e.eta_se,
            e.gci.map_or("-".into(), |g| format!("{g:.5}")),
        ),
        format!(
            "{} of {} points inside ({}); domain {:.6e} m³",
            e.n_inside, e.n_points, e.error_model, r.domain_volume
        ),
    ];
    outcome.summary.extend(lines);
    let warning = e.resolution_warning(r.domain_volume, "m³");
    outcome.summary.extend(warning);
}

const AXIS_NAMES: [&str; 3] = ["x (m)", "y (m)", "z (m)"];

/// Adds slice `number`'s table and heat map to `artifacts` and returns its summary.
fn slice_artifacts(
    artifacts: &mut Vec<Artifact>,
    number: usize,
    plane: Plane,
    at: f64,
    n: usize,
    s: &Slice,
) -> SliceSummary {
    let (a, b, normal) = plane.axes();
    let stem = format!("slice-{number}-{plane:?}").to_lowercase();
    let (csv, svg) = (format!("{stem}.csv"), format!("{stem}.svg"));
    let names = ["x", "y", "z"];
    let mut table = Table::new([names[a], names[b], "inside", "inverse_condition"]);
    table.rows = s
        .values
        .iter()
        .enumerate()
        .map(|(k, v)| {
            vec![
                s.u[k % n].into(),
                s.v[k / n].into(),
                v.is_some().into(),
                (*v).into(),
            ]
        })
        .collect();
    let field = chart::Heatmap {
        colour_axis: "1/κ".into(),
        x: s.u.clone(),
        y: s.v.clone(),
        values: s.values.clone(),
    };
    let title = format!("1/κ on {} = {at} m", names[normal]);
    let chart = Chart::heatmap(title, AXIS_NAMES[a], AXIS_NAMES[b], field);
    artifacts.push(Artifact::Table {
        name: csv.clone(),
        table,
    });
    artifacts.push(Artifact::Chart {
        name: svg.clone(),
        chart: Box::new(chart),
    });
    let inside = s.values.iter().flatten().count();
    SliceSummary {
        plane,
        at,
        cells: n,
        inside_fraction: inside as f64 / s.values.len() as f64,
        max_inverse_condition: s.values.iter().flatten().copied().reduce(f64::max),
        csv,
        svg,
    }
}
