//! The sweep study: an exhaustive grid over named design variables, a weighted utility
//! U = Σ wᵢ ηᵢ of any indices (maximised), lattice refinement around the optimum
//! (`refine`), the landscape as a table and heat maps of pairs of variables through the
//! optimum.
//!
//! A sweep can be split into shards ([`Shard`]): each part returns its nodes' values, and
//! [`merge`](crate::merge()) of the parts returns the single run's outcome, bit for bit (both
//! end in the same `finish`).

mod refine;

use crate::grid::{self, GridRun, NodeOutcome, Prepared, Shard};
use crate::outcome::{Artifact, Cell, Outcome, Table, short};
use crate::registry::StudyMechanism;
use crate::schema::grid::{GridStudy, IndexName, SweepSection};
use crate::schema::mechanism::MechanismSpec;
use crate::{KeyPath, StudyError};
use pkm_draw::chart::{self, Chart, Marker};
use pkm_optimizers::Sense;
use pkm_traits::Progress;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A sweep study (the `[sweep]` section of a [`GridStudy`]).
pub type SweepStudy<M = MechanismSpec> = GridStudy<M>;

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

/// The result of a complete sweep.
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

/// A sweep's settings, checked: its section, utility terms, indices and heat map pairs.
pub(crate) struct Plan<'a> {
    section: &'a SweepSection,
    /// (index, weight) with non-zero weight, in index order.
    terms: Vec<(IndexName, f64)>,
    /// Every index evaluated (terms, then reported ones), in index order, with its key path.
    pub requested: Vec<(IndexName, KeyPath)>,
    /// Heat maps as axis numbers.
    pairs: Vec<(usize, usize)>,
}

impl Plan<'_> {
    /// The indices evaluated, in order.
    pub(crate) fn indices(&self) -> Vec<IndexName> {
        self.requested.iter().map(|(i, _)| *i).collect()
    }
}

/// Checks the sweep's own settings (the grid is checked by [`grid::prepare`]).
///
/// # Errors
/// [`StudyError::Invalid`] at the offending key: no `[sweep]` section, no non-zero weight, a
/// bad refinement level, a heat map of an unknown variable.
pub(crate) fn plan<M: StudyMechanism>(study: &GridStudy<M>) -> Result<Plan<'_>, StudyError> {
    let section = study.sweep.as_ref().ok_or_else(|| {
        StudyError::invalid("sweep", "missing [sweep] section (objective = { ... })")
    })?;
    let terms: Vec<(IndexName, f64)> = section
        .objective
        .iter()
        .filter(|(_, w)| w.0 != 0.0)
        .map(|(i, w)| (*i, w.0))
        .collect();
    if terms.is_empty() {
        return Err(StudyError::invalid(
            "sweep.objective",
            "give at least one non-zero weight",
        ));
    }
    let objective = KeyPath::root().field("sweep").field("objective");
    let report = KeyPath::root().field("sweep").field("report");
    let mut requested: Vec<(IndexName, KeyPath)> = terms
        .iter()
        .map(|(i, _)| (*i, objective.clone().field(i.key())))
        .chain(
            section
                .report
                .iter()
                .enumerate()
                .map(|(k, i)| (*i, report.clone().index(k))),
        )
        .collect();
    requested.sort_by_key(|(i, _)| *i);
    requested.dedup_by_key(|(i, _)| *i);
    refine::check_levels(&section.refine)?;
    let pairs = heatmap_pairs(study, section)?;
    Ok(Plan {
        section,
        terms,
        requested,
        pairs,
    })
}

/// The variable pairs of the heat maps, as axis numbers (default: the first two variables).
fn heatmap_pairs<M: StudyMechanism>(
    study: &GridStudy<M>,
    section: &SweepSection,
) -> Result<Vec<(usize, usize)>, StudyError> {
    let names = &study.variables;
    if section.heatmaps.is_empty() {
        return Ok(if names.len() >= 2 {
            vec![(0, 1)]
        } else {
            Vec::new()
        });
    }
    let find = |k: usize, axis: &str, name: &str| {
        names.iter().position(|v| v.name == name).ok_or_else(|| {
            StudyError::invalid(
                format!("sweep.heatmaps[{k}].{axis}").as_str(),
                format!("`{name}` is not one of the [[variables]]"),
            )
        })
    };
    section
        .heatmaps
        .iter()
        .enumerate()
        .map(|(k, h)| Ok((find(k, "x", &h.x)?, find(k, "y", &h.y)?)))
        .collect()
}

/// Σ wᵢ ηᵢ over `terms`, `values` holding `indices` in order.
fn utility(terms: &[(IndexName, f64)], indices: &[IndexName], values: &[f64]) -> f64 {
    terms.iter().fold(0.0, |sum, (index, weight)| {
        let k = indices.iter().position(|i| i == index).unwrap_or(0);
        sum + weight * values.get(k).copied().unwrap_or(f64::NAN)
    })
}

/// Runs a sweep on the nodes of `shard` ([`Shard::WHOLE`] for a single run): every setting
/// is checked first, then the grid is evaluated; the whole grid is then searched for its
/// optimum, refined, and reported as the landscape table, heat maps (a table and a chart
/// each) and the drawing of the optimum.
///
/// # Errors
/// [`StudyError::Invalid`] for a setting that cannot be used (before any computation) or
/// when no node is feasible; [`StudyError::Optimize`] for a refinement the search refuses;
/// [`StudyError::Cancelled`] when `progress` asks to stop.
pub fn sweep<M: StudyMechanism>(
    study: &SweepStudy<M>,
    shard: Shard,
    progress: &dyn Progress,
) -> Result<Outcome<GridRun<SweepResult>>, StudyError> {
    let plan = plan(study)?;
    let prepared = grid::prepare(study, &plan.requested, progress)?;
    let indices = plan.indices();
    grid::run(&prepared, &indices, study.indices, shard, progress, |o| {
        finish(study, &plan, &prepared, o, progress)
    })
}

/// Finishes a sweep from every node's outcome: optimum, refinement, landscape, heat maps,
/// drawing. A single run and the merge of its shards both end here, so they give the same
/// outcome.
///
/// # Errors
/// No feasible node; search errors; [`StudyError::Cancelled`].
pub(crate) fn finish<M: StudyMechanism>(
    study: &GridStudy<M>,
    plan: &Plan<'_>,
    prepared: &Prepared<M>,
    outcomes: Vec<NodeOutcome>,
    progress: &dyn Progress,
) -> Result<Outcome<SweepResult>, StudyError> {
    let indices = plan.indices();
    let terms = &plan.terms;
    let grid = &prepared.grid;
    let utilities: Vec<Option<f64>> = outcomes
        .iter()
        .map(|o| o.as_ref().ok().map(|v| utility(terms, &indices, v)))
        .collect();
    // The first node of smallest −U, the rule of `pkm_optimizers::grid_search`.
    let negated = utilities.iter().map(|u| u.map(|u| -u));
    let Some((best_node, best_value)) = Sense::Minimise.best(negated) else {
        return Err(grid::no_feasible_design(&outcomes));
    };
    let best_design = grid.design(best_node);
    let best_values = outcomes[best_node].clone().unwrap_or_default();
    let grid_point = point(
        &grid.names,
        &best_design,
        &indices,
        &best_values,
        -best_value,
    );
    progress.phase("refining");
    let (optimum, evaluations) = if plan.section.refine.is_empty() {
        (grid_point.clone(), 0)
    } else {
        let refined = refine::refine(
            prepared,
            terms,
            study.indices,
            &plan.section.refine,
            (best_design, best_value),
            progress,
        )?;
        let values = prepared
            .evaluator
            .evaluate(&refined.best, &indices, refined.settings)?
            .map_err(|r| {
                let m = format!("the refined optimum is infeasible: {r}");
                StudyError::invalid("sweep.refine", m)
            })?;
        let u = utility(terms, &indices, &values);
        let refined_point = point(&grid.names, &refined.best, &indices, &values, u);
        (refined_point, refined.evaluations)
    };
    let infeasible = outcomes.iter().filter(|o| o.is_err()).count();
    let result = SweepResult {
        title: study.title.clone(),
        mechanism: study.mechanism.kind().into(),
        variables: grid
            .names
            .iter()
            .zip(grid.axes())
            .map(|(n, a)| (n.clone(), a.lower(), a.upper(), a.n()))
            .collect(),
        objective: plan
            .section
            .objective
            .iter()
            .map(|(i, w)| (i.key().to_owned(), w.0))
            .collect(),
        nodes: outcomes.len(),
        infeasible,
        grid_optimum: (best_node, grid_point),
        optimum,
        refinement_evaluations: evaluations,
    };
    let mut outcome = Outcome::new(result);
    let landscape = grid::landscape(grid, &outcomes, &indices, &["utility"], |k| {
        vec![utilities[k].into()]
    });
    outcome.artifacts.push(Artifact::Table {
        name: "landscape.csv".into(),
        table: landscape,
    });
    for &pair in &plan.pairs {
        heatmap(&mut outcome, prepared, &utilities, pair);
    }
    summarise(&mut outcome, &grid.names, !plan.section.refine.is_empty());
    let r = &outcome.result;
    let optimum_values: Vec<f64> = grid
        .names
        .iter()
        .filter_map(|n| r.optimum.design.get(n).copied())
        .collect();
    let scene = grid::design_scene(study, prepared, &optimum_values);
    let caption = format!("{}: the sweep's optimum", r.mechanism);
    outcome.robot(caption, scene);
    Ok(outcome)
}

fn point(
    names: &[String],
    design: &[f64],
    indices: &[IndexName],
    values: &[f64],
    utility: f64,
) -> Point {
    Point {
        design: names.iter().cloned().zip(design.iter().copied()).collect(),
        indices: indices
            .iter()
            .map(|i| i.key().to_owned())
            .zip(values.iter().copied())
            .collect(),
        utility,
    }
}

/// The summary lines: nodes, grid optimum, refined optimum.
fn summarise(outcome: &mut Outcome<SweepResult>, names: &[String], refined: bool) {
    let show = |p: &Point| {
        let design: Vec<String> = names
            .iter()
            .filter_map(|k| p.design.get(k).map(|v| format!("{k} = {}", short(*v))))
            .collect();
        let values: Vec<String> = p
            .indices
            .iter()
            .map(|(k, v)| format!("{k} = {v:.6}"))
            .collect();
        format!(
            "{}; {}; U = {:.6}",
            design.join(", "),
            values.join(", "),
            p.utility
        )
    };
    let r = &outcome.result;
    let (best_node, grid_point) = &r.grid_optimum;
    let mut lines = vec![
        format!("{} nodes, {} infeasible", r.nodes, r.infeasible),
        format!("grid optimum (node {best_node}): {}", show(grid_point)),
    ];
    if refined {
        lines.push(format!(
            "refined optimum ({} evaluations): {}",
            r.refinement_evaluations,
            show(&r.optimum)
        ));
    }
    outcome.summary.extend(lines);
}

/// Adds the table and chart of the utility over variables `x`, `y` with the others at the
/// grid optimum's nodes.
fn heatmap<M: StudyMechanism>(
    outcome: &mut Outcome<SweepResult>,
    prepared: &Prepared<M>,
    utilities: &[Option<f64>],
    (x, y): (usize, usize),
) {
    let grid = &prepared.grid;
    let best_node = outcome.result.grid_optimum.0;
    let Some(through) = grid.search.node_index(best_node) else {
        return;
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
    let mut table = Table::new([xn.as_str(), yn.as_str(), "utility"]);
    table.rows = values
        .iter()
        .enumerate()
        .map(|(k, v)| {
            vec![
                Cell::Number(xs[k % nx]),
                Cell::Number(ys[k / nx]),
                (*v).into(),
            ]
        })
        .collect();
    let best = grid.design(best_node);
    let mut markers = vec![Marker {
        x: best[x],
        y: best[y],
        label: "grid optimum".into(),
    }];
    let optimum = &outcome.result.optimum.design;
    if let (Some(ox), Some(oy)) = (optimum.get(xn), optimum.get(yn)) {
        markers.push(Marker {
            x: *ox,
            y: *oy,
            label: "refined".into(),
        });
    }
    let field = chart::Heatmap {
        colour_axis: "U = Σ w·η".into(),
        x: xs,
        y: ys,
        values,
    };
    let title = format!("utility over {xn}, {yn} through the grid optimum");
    let chart = Chart::heatmap(title, xn.clone(), yn.clone(), field).with_markers(markers);
    outcome.artifacts.push(Artifact::Table {
        name: format!("{stem}.csv"),
        table,
    });
    outcome.artifacts.push(Artifact::Chart {
        name: format!("{stem}.svg"),
        chart: Box::new(chart),
    });
}
