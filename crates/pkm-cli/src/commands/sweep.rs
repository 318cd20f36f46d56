//! `pkm sweep FILE`: an exhaustive grid over named design variables, a weighted utility
//! U = Σ wᵢ ηᵢ of any indices (maximised), lattice refinement around the optimum, the landscape
//! as CSV and heat maps of pairs of variables through the optimum.
//!
//! Refinement is `pkm_optimizers::lattice_refine_from` from the grid optimum (the grid is not
//! evaluated twice): each `[[sweep.refine]]` level searches a window of ±`half_width` steps of
//! `step` around the optimum so far, re-centred while the optimum improves on the window's open
//! edge. A level that overrides index settings
//! (e.g. a finer η1 rule) starts a new stage: a grid on its window with the new settings, whose
//! optimum replaces the old one (values under different settings are not compared), then the
//! level itself, as the Linear Delta search of Miller 2004 §2.2.3 does.

use pkm_study::StudyMechanism as _;
use super::{Context, Report, Run};
use crate::CliError;
use crate::grid::{GridOutcome, 
    self, GridStudy, NodeOutcome, Prepared, Shard, landscape_header, landscape_rows,
};
use crate::indices::{IndexName, IndexSettings};
use crate::output::{Output, StudyEcho, cell, short};
use crate::plot::{self, Heatmap, Marker};
use crate::study::units::Real;
use crate::study::{self, StudyFile};
use pkm_optimizers::{
    GridSearch, LatticeLevel, Sense, grid_search, lattice_refine_from, lattice_window,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, Progress};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::PathBuf;
use toml::Spanned;

/// Arguments of `pkm sweep`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
    /// Evaluate only part I of N of the grid (join the parts with `pkm merge`).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
}

/// The `[sweep]` section.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// Weights wᵢ of the utility Σ wᵢ ηᵢ, maximised (a negative weight minimises).
    pub objective: Spanned<BTreeMap<IndexName, Real>>,
    /// Further indices for the landscape.
    #[serde(default)]
    pub report: Vec<Spanned<IndexName>>,
    /// Refinement levels around the grid optimum, in order.
    #[serde(default)]
    pub refine: Vec<RefineLevel>,
    /// Heat maps of two variables through the optimum (default: the first two variables).
    #[serde(default)]
    pub heatmaps: Vec<HeatmapSpec>,
}

/// One `[[sweep.refine]]` level.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineLevel {
    /// Lattice step, in every variable's unit.
    pub step: Spanned<f64>,
    /// Window half-width in steps.
    pub half_width: usize,
    /// Override of `[indices] eta1_points` from this level on.
    pub eta1_points: Option<usize>,
    /// Override of `[indices] eta1_paper_grid` from this level on.
    pub eta1_paper_grid: Option<bool>,
}

impl RefineLevel {
    fn lattice(&self) -> LatticeLevel {
        LatticeLevel {
            step: *self.step.get_ref(),
            half_width: self.half_width,
        }
    }

    /// The settings from this level on, when it overrides any.
    fn overrides(&self, current: IndexSettings) -> Option<IndexSettings> {
        (self.eta1_points.is_some() || self.eta1_paper_grid.is_some()).then(|| IndexSettings {
            eta1_points: self.eta1_points.unwrap_or(current.eta1_points),
            eta1_paper_grid: self.eta1_paper_grid.unwrap_or(current.eta1_paper_grid),
        })
    }
}

/// A `[[sweep.heatmaps]]` pair.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeatmapSpec {
    /// Variable along x.
    pub x: Spanned<String>,
    /// Variable along y.
    pub y: Spanned<String>,
}

/// A design with its index values and utility.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// Variable values.
    pub design: BTreeMap<String, f64>,
    /// Index values.
    pub indices: BTreeMap<String, f64>,
    /// Σ wᵢ ηᵢ.
    pub utility: f64,
}

/// The `result` of a complete sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepResult {
    /// The study's title.
    pub title: Option<String>,
    /// The mechanism kind.
    pub mechanism: String,
    /// Variables in grid order: name, from, to, nodes.
    pub variables: Vec<(String, f64, f64, usize)>,
    /// The weights.
    pub objective: BTreeMap<String, f64>,
    /// Grid nodes.
    pub nodes: usize,
    /// Infeasible nodes.
    pub infeasible: usize,
    /// The best node of the grid and its flat index.
    pub grid_optimum: (usize, Point),
    /// The refined optimum (the grid optimum without refinement).
    pub optimum: Point,
    /// Designs evaluated by the refinement.
    pub refinement_evaluations: usize,
}

/// The utility terms (index, weight) with non-zero weight, in index order.
fn terms(section: &SweepSection) -> Vec<(IndexName, f64)> {
    section
        .objective
        .get_ref()
        .iter()
        .filter(|(_, w)| w.0 != 0.0)
        .map(|(i, w)| (*i, w.0))
        .collect()
}

/// Σ wᵢ ηᵢ over `terms`, `values` holding `indices` in order.
fn utility(terms: &[(IndexName, f64)], indices: &[IndexName], values: &[f64]) -> f64 {
    terms.iter().fold(0.0, |sum, (index, weight)| {
        let k = indices.iter().position(|i| i == index).unwrap_or(0);
        sum + weight * values.get(k).copied().unwrap_or(f64::NAN)
    })
}

/// The indices a sweep evaluates (utility terms, then reported ones), in index order, with
/// where each was asked for.
fn requested(section: &Spanned<SweepSection>) -> Vec<(IndexName, Range<usize>)> {
    let s = section.get_ref();
    let mut all: Vec<(IndexName, Range<usize>)> = terms(s)
        .into_iter()
        .map(|(i, _)| (i, s.objective.span()))
        .chain(s.report.iter().map(|r| (*r.get_ref(), r.span())))
        .collect();
    all.sort_by_key(|(i, _)| *i);
    all.dedup_by_key(|(i, _)| *i);
    all
}

/// The indices a sweep of `file` evaluates, in order, with where each was asked for.
///
/// # Errors
/// A study error when there is no `[sweep]` section or no non-zero weight.
pub fn requested_indices(
    file: &StudyFile<GridStudy>,
) -> Result<Vec<(IndexName, Range<usize>)>, CliError> {
    let section = section(file)?;
    if terms(section.get_ref()).is_empty() {
        return Err(file.error_at(
            section.get_ref().objective.span(),
            "objective: give at least one non-zero weight",
        ));
    }
    Ok(requested(section))
}

fn section(file: &StudyFile<GridStudy>) -> Result<&Spanned<SweepSection>, CliError> {
    file.study
        .sweep
        .as_ref()
        .ok_or_else(|| file.error_at(0..0, "missing [sweep] section (objective = { ... })"))
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let file: StudyFile<GridStudy> = study::load(&self.file)?;
        let echo = StudyEcho {
            file: self.file.display().to_string(),
            text: file.text.clone(),
        };
        let requested = requested_indices(&file)?;
        let prepared = grid::prepare(&file, &requested)?;
        let indices: Vec<IndexName> = requested.iter().map(|(i, _)| *i).collect();
        let shard = self.shard.unwrap_or(Shard::WHOLE);
        let settings = file.study.indices;
        match grid::evaluate_or_write_shard(
            "sweep",
            echo.clone(),
            &prepared,
            &indices,
            settings,
            shard,
            context,
        )? {
            GridOutcome::Shard(report) => Ok(report),
            GridOutcome::Whole(outcomes) => finish(&file, echo, &prepared, outcomes, context),
        }
    }
}

/// The utility of a design as an [`Objective`] (negated: the searches minimise).
struct UtilityObjective<'a> {
    prepared: &'a Prepared,
    terms: &'a [(IndexName, f64)],
    indices: Vec<IndexName>,
    settings: IndexSettings,
    bounds: Vec<Bounds>,
}

impl Objective for UtilityObjective<'_> {
    fn dimension(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn value(&self, design: &[f64]) -> Result<f64, ObjectiveError> {
        match self
            .prepared
            .evaluator
            .evaluate(design, &self.indices, self.settings)
        {
            Ok(Ok(values)) => Ok(-utility(self.terms, &self.indices, &values)),
            Ok(Err(reason)) => Err(ObjectiveError::infeasible(reason)),
            Err(CliError::Cancelled) => Err(ObjectiveError::Cancelled),
            Err(e) => Err(ObjectiveError::infeasible(e.to_string())),
        }
    }
}

/// The refined optimum: design, negated utility, the settings of the last stage, evaluations.
struct Refined {
    best: Vec<f64>,
    settings: IndexSettings,
    evaluations: usize,
}

fn refine(
    prepared: &Prepared,
    terms: &[(IndexName, f64)],
    mut settings: IndexSettings,
    levels: &[RefineLevel],
    (mut best, mut best_value): (Vec<f64>, f64),
    progress: &dyn Progress,
) -> Result<Refined, CliError> {
    let grid_axes = prepared.grid.axes();
    let bounds = prepared.grid.search.bounds();
    let indices: Vec<IndexName> = terms.iter().map(|(i, _)| *i).collect();
    let mut coarse = grid_axes.to_vec();
    let mut evaluations = 0;
    for level in levels {
        let lattice = level.lattice();
        let overrides = level.overrides(settings);
        settings = overrides.unwrap_or(settings);
        let objective = UtilityObjective {
            prepared,
            terms,
            indices: indices.clone(),
            settings,
            bounds: bounds.clone(),
        };
        if overrides.is_some() {
            let window = lattice_window(&bounds, grid_axes, &best, &lattice)?;
            let stage = grid_search(&objective, Sense::Minimise, &GridSearch::new(window.clone())?, progress)?;
            evaluations += stage.evaluations;
            (best, best_value) = (stage.best, stage.best_value);
            coarse = window;
        }
        let refined = lattice_refine_from(
            &objective,
            Sense::Minimise,
            &coarse,
            (best, best_value),
            &[lattice],
            progress,
        )?;
        evaluations += refined.evaluations;
        (best, best_value) = (refined.best, refined.best_value);
    }
    if let Some(last) = levels.last() {
        let step = *last.step.get_ref();
        for (v, axis) in best.iter_mut().zip(grid_axes) {
            if axis.upper() > axis.lower() {
                *v = on_lattice(*v, step);
            }
        }
    }
    Ok(Refined {
        best,
        settings,
        evaluations,
    })
}

/// `v` on the lattice of `step` when `1/step` is an integer (0.1, 0.05, 0.01, …): removes the
/// round-off of `lower + i·step`; unchanged otherwise.
fn on_lattice(v: f64, step: f64) -> f64 {
    let scale = (1.0 / step).round();
    if scale >= 1.0 && ((1.0 / step) - scale).abs() < 1e-9 * scale {
        (v * scale).round() / scale
    } else {
        v
    }
}

fn point(grid_names: &[String], design: &[f64], indices: &[IndexName], values: &[f64], u: f64) -> Point {
    Point {
        design: grid_names.iter().cloned().zip(design.iter().copied()).collect(),
        indices: indices
            .iter()
            .map(|i| i.key().to_owned())
            .zip(values.iter().copied())
            .collect(),
        utility: u,
    }
}

/// Finishes a sweep from every node's outcome: optimum, refinement, landscape CSV, heat maps,
/// `results.json`. A single run and `pkm merge` of its shards both end here, so they write the
/// same bytes.
///
/// # Errors
/// No feasible node; search errors; I/O; [`CliError::Cancelled`].
pub fn finish(
    file: &StudyFile<GridStudy>,
    echo: StudyEcho,
    prepared: &Prepared,
    outcomes: Vec<NodeOutcome>,
    context: &Context,
) -> Result<Report, CliError> {
    let section = section(file)?.get_ref();
    let indices: Vec<IndexName> = requested_indices(file)?
        .into_iter()
        .map(|(i, _)| i)
        .collect();
    let terms = terms(section);
    let grid = &prepared.grid;
    let utilities: Vec<Option<f64>> = outcomes
        .iter()
        .map(|o| o.as_ref().ok().map(|v| utility(&terms, &indices, v)))
        .collect();
    // The first node of smallest −U, the rule of `pkm_optimizers::grid_search`.
    let negated = utilities.iter().map(|u| u.map(|u| -u));
    let best = Sense::Minimise.best(negated);
    let Some((best_node, best_value)) = best else {
        let reason = outcomes.iter().find_map(|o| o.as_ref().err()).cloned().unwrap_or_default();
        return Err(CliError::Invalid(format!(
            "no feasible design among {} nodes (last reason: {reason})",
            outcomes.len()
        )));
    };
    let best_design = grid.design(best_node);
    let best_values = outcomes[best_node].clone().unwrap_or_default();
    let grid_point = point(&grid.names, &best_design, &indices, &best_values, -best_value);
    context.progress.phase("refining");
    let settings = file.study.indices;
    let (optimum, evaluations) = if section.refine.is_empty() {
        (grid_point.clone(), 0)
    } else {
        let refined = refine(
            prepared,
            &terms,
            settings,
            &section.refine,
            (best_design.clone(), best_value),
            &context.progress,
        )?;
        let values = prepared
            .evaluator
            .evaluate(&refined.best, &indices, refined.settings)?
            .map_err(|r| CliError::Invalid(format!("the refined optimum is infeasible: {r}")))?;
        let u = utility(&terms, &indices, &values);
        (point(&grid.names, &refined.best, &indices, &values, u), refined.evaluations)
    };
    let mut out = Output::create(&context.out)?;
    let header = landscape_header(grid, &indices, &["utility"]);
    out.write_csv(
        "landscape.csv",
        &header,
        landscape_rows(grid, &outcomes, indices.len(), |k| vec![cell(utilities[k])]),
    )?;
    let pairs = heatmap_pairs(file, section)?;
    for (x, y) in pairs {
        write_heatmap(&mut out, grid, &utilities, best_node, &optimum, (x, y))?;
    }
    let mut report = Report::default();
    let show = |p: &Point| {
        let design: Vec<String> = grid
            .names
            .iter()
            .filter_map(|k| p.design.get(k).map(|v| format!("{k} = {}", short(*v))))
            .collect();
        let values: Vec<String> = p.indices.iter().map(|(k, v)| format!("{k} = {v:.6}")).collect();
        format!("{}; {}; U = {:.6}", design.join(", "), values.join(", "), p.utility)
    };
    let infeasible = outcomes.iter().filter(|o| o.is_err()).count();
    report.line(format!("{} nodes, {infeasible} infeasible", outcomes.len()));
    report.line(format!("grid optimum (node {best_node}): {}", show(&grid_point)));
    if !section.refine.is_empty() {
        report.line(format!("refined optimum ({evaluations} evaluations): {}", show(&optimum)));
    }
    let result = SweepResult {
        title: file.study.title.clone(),
        mechanism: file.study.mechanism.kind().into(),
        variables: grid
            .names
            .iter()
            .zip(grid.axes())
            .map(|(n, a)| (n.clone(), a.lower(), a.upper(), a.n()))
            .collect(),
        objective: section
            .objective
            .get_ref()
            .iter()
            .map(|(i, w)| (i.key().to_owned(), w.0))
            .collect(),
        nodes: outcomes.len(),
        infeasible,
        grid_optimum: (best_node, grid_point),
        optimum,
        refinement_evaluations: evaluations,
    };
    let optimum_values: Vec<f64> = grid
        .names
        .iter()
        .filter_map(|n| result.optimum.design.get(n).copied())
        .collect();
    let scene = grid::design_scene(file, prepared, &optimum_values);
    let caption = format!("{}: the sweep's optimum", result.mechanism);
    out.write_robot(&mut report, &caption, scene)?;
    let path = out.finish("sweep", echo, result)?;
    report.line(format!("wrote {}", path.display()));
    Ok(report)
}

/// The variable pairs of the heat maps, as axis numbers.
fn heatmap_pairs(
    file: &StudyFile<GridStudy>,
    section: &SweepSection,
) -> Result<Vec<(usize, usize)>, CliError> {
    let names = &file.study.variables;
    let find = |name: &Spanned<String>| {
        names
            .iter()
            .position(|v| v.name.get_ref() == name.get_ref())
            .ok_or_else(|| {
                file.error_at(name.span(), format!("`{}` is not one of the [[variables]]", name.get_ref()))
            })
    };
    if section.heatmaps.is_empty() {
        return Ok(if names.len() >= 2 { vec![(0, 1)] } else { Vec::new() });
    }
    section
        .heatmaps
        .iter()
        .map(|h| Ok((find(&h.x)?, find(&h.y)?)))
        .collect()
}

/// The utility over variables `x`, `y` with the others at the grid optimum's nodes.
fn write_heatmap(
    out: &mut Output,
    grid: &grid::Grid,
    utilities: &[Option<f64>],
    best_node: usize,
    optimum: &Point,
    (x, y): (usize, usize),
) -> Result<(), CliError> {
    let Some(through) = grid.search.node_index(best_node) else {
        return Ok(());
    };
    let (nx, ny) = (grid.axes()[x].n(), grid.axes()[y].n());
    let mut values = Vec::with_capacity(nx * ny);
    for iy in 0..ny {
        for ix in 0..nx {
            let mut index = through.clone();
            index[x] = ix;
            index[y] = iy;
            let flat = grid.search.flat_index(&index);
            values.push(flat.and_then(|k| utilities.get(k).copied().flatten()));
        }
    }
    let (xn, yn) = (&grid.names[x], &grid.names[y]);
    let stem = format!("heatmap-{xn}-{yn}");
    let xs = grid.axes()[x].nodes();
    let ys = grid.axes()[y].nodes();
    out.write_csv(
        &format!("{stem}.csv"),
        &[xn.as_str(), yn.as_str(), "utility"],
        values.iter().enumerate().map(|(k, v)| {
            vec![format!("{}", xs[k % nx]), format!("{}", ys[k / nx]), cell(*v)]
        }),
    )?;
    let best = grid.design(best_node);
    let mut markers = vec![Marker {
        x: best[x],
        y: best[y],
        label: "grid optimum".into(),
    }];
    if let (Some(ox), Some(oy)) = (optimum.design.get(xn), optimum.design.get(yn)) {
        markers.push(Marker {
            x: *ox,
            y: *oy,
            label: "refined".into(),
        });
    }
    let map = Heatmap {
        title: format!("utility over {xn}, {yn} through the grid optimum"),
        x_label: xn.clone(),
        y_label: yn.clone(),
        z_label: "U = Σ w·η".into(),
        x: xs,
        y: ys,
        values,
        markers,
    };
    out.write_svg(&format!("{stem}.svg"), |path| plot::heatmap(&map, path))?;
    Ok(())
}
