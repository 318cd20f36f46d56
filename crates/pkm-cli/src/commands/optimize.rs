//! `pkm optimize FILE`: the study layer's [`pkm_study::optimize()`] on a study file: multistart
//! constrained optimisation of the Tsai platform's workspace volume, η or GCI with the
//! first- and second-order checks at the optimum; the starts as CSV and SVG, the optimum drawn.

use super::{Context, Report, Run};
use crate::CliError;
use std::path::PathBuf;

/// Arguments of `pkm optimize`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_library_study(
            "optimize",
            &self.file,
            context,
            pkm_study::optimize::<pkm_study::MechanismSpec>,
        )
    }
}
