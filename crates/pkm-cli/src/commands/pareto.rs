//! `pkm pareto FILE [--shard I/N]`: the study layer's [`pkm_study::pareto()`] on a study file:
//! the non-dominated designs of two or more indices over the study's grid and the weights that
//! select each. A shard writes its nodes' values for `pkm merge`.

use super::{Context, Report, Run};
use crate::CliError;
use pkm_study::Shard;
use std::path::PathBuf;

/// Arguments of `pkm pareto`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
    /// Evaluate only part I of N of the grid (join the parts with `pkm merge`).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let shard = self.shard.unwrap_or(Shard::WHOLE);
        super::run_library_study(
            "pareto",
            &self.file,
            context,
            |study: &pkm_study::ParetoStudy, progress| pkm_study::pareto(study, shard, progress),
        )
    }
}
