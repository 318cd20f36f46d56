//! The design grid of [`sweep`](crate::sweep()) and [`pareto`](crate::pareto()): the named design
//! variables and their axes, checked with their key paths before any computation; the
//! evaluation of every node (in parallel, collected in node order: bit-identical for any thread
//! count); and the deterministic split into shards that [`merge`](crate::merge()) joins.

use crate::Infeasible;
use crate::indices::Evaluator;
use crate::outcome::{Cell, Outcome, Table};
use crate::registry::{Built, StudyMechanism};
use crate::schema::grid::{GridStudy, IndexName, IndexSettings, VariableSpec};
use crate::schema::mechanism::MechanismSpec;
use crate::task_space::TaskSpaceEvaluator;
use crate::workspace::constraints_of;
use crate::{KeyPath, StudyError};
use pkm_optimizers::{GridAxis, GridSearch, MAX_GRID_NODES};
use pkm_traits::Progress;
use pkm_workspace_indices::GaussLegendre;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::str::FromStr;

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

    /// Whether this is a part I/N with 1 ≤ I ≤ N.
    pub fn is_valid(self) -> bool {
        1 <= self.index && self.index <= self.count
    }

    /// Its nodes among `total`: `[(I−1)·total/N, I·total/N)` (empty for an invalid shard).
    pub fn nodes(self, total: usize) -> Range<usize> {
        if !self.is_valid() {
            return 0..0;
        }
        let bound = |k: usize| (k as u128 * total as u128 / self.count as u128) as usize;
        bound(self.index - 1)..bound(self.index)
    }
}

/// The values of the requested indices at a node, or why it has none.
pub type NodeOutcome = Result<Vec<f64>, Infeasible>;

/// The result of one part of a split grid study: what [`merge`](crate::merge()) joins.
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

/// What a grid study returns for a [`Shard`]: the complete result for the whole grid, the
/// shard's node values for a part of a split one. Serialised as the inner result.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum GridRun<R> {
    /// The whole grid (`Shard::WHOLE`).
    Complete(R),
    /// A part I/N with N > 1.
    Part(ShardResult),
}

/// A checked grid study, ready to evaluate.
#[derive(Debug)]
pub struct Prepared<M = MechanismSpec> {
    /// The grid.
    pub grid: Grid,
    /// Evaluates designs.
    pub evaluator: Evaluator<M>,
}

/// Checks index settings at `path` (`indices`, or a refinement level's overrides).
///
/// # Errors
/// [`StudyError::Invalid`] at `path.eta1_points` for a rule order outside
/// 1..=[`GaussLegendre::MAX_ORDER`].
pub fn check_index_settings(settings: IndexSettings, path: &str) -> Result<(), StudyError> {
    check_eta1_points(settings.eta1_points, path)
}

/// Checks a Gauss–Legendre order given at `path.eta1_points`.
///
/// # Errors
/// As [`check_index_settings`].
pub fn check_eta1_points(points: usize, path: &str) -> Result<(), StudyError> {
    if (1..=GaussLegendre::MAX_ORDER).contains(&points) {
        return Ok(());
    }
    Err(StudyError::invalid(
        format!("{path}.eta1_points").as_str(),
        format!(
            "expected a number of Gauss–Legendre points in 1..={}",
            GaussLegendre::MAX_ORDER
        ),
    ))
}

/// The axis of variable `k`.
fn axis(k: usize, v: &VariableSpec) -> Result<GridAxis, StudyError> {
    let (from, to) = (v.from.0, v.to.0);
    let at =
        |key: &str, m: String| StudyError::invalid(format!("variables[{k}].{key}").as_str(), m);
    let axis = match (v.step, v.steps) {
        (Some(step), None) => GridAxis::with_step(from, to, step)
            .map_err(|e| at("step", format!("{e} (in the variable's unit)")))?,
        (None, Some(steps)) => {
            GridAxis::new(from, to, steps).map_err(|e| at("steps", e.to_string()))?
        }
        _ => {
            let m = format!("variable `{}`: give exactly one of step or steps", v.name);
            return Err(at("name", m));
        }
    };
    if from > to {
        return Err(at("to", format!("variable `{}`: from > to", v.name)));
    }
    Ok(axis)
}

/// The checked variables of `study`: names and axes.
fn variables<M: StudyMechanism>(
    study: &GridStudy<M>,
) -> Result<(Vec<String>, Vec<GridAxis>), StudyError> {
    if study.variables.is_empty() {
        return Err(StudyError::invalid(
            "variables",
            "missing [[variables]]: the grid needs at least one",
        ));
    }
    let mut names: Vec<String> = Vec::new();
    let mut axes = Vec::new();
    let mut probe = study.mechanism.clone();
    for (k, v) in study.variables.iter().enumerate() {
        let at = |m: String| StudyError::invalid(format!("variables[{k}].name").as_str(), m);
        probe.set(&v.name, 0.0).map_err(at)?;
        if names.contains(&v.name) {
            return Err(at(format!("variable `{}` given twice", v.name)));
        }
        names.push(v.name.clone());
        axes.push(axis(k, v)?);
    }
    let nodes = axes
        .iter()
        .try_fold(1usize, |acc, a| acc.checked_mul(a.n()));
    if nodes.is_none_or(|n| n > MAX_GRID_NODES) {
        return Err(StudyError::invalid(
            "variables",
            format!("the grid has more than {MAX_GRID_NODES} nodes"),
        ));
    }
    Ok((names, axes))
}

/// Checks the study's grid, indices and constraints and builds the evaluator for `requested`
/// (each index with the key path that asked for it); the common points are generated in blocks
/// that each check `progress` first.
///
/// # Errors
/// [`StudyError::Invalid`] at the offending key: no, unknown or repeated variable, bad axis,
/// too many nodes, an index the mechanism does not have, a constraint it cannot evaluate,
/// missing sampling or region for a workspace index; [`StudyError::Index`] for bad points;
/// [`StudyError::Cancelled`] when `progress` asks to stop while the points are generated.
pub fn prepare<M: StudyMechanism>(
    study: &GridStudy<M>,
    requested: &[(IndexName, KeyPath)],
    progress: &dyn Progress,
) -> Result<Prepared<M>, StudyError> {
    check_index_settings(study.indices, "indices")?;
    let (names, axes) = variables(study)?;
    for (index, path) in requested {
        if !index.applies_to(&study.mechanism) {
            let kind = study.mechanism.kind();
            let m = format!("{} is not an index of {kind}", index.key());
            return Err(StudyError::invalid(path.clone(), m));
        }
    }
    let constraints = constraints_of(&study.mechanism, study.constraints.as_ref())?;
    let search = GridSearch::new(axes)?;
    let variables = names.clone();
    if let Some(spec) = &study.task_space {
        let robot = study.mechanism.robot_file().ok_or_else(|| {
            StudyError::invalid(
                "task_space",
                "a [task_space] study takes a robot file ([mechanism.robot_file])",
            )
        })?;
        let sampling = study.sampling.clone().unwrap_or_default();
        let task = TaskSpaceEvaluator::new(robot, spec, &sampling)?;
        let evaluator = Evaluator::new(study.mechanism.clone(), variables, constraints, None)
            .with_task_space(task);
        let grid = Grid { names, search };
        return Ok(Prepared { grid, evaluator });
    }
    if let Some(robot) = study.mechanism.robot_file() {
        robot.translational_robot()?;
    }
    let points = match requested.iter().find(|(i, _)| i.needs_points()) {
        None => None,
        Some((index, path)) => {
            let sampling = study.sampling.as_ref().ok_or_else(|| {
                let m = format!("{} needs a [sampling] section with a region", index.key());
                StudyError::invalid(path.clone(), m)
            })?;
            if sampling.region.is_none() {
                return Err(StudyError::invalid(
                    "sampling",
                    "a grid study compares designs on common points: give region = { ... } \
                     (lengths in metres)",
                ));
            }
            let domain = sampling.domain(None)?;
            progress.phase("sampling points");
            Some(sampling.point_set_cancellable(domain, progress)?)
        }
    };
    let grid = Grid { names, search };
    let evaluator = Evaluator::new(study.mechanism.clone(), variables, constraints, points);
    Ok(Prepared { grid, evaluator })
}

/// Evaluates `indices` at the nodes `range` of the grid (in parallel, in node order). A design
/// with a non-finite index value is infeasible.
///
/// # Errors
/// [`StudyError::Cancelled`] when `progress` asks to stop; a study error found while
/// evaluating.
pub fn evaluate_nodes<M: StudyMechanism>(
    prepared: &Prepared<M>,
    indices: &[IndexName],
    settings: IndexSettings,
    range: Range<usize>,
    progress: &dyn Progress,
) -> Result<Vec<NodeOutcome>, StudyError> {
    prepared
        .grid
        .search
        .evaluate_range(range, progress, |design| {
            let outcome = prepared.evaluator.evaluate(design, indices, settings)?;
            Ok(outcome.and_then(|values| {
                if values.iter().all(|v| v.is_finite()) {
                    Ok(values)
                } else {
                    Err(Infeasible::NonFinite { values })
                }
            }))
        })
}

/// The node values of `shard`: every node's outcome for the whole grid, or the finished
/// outcome of a part of a split grid.
pub(crate) enum Evaluated {
    Whole(Vec<NodeOutcome>),
    Part(Outcome<ShardResult>),
}

/// Evaluates the nodes of `shard` (the phase "evaluating the grid").
///
/// # Errors
/// As [`evaluate_nodes`].
pub(crate) fn evaluate_shard<M: StudyMechanism>(
    prepared: &Prepared<M>,
    indices: &[IndexName],
    settings: IndexSettings,
    shard: Shard,
    progress: &dyn Progress,
) -> Result<Evaluated, StudyError> {
    let total = prepared.grid.len();
    let range = shard.nodes(total);
    progress.phase("evaluating the grid");
    let outcomes = evaluate_nodes(prepared, indices, settings, range.clone(), progress)?;
    if shard.count == 1 {
        return Ok(Evaluated::Whole(outcomes));
    }
    let feasible = outcomes.iter().filter(|o| o.is_ok()).count();
    let mut outcome = Outcome::new(ShardResult {
        shard,
        total_nodes: total,
        first_node: range.start,
        indices: indices.to_vec(),
        outcomes,
    });
    outcome.line(format!(
        "shard {}/{}: nodes {}..{} of {total} ({feasible} feasible); join the shards with pkm merge",
        shard.index, shard.count, range.start, range.end
    ));
    Ok(Evaluated::Part(outcome))
}

/// A grid study's run of `shard`: `finish` on every node's outcome for the whole grid, the
/// shard's values for a part.
///
/// # Errors
/// As [`evaluate_shard`] and `finish`.
pub(crate) fn run<M: StudyMechanism, R>(
    prepared: &Prepared<M>,
    indices: &[IndexName],
    settings: IndexSettings,
    shard: Shard,
    progress: &dyn Progress,
    finish: impl FnOnce(Vec<NodeOutcome>) -> Result<Outcome<R>, StudyError>,
) -> Result<Outcome<GridRun<R>>, StudyError> {
    match evaluate_shard(prepared, indices, settings, shard, progress)? {
        Evaluated::Whole(outcomes) => {
            let o = finish(outcomes)?;
            Ok(Outcome {
                result: GridRun::Complete(o.result),
                artifacts: o.artifacts,
                summary: o.summary,
            })
        }
        Evaluated::Part(o) => Ok(Outcome {
            result: GridRun::Part(o.result),
            artifacts: o.artifacts,
            summary: o.summary,
        }),
    }
}

/// The landscape: node, variables, the indices (empty when infeasible), the columns `extra`
/// (`extra(node)` for each row), and the reason of an infeasible node (quoted).
pub fn landscape(
    grid: &Grid,
    outcomes: &[NodeOutcome],
    indices: &[IndexName],
    extra: &[&str],
    extra_cells: impl Fn(usize) -> Vec<Cell>,
) -> Table {
    let mut header = vec!["node".to_owned()];
    header.extend(grid.names.iter().cloned());
    header.extend(indices.iter().map(|i| i.key().to_owned()));
    header.extend(extra.iter().map(|e| (*e).to_owned()));
    header.push("infeasible".to_owned());
    let mut table = Table::new(header);
    for (flat, outcome) in outcomes.iter().enumerate() {
        let mut row = vec![Cell::from(flat)];
        row.extend(grid.design(flat).into_iter().map(Cell::Number));
        match outcome {
            Ok(values) => row.extend(values.iter().copied().map(Cell::Number)),
            Err(_) => row.extend(std::iter::repeat_n(Cell::Missing, indices.len())),
        }
        row.extend(extra_cells(flat));
        row.push(match outcome {
            Ok(_) => Cell::Text(String::new()),
            Err(reason) => Cell::Text(reason.to_string()),
        });
        table.rows.push(row);
    }
    table
}

/// The error of a grid study without a feasible node, with the first node's reason.
pub(crate) fn no_feasible_design(outcomes: &[NodeOutcome]) -> StudyError {
    let reason = outcomes.iter().find_map(|o| o.as_ref().err());
    StudyError::NoFeasibleDesign {
        nodes: outcomes.len(),
        reason: reason.map(ToString::to_string).unwrap_or_default(),
    }
}

/// The drawing of the study's design `values` (in the order of its variables), under the
/// study's constraints, in its sampling region if it gives one; a robot file rated in its task
/// space is drawn at its home pose.
///
/// # Errors
/// As [`crate::scene::design_scene`].
pub fn design_scene<M: StudyMechanism>(
    study: &GridStudy<M>,
    prepared: &Prepared<M>,
    values: &[f64],
) -> Result<pkm_draw::Scene, String> {
    let spec = prepared
        .evaluator
        .mechanism_at(values)
        .map_err(|e| e.to_string())?;
    if let (Some(_), Some(robot)) = (&study.task_space, spec.robot_file()) {
        return crate::task_space::robot_at_home(robot);
    }
    let region = study
        .sampling
        .as_ref()
        .and_then(|s| s.region)
        .map(|r| r.region());
    let built = Built::new(spec).map_err(|e| e.to_string())?;
    crate::scene::design_scene(&built, prepared.evaluator.constraints(), region)
}

#[cfg(test)]
mod tests {
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
        assert_eq!(Shard { index: 0, count: 0 }.nodes(10), 0..0);
    }
}
