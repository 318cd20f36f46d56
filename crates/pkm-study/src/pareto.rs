//! The Pareto study: the non-dominated designs of two or more indices (all maximised) over the
//! study's grid, and for two indices the range of weights w ∈ [0, 1] for which each design
//! maximises w·η₁ + (1 − w)·η₂ (`pkm_optimizers::pareto_front`): what a fixed weighting hides.
//!
//! With more than two indices the front is reported without weight regions (they are polytopes
//! of the weight simplex); the weighted optima of the study's `weights` are reported for any
//! number of indices. Like a sweep, a Pareto study can be split into shards and merged.

use crate::grid::{self, GridRun, NodeOutcome, Prepared, Shard};
use crate::outcome::{Artifact, Cell, Outcome, Table, short};
use crate::registry::StudyMechanism;
use crate::schema::grid::{GridStudy, IndexName};
use crate::schema::mechanism::MechanismSpec;
use crate::{KeyPath, StudyError};
use pkm_draw::chart::{Chart, Colour, LegendPosition, Marker, Series, SeriesStyle};
use pkm_optimizers::{Sense, pareto_front};
use pkm_traits::Progress;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A Pareto study (the `[pareto]` section of a [`GridStudy`]).
pub type ParetoStudy<M = MechanismSpec> = GridStudy<M>;

/// A design of the front.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrontPoint {
    /// Grid node.
    pub node: usize,
    /// Variable values.
    pub design: BTreeMap<String, f64>,
    /// Objective values, in objective order.
    pub values: Vec<f64>,
    /// For two objectives, `[w_min, w_max]` of the weights w for which this design maximises
    /// w·η₁ + (1 − w)·η₂; `None` when no weight selects it (a non-convex part of the front) or
    /// with more than two objectives.
    pub weight_range: Option<(f64, f64)>,
}

/// The optimum of one weighting.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WeightedOptimum {
    /// The weights, in objective order.
    pub weights: Vec<f64>,
    /// Grid node of the optimum (the first of equal ones).
    pub node: usize,
    /// Its values.
    pub values: Vec<f64>,
    /// Σ wᵢ ηᵢ.
    pub utility: f64,
}

/// The result of a complete Pareto study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParetoResult {
    /// The study's title.
    pub title: Option<String>,
    /// The mechanism kind.
    pub mechanism: String,
    /// The objectives.
    pub objectives: Vec<IndexName>,
    /// Grid nodes.
    pub nodes: usize,
    /// Infeasible nodes.
    pub infeasible: usize,
    /// The non-dominated designs, by node.
    pub front: Vec<FrontPoint>,
    /// The optima of the study's weightings.
    pub weighted_optima: Vec<WeightedOptimum>,
}

/// A Pareto study's settings, checked.
pub(crate) struct Plan {
    /// The objectives with their key paths.
    pub requested: Vec<(IndexName, KeyPath)>,
    /// The weightings, each one weight per objective.
    weightings: Vec<Vec<f64>>,
}

impl Plan {
    /// The objectives, in order.
    pub(crate) fn indices(&self) -> Vec<IndexName> {
        self.requested.iter().map(|(i, _)| *i).collect()
    }
}

/// Checks the `[pareto]` section: two or more different objectives, one weight per objective
/// in each weighting.
///
/// # Errors
/// [`StudyError::Invalid`] at `pareto`, `pareto.objectives` or `pareto.weights[k]`.
pub(crate) fn plan<M: StudyMechanism>(study: &GridStudy<M>) -> Result<Plan, StudyError> {
    let section = study.pareto.as_ref().ok_or_else(|| {
        StudyError::invalid("pareto", "missing [pareto] section (objectives = [...])")
    })?;
    let list = &section.objectives;
    let mut unique = list.clone();
    unique.sort();
    unique.dedup();
    if list.len() < 2 || unique.len() != list.len() {
        return Err(StudyError::invalid(
            "pareto.objectives",
            "expected two or more different indices",
        ));
    }
    let path = KeyPath::root().field("pareto").field("objectives");
    let requested = list
        .iter()
        .enumerate()
        .map(|(k, i)| (*i, path.clone().index(k)))
        .collect();
    let m = list.len();
    let mut weightings = Vec::new();
    for (k, w) in section.weights.iter().enumerate() {
        if w.len() != m {
            return Err(StudyError::invalid(
                format!("pareto.weights[{k}]").as_str(),
                format!("expected {m} numbers, one per objective"),
            ));
        }
        weightings.push(w.iter().map(|r| r.0).collect());
    }
    Ok(Plan {
        requested,
        weightings,
    })
}

/// Runs a Pareto study on the nodes of `shard` ([`Shard::WHOLE`] for a single run): every
/// setting is checked first; the whole grid then gives the landscape and front tables, the
/// front's chart and the drawing of the first weighting's optimum.
///
/// # Errors
/// [`StudyError::Invalid`] for a setting that cannot be used (before any computation),
/// [`StudyError::NoFeasibleDesign`], [`StudyError::Cancelled`] when `progress` asks to stop.
pub fn pareto<M: StudyMechanism>(
    study: &ParetoStudy<M>,
    shard: Shard,
    progress: &dyn Progress,
) -> Result<Outcome<GridRun<ParetoResult>>, StudyError> {
    let plan = plan(study)?;
    let prepared = grid::prepare(study, &plan.requested, progress)?;
    let indices = plan.indices();
    grid::run(&prepared, &indices, study.indices, shard, progress, |o| {
        finish(study, &plan, &prepared, &o, progress)
    })
}

/// Finishes a Pareto study from every node's outcome (a single run and the merge of its
/// shards both end here).
///
/// # Errors
/// [`StudyError::NoFeasibleDesign`]; the front's errors.
pub(crate) fn finish<M: StudyMechanism>(
    study: &GridStudy<M>,
    plan: &Plan,
    prepared: &Prepared<M>,
    outcomes: &[NodeOutcome],
    progress: &dyn Progress,
) -> Result<Outcome<ParetoResult>, StudyError> {
    let indices = plan.indices();
    let m = indices.len();
    let feasible: Vec<(usize, &[f64])> = outcomes
        .iter()
        .enumerate()
        .filter_map(|(k, o)| o.as_ref().ok().map(|v| (k, v.as_slice())))
        .collect();
    if feasible.is_empty() {
        return Err(grid::no_feasible_design(outcomes));
    }
    progress.phase("non-dominated set");
    let values: Vec<&[f64]> = feasible.iter().map(|(_, v)| *v).collect();
    let pareto = pareto_front(&values, &vec![Sense::Maximise; m])?;
    let values_of = |node: usize| outcomes[node].as_ref().map(Vec::as_slice).unwrap_or(&[]);
    let grid = &prepared.grid;
    let front: Vec<FrontPoint> = pareto
        .members
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            let node = feasible[i].0;
            let weights = pareto.weight_intervals.as_ref();
            FrontPoint {
                node,
                design: grid.names.iter().cloned().zip(grid.design(node)).collect(),
                values: values_of(node).to_vec(),
                weight_range: weights.and_then(|w| w.get(k).copied().flatten()),
            }
        })
        .collect();
    let weighted_optima: Vec<WeightedOptimum> = plan
        .weightings
        .iter()
        .filter_map(|w| {
            let u = |v: &[f64]| w.iter().zip(v).fold(0.0, |s, (w, v)| s + w * v);
            let (best, utility) = Sense::Maximise.best(values.iter().map(|v| Some(u(v))))?;
            let node = feasible[best].0;
            Some(WeightedOptimum {
                weights: w.clone(),
                node,
                values: values_of(node).to_vec(),
                utility,
            })
        })
        .collect();
    let background: Vec<(f64, f64)> = feasible.iter().map(|(_, v)| (v[0], v[1])).collect();
    let mut outcome = Outcome::new(ParetoResult {
        title: study.title.clone(),
        mechanism: study.mechanism.kind().into(),
        objectives: indices,
        nodes: outcomes.len(),
        infeasible: outcomes.len() - feasible.len(),
        front,
        weighted_optima,
    });
    let landscape = grid::landscape(grid, outcomes, &outcome.result.objectives, &[], |_| {
        Vec::new()
    });
    outcome.artifacts.push(Artifact::Table {
        name: "landscape.csv".into(),
        table: landscape,
    });
    outcome.artifacts.push(Artifact::Table {
        name: "front.csv".into(),
        table: front_table(prepared, &outcome.result),
    });
    outcome.artifacts.push(Artifact::Chart {
        name: "front.svg".into(),
        chart: Box::new(front_chart(&outcome.result, background)),
    });
    summarise(&mut outcome, &grid.names, prepared);
    robot(&mut outcome, study, prepared);
    Ok(outcome)
}

/// The front: node, variables, objectives, and the weight range that selects each design.
fn front_table<M>(prepared: &Prepared<M>, r: &ParetoResult) -> Table {
    let grid = &prepared.grid;
    let mut header = vec!["node".to_owned()];
    header.extend(grid.names.iter().cloned());
    header.extend(r.objectives.iter().map(|i| i.key().to_owned()));
    header.extend(["w_min".to_owned(), "w_max".to_owned()]);
    let mut table = Table::new(header);
    for p in &r.front {
        let mut row = vec![Cell::from(p.node)];
        row.extend(grid.design(p.node).into_iter().map(Cell::Number));
        row.extend(p.values.iter().copied().map(Cell::Number));
        let (lo, hi) = p
            .weight_range
            .map_or((None, None), |(a, b)| (Some(a), Some(b)));
        row.extend([lo.into(), hi.into()]);
        table.rows.push(row);
    }
    table
}

/// The first two objectives of every feasible design (`background`, grey), the front (blue,
/// joined in order of the first objective) and the weighted optima (labelled).
fn front_chart(r: &ParetoResult, background: Vec<(f64, f64)>) -> Chart {
    let (x, y) = (r.objectives[0].key(), r.objectives[1].key());
    let mut front: Vec<(f64, f64)> = r.front.iter().map(|p| (p.values[0], p.values[1])).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    let markers: Vec<Marker> = r
        .weighted_optima
        .iter()
        .map(|o| Marker {
            x: o.values[0],
            y: o.values[1],
            label: format!("w = ({})", shorts(&o.weights)),
        })
        .collect();
    let series = vec![
        Series::points("designs", background).with_colour(Colour::Rgb([170, 170, 170])),
        Series::styled("non-dominated", SeriesStyle::LineAndPoints, front)
            .with_colour(Colour::Rgb([0, 0, 255])),
    ];
    let title = format!("non-dominated designs: {x} vs {y}");
    Chart::series(title, x, y, series)
        .with_markers(markers)
        .with_legend(LegendPosition::LowerLeft)
}

/// Numbers in short form, comma-separated.
fn shorts(values: &[f64]) -> String {
    values
        .iter()
        .map(|x| short(*x))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The summary: counts, the designs some weight selects (by weight), the weighted optima.
fn summarise<M>(outcome: &mut Outcome<ParetoResult>, names: &[String], prepared: &Prepared<M>) {
    let r = &outcome.result;
    let (x, y) = (r.objectives[0].key(), r.objectives[1].key());
    let selected_count = r.front.iter().filter(|p| p.weight_range.is_some()).count();
    let mut lines = vec![format!(
        "{} nodes, {} infeasible; {} non-dominated designs, {selected_count} selected by some \
         weight w of w·{x} + (1 − w)·{y}",
        r.nodes,
        r.infeasible,
        r.front.len(),
    )];
    let mut selected: Vec<(f64, f64, &FrontPoint)> = r
        .front
        .iter()
        .filter_map(|p| p.weight_range.map(|(lo, hi)| (lo, hi, p)))
        .collect();
    selected.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (lo, hi, p) in selected {
        let design: Vec<String> = names
            .iter()
            .zip(prepared.grid.design(p.node))
            .map(|(k, v)| format!("{k} = {}", short(v)))
            .collect();
        lines.push(format!(
            "  w in [{lo:.4}, {hi:.4}]: {} -> ({})",
            design.join(", "),
            shorts(&p.values)
        ));
    }
    for o in &r.weighted_optima {
        lines.push(format!(
            "weights ({}): node {} -> ({})",
            shorts(&o.weights),
            o.node,
            shorts(&o.values)
        ));
    }
    outcome.summary.extend(lines);
}

/// The drawing of the first weighting's optimum (none without weights: a warning line).
fn robot<M: StudyMechanism>(
    outcome: &mut Outcome<ParetoResult>,
    study: &GridStudy<M>,
    prepared: &Prepared<M>,
) {
    let Some(o) = outcome.result.weighted_optima.first() else {
        outcome.line("warning: no drawing of the robot: the study gives no weights");
        return;
    };
    let node = o.node;
    let scene = grid::design_scene(study, prepared, &prepared.grid.design(node));
    let caption = format!(
        "{}: the weighted optimum (node {node})",
        outcome.result.mechanism
    );
    outcome.robot(caption, scene);
}
