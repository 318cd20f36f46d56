//! `pkm merge DIR…`: joins the outputs of `pkm sweep --shard I/N` (or `pkm pareto`) for
//! I = 1…N into the result of a single run, bit for bit: the shards' node values are
//! concatenated in node order and the run is finished by the same code as a single run.

use super::{Context, Report, Run, pareto, sweep};
use crate::CliError;
use crate::grid::{self, GridStudy, Shard, ShardResult};
use crate::output::{Results, SCHEMA, StudyEcho};
use crate::study::{self, StudyFile};
use std::path::{Path, PathBuf};

/// Arguments of `pkm merge`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The `--out` directories of the shards, in any order.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
}

fn read_shard(dir: &Path) -> Result<Results<ShardResult>, CliError> {
    let path = dir.join("results.json");
    let text = std::fs::read_to_string(&path).map_err(|e| CliError::io(&path, e))?;
    let results: Results<serde_json::Value> = serde_json::from_str(&text)
        .map_err(|e| CliError::Invalid(format!("{}: {e}", path.display())))?;
    if results.schema != SCHEMA {
        return Err(CliError::Invalid(format!(
            "{}: schema {} (this pkm reads {SCHEMA})",
            path.display(),
            results.schema
        )));
    }
    let shard: ShardResult = serde_json::from_value(results.result).map_err(|_| {
        CliError::Invalid(format!(
            "{}: not the output of a shard (--shard I/N with N > 1)",
            path.display()
        ))
    })?;
    let Shard { index, count } = shard.shard;
    if !(1 <= index && index <= count) {
        return Err(CliError::Invalid(format!(
            "{}: shard {index}/{count} is not a part I/N with 1 <= I <= N",
            path.display()
        )));
    }
    Ok(Results {
        schema: results.schema,
        command: results.command,
        version: results.version,
        study: results.study,
        result: shard,
        files: results.files,
    })
}

/// Checks that `shards` are the N parts of one run and returns them in order.
fn check(mut shards: Vec<(PathBuf, Results<ShardResult>)>) -> Result<Vec<Results<ShardResult>>, CliError> {
    shards.sort_by_key(|(_, s)| s.result.shard.index);
    let Some((first_dir, first)) = shards.first() else {
        return Err(CliError::Invalid("no shard directories to merge".into()));
    };
    let count = first.result.shard.count;
    let differs = |what: &str, dir: &Path| {
        CliError::Invalid(format!(
            "{} and {}: different {what}; merge only the shards of one run",
            first_dir.display(),
            dir.display()
        ))
    };
    for (dir, s) in &shards {
        if s.command != first.command {
            return Err(differs("commands", dir));
        }
        if s.study.text != first.study.text {
            return Err(differs("study files", dir));
        }
        if s.result.shard.count != count || s.result.total_nodes != first.result.total_nodes {
            return Err(differs("shard counts", dir));
        }
    }
    let indices: Vec<usize> = shards.iter().map(|(_, s)| s.result.shard.index).collect();
    if indices != (1..=count).collect::<Vec<_>>() {
        return Err(CliError::Invalid(format!(
            "expected shards 1..={count} once each, got {indices:?}"
        )));
    }
    for (dir, s) in &shards {
        let range = s.result.shard.nodes(s.result.total_nodes);
        if s.result.first_node != range.start || s.result.outcomes.len() != range.len() {
            return Err(CliError::Invalid(format!(
                "{}: shard {}/{count} should hold nodes {range:?}",
                dir.display(),
                s.result.shard.index
            )));
        }
    }
    Ok(shards.into_iter().map(|(_, s)| s).collect())
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let shards = self
            .dirs
            .iter()
            .map(|d| Ok((d.clone(), read_shard(d)?)))
            .collect::<Result<Vec<_>, CliError>>()?;
        let shards = check(shards)?;
        let Some(first) = shards.first() else {
            return Err(CliError::Invalid("no shard directories to merge".into()));
        };
        let echo: StudyEcho = first.study.clone();
        let command = first.command.clone();
        let indices = first.result.indices.clone();
        let outcomes: Vec<grid::NodeOutcome> = shards
            .into_iter()
            .flat_map(|s| s.result.outcomes)
            .collect();
        let file: StudyFile<GridStudy> =
            study::parse(Path::new(&echo.file), echo.text.clone())?;
        let requested = match command.as_str() {
            "sweep" => sweep::requested_indices(&file)?,
            "pareto" => pareto::requested(&file)?,
            other => {
                return Err(CliError::Invalid(format!("cannot merge the output of `{other}`")));
            }
        };
        if requested.iter().map(|(i, _)| *i).ne(indices.iter().copied()) {
            return Err(CliError::Invalid(
                "the shards evaluated other indices than their study asks for".into(),
            ));
        }
        let prepared = grid::prepare(&file, &requested)?;
        if prepared.grid.len() != outcomes.len() {
            return Err(CliError::Invalid("the shards do not cover the study's grid".into()));
        }
        match command.as_str() {
            "sweep" => sweep::finish(&file, echo, &prepared, outcomes, context),
            _ => pareto::finish(&file, echo, &prepared, outcomes, context),
        }
    }
}

