//! `pkm assembly FILE`: the study layer's [`pkm_study::assembly()`] on a study file: every
//! assembly mode of a robot file at given actuator coordinates or poses, by parameter homotopy
//! where the robot has a polynomial form, with what the search guarantees (`modes.csv`,
//! `modes.svg`, the robot drawn in the first mode).

use super::{Context, Report, Run};
use crate::CliError;
use std::path::PathBuf;

/// Arguments of `pkm assembly`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_library_study("assembly", &self.file, context, pkm_study::assembly)
    }
}
