//! `pkm sweep FILE [--shard I/N]`: the study layer's [`pkm_study::sweep()`] on a study file: an
//! exhaustive grid over design variables, a weighted utility, refinement, the landscape and
//! heat maps. A shard writes its nodes' values for `pkm merge`.

use super::{Context, Report, Run};
use crate::CliError;
use pkm_study::Shard;
use std::path::PathBuf;

/// Arguments of `pkm sweep`.
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
            "sweep",
            &self.file,
            context,
            |study: &pkm_study::SweepStudy, progress| pkm_study::sweep(study, shard, progress),
        )
    }
}
