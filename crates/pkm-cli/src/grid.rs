//! The design grid shared by `pkm sweep` and `pkm pareto`: the study shape, the named design
//! variables and their axes, the evaluation of every node (in parallel, collected in node
//! order: bit-identical for any thread count), and the deterministic split into shards.

use crate::CliError;
use crate::indices::{Evaluator, IndexName, IndexSettings};
use crate::study::StudyFile;
use crate::study::mechanism::{ConstraintsSpec, MechanismSpec};
use crate::study::sampling::SamplingSpec;
use crate::study::units::Real;
use pkm_optimizers::{GridAxis, GridSearch, MAX_GRID_NODES};
use pkm_study::StudyMechanism as _;
use pkm_traits::Progress;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::str::FromStr;
use toml::Spanned;

/// The study of `pkm sweep` and `pkm pareto`: one grid, and the section of each command.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridStudy {
    /// Free text.
    pub title: Option<String>,
    /// The base design; the variables override its parameters.
    pub mechanism: MechanismSpec,
    /// Workspace limits (for the workspace indices).
    pub constraints: Option<Spanned<ConstraintsSpec>>,
    /// Common points of the workspace indices (needed for `volume`, `eta`, `gci`).
    pub sampling: Option<Spanned<SamplingSpec>>,
    /// Settings of the indices.
    #[serde(default)]
    pub indices: IndexSettings,
    /// The design variables: one `[[variables]]` table each.
    pub variables: Vec<VariableSpec>,
    /// The `pkm sweep` section.
    pub sweep: Option<Spanned<crate::commands::sweep::SweepSection>>,
    /// The `pkm pareto` section.
    pub pareto: Option<Spanned<crate::commands::pareto::ParetoSection>>,
}

/// One `[[variables]]` table: a parameter of the mechanism and its grid.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariableSpec {
    /// A parameter key of the mechanism table (its unit).
    pub name: Spanned<String>,
    /// First node.
    pub from: Real,
    /// Last node.
    pub to: Real,
    /// Node spacing (give `step` or `steps`).
    pub step: Option<Spanned<f64>>,
    /// Number of nodes (give `step` or `steps`).
    pub steps: Option<Spanned<usize>>,
}

/// Named axes; node `flat` has the last variable fastest (as `pkm_optimizers::grid_search`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Grid {
    /// Variable names.
    pub names: Vec<String>,
    /// The grid of their axes.
    pub search: GridSearch,
}

impl Grid {
    /// Their axes.
    pub fn axes(&self) -> &[GridAxis] {
        self.search.axes()
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.search.nodes()
    }

    /// Whether the grid has no node (never: a grid has at least one).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The design at node `flat` (empty past the last node).
    pub fn design(&self, flat: usize) -> Vec<f64> {
        self.search.node_design(flat).unwrap_or_default()
    }
}

/// `I/N`: the I-th (from 1) of N contiguous, nearly equal blocks of grid nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// I, from 1.
    pub index: usize,
    /// N.
    pub count: usize,
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let parse = |part: &str| part.trim().parse::<usize>().ok();
        match s.split_once('/').map(|(i, n)| (parse(i), parse(n))) {
            Some((Some(index), Some(count))) if index >= 1 && index <= count => {
                Ok(Self { index, count })
            }
            _ => Err(format!("expected I/N with 1 <= I <= N, got `{s}`")),
        }
    }
}

impl Shard {
    /// The whole grid.
    pub const WHOLE: Self = Self { index: 1, count: 1 };

    /// Its nodes among `total`: `[(I−1)·total/N, I·total/N)`.
    pub fn nodes(self, total: usize) -> Range<usize> {
        let bound = |k: usize| (k as u128 * total as u128 / self.count as u128) as usize;
        bound(self.index - 1)..bound(self.index)
    }
}

/// The value of the requested indices at a node, or why it has none.
pub type NodeOutcome = Result<Vec<f64>, String>;

/// A checked study, ready to evaluate.
#[derive(Debug)]
pub struct Prepared {
    /// The grid.
    pub grid: Grid,
    /// Evaluates designs.
    pub evaluator: Evaluator,
}

/// The axis of one variable.
fn axis<T>(file: &StudyFile<T>, v: &VariableSpec) -> Result<GridAxis, CliError> {
    let (from, to) = (v.from.0, v.to.0);
    let at = |span: Range<usize>, m: String| file.error_at(span, m);
    let axis = match (&v.step, &v.steps) {
        (Some(step), None) => GridAxis::with_step(from, to, *step.get_ref())
            .map_err(|e| at(step.span(), format!("step: {e} (in the variable's unit)")))?,
        (None, Some(steps)) => GridAxis::new(from, to, *steps.get_ref())
            .map_err(|e| at(steps.span(), format!("steps: {e}")))?,
        _ => {
            return Err(at(
                v.name.span(),
                format!(
                    "variable `{}`: give exactly one of step or steps",
                    v.name.get_ref()
                ),
            ));
        }
    };
    if from > to {
        return Err(at(
            v.name.span(),
            format!("variable `{}`: from > to", v.name.get_ref()),
        ));
    }
    Ok(axis)
}

/// Checks the study's grid, indices and constraints and builds the evaluator for `indices`.
///
/// # Errors
/// [`CliError::Study`] at the offending line: unknown or repeated variable, bad axis, too
/// many nodes, an index the mechanism does not have, a constraint it cannot evaluate, missing
/// sampling for a workspace index; [`CliError::Index`] for bad points.
pub fn prepare(
    file: &StudyFile<GridStudy>,
    indices: &[(IndexName, Range<usize>)],
) -> Result<Prepared, CliError> {
    let study = &file.study;
    if study.variables.is_empty() {
        return Err(file.error_at(0..0, "missing [[variables]]: the grid needs at least one"));
    }
    let mut names = Vec::new();
    let mut axes = Vec::new();
    let mut probe = study.mechanism.clone();
    for v in &study.variables {
        let name = v.name.get_ref();
        probe
            .set(name, 0.0)
            .map_err(|m| file.error_at(v.name.span(), m))?;
        if names.contains(name) {
            return Err(file.error_at(v.name.span(), format!("variable `{name}` given twice")));
        }
        names.push(name.clone());
        axes.push(axis(file, v)?);
    }
    let nodes = axes
        .iter()
        .try_fold(1usize, |acc, a| acc.checked_mul(a.n()));
    if nodes.is_none_or(|n| n > MAX_GRID_NODES) {
        return Err(file.error_at(
            study.variables[0].name.span(),
            format!("the grid has more than {MAX_GRID_NODES} nodes"),
        ));
    }
    for (index, span) in indices {
        if !index.applies_to(&study.mechanism) {
            return Err(file.error_at(
                span.clone(),
                format!(
                    "{} is not an index of {}",
                    index.key(),
                    study.mechanism.kind()
                ),
            ));
        }
    }
    let constraints = pkm_study::workspace::constraints_of(
        &study.mechanism,
        study.constraints.as_ref().map(Spanned::get_ref),
    )
    .map_err(|e| match &study.constraints {
        Some(spanned) => file.error_at(spanned.span(), format!("[constraints]: {}", e.message())),
        None => CliError::from(e),
    })?;
    let points = match indices.iter().find(|(i, _)| i.needs_points()) {
        None => None,
        Some((index, span)) => {
            let sampling = study.sampling.as_ref().ok_or_else(|| {
                file.error_at(
                    span.clone(),
                    format!("{} needs a [sampling] section with a region", index.key()),
                )
            })?;
            if sampling.get_ref().region.is_none() {
                return Err(file.error_at(
                    sampling.span(),
                    "[sampling]: a grid study compares designs on common points: give \
                     region = { ... } (lengths in metres)",
                ));
            }
            let domain = sampling.get_ref().domain(None)?;
            Some(sampling.get_ref().point_set(domain)?)
        }
    };
    let search = GridSearch::new(axes)?;
    let grid = Grid { names, search };
    let evaluator = Evaluator::new(
        study.mechanism.clone(),
        grid.names.clone(),
        constraints,
        points,
    );
    Ok(Prepared { grid, evaluator })
}

/// Evaluates `indices` at the nodes `range` of the grid (in parallel, in node order).
///
/// # Errors
/// [`CliError::Cancelled`] on Ctrl-C; a study error found while evaluating.
pub fn evaluate_nodes(
    prepared: &Prepared,
    indices: &[IndexName],
    settings: IndexSettings,
    range: Range<usize>,
    progress: &dyn Progress,
) -> Result<Vec<NodeOutcome>, CliError> {
    prepared
        .grid
        .search
        .evaluate_range(range, progress, |design| {
            let outcome = prepared.evaluator.evaluate(design, indices, settings)?;
            Ok(outcome.and_then(|values| {
                if values.iter().all(|v| v.is_finite()) {
                    Ok(values)
                } else {
                    Err(format!("non-finite index value {values:?}"))
                }
            }))
        })
}

/// The shard part of a `results.json`: what `pkm merge` joins.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardResult {
    /// Which shard.
    pub shard: Shard,
    /// Nodes of the whole grid.
    pub total_nodes: usize,
    /// First node of this shard.
    pub first_node: usize,
    /// The indices evaluated, in order.
    pub indices: Vec<IndexName>,
    /// One outcome per node of the shard.
    pub outcomes: Vec<NodeOutcome>,
}

/// Landscape rows: node, variables, the indices (empty when infeasible), the columns of
/// `extra(node)`, and the reason of an infeasible node.
pub fn landscape_rows<'a>(
    grid: &'a Grid,
    outcomes: &'a [NodeOutcome],
    n_indices: usize,
    extra: impl Fn(usize) -> Vec<String> + 'a,
) -> impl Iterator<Item = Vec<String>> + 'a {
    outcomes.iter().enumerate().map(move |(flat, outcome)| {
        let mut row = vec![flat.to_string()];
        row.extend(grid.design(flat).iter().map(|v| format!("{v}")));
        match outcome {
            Ok(values) => row.extend(values.iter().map(|v| format!("{v}"))),
            Err(_) => row.extend(std::iter::repeat_n(String::new(), n_indices)),
        }
        row.extend(extra(flat));
        row.push(match outcome {
            Ok(_) => String::new(),
            Err(reason) => format!("\"{}\"", reason.replace('"', "'")),
        });
        row
    })
}

/// The CSV header matching [`landscape_rows`].
pub fn landscape_header<'a>(
    grid: &'a Grid,
    indices: &[IndexName],
    extra: &[&'a str],
) -> Vec<String> {
    let mut header = vec!["node".to_owned()];
    header.extend(grid.names.iter().cloned());
    header.extend(indices.iter().map(|i| i.key().to_owned()));
    header.extend(extra.iter().map(|e| (*e).to_owned()));
    header.push("infeasible".to_owned());
    header
}

/// What [`evaluate_or_write_shard`] did.
#[derive(Debug)]
pub enum GridOutcome {
    /// A part of a split grid was written; the summary.
    Shard(crate::Report),
    /// Every node's outcome, for the command to finish.
    Whole(Vec<NodeOutcome>),
}

/// Evaluates the nodes of `shard`. For a part of a split grid (N > 1) it writes that part's
/// `results.json` (what `pkm merge` joins); for the whole grid it returns every node's outcome.
///
/// # Errors
/// As [`evaluate_nodes`]; I/O errors.
pub fn evaluate_or_write_shard(
    command: &str,
    echo: crate::output::StudyEcho,
    prepared: &Prepared,
    indices: &[IndexName],
    settings: IndexSettings,
    shard: Shard,
    context: &crate::Context,
) -> Result<GridOutcome, CliError> {
    let total = prepared.grid.len();
    let range = shard.nodes(total);
    context.progress.phase("evaluating the grid");
    let outcomes = evaluate_nodes(
        prepared,
        indices,
        settings,
        range.clone(),
        &context.progress,
    )?;
    if shard.count == 1 {
        return Ok(GridOutcome::Whole(outcomes));
    }
    let mut report = crate::Report::default();
    let feasible = outcomes.iter().filter(|o| o.is_ok()).count();
    report.line(format!(
        "shard {}/{}: nodes {}..{} of {total} ({feasible} feasible); join the shards with pkm merge",
        shard.index, shard.count, range.start, range.end
    ));
    let out = crate::output::Output::create(&context.out)?;
    let result = ShardResult {
        shard,
        total_nodes: total,
        first_node: range.start,
        indices: indices.to_vec(),
        outcomes,
    };
    let path = out.finish(command, echo, result)?;
    report.line(format!("wrote {}", path.display()));
    Ok(GridOutcome::Shard(report))
}

/// The drawing of the grid study's design `values` (in the order of its variables), under the
/// study's constraints, in its sampling region if it gives one.
///
/// # Errors
/// As [`pkm_study::scene::design_scene`].
pub fn design_scene(
    file: &StudyFile<GridStudy>,
    prepared: &Prepared,
    values: &[f64],
) -> Result<pkm_draw::Scene, String> {
    let spec = prepared.evaluator.mechanism_at(values)?;
    let region = file
        .study
        .sampling
        .as_ref()
        .and_then(|s| s.get_ref().region)
        .map(|r| r.region());
    pkm_study::scene::design_scene(&spec, prepared.evaluator.constraints(), region)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn shards_partition_the_grid_in_order() {
        for total in [0usize, 1, 2, 7, 16016] {
            for count in 1..=5 {
                let mut next = 0;
                for index in 1..=count {
                    let nodes = Shard { index, count }.nodes(total);
                    assert_eq!(nodes.start, next);
                    next = nodes.end;
                }
                assert_eq!(next, total);
            }
        }
        assert_eq!("2/3".parse::<Shard>(), Ok(Shard { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "1/0", "x", "1/", "-1/3"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
