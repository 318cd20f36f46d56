//! `pkm pareto FILE`: the non-dominated designs of two or more indices (all maximised) over the
//! study's grid, and for two indices the range of weights w ∈ [0, 1] for which each design
//! maximises w·η₁ + (1 − w)·η₂: what a fixed weighting hides.
//!
//! With more than two indices the front is reported without weight regions (they are polytopes
//! of the weight simplex); the weighted optima of the study's `weights` are reported for any
//! number of indices.

use pkm_study::StudyMechanism as _;
use pkm_traits::Progress as _;
use super::{Context, Report, Run};
use crate::CliError;
use crate::grid::{GridOutcome, self, GridStudy, NodeOutcome, Prepared, Shard, landscape_header, landscape_rows};
use crate::indices::IndexName;
use crate::output::{Output, StudyEcho, short};
use crate::plot::{self, Marker, Scatter};
use crate::study::units::Real;
use crate::study::{self, StudyFile};
use pkm_optimizers::{Sense, pareto_front};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::PathBuf;
use toml::Spanned;

/// Arguments of `pkm pareto`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
    /// Evaluate only part I of N of the grid (join the parts with `pkm merge`).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
}

/// The `[pareto]` section.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParetoSection {
    /// Two or more indices, all maximised, in this order.
    pub objectives: Spanned<Vec<IndexName>>,
    /// Weightings whose optima are reported and marked, one weight per objective.
    #[serde(default)]
    pub weights: Vec<Spanned<Vec<Real>>>,
}

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

/// The `result` of a complete Pareto study.
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

fn section(file: &StudyFile<GridStudy>) -> Result<&Spanned<ParetoSection>, CliError> {
    file.study
        .pareto
        .as_ref()
        .ok_or_else(|| file.error_at(0..0, "missing [pareto] section (objectives = [...])"))
}

/// The objectives with where they were asked for, checked: at least two, no repeats.
fn objectives(file: &StudyFile<GridStudy>) -> Result<Vec<(IndexName, Range<usize>)>, CliError> {
    let objectives = &section(file)?.get_ref().objectives;
    let list = objectives.get_ref();
    let mut unique = list.clone();
    unique.sort();
    unique.dedup();
    if list.len() < 2 || unique.len() != list.len() {
        return Err(file.error_at(
            objectives.span(),
            "objectives: expected two or more different indices",
        ));
    }
    Ok(list.iter().map(|i| (*i, objectives.span())).collect())
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let file: StudyFile<GridStudy> = study::load(&self.file)?;
        let echo = StudyEcho {
            file: self.file.display().to_string(),
            text: file.text.clone(),
        };
        let requested = objectives(&file)?;
        let prepared = grid::prepare(&file, &requested)?;
        let indices: Vec<IndexName> = requested.iter().map(|(i, _)| *i).collect();
        let shard = self.shard.unwrap_or(Shard::WHOLE);
        match grid::evaluate_or_write_shard(
            "pareto",
            echo.clone(),
            &prepared,
            &indices,
            file.study.indices,
            shard,
            context,
        )? {
            GridOutcome::Shard(report) => Ok(report),
            GridOutcome::Whole(outcomes) => finish(&file, echo, &prepared, outcomes, context),
        }
    }
}

/// The indices a Pareto study evaluates, in objective order.
///
/// # Errors
/// At their line: no `[pareto]` section, fewer than two objectives, or a repeated one.
pub fn requested(file: &StudyFile<GridStudy>) -> Result<Vec<(IndexName, Range<usize>)>, CliError> {
    objectives(file)
}

/// Finishes a Pareto study from every node's outcome (a single run and `pkm merge` both end
/// here).
///
/// # Errors
/// No feasible node; weights of the wrong length; I/O.
pub fn finish(
    file: &StudyFile<GridStudy>,
    echo: StudyEcho,
    prepared: &Prepared,
    outcomes: Vec<NodeOutcome>,
    context: &Context,
) -> Result<Report, CliError> {
    let section = section(file)?.get_ref();
    let indices: Vec<IndexName> = objectives(file)?.into_iter().map(|(i, _)| i).collect();
    let m = indices.len();
    let mut weightings = Vec::new();
    for w in &section.weights {
        if w.get_ref().len() != m {
            return Err(file.error_at(w.span(), format!("weights: expected {m} numbers, one per objective")));
        }
        weightings.push(w.get_ref().iter().map(|r| r.0).collect::<Vec<f64>>());
    }
    let feasible: Vec<(usize, &[f64])> = outcomes
        .iter()
        .enumerate()
        .filter_map(|(k, o)| o.as_ref().ok().map(|v| (k, v.as_slice())))
        .collect();
    if feasible.is_empty() {
        return Err(CliError::Invalid(format!("no feasible design among {} nodes", outcomes.len())));
    }
    context.progress.phase("non-dominated set");
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
            FrontPoint {
                node,
                design: grid.names.iter().cloned().zip(grid.design(node)).collect(),
                values: values_of(node).to_vec(),
                weight_range: pareto.weight_intervals.as_ref().and_then(|w| w.get(k).copied().flatten()),
            }
        })
        .collect();
    let weighted_optima: Vec<WeightedOptimum> = weightings
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
    let mut out = Output::create(&context.out)?;
    out.write_csv(
        "landscape.csv",
        &landscape_header(grid, &indices, &[]),
        landscape_rows(grid, &outcomes, m, |_| Vec::new()),
    )?;
    let mut header = vec!["node".to_owned()];
    header.extend(grid.names.iter().cloned());
    header.extend(indices.iter().map(|i| i.key().to_owned()));
    header.extend(["w_min".to_owned(), "w_max".to_owned()]);
    out.write_csv(
        "front.csv",
        &header,
        front.iter().map(|p| {
            let mut row = vec![p.node.to_string()];
            row.extend(grid.design(p.node).iter().map(|v| format!("{v}")));
            row.extend(p.values.iter().map(|v| format!("{v}")));
            let (lo, hi) = p.weight_range.map_or((None, None), |(a, b)| (Some(a), Some(b)));
            row.push(crate::output::cell(lo));
            row.push(crate::output::cell(hi));
            row
        }),
    )?;
    let mut front_xy: Vec<(f64, f64)> = front.iter().map(|p| (p.values[0], p.values[1])).collect();
    front_xy.sort_by(|a, b| a.0.total_cmp(&b.0));
    let plot = Scatter {
        title: format!("non-dominated designs: {} vs {}", indices[0].key(), indices[1].key()),
        x_label: indices[0].key().into(),
        y_label: indices[1].key().into(),
        background: feasible.iter().map(|(_, v)| (v[0], v[1])).collect(),
        front: front_xy,
        markers: weighted_optima
            .iter()
            .map(|o| Marker {
                x: o.values[0],
                y: o.values[1],
                label: format!(
                    "w = ({})",
                    o.weights.iter().map(|w| short(*w)).collect::<Vec<_>>().join(", ")
                ),
            })
            .collect(),
    };
    out.write_svg("front.svg", |path| plot::scatter(&plot, path))?;
    let infeasible = outcomes.len() - feasible.len();
    let mut report = Report::default();
    report.line(format!(
        "{} nodes, {infeasible} infeasible; {} non-dominated designs, {} selected by some \
         weight w of w·{} + (1 − w)·{}",
        outcomes.len(),
        front.len(),
        front.iter().filter(|p| p.weight_range.is_some()).count(),
        indices[0].key(),
        indices[1].key()
    ));
    let mut selected: Vec<&FrontPoint> = front.iter().filter(|p| p.weight_range.is_some()).collect();
    selected.sort_by(|a, b| {
        let lo = |p: &FrontPoint| p.weight_range.map_or(0.0, |r| r.0);
        lo(a).total_cmp(&lo(b))
    });
    let values = |v: &[f64]| v.iter().map(|x| short(*x)).collect::<Vec<_>>().join(", ");
    for p in selected {
        if let Some((lo, hi)) = p.weight_range {
            let design: Vec<String> = grid
                .names
                .iter()
                .zip(grid.design(p.node))
                .map(|(k, v)| format!("{k} = {}", short(v)))
                .collect();
            report.line(format!(
                "  w in [{lo:.4}, {hi:.4}]: {} -> ({})",
                design.join(", "),
                values(&p.values)
            ));
        }
    }
    for o in &weighted_optima {
        report.line(format!(
            "weights ({}): node {} -> ({})",
            values(&o.weights),
            o.node,
            values(&o.values)
        ));
    }
    let result = ParetoResult {
        title: file.study.title.clone(),
        mechanism: file.study.mechanism.kind().into(),
        objectives: indices,
        nodes: outcomes.len(),
        infeasible,
        front,
        weighted_optima,
    };
    match result.weighted_optima.first() {
        Some(o) => {
            let scene = grid::design_scene(file, prepared, &grid.design(o.node));
            let caption = format!(
                "{}: the weighted optimum (node {})",
                result.mechanism, o.node
            );
            out.write_robot(&mut report, &caption, scene)?;
        }
        None => report.line("warning: no drawing of the robot: the study gives no weights"),
    }
    let path = out.finish("pareto", echo, result)?;
    report.line(format!("wrote {}", path.display()));
    Ok(report)
}
