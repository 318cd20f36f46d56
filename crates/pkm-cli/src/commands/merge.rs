//! `pkm merge DIR…`: joins the outputs of `pkm sweep --shard I/N` (or `pkm pareto`) for
//! I = 1…N into the result of a single run, bit for bit, with the study layer's
//! [`pkm_study::merge()`]. This file reads the shards' `results.json` and checks that they come
//! from one command on one study file.

use super::{Context, Report, Run};
use crate::CliError;
use crate::output::{Output, Results, SCHEMA};
use crate::study;
use pkm_study::{GridKind, GridStudy, ShardResult};
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
    Ok(Results {
        schema: results.schema,
        command: results.command,
        version: results.version,
        study: results.study,
        result: shard,
        files: results.files,
    })
}

/// Checks that the shards in `dirs` come from one command on one study file; returns them.
fn read_shards(dirs: &[PathBuf]) -> Result<Vec<Results<ShardResult>>, CliError> {
    let shards = dirs
        .iter()
        .map(|d| read_shard(d))
        .collect::<Result<Vec<_>, CliError>>()?;
    let Some(first) = shards.first() else {
        return Err(CliError::Invalid("no shard directories to merge".into()));
    };
    for (dir, s) in dirs.iter().zip(&shards) {
        let differs = |what: &str| {
            CliError::Invalid(format!(
                "{} and {}: different {what}; merge only the shards of one run",
                dirs[0].display(),
                dir.display()
            ))
        };
        if s.command != first.command {
            return Err(differs("commands"));
        }
        let robot_text =
            |r: &Results<ShardResult>| r.study.robot_file.as_ref().map(|f| f.text.clone());
        if s.study.text != first.study.text || robot_text(s) != robot_text(first) {
            return Err(differs("study files"));
        }
    }
    Ok(shards)
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let shards = read_shards(&self.dirs)?;
        let Some(first) = shards.first() else {
            return Err(CliError::Invalid("no shard directories to merge".into()));
        };
        let (command, echo) = (first.command.clone(), first.study.clone());
        let parts = shards.into_iter().map(|s| s.result).collect();
        let kind = match command.as_str() {
            "sweep" => GridKind::Sweep,
            "pareto" => GridKind::Pareto,
            other => {
                let m = format!("cannot merge the output of `{other}`");
                return Err(CliError::Invalid(m));
            }
        };
        let (source, grid): (_, GridStudy) = study::study_from_echo(&echo)?;
        let outcome =
            pkm_study::merge(&grid, kind, parts, &context.progress).map_err(|e| source.error(e))?;
        let mut report = Report {
            lines: outcome.summary,
        };
        let mut out = Output::create(&context.out)?;
        out.write_artifacts(&outcome.artifacts, &mut report)?;
        let written = out.finish(&command, echo, outcome.result)?;
        report.line(format!("wrote {}", written.display()));
        Ok(report)
    }
}
