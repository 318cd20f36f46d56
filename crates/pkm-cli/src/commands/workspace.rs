//! `pkm workspace FILE`: the workspace of one design under its constraints: volume ± standard
//! error, η = ∫ 1/κ dW and GCI = η/W over common random points, and planar slices of 1/κ as
//! CSV and SVG.

use super::{Context, Report, Run};
use crate::CliError;
use crate::drawing;
use crate::output::{Output, cell};
use crate::plot::{self, Heatmap};
use crate::study::mechanism::{BuildError, ConstraintsSpec, MechanismSpec, WorkspaceVisitor};
use crate::study::sampling::SamplingSpec;
use crate::study::units::Metres;
use crate::study::StudyFile;
use pkm_traits::{ConstrainedWorkspace, Progress};
use pkm_workspace_indices::{
    BoundingBox, Dim, ErrorModel, Plane, PointSet, Slice, TranslationalCondition, VolumeEstimate,
    Workspace,
};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Arguments of `pkm workspace`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

/// The study of `pkm workspace`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceStudy {
    /// Free text.
    pub title: Option<String>,
    /// The design.
    pub mechanism: MechanismSpec,
    /// Its workspace limits.
    pub constraints: Option<toml::Spanned<ConstraintsSpec>>,
    /// The points of the estimate.
    #[serde(default)]
    pub sampling: SamplingSpec,
    /// What to report.
    #[serde(default)]
    pub workspace: WorkspaceSection,
}

/// The `[workspace]` section.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkspaceSection {
    /// Planar sections of 1/κ.
    #[serde(default)]
    pub slices: Vec<SliceSpec>,
}

/// One `[[workspace.slices]]` entry.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliceSpec {
    /// The plane.
    pub plane: Plane,
    /// Its offset along the normal axis (m).
    pub at: Metres,
    /// Cells per side (default 60, at most 1024).
    #[serde(default = "default_cells")]
    pub cells: toml::Spanned<usize>,
}

fn default_cells() -> toml::Spanned<usize> {
    toml::Spanned::new(0..0, 60)
}

/// Largest number of cells per slice side.
pub const MAX_SLICE_CELLS: usize = 1024;

/// The numbers of one workspace estimate.
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

/// A slice's entry in `results.json`.
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
    /// The CSV file.
    pub csv: String,
    /// The SVG file.
    pub svg: String,
}

/// The `result` of `results.json`.
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
}

/// Resolves a study's constraints and checks that the mechanism can evaluate them, with the
/// error at the `[constraints]` table.
///
/// # Errors
/// [`CliError::Study`] for a constraint that does not fit the mechanism.
pub fn constraints_of<T>(
    file: &StudyFile<T>,
    mechanism: &MechanismSpec,
    spec: Option<&toml::Spanned<ConstraintsSpec>>,
) -> Result<Vec<pkm_traits::WorkspaceConstraint>, CliError> {
    let Some(spanned) = spec else {
        return Ok(Vec::new());
    };
    let at = |m: String| file.error_at(spanned.span(), format!("[constraints]: {m}"));
    let constraints = mechanism.constraints(spanned.get_ref()).map_err(at)?;
    match mechanism.with_workspace(&constraints, CheckOnly) {
        Err(BuildError::Constraint(m)) => Err(at(m)),
        // An invalid base design is reported where it is used (a sweep varies it).
        Ok(()) | Err(BuildError::Design(_)) => Ok(constraints),
    }
}

/// Builds the workspace only to check that its constraints apply.
struct CheckOnly;

impl WorkspaceVisitor for CheckOnly {
    type Output = ();
    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        _: &Workspace<'_, M, NQ>,
    ) where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
    }
}

/// What the workspace command computes on a built workspace.
struct Compute<'a> {
    points: &'a PointSet,
    slices: &'a [(Plane, f64, usize)],
    bounds: BoundingBox,
    progress: &'a dyn Progress,
}

impl WorkspaceVisitor for Compute<'_> {
    type Output = Result<(VolumeEstimate, Vec<Slice>), CliError>;

    fn visit<M: ConstrainedWorkspace<3, NQ> + Sync, const NQ: usize>(
        self,
        workspace: &Workspace<'_, M, NQ>,
    ) -> Self::Output
    where
        Dim<NQ>: TranslationalCondition<NQ>,
    {
        self.progress
            .start("workspace points", self.points.points().len() as u64);
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
            .collect::<Result<Vec<_>, CliError>>()?;
        Ok((estimate, slices))
    }
}

const AXIS_NAMES: [&str; 3] = ["x (m)", "y (m)", "z (m)"];

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_study("workspace", &self.file, context, compute)
    }
}

/// Runs the study in `file`, writing the slices to `context.out`; returns the result (for
/// `results.json`), the summary and the output (for [`Output::finish`]).
///
/// # Errors
/// Study errors at their line, index errors, I/O errors, [`CliError::Cancelled`].
pub fn compute(
    file: &StudyFile<WorkspaceStudy>,
    context: &Context,
) -> Result<(WorkspaceResult, Report, Output), CliError> {
    let study = &file.study;
    let constraints = constraints_of(file, &study.mechanism, study.constraints.as_ref())?;
    let mut slices = Vec::new();
    for s in &study.workspace.slices {
        let n = *s.cells.get_ref();
        if n == 0 || n > MAX_SLICE_CELLS {
            return Err(file.error_at(
                s.cells.span(),
                format!("cells: expected a count of cells per side in 1..={MAX_SLICE_CELLS}"),
            ));
        }
        slices.push((s.plane, s.at.0, n));
    }
    let domain = study.sampling.domain(study.mechanism.reach_region()?)?;
    context.progress.phase("sampling points");
    let points = study.sampling.point_set(domain)?;
    let compute = Compute {
        points: &points,
        slices: &slices,
        bounds: domain.region().bounding_box(),
        progress: &context.progress,
    };
    let (estimate, values) = study.mechanism.with_workspace(&constraints, compute)??;
    let mut out = Output::create(&context.out)?;
    let mut summaries = Vec::new();
    for (k, ((plane, at, n), values)) in slices.iter().zip(&values).enumerate() {
        summaries.push(write_slice(&mut out, k + 1, *plane, *at, *n, values)?);
    }
    let estimate = Estimate::from(&estimate);
    let mut report = Report::default();
    report.line(format!(
        "{}: W = {:.6e} ± {:.2e} m³, η = {:.6e} ± {:.2e} m³, GCI = {}",
        study.mechanism.kind(),
        estimate.volume,
        estimate.volume_se,
        estimate.eta,
        estimate.eta_se,
        estimate.gci.map_or("-".into(), |g| format!("{g:.5}")),
    ));
    report.line(format!(
        "{} of {} points inside ({}); domain {:.6e} m³",
        estimate.n_inside,
        estimate.n_points,
        estimate.error_model,
        domain.volume()
    ));
    let scene = drawing::design_scene(&study.mechanism, &constraints, Some(domain.region()));
    let caption = format!("{} in its workspace", study.mechanism.kind());
    drawing::write(&mut out, &mut report, &caption, scene)?;
    let result = WorkspaceResult {
        title: study.title.clone(),
        mechanism: study.mechanism.kind().into(),
        domain_volume: domain.volume(),
        estimate,
        slices: summaries,
    };
    report.line(format!("wrote {}", out.dir().join("results.json").display()));
    Ok((result, report, out))
}

fn write_slice(
    out: &mut Output,
    number: usize,
    plane: Plane,
    at: f64,
    n: usize,
    s: &Slice,
) -> Result<SliceSummary, CliError> {
    let (a, b, normal) = plane.axes();
    let stem = format!("slice-{number}-{plane:?}").to_lowercase();
    let (csv, svg) = (format!("{stem}.csv"), format!("{stem}.svg"));
    let names = ["x", "y", "z"];
    let header = [names[a], names[b], "inside", "inverse_condition"];
    let rows = s.values.iter().enumerate().map(|(k, v)| {
        vec![
            format!("{}", s.u[k % n]),
            format!("{}", s.v[k / n]),
            u8::from(v.is_some()).to_string(),
            cell(*v),
        ]
    });
    out.write_csv(&csv, &header, rows)?;
    let map = Heatmap {
        title: format!("1/κ on {} = {at} m", names[normal]),
        x_label: AXIS_NAMES[a].into(),
        y_label: AXIS_NAMES[b].into(),
        z_label: "1/κ".into(),
        x: s.u.clone(),
        y: s.v.clone(),
        values: s.values.clone(),
        markers: Vec::new(),
    };
    out.write_svg(&svg, |path| plot::heatmap(&map, path))?;
    let inside = s.values.iter().flatten().count();
    Ok(SliceSummary {
        plane,
        at,
        cells: n,
        inside_fraction: inside as f64 / s.values.len() as f64,
        max_inverse_condition: s.values.iter().flatten().copied().reduce(f64::max),
        csv,
        svg,
    })
}
