//! `pkm workspace FILE`: the study layer's [`pkm_study::workspace()`] on a study file: volume ±
//! standard error, η and GCI, and planar slices of 1/κ as CSV and SVG.

use super::{Context, Report, Run};
use crate::CliError;
use std::path::PathBuf;

/// Arguments of `pkm workspace`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_library_study(
            "workspace",
            &self.file,
            context,
            pkm_study::workspace::<pkm_study::MechanismSpec>,
        )
    }
}
