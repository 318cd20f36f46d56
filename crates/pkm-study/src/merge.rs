//! Joins the parts of a split grid study (the [`ShardResult`]s of `sweep` or `pareto` with
//! shards 1/N … N/N) into the outcome of a single run, bit for bit: the parts' node values are
//! concatenated in node order and the study is finished by the same code as a single run.

use crate::StudyError;
pub use crate::error::MergeError;
use crate::grid::{self, NodeOutcome, ShardResult};
use crate::outcome::Outcome;
use crate::pareto::{self, ParetoResult};
use crate::registry::StudyMechanism;
use crate::schema::grid::{GridStudy, IndexName};
use crate::sweep::{self, SweepResult};
use pkm_traits::Progress;
use serde::{Deserialize, Serialize};

/// The grid study kinds that can be split.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GridKind {
    /// [`sweep`](crate::sweep()).
    Sweep,
    /// [`pareto`](crate::pareto()).
    Pareto,
}

/// The merged outcome of a split study: its kind's complete result. Serialised as the inner
/// result.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Merged {
    /// A sweep's.
    Sweep(SweepResult),
    /// A Pareto study's.
    Pareto(ParetoResult),
}

/// Checks that `parts` are the N parts of one run (in any order) and returns every node's
/// outcome in node order.
///
/// # Errors
/// [`MergeError`] for a set that is empty, mixed, incomplete or holds the wrong nodes.
pub fn join(mut parts: Vec<ShardResult>) -> Result<(Vec<IndexName>, Vec<NodeOutcome>), MergeError> {
    parts.sort_by_key(|p| p.shard.index);
    let first = parts.first().ok_or(MergeError::NoShards)?;
    let (count, total, indices) = (first.shard.count, first.total_nodes, first.indices.clone());
    let mixed =
        |p: &ShardResult| p.shard.count != count || p.total_nodes != total || p.indices != indices;
    if parts.iter().any(mixed) {
        return Err(MergeError::Mixed);
    }
    let got: Vec<usize> = parts.iter().map(|p| p.shard.index).collect();
    if got != (1..=count).collect::<Vec<_>>() {
        return Err(MergeError::Incomplete { count, got });
    }
    for p in &parts {
        let expected = p.shard.nodes(total);
        if p.first_node != expected.start || p.outcomes.len() != expected.len() {
            let index = p.shard.index;
            return Err(MergeError::WrongNodes {
                index,
                count,
                expected,
            });
        }
    }
    Ok((
        indices,
        parts.into_iter().flat_map(|p| p.outcomes).collect(),
    ))
}

/// Merges the parts of a split `kind` study of `study` into the single run's outcome (the
/// same result, artifacts and summary, bit for bit).
///
/// # Errors
/// The study's errors (checked again, before any computation), [`StudyError::Merge`] for parts
/// that are not the whole of one run of this study, and the finishing errors of `kind`.
pub fn merge<M: StudyMechanism>(
    study: &GridStudy<M>,
    kind: GridKind,
    parts: Vec<ShardResult>,
    progress: &dyn Progress,
) -> Result<Outcome<Merged>, StudyError> {
    let (indices, outcomes) = join(parts)?;
    match kind {
        GridKind::Sweep => {
            let plan = sweep::plan(study)?;
            let prepared = grid::prepare(study, &plan.requested, progress)?;
            check_parts(
                &plan.indices(),
                &indices,
                prepared.grid.len(),
                outcomes.len(),
            )?;
            let o = sweep::finish(study, &plan, &prepared, outcomes, progress)?;
            Ok(map(o, Merged::Sweep))
        }
        GridKind::Pareto => {
            let plan = pareto::plan(study)?;
            let prepared = grid::prepare(study, &plan.requested, progress)?;
            check_parts(
                &plan.indices(),
                &indices,
                prepared.grid.len(),
                outcomes.len(),
            )?;
            let o = pareto::finish(study, &plan, &prepared, &outcomes, progress)?;
            Ok(map(o, Merged::Pareto))
        }
    }
}

/// Checks that the parts hold the study's indices on its grid.
fn check_parts(
    expected: &[IndexName],
    got: &[IndexName],
    grid_nodes: usize,
    nodes: usize,
) -> Result<(), MergeError> {
    if expected != got {
        return Err(MergeError::OtherIndices {
            got: got.to_vec(),
            expected: expected.to_vec(),
        });
    }
    if grid_nodes != nodes {
        return Err(MergeError::OtherGrid {
            got: nodes,
            expected: grid_nodes,
        });
    }
    Ok(())
}

fn map<R>(o: Outcome<R>, f: impl FnOnce(R) -> Merged) -> Outcome<Merged> {
    Outcome {
        result: f(o.result),
        artifacts: o.artifacts,
        summary: o.summary,
    }
}
